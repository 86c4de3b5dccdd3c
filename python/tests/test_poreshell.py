"""Tests of the Python package poreshell (run by ctest as `python`, with PYTHONPATH=build/python)."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import time
import zipfile
from xml.etree import ElementTree

import numpy as np
import pytest

import poreshell

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("PORESHELL_DATA_DIR", ROOT / "data"))
BUNNY = DATA / "stanford-bunny.obj"
CLI = pathlib.Path(os.environ.get("PORESHELL_EXE", ROOT / "build" / "app" / "poreshell"))

# A small, quick run: a 20 mm sphere on a coarse grid (well under a second).
SMALL = dict(resolution=41, max_steps=40, threads=2)


@pytest.fixture(scope="module")
def small():
    return poreshell.perforate(poreshell.sphere(20), **SMALL)


def test_bunny_matches_cli(tmp_path):
    """The paper's bunny run gives the CLI's triangle count and pore counts, with the same seed."""
    stl, report = tmp_path / "cli.stl", tmp_path / "cli.json"
    subprocess.run(
        [str(CLI), "--mesh", str(BUNNY), "--units", "m", "--alpha", "2200", "--seed", "7", "-q",
         "-o", str(stl), "--report", str(report)],
        check=True, stdout=subprocess.DEVNULL,
    )
    cli = json.loads(report.read_text())["mesh"]

    r = poreshell.perforate(str(BUNNY), units="m", alpha=2200, seed=7)
    mesh = r.report["mesh"]
    assert len(r.faces) == cli["triangles"] == mesh["triangles"]
    assert mesh["pores_from_euler"] == cli["pores_from_euler"]
    assert mesh["spots_at_iso"] == cli["spots_at_iso"]
    assert r.report["pattern"]["spots"] == json.loads(report.read_text())["pattern"]["spots"]
    assert r.vertices.dtype == np.float64 and r.vertices.shape[1] == 3
    assert r.faces.dtype == np.int32 and r.faces.shape[1] == 3



def test_array_input_gives_a_closed_shell(small):
    v, f = small.vertices, small.faces
    r = poreshell.perforate(v, f, **SMALL)
    mesh = r.report["mesh"]
    assert mesh["closed"] and mesh["manifold"] and mesh["oriented"]
    assert r.report["input"]["kind"] == "mesh"
    assert len(r.faces) == mesh["triangles"]
    assert r.holes.dtype == poreshell.HOLE_DTYPE


def test_result_fields(small):
    assert small.report["mesh"]["closed"]
    assert small.report["input"]["kind"] == "shape"
    assert small.vertices.shape == (small.report["mesh"]["vertices"], 3)
    assert 0 <= small.faces.min() and small.faces.max() < len(small.vertices)
    assert np.abs(small.vertices).max() < 25  # mm: a 20 mm sphere in a thin wall
    assert small.holes["centre"].shape == (len(small.holes), 3)
    assert len(small.outputs) == 1 and small.iso == 0.0


def test_hole_table_of_a_millimetre_request():
    """Each hole measured on the written mesh: about the asked size, round, as a numpy record."""
    r = poreshell.perforate(poreshell.sphere(30), hole_diameter=6, spacing=10, wall=2)
    holes = r.holes
    assert len(holes) > 80  # 105 on a bare sphere of 30 mm (tests/pipeline/test_print_quality.cpp)
    assert abs(holes["diameter"].mean() - 6) < 0.3
    assert np.allclose(np.linalg.norm(holes["centre"], axis=1), 30, atol=1.5)
    # Round pores on a sphere: the cross-sections' axes within a quarter of each other.
    assert (holes["axis_ratio"] > 0.75).all() and (holes["axis_ratio"] <= 1.0).all()
    assert (holes["asked_diameter"] == 6).all()


def test_graded_holes_say_what_each_was_asked():
    """With a grading each hole carries the size asked at its centre: 4 mm at the bottom to 8 at the top."""
    r = poreshell.perforate(poreshell.sphere(30), hole_diameter=6, spacing=10, grade="axis:z:4:8", preview=True)
    holes = r.holes
    z, asked = holes["centre"][:, 2], holes["asked_diameter"]
    assert 4 <= asked.min() < 4.6 and 7.4 < asked.max() <= 8
    assert np.corrcoef(z, asked)[0, 1] > 0.99  # linear in height
    # The preview's discs follow it (docs/printing.md "Grading"): within 15% each, 5% on average.
    deviation = holes["diameter"] / asked - 1
    assert np.abs(deviation).max() < 0.15 and abs(deviation.mean()) < 0.05


@pytest.mark.parametrize(
    "vertices, faces, match",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], "shape"),
        (np.zeros(12), [[0, 1, 2]], "shape"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1]], "shape"),
        (np.array([["a", "b", "c"]] * 3), [[0, 1, 2]], "dtype"),
        (np.zeros((3, 3), dtype=complex), [[0, 1, 2]], "dtype"),
        (np.zeros((3, 3)), np.array([[0.0, 1.0, 2.0]]), "dtype"),
        (np.array([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]]), [[0, 1, 2]], "NaN"),
        (np.array([[0, 0, 0], [1, np.inf, 0], [0, 1, 0]]), [[0, 1, 2]], "NaN"),
        (np.zeros((3, 3)), [[0, 1, 3]], "index"),
        (np.zeros((3, 3)), [[0, -1, 2]], "index"),
    ],
)
def test_bad_arrays_raise_value_error(vertices, faces, match):
    with pytest.raises(ValueError, match=match):
        poreshell.perforate(vertices, faces)


def test_bad_options():
    with pytest.raises(ValueError, match="`hole_diameter`") as e:
        poreshell.perforate(poreshell.sphere(20), hole_diameter=-1)
    assert e.value.code == "invalid_option" and e.value.option == "hole_diameter"
    with pytest.raises(ValueError, match="`resolution`"):
        poreshell.perforate(poreshell.sphere(20), resolution=40.5)
    with pytest.raises(ValueError, match="`solver`"):
        poreshell.perforate(poreshell.sphere(20), solver="slow")
    with pytest.raises(ValueError, match="`keep_out`"):
        poreshell.perforate(poreshell.sphere(20), keep_out=[(0, 0, 0)])
    with pytest.raises(ValueError, match="`grade`"):
        poreshell.perforate(poreshell.sphere(20), hole_diameter=4, grade="diagonal:4:8")
    with pytest.raises(ValueError, match="`units`"):
        poreshell.perforate(poreshell.sphere(20), units="furlong")
    # The library refuses the mixed request, naming the paper's parameter given.
    with pytest.raises(ValueError, match="`alpha` is one of the paper's parameters.*`hole_diameter`") as e:
        poreshell.perforate(poreshell.sphere(20), hole_diameter=5, alpha=2200)
    assert e.value.option == "alpha"
    with pytest.raises(ValueError, match="`iso`.*`spacing`"):
        poreshell.perforate(poreshell.sphere(20), spacing=8, iso=[0.1])
    with pytest.raises(TypeError, match="alpah"):
        poreshell.perforate(poreshell.sphere(20), alpah=2200)
    with pytest.raises(ValueError, match="`spacing`") as e:  # named for itself, not as hole_diameter
        poreshell.perforate(poreshell.sphere(20), hole_diameter=4, spacing=-1)
    assert e.value.option == "spacing"


def test_keywords_are_the_option_table():
    """Every keyword is an option of the report's settings and back (issue 48: one option table)."""
    assert set(poreshell.OPTION_NAMES) >= {"hole_diameter", "keep_out", "max_deviation", "seed"}
    keep_out = np.array([[0, 0, 20, 3]])
    result = poreshell.perforate(poreshell.sphere(20), preview=True, hole_diameter=4, keep_out=keep_out)
    assert sorted(result.report["settings"]) == sorted(poreshell.OPTION_NAMES)
    assert result.report["settings"]["keep_out"] == [{"centre": [0, 0, 20], "radius": 3}]


