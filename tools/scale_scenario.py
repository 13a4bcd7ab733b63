#!/usr/bin/env python3
"""Scale a scenario geometrically: every length times S, the same stresses.

    tools/scale_scenario.py SCENARIO.toml S -o OUT.toml [--scale-crack-length]

The specimen, its grains, the walls, the contact radius, bonding distances and mesh grains
grow by S; the time step and every stage's time grow by S too, so that the walls, moving at
the same speed, strain the specimen at the same rate per step and a stage takes the same
number of steps. Spring constants follow so that stresses stay: contact springs (N/m) by S,
rolling and twisting springs (N m/rad) by S^3, bond springs (N/m^3) by 1/S; gravity by 1/S
(the same ratio of weight to inertia forces). Bond strengths (Pa), friction and damping
ratios, densities and velocities are left as they are.

What this keeps and what it changes (a bonded-particle model's own similarity):
- E, nu, the tensile and flexural strengths of bonded specimens are the same: every force
  grows by S^2 and every displacement by S.
- A notched specimen's K_Ic through its bonds grows by sqrt(S): K = sigma sqrt(length). A
  bonded model's toughness is set by its grain size (Potyondy and Cundall 2004), which is
  how `cleave calibrate` asks to fit a K_Ic that the grain boundaries carry.
- The transgranular criterion's crack length is the material's flaw, not the model's, and is
  left as it is unless --scale-crack-length is given (then the grains' splitting K is the
  same too, and the scaled scenario is the same model, only larger).

Refused, with the file, line and key: [thermal] (conduction time goes as S^2, not S), the
cohesive bond law (its g_c sets a length of its own), and keys this tool does not know.
"""

import argparse
import math
import re
import sys
import tomllib

# (table, key) -> the power of S a value is multiplied by. Table names are as written in
# the file's headers ("wall" for [[wall]]).
LENGTH, TIME, NONE = 1, 1, 0
RULES = {
    "scenario": {"name": NONE, "description": NONE, "length_unit": NONE},
    "specimen": {
        "shape": NONE, "size": LENGTH, "diameter": LENGTH, "thickness": LENGTH, "length": LENGTH,
        "height": LENGTH, "notch_width": LENGTH, "notch_depth": LENGTH, "keep": NONE,
        "grains": NONE, "gap": LENGTH, "seed": NONE,
    },
    "mesh_grain": {"file": NONE, "scale": LENGTH, "position": LENGTH, "convex_hull": NONE},
    "grain": {"r": LENGTH, "r_bar": LENGTH, "t": LENGTH, "t_bar": LENGTH},
    "orientation": {"seed": NONE, "family_mix": NONE, "angles": NONE},
    "split": {"min_fragment_fraction": NONE},
    "output": {"mesh_format": NONE, "mesh_layout": NONE, "frame_meshes": NONE, "checkpoint_every": NONE},
    "material": {"preset": NONE, "density": NONE},
    "contact": {"dilation_radius": LENGTH},
    "contact.particle_particle": {
        "kn": 1, "ks": 1, "kr": 3, "kt": 3, "c_res": NONE, "mu_s": NONE, "mu_r": NONE, "damping": NONE,
    },
    "dynamics": {
        "dt": TIME, "duration": TIME, "gravity": -1, "lift": LENGTH, "frames": NONE,
        "settle_ratio": NONE, "dt_safety": NONE, "search": NONE, "threads": NONE,
        "local_damping": NONE, "density_scale": NONE, "manifold_tolerance": NONE, "in_plane": NONE,
    },
    "wall": {
        "name": NONE, "kind": NONE, "point": LENGTH, "normal": NONE, "velocity": NONE,
        "load_axis": NONE, "u": NONE, "size": LENGTH, "length": LENGTH, "radius": LENGTH,
        "gap": LENGTH,
    },
    "bond": {
        "kbn": -1, "kbs": -1, "tbn": NONE, "tbs": NONE, "law": NONE, "criterion": NONE,
        "sigma_f": NONE, "young": NONE, "poisson": NONE, "radius": LENGTH,
        "strength_modulus": NONE,
    },
    "fracture": {
        "sigma_f_hyd": NONE, "k_ic": NONE, "c": NONE, "crack_length": NONE, "check_every": NONE,
        "criterion": NONE, "sigma_f": NONE, "inertia": NONE,
    },
    "periodic": {"axes": NONE, "stress_control_time": TIME, "stress_control_modulus": NONE},
    "stage": {
        "name": NONE, "kind": NONE, "wall_velocity": NONE, "steps": NONE, "time": TIME,
        "until": NONE, "load_drop": NONE, "load_walls": NONE, "frames": NONE, "ramp_time": TIME,
        "rate_scale": NONE, "hold_cracks": NONE, "cell_strain_rate": -1, "measure_modulus": NONE,
        "distance": LENGTH,
    },
}
RULES["contact.particle_wall"] = RULES["contact.particle_particle"]

