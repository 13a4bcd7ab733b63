"""cleave: exact-polyhedron DEM of brittle polycrystals, from Python.

    import cleave
    sim = cleave.Simulation("scenarios/brazilian_fracture.toml", out="results/bf")
    sim.advance(1000, callback=lambda s: print(s.time), every=100)
    report = sim.finish()
    res = cleave.load_result("results/bf")
    cleave.plot.load_displacement(res, path="ld.png")

The run is sim::Simulation (the same code as `cleave run`): the same scenario gives the same
files and the same final state hash. It runs under the interpreter it was built for
(Debian's /usr/bin/python3) with numpy, both checked here at import; matplotlib is needed for
cleave.plot alone, imported when used.
"""

import sys as _sys

from ._built_for import executable as _built_for, version as _built_version


def _refuse(missing):
    here = f"{_sys.version_info.major}.{_sys.version_info.minor}"
    raise ImportError(
        f"cleave: {missing}. This is {_sys.executable} (Python {here}); cleave's extension was "
        f"built for {_built_for} (Python {_built_version}), which has numpy: run "
        f"`PYTHONPATH=build/python {_built_for} ...`, or rebuild cleave with "
        f"-DPython3_EXECUTABLE={_sys.executable} after installing numpy for it.")


if f"{_sys.version_info.major}.{_sys.version_info.minor}" != _built_version:
    _refuse(f"the extension was built for Python {_built_version}")
try:
    import numpy as _numpy  # noqa: F401  (the state arrays and results are numpy arrays)
except ImportError:
    _refuse("numpy is missing for this interpreter")

from ._cleave import (  # noqa: F401
    CheckpointError,
    Polyhedron,
    ScenarioError,
    Simulation,
    Wall,
    __version__,
    export_meshes,
    hexagonal_prism,
    total_volume,
)
from .results import Result, load_result  # noqa: F401
from . import maps, plot  # noqa: F401


def run(scenario, out=None, overrides=None, quiet=True, max_steps=0, replace=False):
    """Runs a scenario file whole, as `cleave run` does; returns the report (a dict).
    replace=True is `cleave run --replace`."""
    sim = Simulation(scenario, out=out, overrides=overrides, quiet=quiet, max_steps=max_steps, replace=replace)
    sim.start()
    return sim.finish()
