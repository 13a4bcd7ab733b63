# %% [markdown]
# # A Brazilian disc test from Python
# The bonded disc of `scenarios/brazilian_fracture.toml` (187 grains, both fracture modes:
# bonds break between grains, grains split on their cleavage planes) is compacted between
# two platens and loaded until it splits. We step it from Python, watch the load, then
# plot the load-displacement curve and the crack pattern with matplotlib.
#
#     PYTHONPATH=build/python python3 examples/brazilian_disc.py [OUT_DIR]

# %%
import os
import sys

import cleave

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "example_brazilian")
os.chdir(root)
sim = cleave.Simulation("scenarios/brazilian_fracture.toml", out=out, quiet=True)
sim.start()
print(f"{sim.name}: {len(sim.slabs)} exact cleavage slabs")

# %% Step it, a stage at a time, printing what the testing machine reads.
while not sim.done:
    stage = sim.advance_stage()
    if stage is None:
        break
    print(f"  stage {stage['name']:<10} {stage['steps']:>7} steps, ended by {stage['ended_by']}"
          f", peak load {stage['peak_load']:.4g} N, {stage['bonds_broken']} bonds broke, {stage['splits']} splits")
report = sim.finish()
print(f"strength 2P/(pi D t) = {report['brazilian_strength']:.4g} Pa, final state {report['state_hash']}")

# %% Plots: load-displacement and the crack pattern (PNG next to the results).
res = cleave.load_result(out)
cleave.plot.load_displacement(res, path=os.path.join(out, "load_displacement.png"))
cleave.plot.cracks(res, path=os.path.join(out, "cracks.png"))
print(f"plots: {out}/load_displacement.png, {out}/cracks.png")
