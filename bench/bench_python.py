#!/usr/bin/env python3
"""The cost of driving a run from Python against `cleave run`.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [build/app/cleave] [STEPS]

Runs scenarios/mesh_grains.toml (3 grains, the cheapest physics per step, so the overhead
shows most) for STEPS steps (default 40000) five ways, best of 3 each, and prints the
wall time and the time per step:
  cli          `cleave run --max-steps STEPS --quiet` (a process: start-up included)
  api_run      cleave.run(...): the same run through the module, in this process
  advance_all  sim.advance(STEPS): one call
  advance_1    sim.advance(1) STEPS times: a Python call per step
  callback_1   sim.advance(STEPS, callback=f, every=1): a Python callback per step
The per-step overhead of Python is (advance_1 - advance_all) / STEPS.
"""

import os
import subprocess
import sys
import tempfile
import time

import cleave

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "app", "cleave")
steps = int(sys.argv[2]) if len(sys.argv) > 2 else 40000
scenario = "scenarios/mesh_grains.toml"
os.chdir(root)
tmp = tempfile.mkdtemp(prefix="cleave_bench_py_")


def best(f, n=3):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def started():
    sim = cleave.Simulation(scenario, out=os.path.join(tmp, "s"), max_steps=steps)
    sim.start()
    return sim


def timed_steps(drive):
    # Only the stepping is timed: the specimen and the outputs are the same in each way.
    times = []
    for _ in range(3):
        sim = started()
        t0 = time.perf_counter()
        drive(sim)
        times.append(time.perf_counter() - t0)
        assert sim.steps == steps, sim.steps
        sim.finish()
    return min(times)


results = {
    "cli": best(lambda: subprocess.run([binary, "run", scenario, "--out", os.path.join(tmp, "c"), "--quiet",
                                        "--max-steps", str(steps)], check=True)),
    "api_run": best(lambda: cleave.run(scenario, out=os.path.join(tmp, "a"), max_steps=steps)),
    "advance_all": timed_steps(lambda s: s.advance(steps)),
    "advance_1": timed_steps(lambda s: [s.advance(1) for _ in range(steps)]),
    "callback_1": timed_steps(lambda s: s.advance(steps, callback=lambda _: None, every=1)),
}
print(f"mesh_grains.toml, {steps} steps, best of 3 (cleave {cleave.__version__})")
for name, t in results.items():
    print(f"  {name:<12} {t:8.3f} s  {1e6 * t / steps:8.2f} us/step")
print(f"Python per-step overhead: advance(1) {1e6 * (results['advance_1'] - results['advance_all']) / steps:.2f} us, "
      f"callback every step {1e6 * (results['callback_1'] - results['advance_all']) / steps:.2f} us")
