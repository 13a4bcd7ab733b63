# %% [markdown]
# # Strength scatter: a seed sweep and its Weibull plot
# A small Brazilian disc with transgranular fracture (tests/data/sweep_brazilian.toml) with different random crystal orientations (`orientation.seed`)
# breaks at different loads. We run N seeds from Python, collect each disc's Brazilian
# strength 2P/(pi D t) and fit the Weibull modulus, as `cleave sweep` does.
#
#     PYTHONPATH=build/python python3 examples/seed_sweep_weibull.py [N] [OUT_DIR]

# %%
import os
import sys

import cleave

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
n = int(sys.argv[1]) if len(sys.argv) > 1 else 8
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join("results", "example_weibull")
os.chdir(root)

# %% One run per seed; only the seed changes.
strengths = []
for seed in range(1, n + 1):
    report = cleave.run("tests/data/sweep_brazilian.toml", out=os.path.join(out, f"seed_{seed}"),
                        overrides={"orientation.seed": seed})
    strengths.append(report["brazilian_strength"])
    print(f"seed {seed}: peak {report['peak_load']:.4g} N, strength {strengths[-1]:.4g} Pa")

# %% The Weibull plot.
m, s0 = cleave.plot.weibull_fit(strengths)
cleave.plot.weibull(strengths, path=os.path.join(out, "weibull.png"))
print(f"Weibull modulus m = {m:.3g}, scale s0 = {s0:.4g} Pa -> {out}/weibull.png")
