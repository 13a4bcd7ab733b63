#!/usr/bin/env bash
# Fracture-mode maps (docs/FRACTURE_MAPS.md): one sweep and its picture per map.
#
#   tools/fracture_maps.sh MAP [OUT [--draw]]   MAP: brazilian | bending | compression |
#                                        brazilian_friction | brazilian_rate | grain_size
#
# Each map sweeps the grain-boundary strength as a ratio of the grains' cleavage strength
# (bond.tbn/fracture.cleavage_strength: K_Ic / sqrt(pi a) of the lefm criterion) against a
# second key, with SEEDS orientation seeds per point (3; 2 on the friction, rate and grain
# size maps). It then draws OUT/map.{svg,png} (cleave.maps.fracture_map), prints where half
# of the crack area is transgranular, and draws the crack patterns of the map's first row,
# seed 1 (grain_size: along the grain size), in OUT/patterns.{svg,png} (cleave.plot.cracks,
# surfaces=True). --draw: only the pictures, from the sweep already in OUT.
# CLEAVE (default build/app/cleave), JOBS (default 2), SEEDS and PYTHON (default python3)
# are read from the environment.
set -euo pipefail
cd "$(dirname "$0")/.."
map="${1:-}"
out="${2:-results/map_$map}"
cleave="${CLEAVE:-build/app/cleave}"
[[ ${3:-} == --draw ]] && cleave=true

# The bond strength t_bn over 2.5 decades of the cleavage strength (t_bs in the file's ratio
# to it), placed per test around its transition. A bond's stress acts on pi r_d^2 (eq. 2.10):
# 1/318 of a face of the disc's and the beam's grains (0.5 x 5 mm), 1/64 of the compression
# specimen's (0.5 x 1 mm); t_bn / sigma_c = 318 (64) is a boundary as strong as the grain.
strength=(--set 'bond.tbn/fracture.cleavage_strength=30,100,300,1000,3000,10000')
# The bond stiffness k_bn (K_bs / K_bn kept) over 2 decades: the files' (K_bn = 5 N/m), 10
# and 100 times. Softer bonds reach the same loads over longer travel: at 1/10 of the files'
# each run took 10 times as long. At 100 times the disc's and the beam's grains need a
# shorter step (cleave refuses the files' and names the limit: 6.97e-6 s for the disc's,
# 1.07e-5 s for the compression specimen's).
stiffness=(--zip bond.kbn=6.366e8,6.366e9,6.366e10 --set 'bond.kbs/bond.kbn=0.4')
step=(--zip dynamics.dt=1.5e-5,1.5e-5,6.5e-6)
# The dissertation's grains and constants: brazilian_fracture.toml's [fracture].
bending_fracture=(--set fracture.sigma_f_hyd=0 --set fracture.k_ic=0.03
                  --set fracture.crack_length=0.1 --set fracture.check_every=10)
case "$map" in  # seeds a point: 3, and 2 on the maps that are the disc's map again
  brazilian_friction | brazilian_rate | grain_size) seeds="${SEEDS:-2}" ;;
  *) seeds="${SEEDS:-3}" ;;
esac
common=(--seeds "$seeds" --set dynamics.threads=1
        --column cracks_transgranular_area_fraction
        --column cracks_at_peak_transgranular_area_fraction
        --column cracks_transgranular_count_fraction
        --out "$out" --jobs "${JOBS:-2}")
strength_column=strength_Pa  # the disc's: 2P / (pi D t); the beam's and the column's: peak_load_N

