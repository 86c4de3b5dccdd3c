"""poreshell.batch on a 2-worker local Dask cluster (issue 46): four manifest rows, one bad; the three
good rows' meshes are byte for byte the CLI's with the same options, the bad row fails alone, and
summary.csv says so."""

import csv
import json
import math
import os
import pathlib
import struct
import subprocess

import pytest

pytest.importorskip("distributed")

from poreshell import batch  # noqa: E402  (after the skip: needs distributed only to run)

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = pathlib.Path(os.environ.get("PORESHELL_EXE", ROOT / "build" / "app" / "poreshell"))


def write_sphere_obj(path, radius, rings=16, segments=24):
    """A closed UV sphere as OBJ text (counter-clockwise seen from outside)."""
    lines = ["v 0 0 %r" % radius]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            lines.append("v %r %r %r" % (radius * math.sin(theta) * math.cos(phi),
                                         radius * math.sin(theta) * math.sin(phi), radius * math.cos(theta)))
    lines.append("v 0 0 %r" % -radius)
    bottom = 1 + (rings - 1) * segments  # 0-based index of the last vertex

    def ring(i, j):  # 0-based index of ring i (1..rings-1), segment j
        return 1 + (i - 1) * segments + j % segments

    faces = [(0, ring(1, j), ring(1, j + 1)) for j in range(segments)]
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            faces += [(a, b, c), (a, c, d)]
    faces += [(bottom, ring(rings - 1, j + 1), ring(rings - 1, j)) for j in range(segments)]
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


# The good rows' options (hole_diameter, resolution, seed), as manifest cells and as the CLI's flags.
GOOD_VALUES = [("6", "41", "1"), ("5", "41", "2"), ("7", "45", "3")]
GOOD = [
    ({"hole_diameter": d, "resolution": r, "seed": s}, ["--hole-diameter", d, "--resolution", r, "--seed", s])
    for d, r, s in GOOD_VALUES
]


@pytest.fixture(scope="module")
def batch_run(tmp_path_factory):
    top = tmp_path_factory.mktemp("batch")
    write_sphere_obj(top / "ball.obj", 10.0)
    write_sphere_obj(top / "small.obj", 12.0)
    columns = ["input", "units", "hole_diameter", "resolution", "seed"]
    rows = [
        {"input": "ball.obj", "units": "mm", **GOOD[0][0]},
        {"input": "missing.obj", "units": "mm", **GOOD[0][0]},  # the bad row
        {"input": "small.obj", "units": "mm", **GOOD[1][0]},
        {"input": str(top / "ball.obj"), "units": "mm", **GOOD[2][0]},  # an absolute path
    ]
    with open(top / "manifest.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    summary = batch.run(str(top / "manifest.csv"), str(top / "out"), workers=2)
    return top, rows, summary


def test_good_rows_match_the_cli_byte_for_byte(batch_run):
    top, rows, _ = batch_run
    for (row, line), (_, flags) in zip([(1, rows[0]), (3, rows[2]), (4, rows[3])], GOOD):
        stem = pathlib.Path(line["input"]).stem
        ours = top / "out" / ("%d-%s.stl" % (row, stem))
        theirs = top / ("cli-%d.stl" % row)
        subprocess.run(
            [str(CLI), "--mesh", str(top / line["input"]), "--units", "mm", "--threads", "1", "-q", *flags,
             "-o", str(theirs)],
            check=True, stdout=subprocess.DEVNULL,
        )
        assert ours.read_bytes() == theirs.read_bytes(), row
        assert (top / "out" / ("%d-%s.json" % (row, stem))).is_file()


def test_the_bad_row_fails_alone_and_leaves_nothing(batch_run):
    top, _, summary = batch_run
    assert [line["status"] for line in summary] == ["ok", "failed", "ok", "ok"]
    assert "missing.obj" in summary[1]["error"]
    assert not list((top / "out").glob("2-*"))
    assert not list((top / "out").glob("*.tmp*"))


def test_the_summary_file_says_what_each_row_gave(batch_run):
    top, _, summary = batch_run
    with open(top / "out" / "summary.csv", newline="") as f:
        lines = list(csv.DictReader(f))
    assert tuple(lines[0].keys()) == batch.SUMMARY_FIELDS
    assert [int(line["row"]) for line in lines] == [1, 2, 3, 4]
    assert [line["status"] for line in lines] == ["ok", "failed", "ok", "ok"]
    for line in lines:
        if line["status"] != "ok":
            assert line["seconds"] == line["holes"] == line["triangles"] == "" and line["error"]
            continue
        mesh = top / "out" / ("%s-%s.stl" % (line["row"], pathlib.Path(line["input"]).stem))
        with open(mesh, "rb") as stl:
            stl.seek(80)
            assert int(line["triangles"]) == struct.unpack("<I", stl.read(4))[0]
        report = json.loads(mesh.with_suffix(".json").read_text())
        assert int(line["holes"]) == len(report["mesh"]["hole_table"]) > 0
        assert float(line["seconds"]) > 0 and line["error"] == ""


def test_a_bad_manifest_stops_before_any_job(tmp_path, capsys):
    (tmp_path / "manifest.csv").write_text("input,hole_diamter\nball.obj,6\n")
    assert batch.main([str(tmp_path / "manifest.csv"), "--out", str(tmp_path / "out")]) == 2
    assert "hole_diamter" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_an_existing_scheduler_runs_the_rows(batch_run, tmp_path):
    """--scheduler: the jobs go to a cluster someone else started (here one in this process)."""
    from distributed import LocalCluster

    top, _, _ = batch_run
    (tmp_path / "manifest.csv").write_text(
        "input,output,hole_diameter,resolution,seed\n%s,ball.stl,6,41,1\n" % (top / "ball.obj")
    )
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        summary = batch.run(str(tmp_path / "manifest.csv"), str(tmp_path / "out"), scheduler=cluster.scheduler_address)
    assert [line["status"] for line in summary] == ["ok"]
    # The first good row's options: the same bytes as that row's mesh.
    assert (tmp_path / "out" / "ball.stl").read_bytes() == (top / "out" / "1-ball.stl").read_bytes()
