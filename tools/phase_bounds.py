#!/usr/bin/env python3
"""Two-phase cells against the bounds and estimates of composite mechanics (docs/PHASES.md).

  tools/phase_bounds.py OUT_DIR RESULT_F0 RESULT_F1 [RESULT_f ...]

Each RESULT is the folder of one run of scenarios/glass_alumina.toml (or a scenario with the
same stages) at one volume fraction of its second [[phase]] (read from the run's
scenario_as_run.toml). The runs at fraction 0 and 1 give each phase's E and nu (modulus.csv)
and expansion coefficient (cell.csv); from them, for every run:
  - E against the Hashin-Shtrikman bounds (Hashin & Shtrikman 1963), K = E / (3 (1 - 2 nu)),
    G = E / (2 (1 + nu)) of each phase, and against Voigt and Reuss;
  - alpha against Turner's estimate (sum f K alpha / sum f K) and Kerner's (the majority
    phase as matrix), with each phase's K and alpha from its single-phase cell.
E is read in the stages named E_* (modulus.csv), before and after cooling: the first and the
last of them. alpha in the stages named alpha_*: the mean over the three axes of the cell's
length change over the stage, divided by the temperature change (each alpha_* stage starts
from a stress-free cell: just bonded, or at the end of a stress-controlled cooling, and ends
with the cell's mean stresses relaxed). Writes OUT_DIR/phases.csv and
OUT_DIR/phases.svg (E and alpha against the fraction).
"""
import csv
import math
import os
import sys
import tomllib


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_facts(folder):
    with open(os.path.join(folder, "scenario_as_run.toml"), "rb") as f:
        scenario = tomllib.load(f)
    phases = scenario["phase"]
    fraction = phases[-1]["fraction"]
    moduli = [r for r in read_csv(os.path.join(folder, "modulus.csv")) if r["stage"].startswith("E_")]
    cell = read_csv(os.path.join(folder, "cell.csv"))
    stages = scenario["stage"]
    alphas = []
    for i, st in enumerate(stages):
        if not st["name"].startswith("alpha_"):
            continue
        before = ([r for r in cell if r["stage"] == stages[i - 1]["name"]] or cell[:1])[-1]
        after = [r for r in cell if r["stage"] == st["name"]][-1]
        # The temperature the stage starts from: the last target set before it, else [thermal]'s.
        start = scenario["thermal"]["temperature"]
        for prior in stages[:i]:
            start = prior.get("temperature_target", start)
        dt = st["temperature_target"] - start
        strain = sum(float(after[k]) / float(before[k]) - 1.0 for k in ("lx_m", "ly_m", "lz_m")) / 3.0
        alphas.append(strain / dt)
    return {
        "fraction": fraction,
        "E": [float(r["young_Pa"]) for r in moduli],
        "nu": [float(r["poisson"]) for r in moduli],
        "broken": [int(r["bonds_broken"]) for r in moduli],
        "alpha": alphas,
        "names": [p["name"] for p in phases],
    }


def bulk_shear(e, nu):
    return e / (3 * (1 - 2 * nu)), e / (2 * (1 + nu))


def hashin_shtrikman(p1, p2, f2):
    """Lower and upper HS bounds on E, p = (E, nu), f2 the fraction of p2."""
    (k1, g1), (k2, g2) = bulk_shear(*p1), bulk_shear(*p2)
    f1 = 1 - f2
    if f2 in (0.0, 1.0):
        e = p2[0] if f2 == 1.0 else p1[0]
        return e, e
    if k1 > k2:  # phase 2 the stiffer
        (k1, g1, f1), (k2, g2, f2) = (k2, g2, f2), (k1, g1, f1)
    kl = k1 + f2 / (1 / (k2 - k1) + 3 * f1 / (3 * k1 + 4 * g1))
    ku = k2 + f1 / (1 / (k1 - k2) + 3 * f2 / (3 * k2 + 4 * g2))
    gl = g1 + f2 / (1 / (g2 - g1) + 6 * f1 * (k1 + 2 * g1) / (5 * g1 * (3 * k1 + 4 * g1)))
    gu = g2 + f1 / (1 / (g1 - g2) + 6 * f2 * (k2 + 2 * g2) / (5 * g2 * (3 * k2 + 4 * g2)))
    young = lambda k, g: 9 * k * g / (3 * k + g)
    return young(kl, gl), young(ku, gu)


def turner(f2, k1, a1, k2, a2):
    return ((1 - f2) * k1 * a1 + f2 * k2 * a2) / ((1 - f2) * k1 + f2 * k2)


def kerner(f2, k1, g1, a1, k2, g2, a2):
    """Kerner (1956), the majority phase as matrix m, the other as inclusions p."""
    if f2 >= 0.5:
        (km, gm, am, fm), (kp, ap, fp) = (k2, g2, a2, f2), (k1, a1, 1 - f2)
    else:
        (km, gm, am, fm), (kp, ap, fp) = (k1, g1, a1, 1 - f2), (k2, a2, f2)
    mean = fm * am + fp * ap
    return mean + fm * fp * (ap - am) * (kp - km) / (fm * km + fp * kp + 3 * kp * km / (4 * gm))


