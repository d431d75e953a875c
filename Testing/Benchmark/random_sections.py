"""Random layered sections in the Shared curves form, for checks on models not seen before.

Run by hand, with Debian's Python (ParaView's VTK modules):
    /usr/bin/python3 Testing/Benchmark/random_sections.py FIRST_SEED LAST_SEED OUT_DIR
writes OUT_DIR/mNNN.vtp for seeds FIRST_SEED..LAST_SEED-1: 3 to 7 wavy horizons across a box
3 m, 1 km or 25 km wide, 40% of the layers thinned to 1-20% of their thickness (at least
1e-4 of the width), the sides and top closing the regions. Mesh them with
build/bin/triangulate_to_vtu and check them with meshcheck.py (README, Measured).
"""
import os
import sys

import numpy as np
import vtk


def write_vtp(path, poly):
    """Writes poly to path as ASCII VTK XML PolyData (what triangulate_to_vtu reads)."""
    writer = vtk.vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(poly)
    writer.SetDataModeToAscii()
    writer.Write()


def model(seed, path):
    """Writes the section of one seed to path (ASCII VTK XML PolyData)."""
    rng = np.random.default_rng(seed)
    width = rng.choice([1000.0, 25000.0, 3.0])
    height = width * rng.uniform(0.2, 0.6)
    horizons = int(rng.integers(3, 8))
    n = int(rng.integers(20, 200))
    x = np.linspace(0, width, n)
    ys = [np.zeros(n)]
    for _ in range(1, horizons):
        t = height / horizons * rng.uniform(0.3, 1.5)
        thick = t * (1 + 0.9 * np.sin(2 * np.pi * rng.uniform(0.5, 4) * x / width
                                      + rng.uniform(0, 6)))
        if rng.random() < 0.4:  # a thin layer
            thick = np.maximum(thick * rng.uniform(0.01, 0.2), width * 1e-4)
        ys.append(ys[-1] + np.maximum(thick, width * 1e-4) + rng.normal(0, t * 0.01, n).clip(0))
    ys.append(np.full(n, max(ys[-1].max() * 1.1, height)))

    pts = vtk.vtkPoints()
    lines = vtk.vtkCellArray()
    left = vtk.vtkIntArray()
    left.SetName("LeftRegion")
    right = vtk.vtkIntArray()
    right.SetName("RightRegion")
    ids = [[pts.InsertNextPoint(xi, yi, 0.0) for xi, yi in zip(x, y)] for y in ys]

    def add(chain, left_region, right_region):
        line = vtk.vtkPolyLine()
        line.GetPointIds().SetNumberOfIds(len(chain))
        for k, c in enumerate(chain):
            line.GetPointIds().SetId(k, c)
        lines.InsertNextCell(line)
        left.InsertNextValue(left_region)
        right.InsertNextValue(right_region)

    regions = len(ys) - 1  # region i lies between horizons i and i + 1
    for i, row in enumerate(ids):
        add(row, i if i < regions else -1, i - 1 if i > 0 else -1)
    for i in range(regions):
        add([ids[i + 1][0], ids[i][0]], i, -1)  # left side, downward
        add([ids[i][-1], ids[i + 1][-1]], i, -1)  # right side, upward
    poly = vtk.vtkPolyData()
    poly.SetPoints(pts)
    poly.SetLines(lines)
    poly.GetCellData().AddArray(left)
    poly.GetCellData().AddArray(right)
    write_vtp(path, poly)


if __name__ == "__main__":
    os.makedirs(sys.argv[3], exist_ok=True)
    for s in range(int(sys.argv[1]), int(sys.argv[2])):
        model(s, os.path.join(sys.argv[3], "m%03d.vtp" % s))