def test_estimate_before_the_run():
    options = dict(hole_diameter=6, spacing=10, preview=True)
    e = poreshell.estimate(poreshell.sphere(25), **options)
    r = poreshell.perforate(poreshell.sphere(25), **options)
    voxels = r.report["band"]["voxels"]
    assert e["preview"] and abs(e["band_voxels"] - voxels) < 0.15 * voxels
    assert abs(e["triangles"] - len(r.faces)) < 0.10 * len(r.faces)
    assert all(abs(s - 50) < 1 for s in e["size_mm"]) and e["warnings"] == []
    full = poreshell.estimate(poreshell.sphere(25), hole_diameter=6, spacing=10)
    assert not full["preview"] and full["seconds"] > 2 * e["seconds"] and full["ply_bytes"] == 0
    # A scan in metres given as millimetres: the warning names the unit that makes it a usual size.
    v = np.array([[0, 0, 0], [0.15, 0, 0], [0, 0.15, 0], [0, 0, 0.15]])
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert any("`units` m" in w for w in poreshell.estimate(v, f)["warnings"])
    with pytest.raises(ValueError, match="`hole_diameter`"):
        poreshell.estimate(poreshell.sphere(20), hole_diameter=-1)
    with pytest.raises(TypeError, match="estimate.*progress"):
        poreshell.estimate(poreshell.sphere(20), progress=print)


