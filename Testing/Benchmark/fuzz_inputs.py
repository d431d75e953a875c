#!/usr/bin/python3
"""Mutation tests of the input contract (Data/bad_inputs/README.md): valid models of Data/ get
one random defect each, the mesher runs on them, and every outcome is classified.

Run by hand, with Debian's Python (ParaView's VTK modules):
    /usr/bin/python3 Testing/Benchmark/fuzz_inputs.py FIRST_SEED LAST_SEED OUT_DIR \
        --tool build/bin/triangulate_to_vtu --meshcheck ../shared/tools/meshcheck.py
For each seed it writes OUT_DIR/fNNNN.vtp (one of MODELS with one mutation: a point or a curve
end moved by 1e-15 to 1 of the model's size, a curve given twice or reversed or deleted, a
region id changed, a repeated point, a spike A B A, a curve collapsed to a point, a non-finite
coordinate, a loop left open, a zigzag, two points swapped, or valid changes: a curve split in
two, a point added on a segment, the whole model scaled by 1e-12 to 1e15 or moved by 1e6 to
1e12) and appends one JSON line to OUT_DIR/log.jsonl: the mutation, the tool's exit code and
error, and for a mesh its warnings and the checker's figures (invalid triangles, area errors,
topology). A crash (a signal), a run over 90 s, or a mesh with invalid triangles is a defect;
so is a mesh the checker finds wrong without a warning that says so.
"""

import argparse
import json
import os
import random
import subprocess
import sys

import vtk

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
MODELS = ["pinch_out.vtp", "thin_layer.vtp", "geology_marmousi.vtp", "faulted_section.vtp",
          "salt_dome.vtp", "countries_westeurope.vtp", "touching_loops.vtp", "nested_holes.vtp",
          "lake_superior.vtp", "salt_dome_loops.vtp", "eleven_sector_pie.vtp",
          "junction_pair_section.vtp", "guitar.vtp"]


