"""StrataMesh against Gmsh (Frontal-Delaunay and Delaunay) at matched triangle counts.

A benchmark run by hand, not part of ctest or CI. It needs Debian's Gmsh Python API:
    apt-get install -y python3-gmsh        # Debian 12: gmsh 4.8.4
and is run with Debian's Python (VTK, shapely and gmsh come from Debian packages):
    /usr/bin/python3 Testing/Benchmark/compare_gmsh.py --tool build/bin/triangulate_to_vtu \
        --meshcheck ../shared/tools/meshcheck.py [--out /tmp/stratamesh_vs_gmsh] [--timeout 120]

For every model it meshes with StrataMesh (default settings, automatic levels), reads the
triangle count, then rebuilds the model in Gmsh (geo kernel: the model's curves are noded and
polygonized into faces; each face gets the region on its side of the curves; points and lines
are shared between faces; one plane surface per face, holes as extra curve loops; one
physical group per region, tagged with the RegionId) and meshes it with Mesh.Algorithm 6
(Frontal-Delaunay) and 5 (Delaunay) at a uniform target size h, adjusted until Gmsh's triangle
count is within 10% of StrataMesh's. All three meshes go through the independent checker
meshcheck.py. Each Gmsh run is a subprocess with a time limit; a failure becomes a table row.

Seconds: StrataMesh's is the whole triangulate_to_vtu run (read .vtp, mesh, write ASCII .vtu);
Gmsh's is reading the model, building the geometry and the final generate(2), without the
size calibration runs and without writing the mesh. Gmsh runs on one thread.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time
from collections import defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "Data")
MODELS = ["lake_superior", "salt_dome", "gulf_section", "pinch_out", "thin_layer",
          "countries_westeurope", "geology_marmousi", "nested_holes"]
ALGORITHMS = [(6, "Gmsh Frontal-Delaunay"), (5, "Gmsh Delaunay")]
TOLERANCE = 0.10


# ---------------------------------------------------------------- model -> faces with regions

def read_model(path):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    from vtkmodules.util import numpy_support as nps
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    pts = nps.vtk_to_numpy(pd.GetPoints().GetData())[:, :2].astype(float)
    lines = pd.GetLines()
    conn = nps.vtk_to_numpy(lines.GetConnectivityArray())
    offs = nps.vtk_to_numpy(lines.GetOffsetsArray())
    curves = [pts[conn[offs[i]:offs[i + 1]]] for i in range(len(offs) - 1)]
    cd = pd.GetCellData()
    if cd.GetArray("RegionId") is not None:
        return "loops", curves, [int(v) for v in nps.vtk_to_numpy(cd.GetArray("RegionId"))]
    left = nps.vtk_to_numpy(cd.GetArray("LeftRegion"))
    right = nps.vtk_to_numpy(cd.GetArray("RightRegion"))
    return "shared", curves, [(int(a), int(b)) for a, b in zip(left, right)]


def model_faces(path):
    """[(shapely Polygon, region id)] partitioning the model's regions (exterior dropped)."""
    import numpy as np
    from shapely.geometry import LineString, MultiLineString, Point, Polygon
    from shapely.ops import unary_union, polygonize
    from shapely.strtree import STRtree
    form, curves, labels = read_model(path)
    segs = []
    for c, lab in zip(curves, labels):
        if form == "loops" and len(c) > 2 and np.any(c[0] != c[-1]):
            c = np.vstack([c, c[:1]])
        for a, b in zip(c[:-1], c[1:]):
            if np.any(a != b):
                segs.append((tuple(a), tuple(b), lab))
    noded = unary_union(MultiLineString([[a, b] for a, b, _ in segs]))
    faces = list(polygonize(noded))
    out = []
    if form == "loops":
        loops = defaultdict(list)
        for c, r in zip(curves, labels):
            if len(c) >= 3:
                loops[r].append(Polygon(c))
        for f in faces:
            p = f.representative_point()
            inside = [r for r, ls in loops.items() if sum(l.contains(p) for l in ls) % 2 == 1]
            if inside:
                # Overlapping regions: the one with the smallest loops (innermost) wins.
                out.append((f, min(inside, key=lambda r: min(l.area for l in loops[r]
                                                             if l.contains(p)))))
        return out
    lines = [LineString([a, b]) for a, b, _ in segs]
    tree = STRtree(lines)
    index = {id(l): k for k, l in enumerate(lines)}
    for f in faces:
        ring = list(f.exterior.coords)
        edges = sorted(zip(ring[:-1], ring[1:]),
                       key=lambda e: -math.hypot(e[1][0] - e[0][0], e[1][1] - e[0][1]))[:5]
        votes = defaultdict(int)
        for (x0, y0), (x1, y1) in edges:
            mx, my = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            el = math.hypot(x1 - x0, y1 - y0)
            m = Point(mx, my)
            for i in tree.query(m.buffer(1e-9 * max(1.0, el))):
                i = index[id(i)] if hasattr(i, "coords") else int(i)
                (ax, ay), (bx, by), (lab_left, lab_right) = segs[i]
                if lines[i].distance(m) > 1e-7 * max(1.0, el):
                    continue
                sl = math.hypot(bx - ax, by - ay)
                eps = 1e-4 * el
                probe = Point(mx - eps * (by - ay) / sl, my + eps * (bx - ax) / sl)
                votes[lab_left if f.contains(probe) else lab_right] += 1
        if votes:
            lab = max(votes.items(), key=lambda kv: kv[1])[0]
            if lab >= 0:
                out.append((f, lab))
    return out


