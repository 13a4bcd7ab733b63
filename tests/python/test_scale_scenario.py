"""tools/scale_scenario.py: a geometric scaling that keeps stresses (its docstring).

The laws checked here are those of a bonded-particle model under that scaling: E and nu
stay, and a notched beam cracked along its grain boundaries reads K_Ic times sqrt(S).
"""
import csv
import pathlib
import subprocess
import sys
import tomllib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "scale_scenario.py"
MATERIALS = ROOT / "scenarios" / "materials"


def scale(src, factor, out, *extra):
    return subprocess.run([sys.executable, str(TOOL), str(src), str(factor), "-o", str(out), *extra],
                          capture_output=True, text=True)


def measure(binary, test, scenario, out):
    return subprocess.Popen([binary, "measure", test, str(scenario), "-o", str(out), "-q",
                             "--set", "dynamics.threads=1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def result(proc, out):
    _, err = proc.communicate()
    assert proc.returncode == 0, err.decode()
    return tomllib.loads((out / "measure.toml").read_text())


@pytest.mark.parametrize("name", ["sic_elastic", "sic_brazilian", "sic_four_point", "sic_senb"])
@pytest.mark.parametrize("crack_too", [False, True])
def test_every_length_and_time_scales_and_the_springs_follow(tmp_path, name, crack_too):
    s = 0.37
    src = MATERIALS / f"{name}.toml"
    r = scale(src, s, tmp_path / "out.toml", *(["--scale-crack-length"] if crack_too else []))
    assert r.returncode == 0, r.stderr
    a = tomllib.loads(src.read_text())
    b = tomllib.loads((tmp_path / "out.toml").read_text())

    def same(x, y, f, where):
        if isinstance(x, list):
            assert len(x) == len(y), where
            for u, v in zip(x, y):
                same(u, v, f, where)
        else:
            assert y == pytest.approx(x * f, rel=1e-9), where

    for key, v in a["specimen"].items():
        if isinstance(v, (int, float, list)) and key not in ("seed", "grains"):
            same(v, b["specimen"][key], s, f"specimen.{key}")
    for key in ("r", "r_bar", "t", "t_bar"):
        same(a["grain"][key], b["grain"][key], s, f"grain.{key}")
    same(a["contact"]["dilation_radius"], b["contact"]["dilation_radius"], s, "dilation_radius")
    for pair in ("particle_particle", "particle_wall"):
        same(a["contact"][pair]["kn"], b["contact"][pair]["kn"], s, f"{pair}.kn")
        same(a["contact"][pair]["mu_s"], b["contact"][pair]["mu_s"], 1, f"{pair}.mu_s")
    same(a["bond"]["kbn"], b["bond"]["kbn"], 1 / s, "kbn")
    same(a["bond"]["tbn"], b["bond"]["tbn"], 1, "tbn")
    same(a["dynamics"]["dt"], b["dynamics"]["dt"], s, "dt")
    for wa, wb in zip(a["wall"], b["wall"]):
        same(wa["point"], wb["point"], s, "wall.point")
        same(wa["normal"], wb["normal"], 1, "wall.normal")
    for sa, sb in zip(a["stage"], b["stage"]):
        if "time" in sa:
            same(sa["time"], sb["time"], s, "stage.time")
        if "wall_velocity" in sa:
            assert sa["wall_velocity"] == sb["wall_velocity"]
    if "fracture" in a:
        same(a["fracture"]["crack_length"], b["fracture"]["crack_length"], s if crack_too else 1, "crack_length")


def test_refusals_name_the_file_line_and_key(tmp_path):
    r = scale(ROOT / "scenarios" / "thermal_microcracking.toml", 2, tmp_path / "o.toml")
    assert r.returncode == 1 and "thermal_microcracking.toml:" in r.stderr and "'thermal'" in r.stderr
    bad = tmp_path / "bad.toml"
    bad.write_text((MATERIALS / "sic_elastic.toml").read_text().replace("[grain]\n", "[grain]\nwobble = 3\n"))
    r = scale(bad, 2, tmp_path / "o.toml")
    lines = bad.read_text().splitlines()
    line = next(i for i, l in enumerate(lines, start=1) if l.startswith("wobble"))
    assert r.returncode == 1 and f"bad.toml:{line}: key 'grain.wobble'" in r.stderr, r.stderr
    assert not (tmp_path / "o.toml").exists(), "a refused scaling wrote its output"
    r = scale(MATERIALS / "sic_elastic.toml", -1, tmp_path / "o.toml")
    assert r.returncode == 2 and "must be a number > 0" in r.stderr


def test_youngs_modulus_and_poissons_ratio_do_not_change_with_the_scale(tmp_path, cleave_binary):
    scale(MATERIALS / "sic_elastic.toml", 0.5, tmp_path / "half.toml")
    p1 = measure(cleave_binary, "elastic", MATERIALS / "sic_elastic.toml", tmp_path / "one")
    p2 = measure(cleave_binary, "elastic", tmp_path / "half.toml", tmp_path / "two")
    one, half = result(p1, tmp_path / "one"), result(p2, tmp_path / "two")
    assert half["young_Pa"] == pytest.approx(one["young_Pa"], rel=2e-3)
    assert half["poisson"] == pytest.approx(one["poisson"], abs=2e-3)


def first_break_step(out):
    breaks = list(csv.DictReader(open(out / "bond_breaks.csv")))
    assert breaks, f"{out}: no bond broke"
    return int(breaks[0]["step"])


def test_notched_beam_through_its_bonds_is_sics_toughness_and_starts_cracking_at_the_square_root_of_scale(
        tmp_path, cleave_binary):
    # The shipped SENB's crack leaves the notch along grain boundaries (a bond breaks first):
    # K_I of its notched section's statics at that first crack, the value it is judged by
    # (k_ic_Pa_sqrt_m_from_statics_at_first_crack), is SiC's 3.1 MPa m^0.5 within its band.
    # At half the scale its first bond breaks on the same step under a quarter of the load,
    # so K_Ic = P S / (B W^1.5) Y at crack initiation (k_ic_Pa_sqrt_m_at_first_crack) is
    # 1/sqrt(2) of it. (The peak itself need not follow: the notch tip's two bonds are loaded
    # alike, and where rounding breaks only one of them the crack kinks and stops before the
    # peak.)
    scale(MATERIALS / "sic_senb.toml", 0.5, tmp_path / "half.toml")
    p1 = measure(cleave_binary, "senb", MATERIALS / "sic_senb.toml", tmp_path / "one")
    p2 = measure(cleave_binary, "senb", tmp_path / "half.toml", tmp_path / "two")
    one, half = result(p1, tmp_path / "one"), result(p2, tmp_path / "two")
    assert one["first_crack"] == "bond" and half["first_crack"] == "bond"
    assert one["judged"] == "k_ic_Pa_sqrt_m_from_statics_at_first_crack"
    assert one["k_ic_Pa_sqrt_m_from_statics_at_first_crack"] == pytest.approx(3.1e6, rel=0.10)
    assert abs(first_break_step(tmp_path / "one") - first_break_step(tmp_path / "two")) <= 2
    assert half["first_crack_load_N"] / one["first_crack_load_N"] == pytest.approx(0.25, rel=0.01)
    assert (half["k_ic_Pa_sqrt_m_at_first_crack"] / one["k_ic_Pa_sqrt_m_at_first_crack"]
            == pytest.approx(0.5 ** 0.5, rel=0.01))
    assert one["k_ic_Pa_sqrt_m_at_first_crack"] <= one["k_ic_Pa_sqrt_m"]