def read(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    pts = [pd.GetPoint(i)[:2] for i in range(pd.GetNumberOfPoints())]
    cd = pd.GetCellData()
    loops = cd.GetArray("RegionId") is not None
    cells = []
    lines = pd.GetLines()
    ids = vtk.vtkIdList()
    lines.InitTraversal()
    k = 0
    while lines.GetNextCell(ids):
        chain = [list(pts[ids.GetId(j)]) for j in range(ids.GetNumberOfIds())]
        if loops:
            tags = [int(cd.GetArray("RegionId").GetValue(k))]
        else:
            tags = [int(cd.GetArray("LeftRegion").GetValue(k)),
                    int(cd.GetArray("RightRegion").GetValue(k))]
        cells.append([chain, tags])
        k += 1
    return loops, cells


def write(path, loops, cells):
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    lines = vtk.vtkCellArray()
    arrays = []
    names = ["RegionId"] if loops else ["LeftRegion", "RightRegion"]
    for n in names:
        a = vtk.vtkIntArray()
        a.SetName(n)
        arrays.append(a)
    # shared points: the same coordinates get the same id (as the models have them)
    index = {}
    for chain, tags in cells:
        line = vtk.vtkPolyLine()
        line.GetPointIds().SetNumberOfIds(len(chain))
        for j, p in enumerate(chain):
            key = (p[0], p[1])
            if key not in index or random.random() < 0.02:
                index[key] = pts.InsertNextPoint(p[0], p[1], 0.0)
            line.GetPointIds().SetId(j, index[key])
        lines.InsertNextCell(line)
        for a, t in zip(arrays, tags):
            a.InsertNextValue(t)
    pd = vtk.vtkPolyData()
    pd.SetPoints(pts)
    pd.SetLines(lines)
    for a in arrays:
        pd.GetCellData().AddArray(a)
    w = vtk.vtkXMLPolyDataWriter()
    w.SetFileName(path)
    w.SetInputData(pd)
    w.SetDataModeToAscii()
    w.Write()


def size(cells):
    xs = [p[0] for c in cells for p in c[0]]
    ys = [p[1] for c in cells for p in c[0]]
    return max(max(xs) - min(xs), max(ys) - min(ys)), min(xs), min(ys)


def random_segment(rng, chain):
    """A random segment of chain (at least 2 points): its index and its two ends."""
    j = rng.randrange(len(chain) - 1)
    return j, chain[j], chain[j + 1]


def mutate(rng, loops, cells):
    """One random mutation; returns a description."""
    s, x0, y0 = size(cells)
    c = rng.randrange(len(cells))
    chain, tags = cells[c]
    kind = rng.choice(["move", "move_end", "dup_curve", "reverse", "retag", "delete", "dup_point",
                       "spike", "collapse", "nonfinite", "split", "touch", "scale", "offset",
                       "tiny_curve", "near_point", "open_loop", "zigzag", "swap_points",
                       "two_muts"])
    if kind == "move":
        j = rng.randrange(len(chain))
        mag = s * 10 ** rng.uniform(-14, 0)
        chain[j] = [chain[j][0] + rng.uniform(-1, 1) * mag, chain[j][1] + rng.uniform(-1, 1) * mag]
        return "%s cell %d point %d by %.3g" % (kind, c, j, mag)
    if kind == "move_end":
        j = rng.choice([0, len(chain) - 1])
        mag = s * 10 ** rng.uniform(-15, -2)
        chain[j] = [chain[j][0] + rng.uniform(-1, 1) * mag, chain[j][1] + rng.uniform(-1, 1) * mag]
        return "%s cell %d end %d by %.3g" % (kind, c, j, mag)
    if kind == "dup_curve":
        cells.append([list(map(list, chain)), list(tags)])
        return "%s cell %d" % (kind, c)
    if kind == "reverse":
        chain.reverse()
        return "%s cell %d" % (kind, c)
    if kind == "retag":
        t = rng.randrange(len(tags))
        tags[t] = rng.choice([-1, -2, 0, 1, 2, 99, 2 ** 31 - 1, -(2 ** 31), 1000000])
        return "%s cell %d tag %d -> %d" % (kind, c, t, tags[t])
    if kind == "delete":
        del cells[c]
        return "%s cell %d" % (kind, c)
    if kind == "dup_point":
        j = rng.randrange(len(chain))
        for _ in range(rng.randint(1, 5)):
            chain.insert(j, list(chain[j]))
        return "%s cell %d point %d" % (kind, c, j)
    if kind == "spike":
        if len(chain) < 3:
            return "noop"
        j = rng.randrange(1, len(chain) - 1)
        chain.insert(j + 1, list(chain[j - 1]))
        return "%s cell %d point %d (A B A)" % (kind, c, j)
    if kind == "collapse":
        p = chain[0]
        cells[c][0] = [list(p) for _ in chain]
        return "%s cell %d" % (kind, c)
    if kind == "nonfinite":
        j = rng.randrange(len(chain))
        v = rng.choice([float("nan"), float("inf"), -float("inf"), 1e300, -1e300, 1e-310])
        chain[j][rng.randrange(2)] = v
        return "%s cell %d point %d = %r" % (kind, c, j, v)
    if kind == "split":
        if len(chain) < 3:
            return "noop"
        j = rng.randrange(1, len(chain) - 1)
        cells[c][0] = chain[: j + 1]
        cells.append([list(map(list, chain[j:])), list(tags)])
        return "%s cell %d at %d (valid)" % (kind, c, j)
    if kind == "touch":
        d = rng.randrange(len(cells))
        other = cells[d][0]
        if len(other) < 3 or len(chain) < 3:
            return "noop"
        j = rng.randrange(1, len(chain) - 1)
        k = rng.randrange(len(other) - 1)
        t = rng.random()
        a, b = other[k], other[k + 1]
        chain[j] = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        return "%s cell %d point %d onto cell %d segment %d" % (kind, c, j, d, k)
    if kind == "scale":
        f = 10 ** rng.choice([-12, -9, -6, 6, 9, 12, 15])
        for ch, _ in cells:
            for p in ch:
                p[0] *= f
                p[1] *= f
        return "%s by %g (valid)" % (kind, f)
    if kind == "offset":
        o = 10 ** rng.uniform(6, 12)
        for ch, _ in cells:
            for p in ch:
                p[0] += o
                p[1] -= o
        return "%s by %g (valid)" % (kind, o)
    if kind == "tiny_curve":
        p = chain[rng.randrange(len(chain))]
        e = s * 10 ** rng.uniform(-13, -6)
        new = [list(p), [p[0] + e, p[1] + e * 0.3]]
        cells.append([new, [tags[0]] if loops else [tags[0], tags[-1]]])
        return "%s at cell %d, length %.3g" % (kind, c, e)
    if kind == "near_point":
        if len(chain) < 2:
            return "noop"
        j, a, b = random_segment(rng, chain)
        t = 10 ** rng.uniform(-15, -5)
        chain.insert(j + 1, [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
        return "%s cell %d after %d t=%.3g (valid)" % (kind, c, j, t)
    if kind == "open_loop":
        if len(chain) < 4:
            return "noop"
        cut = rng.randint(1, 3)
        cells[c][0] = chain[:-cut]
        return "%s cell %d drop %d last" % (kind, c, cut)
    if kind == "zigzag":
        if len(chain) < 2:
            return "noop"
        j, a, b = random_segment(rng, chain)
        dx, dy = b[0] - a[0], b[1] - a[1]
        n = rng.randint(3, 40)
        amp = rng.uniform(0.01, 2.0)
        pts = []
        for i in range(1, n):
            t = i / n
            sgn = 1 if i % 2 else -1
            pts.append([a[0] + t * dx - sgn * amp * dy / n, a[1] + t * dy + sgn * amp * dx / n])
        chain[j + 1:j + 1] = pts
        return "%s cell %d seg %d n=%d amp=%.2f" % (kind, c, j, n, amp)
    if kind == "swap_points":
        if len(chain) < 3:
            return "noop"
        j = rng.randrange(len(chain) - 1)
        chain[j], chain[j + 1] = chain[j + 1], chain[j]
        return "%s cell %d %d<->%d" % (kind, c, j, j + 1)
    if kind == "two_muts":
        return mutate(rng, loops, cells) + " + " + mutate(rng, loops, cells)
    return "noop"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("first", type=int)
    parser.add_argument("last", type=int)
    parser.add_argument("out")
    parser.add_argument("--tool", required=True, help="triangulate_to_vtu")
    parser.add_argument("--meshcheck", required=True, help="meshcheck.py")
    args = parser.parse_args()
    first, last, out = args.first, args.last, args.out
    tool, check = os.path.abspath(args.tool), os.path.abspath(args.meshcheck)
    os.makedirs(out, exist_ok=True)
    log = open(os.path.join(out, "log.jsonl"), "a")
    for seed in range(first, last):
        rng = random.Random(seed)
        random.seed(seed)
        name = rng.choice(MODELS)
        loops, cells = read(os.path.join(DATA, name))
        what = mutate(rng, loops, cells)
        if not cells:
            continue
        vtp = os.path.join(out, "f%04d.vtp" % seed)
        vtu = os.path.join(out, "f%04d.vtu" % seed)
        write(vtp, loops, cells)
        rec = {"seed": seed, "model": name, "mutation": what}
        try:
            p = subprocess.run(["bash", "-c", "ulimit -v 6000000; exec %s %s %s" % (tool, vtp, vtu)],
                               capture_output=True, text=True, timeout=90)
            rec["rc"] = p.returncode
            rec["stderr"] = p.stderr[-600:]
            if p.returncode == 0:
                try:
                    j = json.loads(p.stdout)
                    rec["triangles"] = j.get("triangles")
                    rec["min_angle"] = j.get("min_angle")
                    rec["warnings"] = [w[:300] for w in j.get("warnings", [])]
                except Exception as e:  # noqa
                    rec["json_error"] = str(e)
                try:
                    q = subprocess.run(["/usr/bin/python3", check, vtp, vtu], capture_output=True,
                                       text=True, timeout=300)
                    m = json.loads(q.stdout)
                    rec["check"] = {k: m.get(k) for k in ["inverted", "degenerate",
                                                          "nonmanifold_edges", "folded_edges",
                                                          "max_region_area_error_pct",
                                                          "topology_mismatches", "min_angle"]}
                except Exception as e:  # noqa
                    rec["check_error"] = str(e)[:200]
        except subprocess.TimeoutExpired:
            rec["rc"] = "HANG"
        log.write(json.dumps(rec) + "\n")
        log.flush()
        for f in (vtu,):
            if os.path.exists(f) and rec.get("rc") == 0:
                os.remove(f)
        print(seed, name, what[:80], rec.get("rc"), flush=True)


if __name__ == "__main__":
    main()
