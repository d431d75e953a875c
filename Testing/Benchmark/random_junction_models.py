"""Random models whose regions meet at small angles at one point or cross thinly (Loops form),
for checks on models not seen before.

Run by hand, with Debian's Python (ParaView's VTK modules, shapely):
    /usr/bin/python3 Testing/Benchmark/random_junction_models.py FIRST_SEED LAST_SEED OUT_DIR [--curves]
writes, for each seed in FIRST_SEED..LAST_SEED-1, six models (OUT_DIR/KINDNNN.vtp):
- pie: a disc cut into 3 to 11 sectors at its centre, 40% of them 0.2 to 3 degrees wide;
- fan: 3 to 9 horizons fanning out from one point of a section's base, 0.3 to 3.4 degrees
  apart (that many pinch-outs at one point);
- xfault: 2 to 4 faults crossing at or within 1e-3 of one point, the k-th at k times 0.6 to 17
  degrees to the first, across 1 to 3 wavy horizons;
- dyke: 2 to 5 wavy horizons cut by 1 to 3 straight dykes 10^-3.5 to 10^-1.5 of the width
  wide, tilted up to 34 degrees (a dyke crossing a horizon, or another dyke, makes small
  angles);
- star: a star-shaped body with 3 to 11 spikes in a box;
- comb: a body with 3 to 14 teeth 10^-3 to 10^-1.5 of the width wide in a box.
Each model is scaled by 10^-3 to 10^5, 30% of them moved up to 1e6 units off the origin. The
line work is noded with shapely and polygonized; each face is a region of its own (faces below
1e-9 of the total area are left out: a hole, the exterior). With --curves each model is also
written in the Shared curves form, OUT_DIR/KINDNNN_curves.vtp: the faces' edges chained from
junction to junction (vertices where the number of edges is not 2 or the region pair changes),
on the same vertices. Mesh them with build/bin/triangulate_to_vtu and check them with
meshcheck.py (README, Measured).
"""
import math
import os
import sys

import numpy as np
from shapely.geometry import LineString, Point, Polygon, box
from shapely.geometry.polygon import orient
from shapely.ops import polygonize, unary_union

from random_faulted_sections import polydata  # same folder
from random_sections import write_vtp


def faces_inside(lines, domain):
    """The faces of the noded line work inside `domain`, without those below 1e-9 of the
    total area."""
    faces = [f for f in polygonize(unary_union(lines)) if domain.buffer(1e-9).contains(f)]
    total = sum(f.area for f in faces)
    return [f for f in faces if f.area > 1e-9 * total]


def wavy(x0, x1, y, amp, n, rng):
    """A horizon from x0 to x1 around height y: one sine of amplitude amp, n points."""
    x = np.linspace(x0, x1, n)
    phase = 2 * np.pi * rng.uniform(0.5, 3) * (x - x0) / (x1 - x0) + rng.uniform(0, 6)
    return LineString(np.c_[x, y + amp * np.sin(phase)])


def pie(rng):
    k = int(rng.integers(3, 12))
    gaps = rng.uniform(0.5, 1.0, k)
    thin = rng.random(k) < 0.4
    gaps[thin] = rng.uniform(0.003, 0.05, thin.sum())
    gaps = gaps / gaps.sum() * 2 * math.pi
    disc = Point(0, 0).buffer(1.0, 256)
    lines = [disc.exterior]
    for t in np.cumsum(gaps) + rng.uniform(0, 6):
        lines.append(LineString([(0, 0), (1.2 * math.cos(t), 1.2 * math.sin(t))]))
    return faces_inside(lines, disc)


def fan(rng):
    width, height = 1.0, rng.uniform(0.2, 0.5)
    section = box(0, 0, width, height)
    lines = [section.exterior]
    k = int(rng.integers(3, 10))
    x0 = rng.uniform(0.0, 0.3) * width
    for a in np.cumsum(rng.uniform(0.005, 0.06, k)):
        lines.append(LineString([(x0, 0), (x0 + 3 * math.cos(a), 3 * math.sin(a))]))
    return faces_inside(lines, section)


def xfault(rng):
    width, height = 1.0, rng.uniform(0.3, 0.8)
    section = box(0, 0, width, height)
    lines = [section.exterior]
    cx, cy = rng.uniform(0.3, 0.7) * width, rng.uniform(0.3, 0.7) * height
    base = rng.uniform(0, math.pi)
    for i in range(int(rng.integers(2, 5))):
        a = base + (rng.uniform(0.01, 0.3) if i else 0) * (1 if rng.random() < 0.5 else -1) * i
        ox = 0 if rng.random() < 0.6 else rng.uniform(-1e-3, 1e-3)
        d = np.array([math.cos(a), math.sin(a)]) * 3
        lines.append(LineString([(cx + ox - d[0], cy - d[1]), (cx + ox + d[0], cy + d[1])]))
    for _ in range(int(rng.integers(1, 4))):
        lines.append(wavy(-0.1, width + 0.1, rng.uniform(0.1, 0.9) * height, 0.05 * height, 80,
                          rng))
    return faces_inside(lines, section)


