"""What a result folder and the Python API show, read by third-party readers (VTK's XML
reader) and checked against closed forms: the grain stresses at the centre of a loaded
Brazilian disc against the elastic disc's solution, each grain's invariants against its own
principal stresses, and the Python arrays against the frames."""

import math
import os
import pathlib
import re
import subprocess
import tomllib

import numpy as np
import pytest
import vtk
from vtk.util.numpy_support import vtk_to_numpy

import cleave

SCENARIO = "scenarios/brazilian_fracture.toml"
STEPS = 30000  # inside the loading stage, before the first bond breaks (step ~36,000)


def read_vtp(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def bodies_of(frame):
    """Per body (by body_index): its centroid from its faces' points and its cell fields."""
    cells = frame.GetCellData()
    index = vtk_to_numpy(cells.GetArray("body_index"))
    points = vtk_to_numpy(frame.GetPoints().GetData())
    polys = frame.GetPolys()
    polys.InitTraversal()
    ids = vtk.vtkIdList()
    corners, first = {}, {}
    k = 0
    while polys.GetNextCell(ids):
        b = int(index[k])
        corners.setdefault(b, set()).update(ids.GetId(j) for j in range(ids.GetNumberOfIds()))
        first.setdefault(b, k)
        k += 1
    fields = {cells.GetArrayName(i): vtk_to_numpy(cells.GetArray(i)) for i in range(cells.GetNumberOfArrays())}
    order = sorted(corners)
    return {
        "centroid": np.array([points[sorted(corners[b])].mean(axis=0) for b in order]),
        **{name: np.array([values[first[b]] for b in order]) for name, values in fields.items()},
    }


def brazilian_closed_form(root, load):
    """The elastic disc under two opposite line loads P (Hondros; Timoshenko & Goodier): at
    its centre sigma_xx = 2P/(pi D t) across the load, sigma_yy = -6P/(pi D t) along it."""
    with open(root / SCENARIO, "rb") as f:
        spec = tomllib.load(f)["specimen"]
    mm = 1e-3
    diameter, thickness = spec["diameter"] * mm, spec["thickness"] * mm
    return load / (math.pi * diameter * thickness), diameter


def von_mises(p):
    return np.sqrt(0.5 * ((p[..., 0] - p[..., 1]) ** 2 + (p[..., 1] - p[..., 2]) ** 2 + (p[..., 2] - p[..., 0]) ** 2))


ROOT = pathlib.Path(__file__).resolve().parents[2]


def run_disc(tmp_path_factory, name, *args):
    out = tmp_path_factory.mktemp("outputs") / name
    binary = os.environ.get("CLEAVE_BINARY", str(ROOT / "build" / "app" / "cleave"))
    subprocess.run([binary, "run", SCENARIO, "--out", str(out), "--quiet", *args], cwd=ROOT, check=True)
    return out


@pytest.fixture(scope="module")
def loaded_disc(tmp_path_factory):
    out = run_disc(tmp_path_factory, "disc", "--max-steps", str(STEPS))
    pvd = (out / "bodies.pvd").read_text()
    last = re.findall(r'file="([^"]+)"', pvd)[-1]
    rows = (out / "load_displacement.csv").read_text().splitlines()
    head = rows[0].split(",")
    load = float(rows[-1].split(",")[head.index("load_N")])
    assert (out / "bond_breaks.csv").read_text().count("\n") == 1, "a bond broke: pick fewer steps"
    return out, bodies_of(read_vtp(out / last)), load


def test_the_frame_is_the_state_at_the_step_limit_inside_the_loading_stage(loaded_disc):
    out, _, load = loaded_disc
    with open(out / "run.toml", "rb") as f:
        facts = tomllib.load(f)["facts"]
    assert int(facts["dynamics_steps"]) == STEPS
    assert load > 0


def contacts_of(frame):
    """Each contact's point and force (on the grain) and whether it is with a wall."""
    cells = frame.GetCellData()
    points = vtk_to_numpy(frame.GetPoints().GetData())
    ids = vtk.vtkIdList()
    at = []
    for k in range(frame.GetNumberOfCells()):
        frame.GetCellPoints(k, ids)
        at.append(points[ids.GetId(0)])
    force = next(cells.GetArray(i) for i in range(cells.GetNumberOfArrays()) if cells.GetArrayName(i).startswith("force"))
    return np.array(at), vtk_to_numpy(force), vtk_to_numpy(cells.GetArray("with_wall")) == 1


def volumes_of(frame):
    """Each body's volume from its faces (divergence theorem), by body_index."""
    return np.array([mass for mass, _, _ in mass_properties(frame, 1.0)])


def test_grain_stresses_sum_to_the_statics_of_the_wall_forces(loaded_disc):
    # Eq. 2.17 summed over the grains: every contact and bond force between two grains acts at
    # one point on both, so in equilibrium sum_i V_i sigma_i = sym(sum over the wall contacts
    # of x (x) f). Its trace and in-plane mean read from bodies.vtp (grain volumes from their
    # faces) against contacts.vtp's wall forces and points; quasi-static loading leaves the
    # inertia's share small.
    out, bodies, _ = loaded_disc
    last = re.findall(r'file="([^"]+)"', (out / "bodies.pvd").read_text())[-1]
    volume = volumes_of(read_vtp(out / last))
    x, f, wall = contacts_of(read_vtp(out / last.replace("bodies_", "contacts_")))
    assert wall.sum() >= 2
    trace_walls = (x[wall] * f[wall]).sum()
    in_plane_walls = 0.5 * (x[wall, 0] * f[wall, 0] + x[wall, 1] * f[wall, 1]).sum()
    assert (volume * 3.0 * bodies["mean_stress_Pa"]).sum() == pytest.approx(trace_walls, rel=2e-3)
    assert (volume * bodies["p_xy_Pa"]).sum() == pytest.approx(in_plane_walls, rel=2e-3)


def test_the_disc_centre_is_compressed_along_the_load_and_pulled_across_it(loaded_disc):
    # The elastic disc (Hondros): sigma_yy = -6P/(pi D t) and sigma_xx = +2P/(pi D t) at its
    # centre, no stress through a thin disc. Grain stresses are over the grains' own volume,
    # a fraction phi of the disc's, so they read 1/phi times the continuum's (the sum of the
    # test above). A disc 14 grains across follows the continuum loosely: the compression
    # within 25 %, and the tension across the load that splits it.
    out, bodies, load = loaded_disc
    s0, diameter = brazilian_closed_form(ROOT, load)
    last = re.findall(r'file="([^"]+)"', (out / "bodies.pvd").read_text())[-1]
    with open(ROOT / SCENARIO, "rb") as f:
        thickness = tomllib.load(f)["specimen"]["thickness"] * 1e-3
    phi = volumes_of(read_vtp(out / last)).sum() / (math.pi * diameter**2 / 4 * thickness)
    c = bodies["centroid"]
    near = np.linalg.norm((c - c.mean(axis=0))[:, :2], axis=1) < 0.2 * diameter / 2
    assert near.sum() >= 5
    p = bodies["principal_stress_Pa"][near].mean(axis=0) / s0  # ascending
    assert p[0] == pytest.approx(-6.0 / phi, rel=0.25)
    assert p[2] > 0.25 * 2.0 / phi
    assert abs(p[1]) < 1e-9 * abs(p[0])


def test_each_grains_invariants_are_those_of_its_principal_stresses(loaded_disc):
    # Von Mises and the mean stress from the principal stresses, computed here, for every grain.
    _, bodies, _ = loaded_disc
    p = bodies["principal_stress_Pa"]
    scale = np.abs(p).max()
    assert np.all(p[:, 0] <= p[:, 1]) and np.all(p[:, 1] <= p[:, 2])
    np.testing.assert_allclose(bodies["von_mises_Pa"], von_mises(p), atol=1e-9 * scale, rtol=1e-9)
    np.testing.assert_allclose(bodies["mean_stress_Pa"], p.mean(axis=1), atol=1e-9 * scale, rtol=1e-9)


def test_python_grain_stresses_are_symmetric_and_those_the_frames_show(root, tmp_path, loaded_disc, monkeypatch):
    monkeypatch.chdir(root)
    _, bodies, _ = loaded_disc
    sim = cleave.Simulation(SCENARIO, out=str(tmp_path / "py"), quiet=True, max_steps=STEPS)
    sim.advance(STEPS)
    stress = sim.grain_stresses
    x = sim.positions
    alive = np.flatnonzero(sim.alive)
    s = stress[alive]
    np.testing.assert_array_equal(s, np.transpose(s, (0, 2, 1)))
    # The same grains as the frame (slots in order), the same principal stresses.
    order = np.argsort(bodies["body_id"])
    np.testing.assert_allclose(np.linalg.eigvalsh(s), bodies["principal_stress_Pa"][order],
                               rtol=1e-9, atol=1e-9 * np.abs(s).max())
    np.testing.assert_allclose(x[alive], bodies["centroid"][order], rtol=0, atol=1e-8)
    # Eq. 2.18's in-plane invariants in the frame, from Python's tensors.
    sxx, syy, sxy = s[:, 0, 0], s[:, 1, 1], s[:, 0, 1]
    scale = np.abs(s).max()
    np.testing.assert_allclose(bodies["p_xy_Pa"][order], 0.5 * (sxx + syy), rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(bodies["q_xy_Pa"][order], np.hypot(0.5 * (sxx - syy), sxy), rtol=1e-9,
                               atol=1e-9 * scale)
    theta = np.degrees(0.5 * np.arctan2(2 * sxy, sxx - syy))
    np.testing.assert_allclose(bodies["theta_xy_deg"][order], theta, atol=1e-6)
    np.testing.assert_array_equal(sim.velocities[alive], bodies["velocity_m_per_s"][order])
    # Each orientation (principal frame to world) turns one principal axis onto the frame's c axis.
    q = sim.orientations[alive]  # x, y, z, w
    xyz, w = q[:, :3], q[:, 3:]
    c_axis = bodies["c_axis"][order]
    best = np.zeros(len(q))
    for e in np.eye(3):
        e = np.broadcast_to(e, xyz.shape)
        turned = e + 2 * w * np.cross(xyz, e) + 2 * np.cross(xyz, np.cross(xyz, e))
        best = np.maximum(best, np.abs(np.einsum("ij,ij->i", turned, c_axis)))
    np.testing.assert_allclose(best, 1.0, atol=1e-9)
    # Each body's force: the sum of its bond and contact forces in the frames, less Cundall's
    # local damping, alpha |F_i| sign(v_i) per component ([dynamics] local_damping).
    net, typical = net_forces(loaded_disc[0], bodies)
    with open(ROOT / SCENARIO, "rb") as f:
        alpha = tomllib.load(f)["dynamics"]["local_damping"]
    v = bodies["velocity_m_per_s"]
    damped = net - alpha * np.abs(net) * np.sign(v)
    np.testing.assert_allclose(sim.forces[alive], damped[order], rtol=0, atol=1e-9 * typical)
    np.testing.assert_array_equal(sim.angular_velocities[alive], bodies["angular_velocity_rad_per_s"][order])
    sim.finish()


def test_contacts_in_the_frame_are_the_linear_spring_law_and_energy_csvs_counts(loaded_disc):
    # The platens press the disc slowly: each wall contact's force is its normal spring,
    # K_n times the overlap (eq. 2.1, [contact.particle_wall] kn, no friction: mu_s = 0),
    # along its normal, within the viscous share of a quasi-static load. energy.csv's
    # contact count and largest overlap at the frame's time are the frame's.
    out, _, _ = loaded_disc
    pvd = (out / "bodies.pvd").read_text()
    time, last = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd)[-1]
    frame = read_vtp(out / last.replace("bodies_", "contacts_"))
    cells = frame.GetCellData()
    force, normal = vtk_to_numpy(cells.GetArray("force_N")), vtk_to_numpy(cells.GetArray("normal"))
    overlap, wall = vtk_to_numpy(cells.GetArray("overlap_m")), vtk_to_numpy(cells.GetArray("with_wall")) == 1
    with open(ROOT / SCENARIO, "rb") as f:
        kn = tomllib.load(f)["contact"]["particle_wall"]["kn"]
    assert wall.sum() >= 2
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0, rtol=1e-12)
    along = np.einsum("ij,ij->i", force, normal)
    np.testing.assert_allclose(np.abs(along[wall]), kn * overlap[wall], rtol=0.02)
    np.testing.assert_allclose(np.linalg.norm(force[wall], axis=1), np.abs(along[wall]), rtol=1e-9)
    row = [r for r in table(out / "energy.csv") if float(r["time_s"]) == pytest.approx(float(time), rel=1e-8)][-1]
    assert int(row["contacts"]) == frame.GetNumberOfCells()
    assert float(row["max_overlap_m"]) == pytest.approx(overlap.max(), rel=1e-5)  # 6 digits


