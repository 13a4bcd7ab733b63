"""cleave: exact-polyhedron DEM of brittle polycrystals, from Python.

    import cleave
    sim = cleave.Simulation("scenarios/brazilian_fracture.toml", out="results/bf")
    sim.advance(1000, callback=lambda s: print(s.time), every=100)
    report = sim.finish()
    res = cleave.load_result("results/bf")
    cleave.plot.load_displacement(res, path="ld.png")

The run is sim::Simulation (the same code as `cleave run`): the same scenario gives the same
files and the same final state hash. numpy is needed for the state arrays and results,
matplotlib for cleave.plot; both are imported only when used.
"""

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
from . import plot  # noqa: F401


def run(scenario, out=None, overrides=None, quiet=True, max_steps=0):
    """Runs a scenario file whole, as `cleave run` does; returns the report (a dict)."""
    sim = Simulation(scenario, out=out, overrides=overrides, quiet=quiet, max_steps=max_steps)
    sim.start()
    return sim.finish()
