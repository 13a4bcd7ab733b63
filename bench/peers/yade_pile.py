# A settled pile of hexagonal prisms in Yade (polyhedra, Elias 2014), timed per step: the
# peer half of bench/peers/run_yade.sh. Run by Yade, not by Python:
#   N=300 SETTLE=4000 STEPS=200 yade -j2 -n -x bench/peers/yade_pile.py
# The prisms are cleave_bench_dynamics' poured ones: side (circumradius) 1 mm, thickness
# 1 mm, density 3100 kg/m^3, random orientation, poured into a box on a floor under
# gravity and left to settle; then STEPS steps are timed and the touching prism pairs
# counted. Prints one line: "yade N=... pairs=... us_per_step=... us_per_pair_step=...".
import math
import os
import random
import time

from yade import polyhedra_utils

n = int(os.environ.get("N", "300"))
settle = int(os.environ.get("SETTLE", "4000"))
steps = int(os.environ.get("STEPS", "200"))
r, t = 1e-3, 1e-3
vertices = [[r * math.cos(k * math.pi / 3), r * math.sin(k * math.pi / 3), z]
            for z in (-t / 2, t / 2) for k in range(6)]

mat = PolyhedraMat(density=3100, young=1e8, poisson=0.25, frictionAngle=math.atan(0.5))
O.materials.append(mat)
random.seed(1)
per_side = max(2, int(math.ceil((n / 4.0) ** 0.5)))  # about four layers when poured
spacing = 2.6 * r
width = per_side * spacing
for i in range(n):
    p = polyhedra_utils.polyhedra(mat, v=vertices)
    layer, k = divmod(i, per_side * per_side)
    x, y = divmod(k, per_side)
    p.state.pos = ((x + 0.5) * spacing, (y + 0.5) * spacing, (layer + 0.5) * spacing)
    p.state.ori = Quaternion(Vector3(random.random() - 0.5, random.random() - 0.5, random.random() - 0.5).normalized(),
                             2 * math.pi * random.random())
    O.bodies.append(p)
walls = [utils.wall(0, axis=2, sense=1, material=mat),
         utils.wall(0, axis=0, sense=1, material=mat), utils.wall(width, axis=0, sense=-1, material=mat),
         utils.wall(0, axis=1, sense=1, material=mat), utils.wall(width, axis=1, sense=-1, material=mat)]
first_wall = len(O.bodies)
O.bodies.append(walls)

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Polyhedra_Aabb(), Bo1_Wall_Aabb()], verletDist=0.05 * r),
    InteractionLoop(
        [Ig2_Wall_Polyhedra_PolyhedraGeom(), Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
        [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
        [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()],
    ),
    NewtonIntegrator(damping=0.7, gravity=(0, 0, -9.81)),
]
O.dt = float(os.environ.get("DT", "1e-5"))
for b in O.bodies:
    if b.id < first_wall:
        b.state.vel = Vector3(0, 0, -0.3)  # a head start: the pour would take 40 ms of fall
O.run(settle, True)


def prism_pairs():
    return sum(1 for i in O.interactions
               if i.isReal and i.id1 < first_wall and i.id2 < first_wall)


start = time.time()
O.run(steps, True)
elapsed = time.time() - start
pairs = prism_pairs()
us_step = 1e6 * elapsed / steps
print("yade settled: kinetic energy %.3g J, %d pairs touching" % (utils.kineticEnergy(), pairs))
print("yade N=%d pairs=%d us_per_step=%.1f us_per_pair_step=%.2f threads=%d"
      % (n, pairs, us_step, us_step / max(pairs, 1), O.numThreads))