def test_a_bonds_force_is_its_normal_and_shear_parts(loaded_disc):
    out, _, _ = loaded_disc
    last = re.findall(r'file="([^"]+)"', (out / "bodies.pvd").read_text())[-1]
    cells = read_vtp(out / last.replace("bodies_", "bonds_")).GetCellData()
    force = vtk_to_numpy(cells.GetArray("force_N"))
    normal, shear = vtk_to_numpy(cells.GetArray("normal_force_N")), vtk_to_numpy(cells.GetArray("shear_force_N"))
    np.testing.assert_allclose(np.linalg.norm(force, axis=1), np.hypot(normal, shear), rtol=1e-6,
                               atol=1e-9 * np.abs(force).max())


def mass_properties(frame, density):
    """Each body's mass, centroid and inertia tensor about it, from its faces alone (fan
    tetrahedra from the origin: int x dV and int x x^T dV), by body_index."""
    index = vtk_to_numpy(frame.GetCellData().GetArray("body_index"))
    points = vtk_to_numpy(frame.GetPoints().GetData()).astype(float)
    polys = frame.GetPolys()
    polys.InitTraversal()
    ids = vtk.vtkIdList()
    sums = {}
    k = 0
    while polys.GetNextCell(ids):
        q = points[[ids.GetId(j) for j in range(ids.GetNumberOfIds())]]
        v, first, second = sums.setdefault(int(index[k]), [0.0, np.zeros(3), np.zeros((3, 3))])
        for j in range(1, len(q) - 1):
            a, b, c = q[0], q[j], q[j + 1]
            vol = np.dot(a, np.cross(b, c)) / 6.0
            s = a + b + c
            v += vol
            first += vol * s / 4.0
            second += vol / 20.0 * (np.outer(a, a) + np.outer(b, b) + np.outer(c, c) + np.outer(s, s))
        sums[int(index[k])] = [v, first, second]
        k += 1
    out = []
    for b in sorted(sums):
        v, first, second = sums[b]
        centroid = first / v
        cov = second - v * np.outer(centroid, centroid)
        out.append((density * v, centroid, density * (np.trace(cov) * np.eye(3) - cov)))
    return out