case "$map" in
  brazilian)
    y=bond.kbn
    "$cleave" sweep scenarios/brazilian_fracture.toml "${strength[@]}" --set 'bond.tbs/bond.tbn=1' \
      "${stiffness[@]}" "${step[@]}" "${common[@]}" ;;
  bending)  # four_point_bending.toml with the Brazilian disc's [fracture], rollers at 0.05 mm/s
    y=bond.kbn
    strength_column=peak_load_N
    "$cleave" sweep scenarios/four_point_bending.toml \
      --set 'bond.tbn/fracture.cleavage_strength=10,30,100,300,1000,3000' --set 'bond.tbs/bond.tbn=1' \
      "${stiffness[@]}" "${step[@]}" "${bending_fracture[@]}" --set 'stage[3].rate_scale=5' "${common[@]}" ;;
  compression)  # uniaxial_fracture.toml (mode II cleavage, gate open), platens at 0.5 mm/s
    y=bond.kbn
    strength_column=peak_load_N
    "$cleave" sweep scenarios/uniaxial_fracture.toml \
      --set 'bond.tbn/fracture.cleavage_strength=0.3,1,3,10,30,100' --set 'bond.tbs/bond.tbn=0.5' \
      "${stiffness[@]}" --zip dynamics.dt=2e-5,2e-5,1e-5 --set 'stage[3].rate_scale=5' "${common[@]}" ;;
  brazilian_friction)  # the grains' friction once a boundary has broken
    y=contact.particle_particle.mu_s
    "$cleave" sweep scenarios/brazilian_fracture.toml "${strength[@]}" --set 'bond.tbs/bond.tbn=1' \
      --set contact.particle_particle.mu_s=0,0.3,1 "${common[@]}" ;;
  brazilian_rate)  # platens at 0.015, 0.05 and 0.15 mm/s
    y='stage[3].rate_scale'
    "$cleave" sweep scenarios/brazilian_fracture.toml "${strength[@]}" --set 'bond.tbs/bond.tbn=1' \
      --set 'stage[3].rate_scale=0.3,1,3' "${common[@]}" ;;
  grain_size)
    # The disc's diameter and every material constant stay; the grains shrink by s in all
    # three directions (the disc, one grain thick, with them): r, r_bar, t, t_bar, the
    # dilation radius and the bonding distance go as s. Then, as tools/scale_scenario.py
    # does for a whole scenario, bond springs k_bn go as 1/s and contact springs as s (E and
    # nu stay), the step as s; t_bn, t_bs (Pa), K_Ic, the flaw a, friction and density stay.
    y=grain.r
    "$cleave" sweep scenarios/brazilian_fracture.toml \
      --set 'bond.tbn/fracture.cleavage_strength=30,100,300,1000,3000' --set 'bond.tbs/bond.tbn=1' \
      --zip grain.r=0.6,0.45,0.36 --zip bond.kbn=6.366e8,8.488e8,1.061e9 \
      --zip dynamics.dt=1.5e-5,1.125e-5,9e-6 \
      --set 'grain.r_bar/grain.r=0.8333333333333334' \
      --set 'grain.t/grain.r=8.333333333333334' --set 'grain.t_bar/grain.r=8.333333333333334' \
      --set 'specimen.thickness/grain.r=8.333333333333334' \
      --set 'contact.dilation_radius/grain.r=0.08333333333333333' \
      --set 'stage[1].distance/grain.r=0.13333333333333333' \
      --set 'bond.kbs/bond.kbn=0.4' \
      --set 'contact.particle_particle.kn/grain.r=8.333333333333334' \
      --set 'contact.particle_particle.ks/contact.particle_particle.kn=0.4' \
      --set 'contact.particle_wall.kn/grain.r=16.666666666666668' \
      --set 'contact.particle_wall.ks/contact.particle_wall.kn=0.2' "${common[@]}" ;;
  *)
    sed -n '2,15p' "$0" >&2
    exit 2 ;;
esac

PYTHONPATH="${PYTHONPATH:-build/python}" "${PYTHON:-python3}" - "$out" "$y" "$strength_column" "$map" <<'EOF'
import sys
import cleave.maps as maps
import cleave.plot
out, y, strength, name = sys.argv[1:]
x = next(c for c in open(out + "/summary.csv").readline().strip().split(",")
         if c.endswith("/fracture.cleavage_strength"))
m = maps.fracture_map(out, x=x, y=y, strength=strength, path=out + "/map.svg", title=name)
m["figure"].savefig(out + "/map.png", dpi=80)
print(f"{out}/map.svg: half of the crack area transgranular at ({x}, {y}):")
for hx, hy in m["half"]:
    print(f"  {hx:.4g}, {hy:.4g}")
# The crack patterns along x at the first y value, seed 1: OUT/patterns.svg.
import csv, matplotlib.pyplot as plt
rows = list(csv.DictReader(l for l in open(out + "/summary.csv") if not l.startswith("#")))
first_y = rows[0][y]
seed1 = [r for r in rows if r.get("orientation.seed", "1") == "1" and r["status"] == "finished"]
row = [r for r in seed1 if r[y] == first_y]
if name == "grain_size":  # along the grain size, at t_bn / sigma_c = 1000
    row = [r for r in seed1 if float(r[x]) == 1000]
if name == "bending":  # a long beam: one above the other
    fig, axes = plt.subplots(len(row), 1, figsize=(7, 1.9 * len(row)), squeeze=False)
else:
    fig, axes = plt.subplots(1, len(row), figsize=(3.2 * len(row), 3.6), squeeze=False)
for ax, r in zip(axes.flat, row):
    cleave.plot.cracks(r["folder"], ax=ax, surfaces=True)
    ax.legend().remove()
    faces, sections = (len(c.get_segments()) for c in ax.collections[1:])
    ax.set_title(f"t_bn / sigma_c = {float(r[x]):g}, {y} = {r[y]}\n"
                 f"{faces} boundaries (red), {sections} cleavages (black)", fontsize=8)
if name == "bending":
    for ax in axes.flat[:-1]:
        ax.set_xlabel("")
fig.suptitle(f"{name}: seed 1")
fig.tight_layout()
fig.savefig(out + "/patterns.svg")
fig.savefig(out + "/patterns.png", dpi=80)
print(f"{out}/patterns.svg")
EOF
