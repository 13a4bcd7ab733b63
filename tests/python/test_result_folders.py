"""Result folders from Python: Simulation(out=...) follows `cleave run`'s rules, and
load_result lists only the run's own tables."""

import pytest

import cleave

MESH_GRAINS = "scenarios/mesh_grains.toml"  # 3 grains dropped 2 mm, with [dynamics]
DEMO = "scenarios/demo.toml"  # no [dynamics]: specimen and fragments only


def test_another_runs_folder_needs_replace_and_then_holds_only_the_new_run(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    out = str(tmp_path / "r")
    cleave.run(MESH_GRAINS, out=out, max_steps=200)
    assert "energy.csv" in {p.name for p in (tmp_path / "r").iterdir()}

    # Another scenario's result: refused before anything is touched, saying how to replace it.
    with pytest.raises(ValueError, match="replace"):
        cleave.Simulation(DEMO, out=out)
    assert cleave.load_result(out).run["facts"]["scenario_name"] == "mesh_grains"

    report = cleave.run(DEMO, out=out, replace=True)
    assert report["status"] == "finished"
    res = cleave.load_result(out)
    assert res.table_names == ["fragments", "specimen"]  # no energy.csv of the earlier run
    listed = {f["path"] for f in res.run["files"]} | {"run.toml", "SHA256SUMS"}
    on_disk = {str(p.relative_to(tmp_path / "r")) for p in (tmp_path / "r").rglob("*") if p.is_file()}
    assert on_disk == listed


def test_a_file_cleave_did_not_write_is_never_removed(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    out = tmp_path / "r"
    cleave.run(DEMO, out=str(out))
    (out / "bond_breaks.csv").write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="bond_breaks.csv"):
        cleave.Simulation(DEMO, out=str(out), replace=True)
    assert (out / "bond_breaks.csv").read_text() == "a,b\n1,2\n"


def test_an_unfinished_simulation_of_this_process_is_replaced_only_when_asked(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    out = str(tmp_path / "r")
    first = cleave.Simulation(MESH_GRAINS, out=out)
    first.advance(10)  # run.toml says "running", written by this very process
    with pytest.raises(ValueError, match="did not end"):
        cleave.Simulation(MESH_GRAINS, out=out)
    second = cleave.Simulation(MESH_GRAINS, out=out, replace=True, max_steps=20)
    assert second.finish()["status"] == "stopped"  # at its max_steps, before its stages end