def test_the_kinetic_energy_in_energy_csv_is_that_of_the_frames_masses_and_velocities(loaded_disc):
    # 1/2 m v^2 + 1/2 w.I w of every grain, with masses and inertia tensors from the frame's
    # polyhedra and the scenario's density, against energy.csv at the frame's time.
    out, bodies, _ = loaded_disc
    pvd = (out / "bodies.pvd").read_text()
    time, last = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd)[-1]
    with open(ROOT / SCENARIO, "rb") as f:
        density = tomllib.load(f)["material"]["density"]
    props = mass_properties(read_vtp(out / last), density)
    v, w = bodies["velocity_m_per_s"], bodies["angular_velocity_rad_per_s"]
    energy = sum(0.5 * m * vi @ vi + 0.5 * wi @ inertia @ wi for (m, _, inertia), vi, wi in zip(props, v, w))
    rows = [r.split(",") for r in (out / "energy.csv").read_text().splitlines()]
    at = [r for r in rows[1:] if float(r[0]) == pytest.approx(float(time), rel=1e-8)]
    assert at, f"no energy.csv row at t = {time}"
    assert energy > 0
    assert float(at[-1][rows[0].index("kinetic_J")]) == pytest.approx(energy, rel=1e-5)


def net_forces(out, bodies):
    """Each grain's bond forces (bonds.vtp, matched to grains by their end points, the grains'
    centroids) and wall contact forces (contacts.vtp) summed, in the body frame's order; and
    the largest bond force."""
    last = re.findall(r'file="([^"]+)"', (out / "bodies.pvd").read_text())[-1]
    frame = read_vtp(out / last.replace("bodies_", "bonds_"))
    points = vtk_to_numpy(frame.GetPoints().GetData())
    cells = frame.GetCellData()
    force = vtk_to_numpy(cells.GetArray("force_N"))
    intact = vtk_to_numpy(cells.GetArray("intact")) == 1
    centroid = bodies["centroid"]
    net = np.zeros_like(centroid)
    ids = vtk.vtkIdList()
    for k in range(frame.GetNumberOfCells()):
        if not intact[k]:
            continue
        frame.GetCellPoints(k, ids)
        a, b = (np.argmin(np.linalg.norm(centroid - points[ids.GetId(j)], axis=1)) for j in (0, 1))
        net[b] += force[k]  # force_N acts on the second grain, its reaction on the first
        net[a] -= force[k]
    x, f, wall = contacts_of(read_vtp(out / last.replace("bodies_", "contacts_")))
    for at, fc in zip(x[wall], f[wall]):
        net[np.argmin(np.linalg.norm(centroid - at, axis=1))] += fc
    return net, np.abs(force[intact]).max()


