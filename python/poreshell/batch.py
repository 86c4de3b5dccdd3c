"""Batches of runs on a Dask distributed cluster: one job per row of a CSV manifest.

    python3 -m poreshell.batch MANIFEST.csv --out DIR [--workers N | --scheduler ADDRESS]

or from Python, poreshell.batch.run("manifest.csv", "out", workers=4). The manifest's columns: `input`
(a mesh file; a relative path is relative to the manifest's folder), `units` (of the file, default mm),
`output` (optional: the mesh's file name under DIR, its extension the format; default
`<row>-<input's stem>.stl`) and any option of poreshell.perforate() by its API name (OPTION_NAMES), a
value a cell: a number, true/false, a word, or a Python literal such as [0, 0.1] or [(0, 0, 10, 5)]. An
empty cell leaves the option at its default. `threads` defaults to 1: one job per worker thread, and
the same bytes as the CLI with the same options (results never depend on it).

Each job writes its mesh and its JSON report (`<mesh's stem>.json`) under DIR, each to a temporary name
first, so that a failed job leaves no file. A job that fails is run once more (on any worker); one that
fails again is written down as failed and the others go on. DIR/summary.csv has a line per row: row
(1 for the first data line), input, status (ok or failed), seconds (the job's wall time on its worker),
holes (those measured on the mesh), triangles, error (the message, for a failed row).

Without --scheduler a local cluster is started: N worker processes (default: the CPU count) of one
thread each. With --scheduler the jobs go to an existing Dask scheduler (tcp://host:8786), whose workers
must see the manifest's input files and DIR at the same paths and have poreshell installed.
docs/batch.md shows the same manifest as a Slurm array over the CLI.
"""

import argparse
import ast
import csv
import os
import sys
import time
import uuid
from typing import Any, Dict, List, Optional

__all__ = ["run", "read_manifest", "main", "SUMMARY_FIELDS"]

#: The columns of DIR/summary.csv.
SUMMARY_FIELDS = ("row", "input", "status", "seconds", "holes", "triangles", "error")

_RESERVED = ("input", "units", "output")


def _value(text: str) -> Any:
    """A manifest cell as an option's value: a Python literal, true/false, or else the text itself."""
    lowered = text.strip().lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        return ast.literal_eval(text.strip())
    except (ValueError, SyntaxError):
        return text.strip()