def test_prepare_once_then_estimate_and_run():
    # A mesh given as arrays that go out of scope: the prepared input keeps what it points to.
    def prepared():
        v, f = poreshell.load_mesh(DATA / "stanford-bunny.obj", units="m")
        return poreshell.prepare(v, f, hole_diameter=8, spacing=14, preview=True, seed=3)

    p = prepared()
    assert p.estimate() == poreshell.estimate(
        *poreshell.load_mesh(DATA / "stanford-bunny.obj", units="m"), hole_diameter=8, spacing=14, preview=True, seed=3
    )
    stages = []
    r = p.perforate(progress=lambda stage, fraction: stages.append(stage))
    direct = poreshell.perforate(
        *poreshell.load_mesh(DATA / "stanford-bunny.obj", units="m"), hole_diameter=8, spacing=14, preview=True, seed=3
    )
    assert np.array_equal(r.faces, direct.faces) and np.array_equal(r.vertices, direct.vertices)
    assert np.array_equal(r.outputs[0].pattern, direct.outputs[0].pattern)
    assert "band" in stages
    assert len(p.perforate().holes) == len(r.holes)  # a Prepared runs more than once
    with pytest.raises(TypeError, match="prepare.*progress"):
        poreshell.prepare(poreshell.sphere(20), hole_diameter=6, progress=print)
    with pytest.raises(ValueError, match="`hole_diameter`"):
        poreshell.prepare(poreshell.sphere(20), hole_diameter=-1)
    with pytest.raises(ValueError, match="max_seconds"):
        p.perforate(max_seconds=-1)


def test_preview_paints_the_input_mesh(tmp_path):
    r = poreshell.perforate(DATA / "stanford-bunny.obj", units="m", hole_diameter=8, spacing=14, preview=True)
    out = r.outputs[0]
    assert out.pattern.shape == (len(out.vertices),) and np.isfinite(out.pattern).all()
    open_share = np.mean(out.pattern > out.iso)
    assert 0.05 < open_share < 0.4, open_share  # the holes are a part of the surface, not none or all
    assert abs(len(out.holes) - r.report["solver"]["layout_holes"]) <= 0.03 * len(out.holes)
    out.save(tmp_path / "p.ply")
    header = (tmp_path / "p.ply").read_bytes()[:400]
    assert b"property uchar red" in header
    assert poreshell.perforate(poreshell.sphere(20), hole_diameter=6, spacing=10).outputs[0].pattern is None


def test_progress_is_called():
    calls = []
    poreshell.perforate(poreshell.sphere(20), progress=lambda stage, f: calls.append((stage, f)), **SMALL)
    stages = [stage for stage, _ in calls]
    assert "solve" in stages and "mesh" in stages
    assert all(isinstance(f, float) and 0.0 <= f <= 1.0 for _, f in calls)


def test_exception_in_progress_cancels_and_propagates():
    class Stop(Exception):
        pass

    seen = []

    def progress(stage, fraction):
        seen.append(stage)
        if stage == "solve":
            raise Stop("stop here")

    with pytest.raises(Stop, match="stop here"):
        poreshell.perforate(poreshell.sphere(20), progress=progress, resolution=81, threads=2)
    assert seen[-1] == "solve"  # nothing after the exception