def test_bond_forces_in_the_frame_hold_each_grain_in_equilibrium(loaded_disc):
    # Quasi-static loading: each grain's forces add up to nearly nothing against the forces
    # themselves.
    out, bodies, _ = loaded_disc
    net, typical = net_forces(out, bodies)
    assert np.abs(net).max() < 0.05 * typical


@pytest.fixture(scope="module")
def broken_disc(tmp_path_factory):
    """The Brazilian disc run to its load drop: bonds broken, grains split."""
    return run_disc(tmp_path_factory, "broken")


def table(path):
    rows = [r.split(",") for r in path.read_text().splitlines()]
    return [dict(zip(rows[0], r)) for r in rows[1:]]


def last_frame(out, series):
    return read_vtp(out / re.findall(r'file="([^"]+)"', (out / f"{series}.pvd").read_text())[-1])


def test_bond_counts_are_the_bond_breaks_and_the_last_bond_frame(broken_disc):
    counts = table(broken_disc / "bonds.csv")[-1]
    breaks = table(broken_disc / "bond_breaks.csv")
    frame = last_frame(broken_disc, "bonds")
    intact = vtk_to_numpy(frame.GetCellData().GetArray("intact"))
    mode = vtk_to_numpy(frame.GetCellData().GetArray("failure_mode"))
    assert len(breaks) > 0
    assert int(counts["intact"]) == int((intact == 1).sum())
    assert int(counts["intact"]) + len(breaks) == frame.GetNumberOfCells()
    for k, name in enumerate(("tension", "shear", "bending", "torsion"), start=1):
        assert int(counts[f"broken_{name}"]) == sum(b["mode"] == name for b in breaks)
        assert int(counts[f"broken_{name}"]) == int(((intact == 0) & (mode == k)).sum()), name
    # Each break lies between its two grains (both its ends' grains are in the specimen).
    bodies = bodies_of(last_frame(broken_disc, "bodies"))
    grains = {int(g): c for g, c in zip(bodies["grain_id"], bodies["centroid"])}
    pitch = math.sqrt(3) * 0.6e-3
    for b in breaks:
        x = np.array([float(b["x_m"]), float(b["y_m"]), float(b["z_m"])])
        for g in (int(b["grain_a"]), int(b["grain_b"])):
            assert np.linalg.norm((x - grains[g])[:2]) < 1.5 * pitch


