#!/usr/bin/env bash
# Seed 002's parameter studies (Chen et al. 2020, figs 11-15, 19, 20, 26) as sweeps over
# `cleave validate` on the coarse strips of scenarios/validation/ (docs/VALIDATION.md).
#
#   tools/parameter_studies.sh STUDY [OUT [--draw]]
#     STUDY: dcb_g | dcb_radius | dcb_rate | dcb_young | dcb_poisson | enf_a0 | enf_g | mmb_g
#
# Each run is judged against the cohesive beam of its own parameters (the coarse bounds:
# stage I mean, peak); OUT/curves.{svg,png} overlays every run's load-deflection curve on its
# reference, the way the paper's figures do, and OUT/table.md lists the verdicts and the
# first peaks against the cohesive beam's (--draw: only those, from the sweep in OUT).
# CLEAVE (default build/app/cleave), JOBS (default 2) and PYTHON (default python3) are read
# from the environment.
set -euo pipefail
cd "$(dirname "$0")/.."
study="${1:-}"
out="${2:-results/studies/$study}"
cleave="${CLEAVE:-build/app/cleave}"
sweep=("$cleave" sweep --command validate --set dynamics.threads=1 --out "$out" --jobs "${JOBS:-2}")
[[ ${3:-} == --draw ]] && sweep=(true)  # only the pictures and the table, from OUT
v=scenarios/validation

case "$study" in
  dcb_g)        # fig. 11: G_Ic = 0.13, 0.26, 0.39 N/mm (the weak plane and the closed forms)
    "${sweep[@]}" "$v/dcb_coarse.toml" --zip material.fracture_energy=130,260,390 \
      --set 'material.g_Ic/material.fracture_energy=1' ;;
  dcb_radius)   # fig. 12: r = 0.125 and 0.10 mm, each on a strip two cubes across
    "${sweep[@]}" "$v/dcb_coarse.toml" --zip specimen.particle_radius=0.125,0.1 \
      --zip specimen.breadth=0.5,0.4 ;;
  dcb_rate)     # fig. 13: the arms' speed v0 (eq. 56), 0.15 to 0.6 m/s
    "${sweep[@]}" "$v/dcb_coarse.toml" --set loading.velocity=0.15,0.3,0.6 ;;
  dcb_young)    # fig. 14
    "${sweep[@]}" "$v/dcb_coarse.toml" --set material.young=60e9,120e9,240e9 ;;
  dcb_poisson)  # fig. 15 (the lattice takes nu < 0.25)
    "${sweep[@]}" "$v/dcb_coarse.toml" --set material.poisson=0.1,0.2,0.24 ;;
  enf_a0)       # fig. 19: a0 = 6, 9, 12 mm; deflection to 0.8 mm, past the stiffest's peak
    "${sweep[@]}" "$v/enf_coarse.toml" --set specimen.initial_crack=6,9,12 \
      --set loading.deflection=0.8 ;;
  enf_g)        # fig. 20: G_IIc x 0.5, 1, 1.5
    "${sweep[@]}" "$v/enf_coarse.toml" --zip material.fracture_energy=501,1002,1503 \
      --set 'material.g_IIc/material.fracture_energy=1' ;;
  mmb_g)        # fig. 26: beta = 50 %, G_c x 0.5, 1, 1.5 (G_Ic = G_IIc = G_c, as the file);
                # to 0.8 mm, past the toughest one's peak
    "${sweep[@]}" "$v/mmb_50_coarse.toml" --zip material.fracture_energy=501,1002,1503 \
      --set loading.deflection=0.8 \
      --set 'material.g_Ic/material.fracture_energy=1' \
      --set 'material.g_IIc/material.fracture_energy=1' ;;
  *)
    sed -n '2,14p' "$0" >&2
    exit 2 ;;
esac

"${PYTHON:-python3}" - "$out" "$study" <<'EOF'
import csv, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out, study = sys.argv[1:]
with open(os.path.join(out, "summary.csv"), newline="") as f:
    rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
first = list(rows[0].keys())
keys = []  # the keys varied, ratio columns and repeats of another column left out
for k in first[: first.index("status")]:
    values = [r[k] for r in rows]
    if k in ("run", "dynamics.threads") or "/" in k or len(set(values)) < 2:
        continue
    if not any(values == [r[j] for r in rows] for j in keys):
        keys.append(k)

def curve(path, x="delta_mm", y="load_N"):
    with open(path, newline="") as f:
        rs = list(csv.DictReader(f))
    return [float(r[x]) for r in rs], [float(r[y]) for r in rs]

fig, ax = plt.subplots(figsize=(6.5, 4.5))
reach = 0.0
for i, r in enumerate(rows):
    if r["status"] != "finished":
        continue
    colour = f"C{i}"
    label = ", ".join(f"{k.split('.')[-1]} = {r[k]}" for k in keys)
    x, y = curve(os.path.join(r["folder"], "measured.csv"))
    ax.plot(x, y, color=colour, label=f"{label} ({r['verdict']})")
    reach = max(reach, max(x))
    x, y = curve(os.path.join(r["folder"], "cohesive_beam.csv"))
    ax.plot(x, y, color=colour, linestyle="--", linewidth=1)
ax.set_xlim(0, reach)
ax.set_xlabel("deflection (mm)")
ax.set_ylabel("load (N)")
ax.set_title(f"{study}: cleave (solid) and the cohesive beam (dashed)")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(out, "curves.svg"))
fig.savefig(os.path.join(out, "curves.png"), dpi=80)


def first_peak(loads, drop=0.03):
    """The first maximum: the largest load before the load first falls 3 % below it (past
    30 % of the largest, under which the start rings); None: it never does."""
    top, floor = 0.0, 0.3 * max(loads)
    for p in loads:
        if top > floor and p < (1 - drop) * top:
            return top
        top = max(top, p)
    return None


# OUT/table.md: each run against its cohesive beam, first peak to first peak.
head = [k.split(".")[-1] for k in keys] + [
    "verdict", "stage I mean error", "first peak (N)", "cohesive beam's (N)", "ratio",
    "LEFM peak (N)", "wall (s)"]
lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
for r in rows:
    if r["status"] != "finished":
        lines.append("| " + " | ".join([r[k] for k in keys] + [r["status"]]) + " |")
        continue
    m = list(csv.DictReader(open(os.path.join(r["folder"], "measured.csv"))))
    reach = max(float(p["delta_mm"]) for p in m)
    cb = list(csv.DictReader(open(os.path.join(r["folder"], "cohesive_beam.csv"))))
    peak = first_peak([float(p["load_N"]) for p in m])
    ref = first_peak([float(p["load_N"]) for p in cb if float(p["delta_mm"]) <= reach])
    cells = [r[k] for k in keys] + [
        r["verdict"], f"{100 * float(r['stage1_mean_error']):.1f} %",
        f"{peak:.3g}" if peak else "no drop", f"{ref:.3g}" if ref else "no drop",
        f"{peak / ref:.2f}" if peak and ref else "-",
        f"{float(r['closed_form_peak_N']):.3g}", f"{float(r['wall_s']):.0f}"]
    lines.append("| " + " | ".join(cells) + " |")
open(os.path.join(out, "table.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
print(f"{out}/curves.svg, curves.png, table.md")
EOF
