#!/usr/bin/python3
"""Uniformity of the holes on the sphere (docs/solver.md "Layout"): per seed, the written mesh's holes
(the --holes table) as spherical-Voronoi cell-area CV, nearest-neighbour (NN) distance CV and diameter
CV, CV = population std / mean; the solver's steps and the
report's total seconds beside them.

  bench/layout_uniformity.py [--poreshell build/app/poreshell] [--seeds 1-5] [--layout cvt] [--keep DIR]

Runs `poreshell --shape sphere --radius 50 --hole-diameter 6 --spacing 10 --wall 2 --seed S` per seed
(about 2 s each with cvt). Needs numpy and scipy (Debian: python3-scipy).
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile

import numpy as np
from scipy.spatial import SphericalVoronoi, cKDTree


def cv(x):
    return float(np.std(x) / np.mean(x))


def measure(holes_csv):
    with open(holes_csv) as f:
        rows = list(csv.DictReader(f))
    centres = np.array([[float(r["x_mm"]), float(r["y_mm"]), float(r["z_mm"])] for r in rows])
    diameters = np.array([float(r["diameter_mm"]) for r in rows])
    centre = centres.mean(axis=0)
    unit = centres - centre
    unit /= np.linalg.norm(unit, axis=1)[:, None]
    cells = SphericalVoronoi(unit, 1.0).calculate_areas()
    nn = cKDTree(centres).query(centres, 2)[0][:, 1]
    return len(rows), cv(cells), cv(nn), cv(diameters)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--poreshell", default="build/app/poreshell")
    ap.add_argument("--seeds", default="1-5")
    ap.add_argument("--layout", default=None, help="cvt or paper (default: the CLI's)")
    ap.add_argument("--keep", default=None, help="folder for the meshes, tables and reports")
    a = ap.parse_args()
    lo, _, hi = a.seeds.partition("-")
    seeds = range(int(lo), int(hi or lo) + 1)
    out = a.keep or tempfile.mkdtemp()
    os.makedirs(out, exist_ok=True)
    rows = []
    print("| seed | holes | cell-area CV | NN CV | diameter CV | steps | s |\n| --- | --- | --- | --- | --- | --- | --- |")
    for s in seeds:
        holes = os.path.join(out, f"h{s}.csv")
        cmd = [a.poreshell, "--shape", "sphere", "--radius", "50", "--hole-diameter", "6", "--spacing", "10",
               "--wall", "2", "--seed", str(s), "--holes", holes, "--report", os.path.join(out, f"r{s}.json"),
               "-o", os.path.join(out, f"s{s}.stl")]
        if a.layout:
            cmd += ["--layout", a.layout]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        n, cell, nn, dia = measure(holes)
        with open(os.path.join(out, f"r{s}.json")) as f:
            report = json.load(f)
        steps, seconds = report["solver"]["steps"], report["seconds"]["total"]
        rows.append((cell, nn, dia, steps, seconds))
        print(f"| {s} | {n} | {cell:.4f} | {nn:.4f} | {dia:.4f} | {steps} | {seconds:.1f} |", flush=True)
    m = np.mean(rows, axis=0)
    print(f"| mean | | {m[0]:.4f} | {m[1]:.4f} | {m[2]:.4f} | {m[3]:.1f} | {m[4]:.1f} |")


if __name__ == "__main__":
    main()