def svg(path, rows, label):
    """E (GPa) and alpha (1e-6/K) against the fraction, bounds as lines, runs as dots."""
    w, h, m = 420, 300, 50

    def panel(x0, title, series, points, lo, hi):  # noqa: PLR0913
        out = [f'<g transform="translate({x0},0)">',
               f'<rect x="{m}" y="20" width="{w - m - 10}" height="{h - m - 20}" fill="none" stroke="black"/>',
               f'<text x="{w / 2}" y="14" text-anchor="middle" font-size="13">{title}</text>']
        sx = lambda f: m + f * (w - m - 10)
        sy = lambda v: 20 + (h - m - 20) * (1 - (v - lo) / (hi - lo))
        for t in range(5):
            v = lo + (hi - lo) * t / 4
            out.append(f'<text x="{m - 4}" y="{sy(v) + 4:.1f}" text-anchor="end" font-size="10">{v:.3g}</text>')
            f = t / 4
            out.append(f'<text x="{sx(f):.1f}" y="{h - m + 14}" text-anchor="middle" font-size="10">{f:g}</text>')
        out.append(f'<text x="{w / 2}" y="{h - 12}" text-anchor="middle" font-size="11">{label}</text>')
        for name, colour, dash, xs, ys in series:
            pts = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs, ys))
            out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-dasharray="{dash}"/>')
        for name, colour, xs, ys in points:
            for x, y in zip(xs, ys):
                out.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="3.5" fill="{colour}"/>')
        legend = [(n, c) for n, c, *_ in series] + [(n, c) for n, c, *_ in points]
        for i, (n, c) in enumerate(legend):
            out.append(f'<text x="{m + 6}" y="{34 + 12 * i}" font-size="10" fill="{c}">{n}</text>')
        out.append("</g>")
        return out

    fs = [i / 40 for i in range(41)]
    first, last = rows[0], rows[-1]
    p1, p2 = (first["E"][0], first["nu"][0]), (last["E"][0], last["nu"][0])
    hs = [hashin_shtrikman(p1, p2, f) for f in fs]
    es = [v for r in rows for v in r["E"]] + [b for pair in hs for b in pair]
    k1, g1 = bulk_shear(*p1)
    k2, g2 = bulk_shear(*p2)
    a1, a2 = first["alpha"][0], last["alpha"][0]
    tu = [turner(f, k1, a1, k2, a2) for f in fs]
    ke = [kerner(f, k1, g1, a1, k2, g2, a2) for f in fs]
    al = [v for r in rows for v in r["alpha"]] + tu + ke
    x = [r["fraction"] for r in rows]
    body = panel(0, "Young's modulus, GPa",
                 [("HS lower", "blue", "4 2", fs, [b[0] / 1e9 for b in hs]),
                  ("HS upper", "blue", "", fs, [b[1] / 1e9 for b in hs])],
                 [("before cooling", "black", x, [r["E"][0] / 1e9 for r in rows]),
                  ("after cooling", "red", x, [r["E"][-1] / 1e9 for r in rows])],
                 0.0, max(es) / 1e9 * 1.05)
    body += panel(w, "expansion, 1e-6/K",
                  [("Turner", "green", "", fs, [v * 1e6 for v in tu]),
                   ("Kerner", "purple", "4 2", fs, [v * 1e6 for v in ke])],
                  [("before cooling", "black", x, [r["alpha"][0] * 1e6 for r in rows]),
                   ("after cooling", "red", x, [r["alpha"][-1] * 1e6 for r in rows])],
                  min(al) * 1e6 * 0.9, max(al) * 1e6 * 1.05)
    with open(path, "w") as f:
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * w}" height="{h}" font-family="sans-serif">\n')
        f.write('<rect width="100%" height="100%" fill="white"/>\n')
        f.write("\n".join(body) + "\n</svg>\n")


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    out = argv[1]
    rows = sorted((run_facts(d) for d in argv[2:]), key=lambda r: r["fraction"])
    if rows[0]["fraction"] != 0.0 or rows[-1]["fraction"] != 1.0:
        sys.exit("phase_bounds: give the runs at fraction 0 and 1 (each phase alone)")
    first, last = rows[0], rows[-1]
    p1, p2 = (first["E"][0], first["nu"][0]), (last["E"][0], last["nu"][0])
    (k1, g1), (k2, g2) = bulk_shear(*p1), bulk_shear(*p2)
    a1, a2 = first["alpha"][0], last["alpha"][0]
    os.makedirs(out, exist_ok=True)
    fields = ["fraction", "E_before_GPa", "E_after_GPa", "nu_before", "bonds_broken", "HS_lower_GPa",
              "HS_upper_GPa", "Reuss_GPa", "Voigt_GPa", "alpha_before_per_K", "alpha_after_per_K",
              "Turner_per_K", "Kerner_per_K"]
    with open(os.path.join(out, "phases.csv"), "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(fields)
        for r in rows:
            f2 = r["fraction"]
            lo, hi = hashin_shtrikman(p1, p2, f2)
            wr.writerow([f"{f2:g}", f"{r['E'][0] / 1e9:.4g}", f"{r['E'][-1] / 1e9:.4g}", f"{r['nu'][0]:.3f}",
                         r["broken"][-1], f"{lo / 1e9:.4g}", f"{hi / 1e9:.4g}",
                         f"{1 / ((1 - f2) / p1[0] + f2 / p2[0]) / 1e9:.4g}",
                         f"{((1 - f2) * p1[0] + f2 * p2[0]) / 1e9:.4g}", f"{r['alpha'][0]:.4g}",
                         f"{r['alpha'][-1]:.4g}", f"{turner(f2, k1, a1, k2, a2):.4g}",
                         f"{kerner(f2, k1, g1, a1, k2, g2, a2):.4g}"])
    svg(os.path.join(out, "phases.svg"), rows, f"volume fraction of {last['names'][-1]}")
    with open(os.path.join(out, "phases.csv")) as f:
        sys.stdout.write(f.read())


if __name__ == "__main__":
    main(sys.argv)
