"""Reading a result folder: `cleave.load_result(dir)`."""

import os
import tomllib


class Result:
    """A result folder: its tables (CSV files as numpy structured arrays, by file stem),
    run.toml and the scenario as run (dicts)."""

    def __init__(self, path):
        self.path = os.fspath(path)
        run_toml = os.path.join(self.path, "run.toml")
        if not os.path.isfile(run_toml):
            raise FileNotFoundError(f"{self.path}: not a cleave result folder (no run.toml)")
        with open(run_toml, "rb") as f:
            self.run = tomllib.load(f)
        self.scenario = {}
        as_run = os.path.join(self.path, "scenario_as_run.toml")
        if os.path.isfile(as_run):
            with open(as_run, "rb") as f:
                self.scenario = tomllib.load(f)
        self._tables = {}
        # The run's own tables: those its manifest lists (a closed run), else the folder's.
        listed = [f.get("path", "") for f in self.run.get("files", [])]
        names = listed if listed else os.listdir(self.path)
        self.table_names = sorted(n[:-4] for n in names if n.endswith(".csv") and "/" not in n)

    @property
    def status(self):
        """run.toml's status: "finished" (every stage ran), "stopped" (a step limit,
        max_steps / --max-steps, ended it before its stages did: see `reason`),
        "interrupted", "failed" (see `reason`) or "running" (under way, or killed)."""
        return self.run.get("status")

    @property
    def reason(self):
        """Why the run stopped or failed ("" for a finished run)."""
        return self.run.get("reason", "")

    @property
    def facts(self):
        """run.toml's [facts] (peak_load_N, final_state_hash, ...)."""
        return self.run.get("facts", {})

    def table(self, name):
        """The CSV `name` (without .csv) as a numpy structured array, columns by header name."""
        if name not in self._tables:
            import numpy as np

            path = os.path.join(self.path, name + ".csv")
            if not os.path.isfile(path):
                raise KeyError(f"{self.path}: no table {name}.csv (there are: {', '.join(self.table_names)})")
            data = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8",
                                 deletechars="", autostrip=True)
            self._tables[name] = np.atleast_1d(data)
        return self._tables[name]

    def __getitem__(self, name):
        return self.table(name)

    def __repr__(self):
        return f"<cleave.Result {self.path}: {self.status}, tables {', '.join(self.table_names)}>"


def load_result(path):
    """A result folder of `cleave run` (or of Simulation.finish())."""
    return Result(path)