def test_each_split_adds_its_pieces_and_reads_the_criterion_of_eqs_3_23_to_3_25(broken_disc):
    # K_I = sigma sqrt(pi a), K_II = |tau| sqrt(pi a) (eq. 3.23) and the ellipse
    # (K_I / K_Ic)^2 + (K_II / (c K_Ic))^2 >= 1 (eq. 3.25), from the scenario's constants;
    # a closing section (sigma < 0, K_I < 0) adds nothing to the ellipse: shear alone splits it.
    with open(ROOT / SCENARIO, "rb") as f:
        fracture = tomllib.load(f)["fracture"]
    a = fracture["crack_length"] * 1e-3
    k_ic, c = fracture["k_ic"], fracture["c"]
    splits = table(broken_disc / "splits.csv")
    assert len(splits) > 0
    for s in splits:
        k_i, k_ii = float(s["K_I_Pa_sqrt_m"]), float(s["K_II_Pa_sqrt_m"])
        assert k_i == pytest.approx(float(s["sigma_Pa"]) * math.sqrt(math.pi * a), rel=1e-4)
        assert k_ii == pytest.approx(abs(float(s["tau_Pa"])) * math.sqrt(math.pi * a), rel=1e-4)
        criterion = (max(k_i, 0.0) / k_ic) ** 2 + (k_ii / (c * k_ic)) ** 2
        assert float(s["criterion"]) == pytest.approx(criterion, rel=1e-4)
        assert criterion >= 1.0
        assert float(s["mean_stress_Pa"]) >= fracture["sigma_f_hyd"]  # eq. 3.22's gate
    grains = len(table(broken_disc / "specimen.csv"))
    added = sum(len(s["pieces"].split()) - 1 for s in splits)
    bodies = bodies_of(last_frame(broken_disc, "bodies"))
    assert len(bodies["body_id"]) == grains + added


