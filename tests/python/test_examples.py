"""The examples run as a user would run them, and make their plots."""

import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def run_example(name, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(ROOT / "examples" / name), *args], env=env, check=True,
                          capture_output=True, text=True).stdout


def test_brazilian_disc_example_plots_its_curve_and_cracks(tmp_path):
    out = run_example("brazilian_disc.py", str(tmp_path / "bd"))
    assert "strength 2P/(pi D t)" in out
    for png in ("load_displacement.png", "cracks.png"):
        assert (tmp_path / "bd" / png).stat().st_size > 10000


def test_seed_sweep_example_fits_a_weibull_modulus(tmp_path):
    out = run_example("seed_sweep_weibull.py", "3", str(tmp_path / "w"))
    strengths = [float(line.split("strength ")[1].split()[0]) for line in out.splitlines() if "strength " in line]
    assert len(strengths) == 3 and len(set(strengths)) > 1  # the seeds give different strengths
    assert "Weibull modulus m =" in out
    assert (tmp_path / "w" / "weibull.png").stat().st_size > 10000
