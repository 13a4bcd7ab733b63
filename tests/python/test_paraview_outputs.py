"""What ParaView, VTK and meshio make of a result folder: the cleave binary runs short
scenarios and its outputs are read back with third-party readers (VTK's XML, OBJ and STL
readers from python3-vtk9, meshio from python3-meshio) and checked against the scenario,
the run's CSV tables and closed forms (polygon areas, divergence-theorem volumes)."""

import csv
import math
import os
import pathlib
import subprocess
import tomllib
import xml.etree.ElementTree as ET

import numpy as np
import pytest

vtk = pytest.importorskip("vtkmodules.all", reason="python3-vtk9 is not installed")
meshio = pytest.importorskip("meshio", reason="python3-meshio is not installed")
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "tests" / "data" / "paraview_brazilian.toml"
MM = 1e-3  # the test scenario's length unit


def run_cleave(binary, *args):
    done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True,
                          env={**os.environ, "OMP_NUM_THREADS": "1"})
    assert done.returncode == 0, done.stderr[-3000:]


@pytest.fixture(scope="module")
def binary():
    path = os.environ.get("CLEAVE_BINARY", str(ROOT / "build" / "app" / "cleave"))
    if not os.path.exists(path):
        pytest.fail(f"the cleave binary is not at {path} (set CLEAVE_BINARY)")
    return path


@pytest.fixture(scope="module")
def result(binary, tmp_path_factory):
    """The small bonded Brazilian disc, run once (about a second)."""
    out = tmp_path_factory.mktemp("paraview") / "run"
    run_cleave(binary, "run", SCENARIO, "--out", out, "--quiet")
    return out


@pytest.fixture(scope="module")
def scenario():
    with open(SCENARIO, "rb") as f:
        return tomllib.load(f)


def pvd_entries(pvd):
    """(time, file) of each DataSet of a .pvd, read with Python's XML parser."""
    root = ET.parse(pvd).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def read_vtp(path):
    """A .vtp through vtkXMLPolyDataReader; fails on any error or warning VTK reports."""
    reader = vtk.vtkXMLPolyDataReader()
    errors = []
    reader.AddObserver(vtk.vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
    reader.AddObserver(vtk.vtkCommand.WarningEvent, lambda o, e: errors.append(e))
    reader.SetFileName(str(path))
    reader.Update()
    assert not errors, f"VTK reported {errors} reading {path}"
    return reader.GetOutput()


def cell_array(poly, name):
    a = poly.GetCellData().GetAbstractArray(name)
    assert a is not None, f"no cell array {name}"
    if isinstance(a, vtk.vtkStringArray):
        return [a.GetValue(i) for i in range(a.GetNumberOfValues())]
    return vtk_to_numpy(a)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def up_to(rows, time):
    """Rows of a CSV table with time_s at or before `time` (the tables print 9 digits)."""
    return [r for r in rows if float(r["time_s"]) <= time * (1 + 1e-8) + 1e-15]


def breaks_in(rows, time):
    """bond_breaks.csv's rows of breaks in the steps up to `time`: a break is stamped with the
    time its step began (the force evaluation's), so one stamped `time` is in the next step."""
    return [r for r in rows if float(r["time_s"]) < time * (1 - 1e-8)]


def polygon_area(points):
    """Area of a planar polygon: half the norm of the sum of its corners' cross products."""
    p = np.asarray(points)
    return 0.5 * np.linalg.norm(np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0))