HEADER = re.compile(r"^\s*\[\[?\s*([A-Za-z_.]+)\s*\]\]?\s*(#.*)?$")
KEY = re.compile(r"^(\s*)([A-Za-z_]+)(\s*=\s*)(.*?)(\s*)(#.*)?$")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


class ScaleError(Exception):
    pass


def fmt(x):
    return "%.10g" % x


def scaled_value(text, factor):
    """The value's text with every number times factor (a number or an array of them)."""
    if text.startswith("["):
        return NUMBER.sub(lambda m: fmt(float(m.group(0)) * factor), text)
    return fmt(float(text) * factor)


def scale_text(text, source, s, scale_crack_length=False):
    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScaleError(f"{source}: not TOML: {e}")
    table = ""
    out = []
    for number, line in enumerate(text.splitlines(keepends=True), start=1):
        body = line.rstrip("\n")
        header = HEADER.match(body)
        if header:
            table = header.group(1)
            if table == "thermal":
                raise ScaleError(f"{source}:{number}: table 'thermal': a thermal run does not scale "
                                 "with its lengths (conduction times go as S^2); scale it by hand")
            if table not in RULES:
                raise ScaleError(f"{source}:{number}: table '{table}': scale_scenario does not know it")
            out.append(line)
            continue
        if not body.strip() or body.lstrip().startswith("#"):
            out.append(line)
            continue
        key = KEY.match(body)
        if not key:
            raise ScaleError(f"{source}:{number}: a line scale_scenario cannot read (one key a line)")
        indent, name, eq, value, space, comment = key.groups()
        where = f"{source}:{number}: key '{table}.{name}'"
        rules = RULES.get(table, {})
        if name not in rules:
            raise ScaleError(f"{where}: scale_scenario does not know how it scales")
        if table == "bond" and name == "law" and "cohesive" in value:
            raise ScaleError(f"{where}: the cohesive law's g_c sets a length of its own; it does not scale")
        if table == "stage" and name.startswith(("temperature", "quench")):
            raise ScaleError(f"{where}: a thermal stage does not scale with its lengths")
        power = rules[name]
        if table == "fracture" and name == "crack_length" and scale_crack_length:
            power = 1
        if power == 0:
            out.append(line)
            continue
        try:
            new = scaled_value(value.strip(), s ** power)
        except ValueError:
            raise ScaleError(f"{where}: not a number: {value.strip()}")
        out.append(f"{indent}{name}{eq}{new}{space}{comment or ''}\n")
    result = "".join(out)
    tomllib.loads(result)  # what was written still reads
    return result


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scenario")
    p.add_argument("factor", type=float, help="S: every length times S")
    p.add_argument("-o", "--out", required=True, help="the scaled scenario (TOML)")
    p.add_argument("--scale-crack-length", action="store_true",
                   help="scale [fracture] crack_length too (the same model, larger)")
    a = p.parse_args(argv)
    if not (math.isfinite(a.factor) and a.factor > 0):
        print(f"scale_scenario: factor {a.factor}: must be a number > 0", file=sys.stderr)
        return 2
    try:
        text = open(a.scenario, encoding="utf-8").read()
    except OSError as e:
        print(f"scale_scenario: {a.scenario}: {e.strerror}", file=sys.stderr)
        return 2
    try:
        result = scale_text(text, a.scenario, a.factor, a.scale_crack_length)
    except ScaleError as e:
        print(f"scale_scenario: {e}", file=sys.stderr)
        return 1
    with open(a.out, "w", encoding="utf-8") as f:
        f.write(result)
    print(f"{a.scenario} x {a.factor:g} -> {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