def dyke(rng):
    width, height = 1.0, rng.uniform(0.3, 0.6)
    section = box(0, 0, width, height)
    lines = [section.exterior]
    for j in range(int(rng.integers(2, 6))):
        lines.append(wavy(-0.1, width + 0.1, (j + 1) / 6 * height, height / 60, 100, rng))
    for _ in range(int(rng.integers(1, 4))):
        x = rng.uniform(0.1, 0.9) * width
        w = 10 ** rng.uniform(-3.5, -1.5) * width
        dx = math.tan(rng.uniform(-0.6, 0.6)) * 2 * height
        for off in (0, w):
            lines.append(LineString([(x + off - dx, -height), (x + off + dx, 2 * height)]))
    return faces_inside(lines, section)


def star(rng):
    frame = box(-1.5, -1.5, 1.5, 1.5)
    k = int(rng.integers(3, 12))
    ring = []
    for i in range(k):
        t = 2 * math.pi * i / k + rng.uniform(-0.2, 0.2)
        r = rng.uniform(0.8, 1.4)
        ring.append((0.3 * math.cos(t - math.pi / k), 0.3 * math.sin(t - math.pi / k)))
        ring.append((r * math.cos(t), r * math.sin(t)))
    body = Polygon(ring).buffer(0)
    return faces_inside([frame.exterior, body.exterior], frame)


def comb(rng):
    width, height = 1.0, 0.5
    w = 10 ** rng.uniform(-3, -1.5)
    ring = [(0, 0), (width, 0), (width, 0.2 * height)]
    for x in np.linspace(width * 0.95, width * 0.05, int(rng.integers(3, 15))):
        h = rng.uniform(0.4, 0.95) * height
        ring += [(x + w / 2, 0.2 * height), (x + w / 2, h), (x - w / 2, h),
                 (x - w / 2, 0.2 * height)]
    ring.append((0, 0.2 * height))
    frame = box(0, 0, width, height)
    return faces_inside([frame.exterior, Polygon(ring).buffer(0).exterior], frame)


KINDS = {"pie": pie, "fan": fan, "xfault": xfault, "dyke": dyke, "star": star, "comb": comb}


def shared_curves(loops, ids):
    """The Shared curves form of closed loops (each with its region on its left, the others'
    or the exterior, -1, on its right): chains of edges from junction to junction, each with
    its (left, right) regions."""
    side = {}
    for loop, region in zip(loops, ids):
        for a, b in zip(loop[:-1], loop[1:]):
            side[(a, b)] = region
    edges = {}  # undirected edge -> (start, end, left, right), its left region's direction
    for (a, b), region in side.items():
        if (b, a) in side and side[(b, a)] > region:
            continue  # the twin, with the larger region on its left, is the edge's direction
        edges[frozenset((a, b))] = (a, b, region, side.get((b, a), -1))
    at = {}
    for key, (a, b, _, _) in edges.items():
        at.setdefault(a, []).append(key)
        at.setdefault(b, []).append(key)

    def labels(v, key):
        """The (left, right) regions of an edge walked away from v."""
        a, _, left, right = edges[key]
        return (left, right) if a == v else (right, left)

    junction = {v for v, keys in at.items()
                if len(keys) != 2 or labels(v, keys[0])[::-1] != labels(v, keys[1])}
    used, chains = set(), []

    def walk(v, key):
        chain, pair = [v], labels(v, key)
        while True:
            used.add(key)
            a, b, _, _ = edges[key]
            v = b if a == v else a
            chain.append(v)
            if v in junction or v == chain[0]:
                return chain, pair
            key = next(k for k in at[v] if k != key)

    for v in sorted(junction):
        for key in at[v]:
            if key not in used:
                chains.append(walk(v, key))
    for key in edges:
        if key not in used:  # a closed curve without junctions
            chains.append(walk(edges[key][0], key))
    return chains


def model(kind, seed, path, curves=False):
    """Writes the model of one kind and seed to path (and, with curves, its Shared curves form
    beside it)."""
    rng = np.random.default_rng(seed * 100 + len(kind))
    faces = KINDS[kind](rng)
    scale = 10 ** rng.uniform(-3, 5)
    offset = rng.uniform(-1e6, 1e6, 2) if rng.random() < 0.3 else np.zeros(2)
    loops, ids, oriented = [], [], []
    for i, face in enumerate(faces):
        for ring in [face.exterior] + list(face.interiors):
            loops.append([tuple(p) for p in np.array(ring.coords) * scale + offset])
            ids.append(i)
        for ring in [orient(face).exterior] + list(orient(face).interiors):  # face on the left
            oriented.append([tuple(p) for p in np.array(ring.coords) * scale + offset])
    name = "%s%03d" % (kind, seed)
    source = "random_junction_models.py seed %d: %s, %d regions, scale %.4g, offset (%.6g, %.6g)" % (
        seed, kind, len(faces), scale, offset[0], offset[1])
    write_vtp(path, polydata(loops, [("RegionId", ids)], name, source))
    if curves:
        chains = shared_curves(oriented, ids)
        write_vtp(path.replace(".vtp", "_curves.vtp"), polydata(
            [c for c, _ in chains], [("LeftRegion", [lr[0] for _, lr in chains]),
                                     ("RightRegion", [lr[1] for _, lr in chains])],
            name + "_curves", source + " (Shared curves form)"))


if __name__ == "__main__":
    first, last, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    os.makedirs(out, exist_ok=True)
    for s in range(first, last):
        for kind in KINDS:
            model(kind, s, os.path.join(out, "%s%03d.vtp" % (kind, s)), "--curves" in sys.argv[4:])