def test_ctrl_c_cancels_promptly():
    """SIGINT during the solve: KeyboardInterrupt out of perforate() well within a second."""
    code = (
        "import poreshell, sys\n"
        "try:\n"
        "    poreshell.perforate(poreshell.sphere(20), resolution=131, tolerance=1e-12, max_steps=100000,\n"
        "        progress=lambda s, f: s == 'solve' and print(s, flush=True))\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True); sys.exit(3)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "solve"
        start = time.monotonic()
        p.send_signal(signal.SIGINT)
        out = p.stdout.read()
        assert p.wait(timeout=30) == 3
        assert time.monotonic() - start < 2.0
        assert out.strip().endswith("interrupted")
    finally:
        if p.poll() is None:
            p.kill()


def test_time_budget_stops_the_run():
    start = time.monotonic()
    with pytest.raises(RuntimeError, match="time budget of 0.5 s") as failure:
        poreshell.perforate(poreshell.sphere(20), resolution=131, tolerance=1e-12, max_steps=100000, max_seconds=0.5)
    assert failure.value.code == "out_of_time"
    assert time.monotonic() - start < 10.0  # a loose bound: the run alone would take minutes
    with pytest.raises(ValueError, match="max_seconds"):
        poreshell.perforate(poreshell.sphere(20), max_seconds=-1)


def test_save_round_trips_through_load_mesh(small, tmp_path):
    for ext in ("stl", "ply", "obj"):
        path = tmp_path / ("sphere." + ext)
        small.save(path)
        v, f = poreshell.load_mesh(path)
        assert len(f) == len(small.faces)
        assert v.dtype == np.float64 and f.dtype == np.int32
        # Welded on load: compare as sets of vertices (STL keeps float32).
        a = np.unique(np.round(small.vertices, 3), axis=0)
        b = np.unique(np.round(v, 3), axis=0)
        assert a.shape == b.shape
        np.testing.assert_allclose(np.sort(small.vertices, axis=0), np.sort(v, axis=0), atol=1e-4)
    small.save_report(tmp_path / "r.json")
    assert json.loads((tmp_path / "r.json").read_text()) == small.report


def test_save_errors(small, tmp_path):
    with pytest.raises(RuntimeError):
        small.save(tmp_path / "missing" / "x.stl")
    with pytest.raises(ValueError, match="missing.obj") as e:  # the library: a bad input
        poreshell.load_mesh(tmp_path / "missing.obj")
    assert e.value.code == "invalid_input"


def test_load_mesh_units():
    v_mm, f = poreshell.load_mesh(BUNNY, units="m")
    v_m, f_m = poreshell.load_mesh(BUNNY)
    np.testing.assert_array_equal(f, f_m)
    np.testing.assert_allclose(v_mm, v_m * 1000)


def test_points_input():
    rng = np.random.default_rng(1)
    p = rng.normal(size=(4000, 3))
    p = 20 * p / np.linalg.norm(p, axis=1, keepdims=True)
    r = poreshell.perforate(poreshell.points(p, units="mm"), **SMALL)
    assert r.report["input"]["kind"] == "points"
    assert r.report["mesh"]["closed"]


def test_several_levels(tmp_path):
    r = poreshell.perforate(poreshell.sphere(20), iso=[0.3, 0.0], **SMALL)
    assert [o.iso for o in r.outputs] == [0.3, 0.0]
    assert len(r.report["mesh"]["outputs"]) == 2
    r.outputs[1].save(tmp_path / "b.3mf")
    # A 3MF any ZIP and XML reader takes: Python's own check every entry's CRC and read the model.
    with zipfile.ZipFile(tmp_path / "b.3mf") as package:
        assert package.testzip() is None
        assert {"[Content_Types].xml", "_rels/.rels", "3D/3dmodel.model"} <= set(package.namelist())
        model = ElementTree.fromstring(package.read("3D/3dmodel.model"))
    core = "{http://schemas.microsoft.com/3dmanufacturing/core/2015/02}"
    assert model.get("unit") == "millimeter"
    v, f = r.outputs[1].vertices, r.outputs[1].faces
    vertices = model.findall(f".//{core}vertex")
    triangles = model.findall(f".//{core}triangle")
    assert len(vertices) == len(v) and len(triangles) == len(f)
    xyz = np.array([[float(e.get(a)) for a in "xyz"] for e in vertices], dtype=np.float32)
    np.testing.assert_array_equal(xyz, np.asarray(v, dtype=np.float32))
    corners = np.array([[int(e.get(a)) for a in ("v1", "v2", "v3")] for e in triangles])
    np.testing.assert_array_equal(corners, f)


def test_help_is_useful():
    doc = poreshell.perforate.__doc__
    for word in ("vertices", "(n, 3)", "mm", "hole_diameter", "progress", "ValueError", "Shape"):
        assert word in doc


def _open_sleeve(radius=15.0, length=30.0, segments=24, rings=4):
    """An open cylinder: vertices (n, 3) and faces (m, 3), as tests/support/test_meshes.hpp's."""
    a = 2 * np.pi * np.arange(segments) / segments
    v = np.array([[radius * np.cos(t), radius * np.sin(t), length * r / rings]
                  for r in range(rings + 1) for t in a])
    f = []
    for r in range(rings):
        for s in range(segments):
            i, j = r * segments + s, r * segments + (s + 1) % segments
            f += [[i, j, j + segments], [i, j + segments, i + segments]]
    return v, np.array(f, dtype=np.int32)


def test_mesh_preview_runs_the_equation_with_either_solver():
    """issue 47: perforate(V, F, preview=True) with the paper's parameters (or layout='paper') solved on
    the band's surface layer and killed the interpreter. Run in a child so that a crash fails the test
    instead of ending pytest."""
    code = (
        "import numpy as np, poreshell, sys\n"
        "sys.path.insert(0, %r)\n"
        "from test_poreshell import _open_sleeve\n"
        "v, f = _open_sleeve()\n"
        "for solver in ('fast', 'reference'):\n"
        "    for extra in (dict(resolution=41), dict(hole_diameter=6, spacing=10, layout='paper')):\n"
        "        r = poreshell.perforate(v, f, preview=True, solver=solver, max_steps=4, threads=2, **extra)\n"
        "        assert r.report['solver']['steps'] > 0, r.report['solver']\n"
        "        assert r.outputs[0].pattern.shape == (len(r.vertices),)\n"
        "        assert np.isfinite(r.outputs[0].pattern).all()\n"
        "print('ok')\n" % str(pathlib.Path(__file__).parent)
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=280)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "ok"


# A closed 20 mm cube, outward triangles.
CUBE_V = np.array([[0, 0, 0], [20, 0, 0], [20, 20, 0], [0, 20, 0],
                   [0, 0, 20], [20, 0, 20], [20, 20, 20], [0, 20, 20]], dtype=float)
CUBE_F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                   [2, 3, 7], [2, 7, 6], [1, 2, 6], [1, 6, 5], [0, 4, 7], [0, 7, 3]], dtype=np.int32)


