"""The Python module against the CLI, closed forms and its own promises."""

import fractions
import math
import random
import subprocess
import threading
import time
import tomllib

import numpy as np
import pytest

import cleave

MESH_GRAINS = "scenarios/mesh_grains.toml"  # 3 grains dropped 2 mm: 160,000 steps in ~1 s


def cli_run(binary, root, scenario, out, *args):
    subprocess.run([binary, "run", scenario, "--out", str(out), "--quiet", *args], cwd=root, check=True)
    with open(out / "run.toml", "rb") as f:
        return tomllib.load(f)


def test_stepping_from_python_gives_the_cli_state_hash_and_files(root, cleave_binary, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    cli = cli_run(cleave_binary, root, MESH_GRAINS, tmp_path / "cli")
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "api"))
    sim.start()
    # Uneven chunks, a callback, a stage run to its end: the steps are the same.
    assert sim.advance(7) == 7
    seen = []
    sim.advance(1000, callback=lambda s: seen.append(s.steps), every=333)
    assert seen == [340, 673, 1006, 1007]
    report = sim.finish()
    assert report["status"] == "finished"
    assert report["state_hash"] == cli["facts"]["final_state_hash"]
    for name in ("energy.csv", "walls.csv", "load_displacement.csv", "fragments.csv", "bodies.pvd"):
        assert (tmp_path / "api" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name


def test_state_arrays_are_read_only_snapshots_and_a_new_read_sees_the_next_step(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.advance(10)
    x = sim.positions
    assert x.shape == (3, 3) and sim.orientations.shape == (3, 4)
    assert not x.flags.writeable
    before = x.copy()
    sim.advance(100)
    # The array kept is the state when it was read; reading again gives the state now.
    assert np.array_equal(x, before)
    assert not np.shares_memory(x, sim.positions)
    x1, v = sim.positions, sim.velocities
    assert np.all(x1[:, 2] < before[:, 2])  # the grains fall under gravity
    # Free fall from rest (no contact in the first 110 steps): the drop is g (t1^2 - t0^2) / 2,
    # to within the integrator's O(dt) offset (1 % here), and v = -g t.
    dt = 5e-7
    t0, t1 = 10 * dt, 110 * dt
    g = 9.80665
    assert np.allclose(before[:, 2] - x1[:, 2], 0.5 * g * (t1**2 - t0**2), rtol=2e-2)
    assert np.allclose(v[:, 2], -g * t1, rtol=1e-3)
    q = sim.orientations
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0)
    assert sim.alive.all() and len(sim.grain_stresses) == 3


def falling_grains_that_split_soon(root):
    """scenarios/falling_grains.toml with its floor 1 mm below the grains and gravity 20 g: the
    same impact speed as its 20 mm fall (sqrt(2 g h)), so grains split within ~7000 steps."""
    text = (root / "scenarios/falling_grains.toml").read_text()
    for old, new in (("point = [0.0, -19.95, 0.0]", "point = [0.0, -1.0, 0.0]"),
                     ("gravity = [0.0, -9.81, 0.0]", "gravity = [0.0, -196.2, 0.0]")):
        assert old in text
        text = text.replace(old, new)
    return text


def test_a_state_array_kept_across_a_grain_split_keeps_its_values(root, tmp_path):
    # A split adds body slots and moves the World's state array: an array read before it must
    # not look into the memory it left (it read values like 6.9e-310 when it was a view).
    sim = cleave.Simulation.from_toml(falling_grains_that_split_soon(root), out=str(tmp_path / "r"),
                                      base_dir=str(root / "scenarios"))
    sim.advance(1)
    kept = {name: getattr(sim, name) for name in
            ("positions", "orientations", "velocities", "angular_velocities", "angular_momenta", "forces",
             "torques")}
    values = {name: a.copy() for name, a in kept.items()}
    slots = len(sim.alive)
    while len(sim.alive) == slots and sim.steps < 20000:
        sim.advance(500)
    assert len(sim.alive) > slots, "no grain split: the test needs one"
    for name, a in kept.items():
        assert np.array_equal(a, values[name]), name
        assert len(getattr(sim, name)) == len(sim.alive), name
    assert np.all(np.abs(kept["positions"]) < 0.05)  # metres: inside the rig


def test_split_volumes_are_exact_fractions_that_sum_to_the_grain():
    side, t = 0.6e-3, 5e-3
    prism = cleave.hexagonal_prism(side, t)
    volume = prism.volume
    assert isinstance(volume, fractions.Fraction)
    # Closed form of a regular hexagonal prism, 3 sqrt(3)/2 s^2 t (its corners come from doubles).
    assert math.isclose(float(volume), 1.5 * math.sqrt(3) * side**2 * t, rel_tol=1e-12)
    rng = random.Random(7)
    for _ in range(20):
        n = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
        below, above = prism.split(n, rng.uniform(-1e-5, 1e-5))
        assert below.volume + above.volume == volume  # exact, no tolerance
        assert below.volume > 0 and above.volume > 0
    slabs = prism.cleavage_slabs("11-20", 60)
    assert len(slabs) == 3 and cleave.total_volume(slabs) == volume
    with pytest.raises(ValueError):
        prism.split((1, 0, 0), 1.0)  # misses it


def test_meshes_export_to_files(tmp_path):
    slabs = cleave.hexagonal_prism(1e-3, 1e-3).cleavage_slabs("10-10", 0)
    files = [f for f in cleave.export_meshes(slabs, tmp_path, "slab", "obj", "per_fragment") if f.endswith(".obj")]
    assert len(files) == 2
    text = open(files[0]).read()
    assert text.count("\nv ") >= 6 and "\nf " in text


def test_a_bad_key_raises_with_its_file_and_line_as_the_cli_says(root, cleave_binary, tmp_path):
    text = (root / "scenarios/demo_drop.toml").read_text().splitlines()
    k = next(i for i, line in enumerate(text) if line.startswith("dt ="))
    text[k] = "dt = -1.0"
    bad = tmp_path / "bad.toml"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(cleave.ScenarioError) as err:
        cleave.Simulation(str(bad))
    e = err.value
    assert isinstance(e, ValueError)
    assert (e.file, e.line, e.key) == (str(bad), k + 1, "dynamics.dt")
    assert str(e).startswith(f"{bad}:{k + 1}:")
    cli = subprocess.run([cleave_binary, "run", str(bad), "--out", str(tmp_path / "o")], capture_output=True,
                         text=True)
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"cleave: error: {e}"
    with pytest.raises(cleave.ScenarioError) as err:
        cleave.Simulation.from_toml((root / MESH_GRAINS).read_text(), source="inline.toml",
                                    overrides={"dynamics.dt": -2.0}, base_dir=str(root / "scenarios"))
    assert err.value.file == "inline.toml" and err.value.key == "dynamics.dt"
    # The value is not in the text: the error names the override, not a line.
    assert err.value.line == 0
    assert str(err.value).startswith("override dynamics.dt=-2.0: key 'dynamics.dt': must be > 0")


def test_an_override_may_carry_its_unit_and_is_recorded(root, tmp_path, monkeypatch):
    # dt = "0.25 us" is 2.5e-7 s: ten steps take 2.5e-6 s; run.toml lists the override.
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"), overrides={"dynamics.dt": "0.25 us"},
                            max_steps=10)
    report = sim.finish()
    assert report["steps"] == 10
    assert report["time"] == pytest.approx(10 * 2.5e-7, rel=1e-12)
    with open(tmp_path / "r" / "run.toml", "rb") as f:
        assert tomllib.load(f)["provenance"]["overrides"] == "dynamics.dt=0.25 us"
    with pytest.raises(cleave.ScenarioError) as err:
        cleave.Simulation(MESH_GRAINS, overrides={"dynamics.dt": "0.25 mm"})
    assert str(err.value).startswith("override dynamics.dt=0.25 mm: key 'dynamics.dt': 'mm' is the unit of a length")