# ---------------------------------------------------------------- Gmsh worker (subprocess)

def gmsh_worker(model, vtu, algorithm, target):
    import gmsh
    t0 = time.perf_counter()
    faces = model_faces(model)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.model.add("m")
    geo = gmsh.model.geo
    points, lines = {}, {}

    def point(xy):
        if xy not in points:
            points[xy] = geo.addPoint(xy[0], xy[1], 0.0)
        return points[xy]

    def loop(coords):
        coords = list(coords)[:-1]
        tags = []
        for i in range(len(coords)):
            a, b = point(coords[i]), point(coords[(i + 1) % len(coords)])
            key = (min(a, b), max(a, b))
            if key not in lines:
                lines[key] = geo.addLine(key[0], key[1])
            tags.append(lines[key] if a == key[0] else -lines[key])
        return geo.addCurveLoop(tags)

    by_region = defaultdict(list)
    area = 0.0
    for f, r in faces:
        rings = [loop(f.exterior.coords)] + [loop(h.coords) for h in f.interiors]
        by_region[r].append(geo.addPlaneSurface(rings))
        area += f.area
    geo.synchronize()
    for r, surfs in by_region.items():
        gmsh.model.addPhysicalGroup(2, surfs, r + 1)   # tags must be > 0: RegionId + 1
    build = time.perf_counter() - t0
    for name, v in [("Mesh.Algorithm", algorithm), ("Mesh.MeshSizeFromPoints", 0),
                    ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.MeshSizeExtendFromBoundary", 0),
                    ("Mesh.MeshSizeMin", 0.0)]:
        gmsh.option.setNumber(name, v)
    h = math.sqrt(4.0 * area / (math.sqrt(3.0) * target))
    best = None
    for _ in range(10):
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.mesh.clear()
        t1 = time.perf_counter()
        gmsh.model.mesh.generate(2)
        seconds = build + time.perf_counter() - t1
        count = sum(len(gmsh.model.mesh.getElements(2, s)[1][0]) if
                    len(gmsh.model.mesh.getElements(2, s)[1]) else 0
                    for surfs in by_region.values() for s in surfs)
        if best is None or abs(count - target) < abs(best[1] - target):
            best = (h, count, seconds)
        if abs(count - target) <= TOLERANCE * target:
            break
        # A uniform size: count ~ 1/h^2 away from the fixed boundary nodes.
        h *= min(2.0, max(0.5, math.sqrt(count / float(target)) ** 1.1))
    if best[0] != h:
        h, _, _ = best
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.mesh.clear()
        t1 = time.perf_counter()
        gmsh.model.mesh.generate(2)
        best = (h, best[1], build + time.perf_counter() - t1)
    empty = [s for surfs in by_region.values() for s in surfs
             if not len(gmsh.model.mesh.getElements(2, s)[1])]
    write_vtu(gmsh, by_region, vtu)
    gmsh.finalize()
    res = {"h": best[0], "triangles": best[1], "seconds": best[2], "surfaces": len(faces),
           "empty_surfaces": len(empty)}
    print(json.dumps(res))