def test_a_far_vertex_is_refused_not_dropped():
    """issue 47: a corner at 1e20 made needles of its triangles, which were dropped without a word
    (the cube came out open, exit 0)."""
    v = CUBE_V.copy()
    v[7] = 1e20
    with pytest.raises(ValueError, match=r"vertex 7 .* lies far outside the rest of the mesh"):
        poreshell.perforate(v, CUBE_F, resolution=33, max_steps=5)


def test_holes_wider_than_the_model_name_the_unit_that_fits():
    """issue 47: a model in metres read as mm (0.02 mm across) with 8 mm holes was told to ask for smaller
    holes; the unit comes first now."""
    with pytest.raises(ValueError, match=r"fit nowhere .* say `units` m \(it is then 20 mm across\)"):
        poreshell.perforate(CUBE_V / 1000.0, CUBE_F, hole_diameter=8)
    with pytest.raises(ValueError, match=r"holes of 30 mm fit nowhere"):
        poreshell.perforate(CUBE_V, CUBE_F, hole_diameter=30)


def test_repeated_triangles_are_dropped_and_counted():
    """issue 47: an object repeated in place (or a polygon fanned over a few corners) gave thousands of
    coincident triangles that made every search slow; each is kept once and the rest counted."""
    v = np.vstack([CUBE_V] * 200)
    f = np.vstack([CUBE_F + 8 * k for k in range(200)]).astype(np.int32)
    r = poreshell.perforate(v, f, resolution=25, max_steps=3, threads=2)
    assert r.report["input"]["triangles"] == 12
    assert r.report["input"]["dropped_duplicate"] == 12 * 199
    assert r.report["input"]["boundary_edges"] == 0