def test_the_gil_is_released_while_stepping(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.start()
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    worker = threading.Thread(target=spin)
    worker.start()
    time.sleep(0.05)
    before = count[0]
    t0 = time.perf_counter()
    sim.advance(20000)
    during = count[0] - before
    elapsed = time.perf_counter() - t0
    stop.set()
    worker.join()
    assert elapsed > 0.02
    # Holding the GIL the whole call, the other thread could not count at all.
    assert during > 1000, (during, elapsed)


def test_walls_can_be_read_and_moved(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.advance(1)
    walls = sim.walls
    assert walls and walls[0].name
    w = walls[0]
    o = np.array(w.origin)
    w.velocity = (0.0, 0.0, -1e-3)
    sim.advance(1000)
    assert np.allclose(np.array(w.origin) - o, (0, 0, -1e-3 * 1000 * 5e-7), rtol=1e-9, atol=1e-15)
    w.move((0, 0, 1e-6))
    assert math.isclose(w.origin[2] - o[2], 1e-6 - 5e-7, rel_tol=1e-9)


def test_a_wall_velocity_or_place_that_is_not_finite_raises_naming_the_wall(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.advance(1)
    w = sim.walls[0]
    origin, velocity = np.array(w.origin), np.array(w.velocity)
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValueError, match=f"wall '{w.name}': velocity must be finite"):
            w.velocity = (0.0, bad, 0.0)
        with pytest.raises(ValueError, match=f"wall '{w.name}': origin must be finite"):
            w.origin = (bad, 0.0, 0.0)
        with pytest.raises(ValueError, match=f"wall '{w.name}'"):
            w.move((0.0, 0.0, bad))
    w.origin = (0.0, 0.0, 1e308)
    with pytest.raises(ValueError, match=f"wall '{w.name}': origin after the move must be finite"):
        w.move((0.0, 0.0, 1e308))  # a finite move to a place that is not
    w.origin = tuple(origin)
    # The refused values changed nothing: the run goes on with the wall as it was.
    assert np.array_equal(w.velocity, velocity) and np.array_equal(w.origin, origin)
    sim.advance(10)
    assert np.all(np.isfinite(w.origin)) and np.all(np.isfinite(sim.positions))


def test_set_temperatures_without_a_thermal_section_raises_naming_it(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.advance(1)
    with pytest.raises(RuntimeError, match=r"has no \[thermal\] section"):
        sim.set_temperatures(np.full(len(sim.alive), 300.0))


def test_stepping_or_changing_the_run_after_finish_raises(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"), max_steps=50)
    sim.advance(10)
    w = sim.walls[0]
    sim.finish()
    for call in (lambda: sim.advance(1), lambda: sim.advance(5, callback=lambda s: None), sim.advance_stage,
                 lambda: setattr(w, "velocity", (0.0, 0.0, 1.0)), lambda: setattr(w, "origin", (0.0, 0.0, 0.0)),
                 lambda: w.move((0.0, 0.0, 1e-6)), lambda: sim.set_temperatures(np.full(3, 300.0))):
        with pytest.raises(RuntimeError, match="the run has ended"):
            call()
    # Reading the final state still works, and the result is as finish() left it.
    assert sim.positions.shape == (3, 3) and sim.steps == 50
    assert sim.finish()["steps"] == 50


def test_a_run_cut_by_max_steps_is_stopped_not_finished(root, tmp_path, monkeypatch):
    # Four-point bending ends its approach stage on walls_touch after a few hundred steps: a
    # limit of 1000 steps falls in the loading stage, long before its load drop.
    monkeypatch.chdir(root)
    report = cleave.run("scenarios/four_point_bending.toml", out=str(tmp_path / "r"), max_steps=1000)
    assert report["status"] == "stopped"
    assert "step 1000 " in report["message"] and "'loading'" in report["message"]
    assert report["stages"][-1]["ended_by"] == "max_steps"
    res = cleave.load_result(tmp_path / "r")
    assert res.status == "stopped" and res.reason == report["message"]
    assert res.facts["stopped_at_step"] == "1000" and res.facts["stopped_in_stage"] == "loading"


def test_an_override_error_or_warning_names_the_override_not_a_line_of_the_file(root, tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(root)
    # A stage the scenario does not have: named as the override was given.
    with pytest.raises(ValueError) as err:
        cleave.Simulation("scenarios/four_point_bending.toml", overrides={"stage[9].time": 1})
    assert str(err.value).startswith("override stage[9].time=1: ")
    # Dilated grains that overlap at the start (a warning at start): the scenario is parsed from
    # a rewritten text whose lines are not the file's; the warning names the override instead.
    sim = cleave.Simulation("scenarios/brazilian_fracture.toml", out=str(tmp_path / "r"),
                            overrides={"contact.dilation_radius": 0.09})
    sim.start()
    warning = capfd.readouterr().err
    assert "warning: override contact.dilation_radius=0.09: key 'contact.dilation_radius'" in warning, warning
    assert "brazilian_fracture.toml:" not in warning, warning


def test_load_result_reads_the_tables_and_plots(root, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    report = cleave.run(MESH_GRAINS, out=str(tmp_path / "r"))
    res = cleave.load_result(report["out"])
    assert res.status == "finished"
    assert res.facts["final_state_hash"] == report["state_hash"]
    energy = res["energy"]
    assert energy["time_s"][0] > 0.0 and np.all(np.diff(energy["time_s"]) > 0)
    assert energy["time_s"][-1] == pytest.approx(report["time"])
    assert len(res["fragments"]) > 0 and "volume_m3" in res["fragments"].dtype.names
    png = tmp_path / "energy.png"
    cleave.plot.energy(res, path=png)
    assert png.stat().st_size > 5000
    sizes = res["fragment_sizes"]
    assert len(sizes) == int(res.facts["fragments.count"]) and np.all(np.diff(sizes["passing"]) >= 0)
    cleave.plot.fragment_sizes(res, path=tmp_path / "sizes.png")
    assert (tmp_path / "sizes.png").stat().st_size > 5000
    with pytest.raises(KeyError):
        res.table("nope")


def test_crack_surfaces_are_drawn_as_area_over_thickness(tmp_path):
    # Grains 5 mm thick: a 2.5 mm^2 boundary face is a 0.5 mm segment across its normal, a
    # 5 mm^2 cleavage section a 1 mm one.
    from matplotlib.collections import LineCollection

    (tmp_path / "run.toml").write_text('status = "finished"\n')
    (tmp_path / "scenario_as_run.toml").write_text(
        '[scenario]\nlength_unit = "mm"\n[grain]\nr = 0.6\nr_bar = 0.5\nt = 5.0\nt_bar = 5.0\n')
    (tmp_path / "specimen.csv").write_text("grain_id,x_m,y_m,z_m\n0,0.001,0.002,0.0025\n")
    (tmp_path / "bond_breaks.csv").write_text(
        "x_m,y_m,z_m,nx,ny,nz,mode,face_area_m2\n0.001,0.002,0.0025,1,0,0,tension,2.5e-6\n")
    (tmp_path / "splits.csv").write_text(
        "x_m,y_m,z_m,nx,ny,nz,section_area_m2\n0.003,0.004,0.0025,0,1,0,5e-6\n")
    ax = cleave.plot.cracks(str(tmp_path), surfaces=True, path=tmp_path / "p.svg")
    faces, sections = [c.get_segments() for c in ax.collections if isinstance(c, LineCollection)]
    assert len(faces) == 1 and len(sections) == 1
    (x0, y0), (x1, y1) = faces[0]
    assert (x0, x1) == pytest.approx((1.0, 1.0))
    assert sorted((y0, y1)) == pytest.approx([1.75, 2.25])
    (x0, y0), (x1, y1) = sections[0]
    assert sorted((x0, x1)) == pytest.approx([2.5, 3.5])
    assert (y0, y1) == pytest.approx((4.0, 4.0))
    assert (tmp_path / "p.svg").stat().st_size > 1000


def test_ctrl_c_interrupts_a_long_advance_and_the_run_goes_on(root, tmp_path, monkeypatch):
    import _thread

    monkeypatch.chdir(root)
    sim = cleave.Simulation(MESH_GRAINS, out=str(tmp_path / "r"))
    sim.start()
    timer = threading.Timer(0.05, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.advance(150000)  # about 1 s of stepping
    timer.join()
    assert 0 < sim.steps < 150000
    sim.advance(10)  # still usable
    assert sim.finish()["status"] == "finished"


COOLING = "temperature_rate = -2960.0   # K/s: 1773 K to 293 K over the stage\ntemperature_target = 293.0\n"


def test_a_temperature_field_set_from_python_each_step_is_the_scenarios_prescribed_field(root, tmp_path):
    # The same field, T = 1773 - 2000 t + 30 x (x in mm, t in s since the stage began), once
    # as the cooling stage's temperature_field and once computed in numpy from the grains'
    # centroids and set before every step: the two runs end in the same state, bit for bit.
    text = (root / "scenarios/thermal_microcracking.toml").read_text()
    assert COOLING in text
    field = tmp_path / "field.toml"
    field.write_text(text.replace(COOLING, 'temperature_field = "1773 - 2000*t + 30*x"\n'))
    plain = tmp_path / "plain.toml"
    plain.write_text(text.replace(COOLING, ""))
    a = cleave.Simulation(str(field), out=str(tmp_path / "a"))
    a.advance_stage()  # bond
    a.advance(200)
    b = cleave.Simulation(str(plain), out=str(tmp_path / "b"))
    b.advance_stage()
    dt = 2e-5
    for k in range(200):
        x = b.positions[:, 0]
        b.set_temperatures(1773 - 2000 * ((k + 1) * dt) + 30 * (x / 0.001))
        b.advance(1)
    assert np.array_equal(a.temperatures, b.temperatures)
    assert a.state_hash == b.state_hash
    assert a.temperatures.max() - a.temperatures.min() > 30 * 3  # the specimen spans > 3 mm
    # NaN leaves a body as it is; a wrong shape or a temperature at or below 0 K is refused.
    t = b.temperatures.copy()
    b.set_temperatures(np.full(len(t), np.nan))
    assert np.array_equal(b.temperatures, t)
    with pytest.raises(ValueError, match="one per slot"):
        b.set_temperatures(t[:-1])
    t[3] = -1.0
    with pytest.raises(ValueError, match="slot 3"):
        b.set_temperatures(t)


def test_import_under_an_interpreter_without_numpy_names_what_is_missing_and_what_to_use():
    # -S leaves out site-packages (numpy among them): as a python3 that is not Debian's.
    import os
    import sys

    done = subprocess.run([sys.executable, "-S", "-c", "import cleave"], capture_output=True, text=True,
                          env=dict(os.environ))
    assert done.returncode != 0
    assert "numpy is missing for this interpreter" in done.stderr, done.stderr
    assert "built for /usr/bin/python3" in done.stderr, done.stderr