def read_manifest(manifest: str) -> List[Dict[str, Any]]:
    """The manifest's jobs: dicts with row, input (absolute), units, output (a file name or None) and
    options. Raises ValueError naming the column for an unknown option or a missing `input` column;
    a row's own problems (a missing file, a bad value) are its job's failure, not the batch's."""
    from . import OPTION_NAMES

    base = os.path.dirname(os.path.abspath(manifest))
    with open(manifest, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        columns = [c.strip() for c in (reader.fieldnames or [])]
        if "input" not in columns:
            raise ValueError("manifest %s has no `input` column (the header must name it)" % manifest)
        unknown = [c for c in columns if c not in _RESERVED and c not in OPTION_NAMES]
        if unknown:
            raise ValueError(
                "manifest %s: unknown column(s) %s: use input, units, output and perforate()'s option "
                "names (poreshell.OPTION_NAMES)" % (manifest, ", ".join(repr(c) for c in unknown))
            )
        jobs = []
        for number, line in enumerate(reader, start=1):
            cells = {k.strip(): (v or "").strip() for k, v in line.items() if k is not None}
            options = {k: _value(v) for k, v in cells.items() if k not in _RESERVED and v != ""}
            options.setdefault("threads", 1)
            source = cells.get("input", "")
            jobs.append(
                {
                    "row": number,
                    "input": os.path.join(base, source) if source else "",
                    "units": cells.get("units") or "mm",
                    "output": cells.get("output") or None,
                    "options": options,
                }
            )
    return jobs


def _output_name(job: Dict[str, Any]) -> str:
    if job["output"]:
        return job["output"]
    stem = os.path.splitext(os.path.basename(job["input"]))[0] or "input"
    return "%d-%s.stl" % (job["row"], stem)


def run_job(job: Dict[str, Any], out: str) -> Dict[str, Any]:
    """One manifest row, on a worker: perforates, writes the mesh and the report, returns the summary's
    figures. Raises what perforate() raises; nothing is left behind then."""
    import poreshell

    start = time.perf_counter()
    if not job["input"]:
        raise ValueError("row %d has no `input`: give a mesh file's path" % job["row"])
    result = poreshell.perforate(job["input"], units=job["units"], **job["options"])
    mesh = os.path.join(out, _output_name(job))
    report = os.path.splitext(mesh)[0] + ".json"
    try:
        result.save(mesh)
        result.save_report(report)
    except BaseException:
        for path in (mesh, report):
            if os.path.exists(path):
                os.remove(path)
        raise
    return {
        "seconds": round(time.perf_counter() - start, 3),
        "holes": len(result.holes),
        "triangles": len(result.faces),
    }


def _summary_line(job: Dict[str, Any], figures: Optional[Dict[str, Any]], error: str) -> Dict[str, Any]:
    line = {"row": job["row"], "input": job["input"], "status": "ok" if figures else "failed",
            "seconds": "", "holes": "", "triangles": "", "error": error}
    if figures:
        line.update(figures)
    return line


def run(
    manifest: str,
    out: str,
    workers: Optional[int] = None,
    scheduler: Optional[str] = None,
    retries: int = 1,
) -> List[Dict[str, Any]]:
    """Runs the manifest's jobs on Dask and writes DIR/summary.csv; returns its lines (dicts of
    SUMMARY_FIELDS, in row order). `workers`: the local cluster's worker processes (default: the CPU
    count); `scheduler`: an existing scheduler's address instead; `retries`: how often a failed job is
    run again (1: once)."""
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise RuntimeError(
            "poreshell.batch needs Dask's distributed: apt-get install python3-distributed "
            "(scripts/install-deps), or pip install 'poreshell[batch]'"
        ) from None

    if workers is not None and scheduler is not None:
        raise ValueError("give `workers` (a local cluster) or `scheduler` (an existing one), not both")
    if workers is not None and workers < 1:
        raise ValueError("`workers` must be at least 1, got %r" % (workers,))
    jobs = read_manifest(manifest)
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    cluster = None
    if scheduler is None:
        # One thread per worker: each job uses `threads` of its own, and the outputs are the CLI's.
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                               processes=True, dashboard_address=None)
    lines: Dict[int, Dict[str, Any]] = {}
    try:
        with Client(cluster if cluster is not None else scheduler) as client:
            futures = {}
            batch = uuid.uuid4().hex[:8]  # keys unique on a scheduler that other batches share
            for job in jobs:
                key = "poreshell-%s-row-%d" % (batch, job["row"])
                futures[client.submit(run_job, job, out, retries=retries, pure=False, key=key)] = job
            for future in as_completed(futures):
                job = futures[future]
                if future.status == "finished":
                    lines[job["row"]] = _summary_line(job, future.result(), "")
                else:  # failed on its last try: the batch goes on
                    error = future.exception()
                    message = "%s: %s" % (type(error).__name__, error)
                    lines[job["row"]] = _summary_line(job, None, message)
                future.release()
    finally:
        if cluster is not None:
            cluster.close()
    summary = [lines[job["row"]] for job in jobs]
    path = os.path.join(out, "summary.csv")
    tmp = "%s.tmp%d" % (path, os.getpid())
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=SUMMARY_FIELDS)
        writer.writeheader()
        writer.writerows(summary)
    os.replace(tmp, path)
    return summary


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python3 -m poreshell.batch",
        description="Runs one poreshell job per manifest row on a Dask cluster; writes DIR/summary.csv.",
    )
    parser.add_argument("manifest", help="CSV: input, units, output and perforate()'s options by API name")
    parser.add_argument("--out", required=True, metavar="DIR", help="where the meshes, reports and summary go")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: CPU count)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, tcp://host:8786")
    args = parser.parse_args(argv)
    try:
        summary = run(args.manifest, args.out, workers=args.workers, scheduler=args.scheduler)
    except (OSError, ValueError, RuntimeError) as e:
        print("poreshell.batch: error: %s" % e, file=sys.stderr)
        return 2
    failed = [line for line in summary if line["status"] != "ok"]
    print("poreshell.batch: %d of %d rows ok; %s" % (len(summary) - len(failed), len(summary),
                                                    os.path.join(os.path.abspath(args.out), "summary.csv")))
    for line in failed:
        print("  row %d failed: %s" % (line["row"], line["error"]), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