def write_vtu(gmsh, by_region, path):
    import numpy as np
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid, vtkCellArray, VTK_TRIANGLE
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    from vtkmodules.util import numpy_support as nps
    tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords).reshape(-1, 3)
    index = {int(t): i for i, t in enumerate(tags)}
    tris, regs = [], []
    for r, surfs in by_region.items():
        for s in surfs:
            types, _, nodes = gmsh.model.mesh.getElements(2, s)
            for t, n in zip(types, nodes):
                if t == 2:
                    n = np.asarray(n).reshape(-1, 3)
                    tris.append(n)
                    regs.append(np.full(len(n), r))
    tris = np.vstack(tris) if tris else np.zeros((0, 3), int)
    regs = np.concatenate(regs) if regs else np.zeros(0, int)
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(nps.numpy_to_vtk(coords.copy(), deep=1))
    ug.SetPoints(p)
    conn = np.vectorize(index.get)(tris).astype(np.int64) if len(tris) else tris
    cells = vtkCellArray()
    cells.SetData(nps.numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64),
                                               deep=1),
                  nps.numpy_to_vtkIdTypeArray(conn.ravel().astype(np.int64), deep=1))
    ug.SetCells(VTK_TRIANGLE, cells)
    arr = nps.numpy_to_vtk(regs.astype(np.int32), deep=1, array_type=6)  # VTK_INT
    arr.SetName("RegionId")
    ug.GetCellData().AddArray(arr)
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(ug)
    w.Write()


# ---------------------------------------------------------------- driver

def meshcheck(args, model, vtu, tag):
    out = subprocess.run(["/usr/bin/python3", args.meshcheck, model, vtu,
                          "--json", os.path.join(args.out, tag + ".json")],
                         check=True, capture_output=True, text=True, timeout=1800).stdout
    return json.loads(out[out.index("{"):])


def row(name, mesher, m, seconds):
    return ("| %s | %s | %d | %.2f | %.1f | %.2f | %.2f%% | %.2f |"
            % (name, mesher, m["triangles"], m["min_angle"], m["pct_tris_minangle_ge_30"],
               m["hausdorff_over_h"], m["max_region_area_error_pct"], seconds))


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        gmsh_worker(sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]))
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshcheck", required=True)
    ap.add_argument("--out", default="/tmp/stratamesh_vs_gmsh")
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per Gmsh run")
    ap.add_argument("--models", nargs="*", default=MODELS)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in args.models:
        model = os.path.join(DATA, name + ".vtp")
        vtu = os.path.join(args.out, name + "_stratamesh.vtu")
        start = time.perf_counter()
        subprocess.run([args.tool, model, vtu], check=True, capture_output=True)
        seconds = time.perf_counter() - start
        m = meshcheck(args, model, vtu, name + "_stratamesh")
        rows.append(row(name, "StrataMesh", m, seconds))
        print(rows[-1], file=sys.stderr, flush=True)
        target = m["triangles"]
        for algorithm, mesher in ALGORITHMS:
            tag = "%s_gmsh%d" % (name, algorithm)
            gvtu = os.path.join(args.out, tag + ".vtu")
            try:
                p = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", model,
                                    gvtu, str(algorithm), str(target)],
                                   capture_output=True, text=True, timeout=args.timeout)
                if p.returncode != 0:
                    last = (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]
                    raise RuntimeError(last[:120])
                g = json.loads(p.stdout.strip().splitlines()[-1])
                if g["empty_surfaces"]:
                    raise RuntimeError("%d of %d surfaces not meshed"
                                       % (g["empty_surfaces"], g["surfaces"]))
                if abs(g["triangles"] - target) > 0.15 * target:
                    raise RuntimeError("no size within 15%% of %d triangles (closest %d)"
                                       % (target, g["triangles"]))
                rows.append(row(name, mesher, meshcheck(args, model, gvtu, tag), g["seconds"]))
            except subprocess.TimeoutExpired:
                rows.append("| %s | %s | failed: no mesh within %.0f s | | | | | |"
                            % (name, mesher, args.timeout))
            except Exception as e:  # noqa: BLE001 - a failure is a result here
                rows.append("| %s | %s | failed: %s | | | | | |"
                            % (name, mesher, str(e).replace("|", "/")))
            print(rows[-1], file=sys.stderr, flush=True)
    print("| model | mesher | triangles | min angle | % triangles min angle >= 30 |"
          " boundary Hausdorff / h | worst region area error | seconds |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
