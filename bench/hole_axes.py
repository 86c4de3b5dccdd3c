#!/usr/bin/python3
"""Axis ratios of a written part's holes, measured apart from poreshell's own hole table.

Usage: bench/hole_axes.py OUT.stl HOLES.csv [--worst K]

The hole table has its own axis_ratio column, from the loop it cuts along the wall's middle; this is
the check on it with a plain plane cut.

For each of the K holes of least circularity in HOLES.csv (`--holes`), cuts the binary STL by the
plane through the hole's centre normal to its normal, chains the cut's segments within 8 mm into
closed loops, takes the smallest loop that winds around the centre and reports its equivalent
diameter and axis ratio: sqrt of the ratio of the principal second moments of the loop's area, 1 for
a circle, b / a for an ellipse. Issue 19 asks for none under 0.6. Circularity says little about
elongation (an ellipse of axis ratio 0.75 has circularity 0.97, of 0.6 still 0.91), hence this check.

Needs python3-numpy and python3-scipy (Debian).
"""
import argparse
from collections import defaultdict

import numpy as np
from scipy.spatial import cKDTree


def read_binary_stl(path):
    data = open(path, "rb").read()
    count = int(np.frombuffer(data[80:84], np.uint32)[0])
    facet = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    return np.frombuffer(data[84:84 + 50 * count], dtype=facet)["v"].astype(float)


def plane_cut(triangles, centre, normal):
    """Segments of the cut in the plane's own 2D frame."""
    side = (triangles - centre) @ normal
    u = np.cross(normal, [1.0, 0.0, 0.0])
    if np.linalg.norm(u) < 0.1:
        u = np.cross(normal, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    segments = []
    for tri, s in zip(triangles, side):
        ends = []
        for a in range(3):
            b = (a + 1) % 3
            if (s[a] > 0) != (s[b] > 0):
                x = tri[a] + (tri[b] - tri[a]) * (s[a] / (s[a] - s[b]))
                ends.append(((x - centre) @ u, (x - centre) @ w))
        if len(ends) == 2:
            segments.append(ends)
    return segments


def closed_loops(segments):
    key = lambda p: (round(p[0], 7), round(p[1], 7))
    at = defaultdict(list)
    for i, (p, q) in enumerate(segments):
        at[key(p)].append((i, q))
        at[key(q)].append((i, p))
    used = set()
    for i, (p, q) in enumerate(segments):
        if i in used:
            continue
        used.add(i)
        loop, here = [p], q
        while key(here) != key(p):
            loop.append(here)
            onward = [(j, r) for j, r in at[key(here)] if j not in used]
            if not onward:
                loop = None
                break
            j, here = onward[0]
            used.add(j)
        if loop is not None and len(loop) >= 8:
            yield np.array(loop)


def winds_around_origin(loop):
    turn = np.diff(np.append(np.arctan2(loop[:, 1], loop[:, 0]), np.arctan2(loop[0, 1], loop[0, 0])))
    return abs(((turn + np.pi) % (2 * np.pi) - np.pi).sum()) > np.pi


def area_and_axis_ratio(loop):
    x, y = loop[:, 0], loop[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    cx, cy = ((x + xn) * cross).sum() / (6 * area), ((y + yn) * cross).sum() / (6 * area)
    iyy = ((y * y + y * yn + yn * yn) * cross).sum() / 12 - area * cy * cy
    ixx = ((x * x + x * xn + xn * xn) * cross).sum() / 12 - area * cx * cx
    ixy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * cross).sum() / 24 - area * cx * cy
    low, high = np.linalg.eigvalsh(np.sign(area) * np.array([[ixx, ixy], [ixy, iyy]]))
    return abs(area), np.sqrt(max(low, 0.0) / high)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("holes")
    parser.add_argument("--worst", type=int, default=20)
    args = parser.parse_args()
    triangles = read_binary_stl(args.mesh)
    columns = open(args.holes).readline().strip().split(",")
    holes = np.genfromtxt(args.holes, delimiter=",", skip_header=1).reshape(-1, len(columns))
    table_ratio = columns.index("axis_ratio") if "axis_ratio" in columns else None
    near = cKDTree(triangles.mean(axis=1))
    ratios = []
    for i in np.argsort(holes[:, 7])[: args.worst]:
        centre, normal = holes[i, :3], holes[i, 3:6] / np.linalg.norm(holes[i, 3:6])
        local = triangles[near.query_ball_point(centre, 8.0)]
        loops = [l for l in closed_loops(plane_cut(local, centre, normal)) if winds_around_origin(l)]
        if not loops:
            print(f"hole {i:4d} at {centre.round(2)}: no closed loop in the plane (a bend; the table's cut follows the wall)")
            continue
        area, ratio = min(area_and_axis_ratio(l) for l in loops)
        ratios.append(ratio)
        table = f" axis ratio {holes[i, table_ratio]:.3f}" if table_ratio is not None else ""
        print(f"hole {i:4d} at {centre.round(2)}: table d {holes[i, 6]:.2f} circ {holes[i, 7]:.3f}{table}; "
              f"plane cut d {2 * np.sqrt(area / np.pi):.2f} axis ratio {ratio:.3f}")
    if ratios:
        print(f"{len(ratios)} of the {args.worst} least circular holes cut; least axis ratio {min(ratios):.3f}")


if __name__ == "__main__":
    main()