def cell_points(poly, c):
    ids = poly.GetCell(c).GetPointIds()
    return [poly.GetPoint(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]


def closed_volume(points, faces):
    """Divergence theorem over fan-triangulated faces (positive for outward faces)."""
    v = 0.0
    for f in faces:
        a = points[f[0]]
        for k in range(1, len(f) - 1):
            v += np.dot(a, np.cross(points[f[k]], points[f[k + 1]])) / 6.0
    return v


def mesh_volume(mesh):
    return sum(closed_volume(mesh.points, block.data) for block in mesh.cells)


# ------------------------------------------------------------------------------------------
# The .pvd series


def series(folder):
    return sorted(p.stem for p in folder.glob("*.pvd"))


def test_every_series_lists_each_time_once_and_every_file_reads(result):
    names = series(result)
    frames = None
    for name in names:
        entries = pvd_entries(result / f"{name}.pvd")
        times = [t for t, _ in entries]
        assert len(times) == len(set(times)), f"{name}.pvd lists a time twice: {times}"
        assert times == sorted(times)
        frames = frames or len(entries)
        assert len(entries) == frames, f"{name}.pvd has {len(entries)} frames, bodies {frames}"
        for _, file in entries:
            assert (result / file).is_file(), f"{name}.pvd names {file}, which is missing"
            read_vtp(result / file)
    assert {"bodies", "contacts", "bonds", "walls", "cracks"} <= set(names)
    # No frame file outside the lists: no duplicate left on disk.
    listed = {f for n in names for _, f in pvd_entries(result / f"{n}.pvd")}
    on_disk = {f"frames/{p.name}" for p in (result / "frames").iterdir()}
    assert on_disk == listed


def test_the_first_frame_is_the_bonded_one(result):
    # The bond stage writes at t = 0 like the start does: the one frame kept there is the one
    # with the bonds, as many as bonds.csv counts at t = 0.
    time, file = pvd_entries(result / "bonds.pvd")[0]
    assert time == 0.0
    first = read_csv(result / "bonds.csv")[0]
    assert float(first["time_s"]) == 0.0
    assert read_vtp(result / file).GetNumberOfCells() == int(first["intact"])


def test_a_restart_lists_each_time_once(binary, result, tmp_path):
    out = tmp_path / "restarted"
    run_cleave(binary, "run", SCENARIO, "--out", out, "--quiet", "--checkpoint-every", 1000)
    assert (out / "checkpoint").is_file()
    run_cleave(binary, "restart", out, "--quiet")
    for name in series(result):
        entries = pvd_entries(out / f"{name}.pvd")
        times = [t for t, _ in entries]
        assert len(times) == len(set(times)), f"{name}.pvd after a restart: {times}"
        assert entries == pvd_entries(result / f"{name}.pvd")


# ------------------------------------------------------------------------------------------
# Walls


def test_walls_are_drawn_with_their_sizes_and_reactions(result, scenario):
    walls = scenario["wall"]
    rows = read_csv(result / "walls.csv")
    checked_reaction = 0
    for time, file in pvd_entries(result / "walls.pvd"):
        poly = read_vtp(result / file)
        index = cell_array(poly, "wall_index")
        assert sorted(set(index)) == list(range(len(walls)))
        names = cell_array(poly, "name")
        for c in range(poly.GetNumberOfCells()):
            assert names[c] == walls[index[c]]["name"]
        for w, wall in enumerate(walls):
            cells = [c for c in range(poly.GetNumberOfCells()) if index[c] == w]
            corners = np.array([p for c in cells for p in cell_points(poly, c)])
            if wall["kind"] == "platen":
                assert len(cells) == 1
                area = polygon_area(cell_points(poly, cells[0]))
                assert area == pytest.approx(wall["size"][0] * wall["size"][1] * MM**2, rel=1e-12)
            elif wall["kind"] == "cylinder":
                axis = np.array(wall["normal"]) / np.linalg.norm(wall["normal"])
                end = cell_array(poly, "origin_m")[cells[0]]
                along = (corners - end) @ axis
                across = np.linalg.norm(corners - end - np.outer(along, axis), axis=1)
                assert np.allclose(across, wall["radius"] * MM, rtol=1e-12)
                assert along.min() == pytest.approx(0.0, abs=1e-15)
                assert along.max() == pytest.approx(wall["length"] * MM, rel=1e-12)
            else:  # an infinite plane, drawn under the whole specimen
                normal = np.array(wall["normal"]) / np.linalg.norm(wall["normal"])
                assert np.allclose((corners - np.array(wall["point"]) * MM) @ normal, 0.0, atol=1e-15)
                bodies = read_vtp(result / file.replace("walls_", "bodies_")).GetBounds()
                lo, hi = corners.min(axis=0), corners.max(axis=0)
                for k in range(3):
                    if abs(normal[k]) < 1e-12:
                        assert lo[k] < bodies[2 * k] and hi[k] > bodies[2 * k + 1]
        # The reaction field is walls.csv's row at the same time.
        row = [r for r in rows if float(r["time_s"]) == pytest.approx(time, rel=1e-8, abs=1e-15)]
        if not row:
            continue
        reaction = cell_array(poly, "reaction_force_N")
        for w, wall in enumerate(walls):
            c = list(index).index(w)
            expected = [float(row[-1][f"{wall['name']}_F{a}_N"]) for a in "xyz"]
            assert reaction[c] == pytest.approx(expected, rel=1e-8, abs=1e-20)
        checked_reaction += 1
    assert checked_reaction >= 2, "no frame time matched a walls.csv row"


# ------------------------------------------------------------------------------------------
# Cracks


def test_cracks_are_the_broken_bonds_and_split_sections_so_far(result):
    breaks = read_csv(result / "bond_breaks.csv")
    splits = read_csv(result / "splits.csv")
    assert breaks and splits, "the test scenario should break bonds and split grains"
    seen_cracks = 0
    for time, file in pvd_entries(result / "cracks.pvd"):
        poly = read_vtp(result / file)
        assert poly.GetCellData().GetScalars().GetName() == "mode"  # ParaView colours by it
        kind = cell_array(poly, "kind") if poly.GetNumberOfCells() else np.array([], int)
        bonds_so_far = breaks_in(breaks, time)
        assert int(np.sum(kind == 1)) == len(bonds_so_far), f"frame at t = {time}"
        # Each split leaves one section face at least (more once a piece splits again).
        assert int(np.sum(kind == 2)) >= len(up_to(splits, time))
        assert (int(np.sum(kind == 2)) == 0) == (len(up_to(splits, time)) == 0)
        if len(kind):
            mode = cell_array(poly, "mode")
            modes = {"tension": 1, "shear": 2, "bending": 3, "torsion": 4}
            assert sorted(mode[kind == 1]) == sorted(modes[r["mode"]] for r in bonds_so_far)
            assert set(mode[kind == 2]) <= {5}
            broken_at = cell_array(poly, "broken_at_s")[kind == 1]
            assert sorted(broken_at) == pytest.approx(
                sorted(float(r["time_s"]) for r in bonds_so_far), rel=1e-8)
        seen_cracks = max(seen_cracks, len(kind))
    assert seen_cracks > 0


def run_facts(folder):
    with open(folder / "run.toml", "rb") as f:
        return tomllib.load(f)["facts"]


def test_crack_areas_are_the_bonds_faces_and_the_exact_sections(result):
    """cracks.csv sums the broken bonds' face areas and the splits' section areas; its
    transgranular fractions, with the intergranular ones formed from its areas and counts,
    sum to one, and are empty before the first crack."""
    breaks = read_csv(result / "bond_breaks.csv")
    splits = read_csv(result / "splits.csv")
    rows = read_csv(result / "cracks.csv")
    assert rows and breaks and splits
    assert list(rows[0]) == ["time_s", "stage", "intergranular_area_m2", "transgranular_area_m2",
                             "transgranular_area_fraction", "intergranular_count",
                             "transgranular_count", "transgranular_count_fraction"]
    for r in rows:
        t = float(r["time_s"])
        inter = sum(float(b["face_area_m2"]) for b in breaks_in(breaks, t))
        trans = sum(float(s["section_area_m2"]) for s in up_to(splits, t))
        assert float(r["intergranular_area_m2"]) == pytest.approx(inter, rel=1e-8, abs=1e-30)
        assert float(r["transgranular_area_m2"]) == pytest.approx(trans, rel=1e-8, abs=1e-30)
        ni, nt = int(r["intergranular_count"]), int(r["transgranular_count"])
        assert (ni, nt) == (len(breaks_in(breaks, t)), len(up_to(splits, t)))
        if ni + nt == 0:
            assert r["transgranular_area_fraction"] == r["transgranular_count_fraction"] == ""
            continue
        a_i, a_t = float(r["intergranular_area_m2"]), float(r["transgranular_area_m2"])
        assert float(r["transgranular_area_fraction"]) + a_i / (a_i + a_t) == pytest.approx(1.0, abs=1e-8)
        assert float(r["transgranular_count_fraction"]) + ni / (ni + nt) == pytest.approx(1.0, abs=1e-8)
    # A grain's first split cuts the whole prism (side r_bar, thickness t_bar) through two of
    # its corners: a section of t_bar x 2 r_bar (<10-10>) or t_bar x sqrt(3) r_bar (<11-20>);
    # a piece's split cuts part of that.
    t_bar, r_bar = 5.0 * MM, 0.5 * MM
    sections = [t_bar * 2 * r_bar, t_bar * math.sqrt(3) * r_bar]
    assert any("." not in s["parent"] for s in splits)
    for s in splits:
        a = float(s["section_area_m2"])
        if "." not in s["parent"]:
            assert min(abs(a / want - 1) for want in sections) < 1e-8, s
        else:
            assert 0 < a <= sections[0] * (1 + 1e-8), s


def test_crack_surfaces_in_vtk_carry_the_areas_run_toml_reports(result):
    """Read by VTK, every frame of cracks.pvd has cell data area_m2 (a bond's octagon and a
    section's polygon of that area), opened_at_s and kind; the areas of a frame sum to the
    breaks and splits up to its time, and the last frame's to run.toml's totals."""
    breaks = read_csv(result / "bond_breaks.csv")
    splits = read_csv(result / "splits.csv")
    split_times = [float(s["time_s"]) for s in splits]
    last = None
    for time, file in pvd_entries(result / "cracks.pvd"):
        poly = read_vtp(result / file)
        if poly.GetNumberOfCells() == 0:
            continue
        kind = cell_array(poly, "kind")
        area = cell_array(poly, "area_m2")
        opened = cell_array(poly, "opened_at_s")
        broken = cell_array(poly, "broken_at_s")
        drawn = np.array([polygon_area(cell_points(poly, c)) for c in range(poly.GetNumberOfCells())])
        assert np.all(area > 0)
        assert drawn == pytest.approx(area, rel=1e-6)
        assert np.all(np.isfinite(opened)) and np.all(opened <= time * (1 + 1e-12))
        assert np.array_equal(opened[kind == 1], broken[kind == 1])
        for t in opened[kind == 2]:
            assert min(abs(t - s) for s in split_times) <= 1e-8 * t
        assert area[kind == 1].sum() == pytest.approx(
            sum(float(b["face_area_m2"]) for b in breaks_in(breaks, time)), rel=1e-8)
        assert area[kind == 2].sum() == pytest.approx(
            sum(float(s["section_area_m2"]) for s in up_to(splits, time)), rel=1e-8, abs=1e-30)
        last = (time, kind, area)
    assert last is not None
    facts = run_facts(result)
    time, kind, area = last
    assert time == pytest.approx(float(facts["dynamics_time_s"]), rel=1e-8)
    assert area[kind == 1].sum() == pytest.approx(float(facts["cracks_intergranular_area_m2"]), rel=1e-8)
    assert area[kind == 2].sum() == pytest.approx(float(facts["cracks_transgranular_area_m2"]), rel=1e-8)


def test_run_toml_reports_crack_areas_per_stage_and_at_the_peak(result):
    facts = run_facts(result)
    rows = read_csv(result / "cracks.csv")
    end = rows[-1]
    for key in ["intergranular_area_m2", "transgranular_area_m2", "transgranular_area_fraction",
                "intergranular_count", "transgranular_count", "transgranular_count_fraction"]:
        assert float(facts["cracks_" + key]) == pytest.approx(float(end[key]), rel=1e-8)
    for at in ["cracks_", "cracks_at_peak_", "stage_loading_cracks_", "stage_loading_cracks_at_peak_"]:
        for by in ["area", "count"]:
            inter = float(facts[f"{at}intergranular_{by}_fraction"])
            trans = float(facts[f"{at}transgranular_{by}_fraction"])
            if math.isnan(inter) or math.isnan(trans):  # no crack yet: both
                assert math.isnan(inter) and math.isnan(trans) and \
                    int(facts[f"{at}intergranular_count"]) + int(facts[f"{at}transgranular_count"]) == 0
                continue
            assert inter + trans == pytest.approx(1.0, abs=2e-9), at
    # The stages' own cracks add up to the run's.
    stages = ["bonding", "approach", "loading"]
    for key in ["intergranular_area_m2", "transgranular_area_m2", "intergranular_count",
                "transgranular_count"]:
        assert sum(float(facts[f"stage_{s}_cracks_{key}"]) for s in stages) == \
            pytest.approx(float(facts["cracks_" + key]), rel=1e-8)
    # Before the first crack the fractions are nan (0/0): the bonding stage breaks nothing.
    assert math.isnan(float(facts["stage_bonding_cracks_transgranular_area_fraction"]))
    # At the peak (the loading stage's: the run's peak), the cracks so far: no more than at
    # the end, and the row of cracks.csv at the peak's time has them.
    assert float(facts["peak_load_N"]) == pytest.approx(float(facts["stage_loading_peak_load_N"]))
    for key in ["intergranular_count", "transgranular_count"]:
        assert int(facts["cracks_at_peak_" + key]) <= int(facts["cracks_" + key])
        assert int(facts["stage_loading_cracks_at_peak_" + key]) <= int(facts["stage_loading_cracks_" + key])


# ------------------------------------------------------------------------------------------
# Meshes


def obj_groups(path):
    """The names of the OBJ's groups ("g" lines), read as text."""
    with open(path) as f:
        return [line.split(maxsplit=1)[1].strip() for line in f if line.startswith("g ")]


def test_frame_meshes_have_a_folder_per_frame_holding_that_frames_bodies(result):
    grains = len({r["grain_id"] for r in read_csv(result / "fragments.csv")})
    total = sum(float(r["volume_m3"]) for r in read_csv(result / "fragments.csv"))
    splits = read_csv(result / "splits.csv")
    entries = pvd_entries(result / "bodies.pvd")
    folders = sorted((result / "frame_meshes").iterdir())
    assert all(p.is_dir() for p in folders)
    assert [p.name for p in folders] == [
        "frame_" + pathlib.Path(f).stem.removeprefix("bodies_") for _, f in entries]
    for (time, _), folder in zip(entries, folders):
        files = sorted(folder.iterdir())
        # Every body of that frame once: the grains and one piece more per split so far.
        assert len(files) == grains + len(up_to(splits, time)), folder.name
        volume = 0.0
        for f in files:
            assert obj_groups(f) == [f.stem]
            volume += mesh_volume(meshio.read(f))
        assert volume == pytest.approx(total, rel=1e-9), folder.name


@pytest.fixture(scope="module")
def demo(binary, tmp_path_factory):
    """scenarios/demo.toml's fragments in each mesh format (no dynamics: a fraction of a second)."""
    base = tmp_path_factory.mktemp("demo")
    for fmt in ("obj", "stl", "stl_ascii"):
        run_cleave(binary, "run", ROOT / "scenarios" / "demo.toml", "--out", base / fmt,
                   "--quiet", "--mesh-format", fmt)
    return base


def test_meshio_and_vtk_read_the_obj_with_a_named_group_per_fragment(demo):
    rows = read_csv(demo / "obj" / "fragments.csv")
    path = demo / "obj" / "meshes" / "fragments.obj"
    assert obj_groups(path) == [r["name"] for r in rows]
    mesh = meshio.read(path)
    ids = np.concatenate(mesh.cell_data["obj:group_ids"])
    assert sorted(set(ids)) == list(range(len(rows)))
    volume = {}
    for block, group in zip(mesh.cells, mesh.cell_data["obj:group_ids"]):
        for face, g in zip(block.data, group):
            volume[g] = volume.get(g, 0.0) + closed_volume(mesh.points, [face])
    for g, r in enumerate(rows):
        assert volume[g] == pytest.approx(float(r["volume_m3"]), rel=1e-9), r["name"]
    reader = vtk.vtkOBJReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    assert out.GetNumberOfCells() == sum(len(b.data) for b in mesh.cells)
    groups = vtk_to_numpy(out.GetCellData().GetArray("GroupIds"))
    assert len(set(groups)) == len(rows)


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii"])
def test_meshio_and_vtk_read_the_stl(demo, fmt):
    rows = read_csv(demo / fmt / "fragments.csv")
    path = demo / fmt / "meshes" / "fragments.stl"
    mesh = meshio.read(path)
    # Binary STL holds float32: the volume to single precision.
    rel = 1e-5 if fmt == "stl" else 1e-9
    assert mesh_volume(mesh) == pytest.approx(sum(float(r["volume_m3"]) for r in rows), rel=rel)
    reader = vtk.vtkSTLReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert reader.GetOutput().GetNumberOfCells() == sum(len(b.data) for b in mesh.cells)


def test_fragments_are_the_components_of_the_last_frames_intact_bonds(result):
    """fragment_sizes.csv against the last ParaView frames read with VTK: the bodies joined
    by intact bond lines (their ends are the bodies' centroids) make one fragment each, and
    a body on no intact line is a fragment of its own."""
    last_bonds = pvd_entries(result / "bonds.pvd")[-1][1]
    last_bodies = pvd_entries(result / "bodies.pvd")[-1][1]
    bonds = read_vtp(result / last_bonds)
    intact = cell_array(bonds, "intact")
    parent = {}

    def root(p):
        while parent.setdefault(p, p) != p:
            p = parent[p]
        return p

    for c in range(bonds.GetNumberOfCells()):
        if intact[c] != 1:
            continue
        ends = [tuple(p) for p in cell_points(bonds, c)]
        a, b = root(ends[0]), root(ends[1])
        if a != b:
            parent[max(a, b)] = min(a, b)
    joined = {root(p) for p in list(parent)}
    bodies = len(set(cell_array(read_vtp(result / last_bodies), "body_id").tolist()))
    expected = len(joined) + bodies - len(parent)
    rows = [r for r in read_csv(result / "fragment_sizes.csv") if not r["bodies"].startswith("#")]
    with open(result / "run.toml", "rb") as f:
        facts = tomllib.load(f)["facts"]
    assert len(rows) == expected == int(facts["fragments.count"])
    assert sum(int(r["bodies"]) for r in rows) == bodies
    sizes = sorted(int(r["bodies"]) for r in rows if int(r["bodies"]) > 1)
    counts = {}
    for p in parent:
        counts[root(p)] = counts.get(root(p), 0) + 1
    assert sizes == sorted(counts.values())


def test_a_two_phase_specimens_grains_carry_their_phase_in_the_table_and_the_frames(binary, tmp_path):
    # The disc with two [[phase]] tables: specimen.csv names each grain's phase, the body
    # frames carry it as the index of its [[phase]] table; both agree grain by grain.
    text = SCENARIO.read_text() + (
        '\n[[phase]]\nname = "matrix"\nfraction = 0.6\n'
        '\n[[phase]]\nname = "soft"\nfraction = 0.4\nstiffness = 0.5\n')
    scenario = tmp_path / "two_phase.toml"
    scenario.write_text(text)
    out = tmp_path / "run"
    run_cleave(binary, "run", scenario, "--out", out, "--quiet", "--max-steps", "20")
    rows = read_csv(out / "specimen.csv")
    names = ["matrix", "soft"]
    phase_of = {int(r["grain_id"]): names.index(r["phase"]) for r in rows}
    assert set(phase_of.values()) == {0, 1}
    _, first = pvd_entries(out / "bodies.pvd")[0]
    poly = read_vtp(out / first)
    grains = cell_array(poly, "grain_id")
    phases = cell_array(poly, "phase")
    assert len(grains) == len(phases) > 0
    for g, p in zip(grains, phases):
        assert phase_of[int(g)] == int(p)
