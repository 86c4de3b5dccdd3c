"""The package's surface as its users meet it (issue 46): the namespace, the type stubs, the viewer page
from a Result, the `holes` progress stage and mesh objects with `.vertices` and `.faces`."""

import pathlib
import shutil
import struct

import numpy as np
import pytest

import poreshell

# A small, quick run: a 20 mm sphere on a coarse grid (well under a second).
SMALL = dict(hole_diameter=6, resolution=41, max_steps=40, threads=2)
PACKAGE = pathlib.Path(poreshell.__file__).parent


@pytest.fixture(scope="module")
def small():
    return poreshell.perforate(poreshell.sphere(20), **SMALL)


def test_namespace_holds_only_the_api():
    public = {name for name in dir(poreshell) if not name.startswith("_")}
    submodules = {"batch"}  # present once imported
    assert public - submodules <= set(poreshell.__all__), public - set(poreshell.__all__)
    for leaked in ("np", "os", "json", "numpy"):
        assert not hasattr(poreshell, leaked), leaked
    for name in poreshell.__all__:
        assert hasattr(poreshell, name), name


def test_type_stubs_cover_all_of_the_api():
    stub = PACKAGE / "__init__.pyi"
    assert (PACKAGE / "py.typed").is_file()
    assert stub.is_file()
    text = stub.read_text()
    for name in poreshell.__all__:
        assert name in text, name
    # The stub is valid Python, as type checkers read it.
    compile(text, str(stub), "exec")


def test_result_saves_the_viewer_page(small, tmp_path):
    page = tmp_path / "view.html"
    small.save(page)
    text = page.read_text()
    assert text.lstrip().lower().startswith("<!doctype html")
    # The page carries the run's report: its hole count is the result's.
    assert '"pores_from_euler"' in text
    assert not list(tmp_path.glob("*.tmp*"))
    # Every output of a result has its page.
    small.outputs[0].save(tmp_path / "level.html")
    assert (tmp_path / "level.html").stat().st_size > 1000


def test_a_hand_made_output_has_no_page(tmp_path):
    holes = np.zeros(0, poreshell.HOLE_DTYPE)
    level = {"iso": 0.0, "vertices": np.zeros((0, 3)), "faces": np.zeros((0, 3), np.int32),
             "holes": {f: holes[f] for f in poreshell.HOLE_DTYPE.names}}
    with pytest.raises(ValueError, match="perforate"):
        poreshell.Output(level).save(tmp_path / "x.html")


@pytest.mark.skipif(not any(shutil.which(c) for c in ("chromium", "chromium-browser", "google-chrome")),
                    reason="needs chromium")
def test_result_saves_the_viewer_picture(small, tmp_path):
    picture = tmp_path / "view.png"
    small.save(picture)
    data = picture.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])
    assert width > 100 and height > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == ["view.png"]  # the page it was taken of is gone


def test_every_documented_stage_reports_in_order():
    stages = []
    poreshell.perforate(poreshell.sphere(20), progress=lambda s, f: stages.append(s), **SMALL)
    order = [s for i, s in enumerate(stages) if i == 0 or stages[i - 1] != s]
    assert order == ["input", "band", "solve", "shell", "mesh", "holes"]


class TrimeshLike:
    """What trimesh.Trimesh offers: `.vertices` float64 (n, 3) and `.faces` int64 (m, 3)."""

    def __init__(self, vertices, faces):
        self.vertices = np.asarray(vertices, np.float64)
        self.faces = np.asarray(faces, np.int64)


def test_a_mesh_object_is_an_input(small):
    mesh = TrimeshLike(small.vertices, small.faces)
    # The input is a perforated shell: thinner everywhere than the thin-feature rule's 1.5 holes, and creased
    # at every pore's rim.
    options = dict(hole_diameter=6, resolution=41, max_steps=40, threads=2, thin_feature_ratio=0, crease_angle=0)
    by_object = poreshell.perforate(mesh, **options)
    by_arrays = poreshell.perforate(small.vertices, small.faces, **options)
    assert np.array_equal(by_object.vertices, by_arrays.vertices)
    assert np.array_equal(by_object.faces, by_arrays.faces)
    assert poreshell.estimate(mesh, **options)["triangles"] == poreshell.estimate(
        small.vertices, small.faces, **options
    )["triangles"]
    with pytest.raises(ValueError, match="faces"):
        poreshell.perforate(TrimeshLike(small.vertices, small.faces[:, :2]), **options)