def test_each_grains_c_axis_is_the_normal_of_its_hexagonal_faces(loaded_disc):
    # A prism's crystal c axis is its hexagonal faces' normal, read here off the frame's
    # own faces; energy.csv's potential energy is zero without gravity.
    out, bodies, _ = loaded_disc
    last = re.findall(r'file="([^"]+)"', (out / "bodies.pvd").read_text())[-1]
    frame = read_vtp(out / last)
    index = vtk_to_numpy(frame.GetCellData().GetArray("body_index"))
    points = vtk_to_numpy(frame.GetPoints().GetData()).astype(float)
    axis = {}
    ids = vtk.vtkIdList()
    for k in range(frame.GetNumberOfCells()):
        frame.GetCellPoints(k, ids)
        if ids.GetNumberOfIds() == 6:
            q = points[[ids.GetId(j) for j in range(6)]]
            n = np.cross(q[2] - q[0], q[4] - q[0])
            axis[int(index[k])] = n / np.linalg.norm(n)
    order = sorted(axis)
    assert len(order) == len(bodies["c_axis"])
    dots = np.abs(np.einsum("ij,ij->i", np.array([axis[b] for b in order]), bodies["c_axis"]))
    np.testing.assert_allclose(dots, 1.0, atol=1e-6)
    with open(ROOT / SCENARIO, "rb") as f:
        assert tomllib.load(f)["dynamics"]["gravity"] == [0.0, 0.0, 0.0]
    assert all(float(r["potential_J"]) == 0.0 for r in table(out / "energy.csv"))
