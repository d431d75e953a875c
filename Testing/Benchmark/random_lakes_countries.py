"""Random lakes with islands and random country partitions (Loops form), for checks on models
not seen before.

Run by hand, with Debian's Python (ParaView's VTK modules, shapely, scipy):
    /usr/bin/python3 Testing/Benchmark/random_lakes_countries.py FIRST_SEED LAST_SEED OUT_DIR
writes, for each seed in FIRST_SEED..LAST_SEED-1 and a size of 1 to 1e5 model units:
- OUT_DIR/lakeNNN.vtp: a lake (region 0) whose shore is a circle with 1500 points whose
  radius carries random harmonics 2-11; 10 to 39 islands inside it, 1e-3.5 to 1e-0.8 times
  its size, made the same way with 60 points (holes by the even-odd rule);
- OUT_DIR/countriesNNN.vtp: 15 to 39 countries, the Voronoi cells of random seeds cut by such
  a coast, each part of a cell one loop with its cell's id (triple junctions where three cells
  meet; tiny parts where a cell's cut leaves slivers).
Mesh them with build/bin/triangulate_to_vtu and check them with meshcheck.py (README,
Measured).
"""
import os
import sys

import numpy as np
import vtk
from scipy.spatial import Voronoi
from shapely.geometry import Point, Polygon

from random_sections import write_vtp  # same folder


def noisy_ring(cx, cy, r, n, rough, rng):
    """A closed curve around (cx, cy): radius r times 1 + random harmonics 2-11."""
    th = np.sort(rng.uniform(0, 2 * np.pi, n))
    rr = np.ones(n)
    for k in range(2, 12):
        rr += rough * rng.normal() / k * np.cos(k * th + rng.uniform(0, 2 * np.pi))
    rr = np.clip(rr, 0.3, 2.0) * r
    p = Polygon(np.c_[cx + rr * np.cos(th), cy + rr * np.sin(th)]).buffer(0)
    return p if p.geom_type == "Polygon" else max(p.geoms, key=lambda g: g.area)


def write(path, loops, ids):
    """ASCII VTK XML PolyData, one closed polyline per loop, cell array RegionId."""
    pd = vtk.vtkPolyData()
    points = vtk.vtkPoints()
    points.SetDataTypeToDouble()
    lines = vtk.vtkCellArray()
    for loop in loops:
        lines.InsertNextCell(len(loop))
        for x, y in loop:
            lines.InsertCellPoint(points.InsertNextPoint(x, y, 0.0))
    pd.SetPoints(points)
    pd.SetLines(lines)
    region = vtk.vtkIntArray()
    region.SetName("RegionId")
    for i in ids:
        region.InsertNextValue(int(i))
    pd.GetCellData().AddArray(region)
    write_vtp(path, pd)


def lake(seed, path):
    rng = np.random.default_rng(seed)
    size = 10 ** rng.uniform(0, 5)
    shore = noisy_ring(0, 0, size, 1500, 1.2, rng)
    loops = [np.array(shore.exterior.coords)]
    islands = []
    for _ in range(rng.integers(10, 40)):
        for _attempt in range(20):
            c = Point(rng.uniform(*shore.bounds[0::2]), rng.uniform(*shore.bounds[1::2]))
            r = size * 10 ** rng.uniform(-3.5, -0.8)
            island = noisy_ring(c.x, c.y, r, 60, 0.5, rng)
            if shore.buffer(-r * 0.05).contains(island) and all(
                island.distance(o) > r * 0.02 for o in islands
            ):
                islands.append(island)
                loops.append(np.array(island.exterior.coords))
                break
    write(path, loops, [0] * len(loops))


def countries(seed, path):
    rng = np.random.default_rng(seed)
    size = 10 ** rng.uniform(0, 5)
    coast = noisy_ring(0, 0, size, 1500, 1.0, rng)
    n = int(rng.integers(15, 40))
    seeds = np.c_[rng.uniform(*coast.bounds[0::2], n), rng.uniform(*coast.bounds[1::2], n)]
    far = 20 * size  # four far seeds bound every cell of the real ones
    vor = Voronoi(np.vstack([seeds, [[far, far], [-far, far], [far, -far], [-far, -far]]]))
    loops, ids = [], []
    for i in range(n):
        cell = Polygon(vor.vertices[vor.regions[vor.point_region[i]]]).intersection(coast)
        for part in getattr(cell, "geoms", [cell]):
            if part.geom_type == "Polygon" and part.area > 1e-6 * coast.area:
                loops.append(np.array(part.exterior.coords))
                ids.append(i)
    write(path, loops, ids)


if __name__ == "__main__":
    first, last, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    os.makedirs(out, exist_ok=True)
    for s in range(first, last):
        lake(s, os.path.join(out, "lake%03d.vtp" % s))
        countries(s, os.path.join(out, "countries%03d.vtp" % s))
