"""Quality table of StrataMesh on the bundled models, checked by the independent mesh checker.

Run by hand (not part of ctest), with Debian's Python:
    /usr/bin/python3 Testing/Benchmark/quality_table.py --tool build/bin/triangulate_to_vtu \
        --meshcheck ../shared/tools/meshcheck.py [--out /tmp/quality] [--tool-args "--no-curve-recovery"]
For every model it meshes with the default settings (automatic levels) and, for the paper's
three models, at the MaxLevel whose triangle count is nearest the paper's; then prints a
Markdown table of what meshcheck.py recomputes from the geometry alone, plus one figure of
its own: the boundary deviation over the *local* edge length (issue 4's "at most one local
edge length", issue 5's "within half the local edge length ... both ways"): points every
eighth of a mesh boundary edge and every half of the finest edge length along the input
curves (the tool's `finest_edge_length`), each one's exact distance to the other side's
segments divided by the local edge length there: the mean edge length of the (one or two)
mesh triangles beside the mesh boundary edge that realizes the distance (the edge a mesh
sample lies on; the boundary edge nearest a curve sample), the mesher's own definition
(`MaxRelativeBoundaryDeviation`).
It is given twice: over all points, and without the points inside a region narrower than
the finest edge length (issue 5's exemption; `--exempt-width` scales that width): the curve
points beside such a region, and the mesh points whose nearest curve point is beside one.
Beside it, on either side of the curve: another curve within that width along the curve's
normal, or the disc of that diameter touching the point, shrunk by 10%, cut by a curve (see
narrow()).
With `--models FILE_OR_DIR ...` it meshes those models instead (every .vtp of a folder, e.g.
the output of random_faulted_sections.py), one row each (a failed run or check is a row with
its error), and prints the counts issue 5 asks about under the table, with issue 4's count
of meshes whose boundary vertices all lie on the curves (within 1e-9 of the model's size).
"""
import argparse
import importlib.util
import json
import os
import subprocess
import time

import numpy as np
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "Data")
MODELS = ["lake_superior", "lake_superior_full", "salt_dome", "salt_dome_loops", "gulf_section",
          "gulf_section_loops", "countries_westeurope", "countries_westeurope_loops",
          "geology_marmousi", "guitar", "pinch_out", "thin_layer", "nested_holes",
          "touching_loops", "faulted_section", "faulted_thin_layers"]
# The paper's figures: (MaxLevel giving a similar count, paper triangles, paper min angle).
PAPER = {"lake_superior": (1906, 11.5), "salt_dome": (6183, 10.4),
         "gulf_section": (11015, 5.25)}
LEVELS = range(5, 14)  # MaxLevel values tried for the paper's counts


def nearest_level(args, name):
    """The MaxLevel (of LEVELS) whose triangle count, with the tool's options, is nearest the
    paper's."""
    model = os.path.join(DATA, name + ".vtp")
    counts = {}
    for level in LEVELS:
        out = subprocess.run([args.tool, model, os.path.join(args.out, "probe.vtu"),
                              "--max-level", str(level)] + args.tool_args.split(),
                             check=True, capture_output=True, text=True).stdout
        counts[level] = json.loads(out)["triangles"]
    return min(counts, key=lambda level: abs(counts[level] - PAPER[name][0]))


def run(args, name, extra, model=None):
    model = model or os.path.join(DATA, name + ".vtp")
    options = extra + args.tool_args.split()
    tag = name + ("_L%s" % extra[1] if extra else "")
    vtu = os.path.join(args.out, tag + ".vtu")
    start = time.perf_counter()
    tool_out = subprocess.run([args.tool, model, vtu] + options, check=True,
                              capture_output=True, text=True).stdout
    seconds = time.perf_counter() - start
    out = subprocess.run(["/usr/bin/python3", args.meshcheck, model, vtu,
                          "--json", os.path.join(args.out, tag + ".json")],
                         check=True, capture_output=True, text=True).stdout
    m = json.loads(out[out.index("{"):])
    finest = json.loads(tool_out)["finest_edge_length"]
    m["deviation_over_local_edge"], m["deviation_not_exempt"], m["vertex_off_curves"] = \
        local_deviation(args.checker, model, vtu, finest, args.exempt_width)
    return tag, m, seconds


def sample_with_owner(P, Q, step):
    """Points along the segments PQ at most `step` apart, and the segment of each."""
    n = np.maximum(1, np.ceil(np.linalg.norm(Q - P, axis=1) / step).astype(int))
    owner = np.repeat(np.arange(len(P)), n + 1)
    t = np.concatenate([np.linspace(0.0, 1.0, k + 1) for k in n])[:, None]
    return P[owner] + t * (Q[owner] - P[owner]), owner


def exact_distances(points, A, B, step, todo):
    """Distances from `points` to the nearest of the segments AB, and that segment's index:
    within step / 2 for all points (through samples `step` apart), exact for the points where
    `todo(distance, segment)` is true (the segments with a sample within the approximate
    distance + step / 2 hold the nearest)."""
    samples, owner = sample_with_owner(A, B, step)
    tree = cKDTree(samples)
    d, k = tree.query(points)
    seg = owner[k]
    for i in np.nonzero(todo(d, seg))[0]:
        segs = np.unique(owner[tree.query_ball_point(points[i], d[i] + 0.5 * step * 1.001)])
        a, ab = A[segs], B[segs] - A[segs]
        t = np.clip(((points[i] - a) * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-300), 0, 1)
        dist = np.linalg.norm(a + t[:, None] * ab - points[i], axis=1)
        j = int(np.argmin(dist))
        if dist[j] <= d[i]:
            d[i], seg[i] = float(dist[j]), segs[j]
    return d, seg


NARROW_MARGIN = 0.1  # as the mesher's kNarrowMargin


def segment_distances(x, P, Q):
    """Distances from the point x to every segment PQ."""
    pq = Q - P
    t = np.clip(((x - P) * pq).sum(1) / np.maximum((pq * pq).sum(1), 1e-300), 0, 1)
    return np.linalg.norm(P + t[:, None] * pq - x, axis=1)


def narrow(x, seg, P, Q, width):
    """Whether a curve point x on segment `seg` bounds a region narrower than `width` there,
    on either side (the mesher's definition): along the segment's normal another curve
    within `width` (a layer across), or the disc of diameter `width` touching x on that side,
    shrunk by NARROW_MARGIN, cut by a curve (a thin region's end, a corner sharper than about
    155 degrees). At a segment's end (a corner's apex) it is measured a hair inside the
    segment: 1e-4 of its way to the segment's middle, at most 0.5% of `width` (1e-4 of a
    long segment is many finest edges: beside a wedge's tip on a section's side 660 long, the
    point tested lay 0.033 farther along, where the wedge is wider than the finest edge; much
    less is too little: at a 1.6-degree spike's apex the ray then meets the spike's other
    side nearer than the self-hit margin below)."""
    length = float(np.linalg.norm(Q[seg] - P[seg]))
    x = x + 1e-4 * min(1.0, 100.0 * width / max(length, 1e-300)) * (0.5 * (P[seg] + Q[seg]) - x)
    scale = 1.0 + np.abs(x).max()
    # The segment itself, and its twin in the other region's ring (the Loops form).
    same = (np.all(P == P[seg], axis=1) & np.all(Q == Q[seg], axis=1)) | \
        (np.all(P == Q[seg], axis=1) & np.all(Q == P[seg], axis=1))
    u = Q[seg] - P[seg]
    u = u / max(np.linalg.norm(u), 1e-300)
    for n in (np.array([-u[1], u[0]]), np.array([u[1], -u[0]])):
        if segment_distances(x + 0.5 * width * n, P, Q).min() < (1 - NARROW_MARGIN) * 0.5 * width:
            return True
        # x + s n = P + r (Q - P): solve for s > 0, r in [0, 1] over all segments.
        e = Q - P
        den = n[0] * e[:, 1] - n[1] * e[:, 0]
        w = P - x
        ok = np.abs(den) > 1e-300
        s = np.where(ok, (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / np.where(ok, den, 1), np.inf)
        r = np.where(ok, (w[:, 0] * n[1] - w[:, 1] * n[0]) / np.where(ok, den, 1), -1)
        hit = ok & (r >= 0) & (r <= 1) & (s > 1e-9 * scale)
        hit[same] = False
        if hit.any() and float(s[hit].min()) < width:
            return True
    return False


def local_deviation(mc, model_path, mesh_path, finest, exempt_width=1.0):
    """Largest two-way boundary distance over the local edge length (see the module doc):
    (over all samples, over those not exempt), and the largest distance of a vertex of the
    mesh's boundary to the curves over the model's size (issue 4: at most 1e-9). A curve
    sample is exempt when a region beside it is narrower than `finest` (the tool's finest
    edge length) there (narrow()), a mesh sample when a region beside its nearest curve point
    is: issue 5's
    "except inside a region narrower than the finest edge length" (`exempt_width` finest
    edges: 1 for the issue's bound)."""
    model = mc.read(model_path)
    pts, tris, reg, _ = mc.mesh_arrays(mc.read(mesh_path), "RegionId")
    e, key, owner = mc.edges_of(tris)
    faces = {}
    for i, k in enumerate(map(tuple, key)):
        faces.setdefault(k, []).append(owner[i])
    bedges = np.array([k for k, f in faces.items() if len(f) == 1 or reg[f[0]] != reg[f[1]]])
    if len(bedges) == 0:
        return float("nan"), float("nan"), float("nan")
    curves = mc.model_curves(model)
    P = np.concatenate([c[:-1] for c in curves if len(c) > 1])
    Q = np.concatenate([c[1:] for c in curves if len(c) > 1])
    keep = np.linalg.norm(Q - P, axis=1) > 0
    P, Q = P[keep], Q[keep]
    A, B = pts[bedges[:, 0]], pts[bedges[:, 1]]
    tri_pts = pts[tris]
    tri_edge = np.mean([np.linalg.norm(tri_pts[:, i] - tri_pts[:, (i + 1) % 3], axis=1)
                        for i in range(3)], axis=0)
    # The local edge of each boundary edge: the mean of its (one or two) triangles'.
    local = np.array([np.mean(tri_edge[faces[tuple(k)]]) for k in bedges])
    step = 0.5 * finest
    # The boundary's vertices: exact distances for those near the curves.
    vertices = pts[np.unique(bedges.ravel())]
    size = float(np.ptp(np.concatenate([P, Q]), axis=0).max())
    off, _ = exact_distances(vertices, P, Q, 0.5 * step, lambda approx, e: approx < step)
    vertex_off = float(off.max()) / size
    # Mesh -> curves: eight samples per boundary edge; curves -> mesh: every half finest edge.
    s_mesh = (A[:, None, :] + np.linspace(0, 1, 9)[None, :, None] * (B - A)[:, None, :]).reshape(-1, 2)
    s_in, s_seg = sample_with_owner(P, Q, step)
    worst, worst_kept = 0.0, 0.0
    h_mesh = np.repeat(local, 9)
    for samples, (a, b), curve in ((s_mesh, (P, Q), False), (s_in, (A, B), True)):
        if curve:
            # Exact from a quarter of the sampled nearest edge's local edge on (the exact
            # nearest edge's may differ: this leaves room for one up to twice smaller).
            d, nearest = exact_distances(samples, a, b, 0.5 * step,
                                         lambda approx, e: approx > 0.25 * local[e])
            h = local[nearest]
        else:
            h = h_mesh
            d, nearest = exact_distances(samples, a, b, 0.5 * step, lambda approx, e: approx > 0.4 * h)
        ratio = d / h
        worst = max(worst, float(ratio.max()))
        exempt = np.zeros(len(samples), dtype=bool)
        for i in np.nonzero(ratio > 0.5)[0]:
            if curve:
                exempt[i] = narrow(samples[i], s_seg[i], P, Q, exempt_width * finest)
            else:
                # A mesh sample whose nearest curve point is beside a narrow region.
                s, pq = nearest[i], Q[nearest[i]] - P[nearest[i]]
                t = np.clip(np.dot(samples[i] - P[s], pq) / max(np.dot(pq, pq), 1e-300), 0, 1)
                exempt[i] = narrow(P[s] + t * pq, s, P, Q, exempt_width * finest)
        worst_kept = max(worst_kept, float(ratio[~exempt].max()))
    return worst, worst_kept, vertex_off


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshcheck", required=True)
    ap.add_argument("--out", default="/tmp/stratamesh_quality")
    ap.add_argument("--tool-args", default="",
                    help="extra options for the tool on every run, e.g. \"--no-curve-recovery\"")
    ap.add_argument("--models", nargs="+", default=None,
                    help="mesh these .vtp files (or every .vtp of these folders) instead")
    ap.add_argument("--exempt-width", type=float, default=1.0,
                    help="curve points inside a region narrower than this many finest edge"
                         " lengths are exempt from the deviation bound (issue 5: 1)")
    args = ap.parse_args()
    spec = importlib.util.spec_from_file_location("meshcheck", args.meshcheck)
    args.checker = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(args.checker)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    if args.models:
        paths = []
        for p in args.models:
            paths += sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith(".vtp")) \
                if os.path.isdir(p) else [p]
        for path in paths:
            name = os.path.basename(path)[:-4]
            try:
                rows.append(run(args, name, [], path))
            except subprocess.CalledProcessError as e:
                rows.append((name, (e.stderr or b"").decode(errors="replace").strip()[-300:]
                             or "exit code %d" % e.returncode, 0.0))
    else:
        for name in MODELS:
            rows.append(run(args, name, []))
            if name in PAPER:
                rows.append(run(args, name, ["--max-level", str(nearest_level(args, name))]))
    exempt = "the finest edge" if args.exempt_width == 1.0 else \
        "%g finest edges" % args.exempt_width
    print("| model | triangles | min angle | max angle | %% triangles min angle >= 30 |"
          " boundary Hausdorff / h | deviation / local edge (all; outside regions narrower"
          " than %s) | worst region area error | topology mismatches | seconds |"
          % exempt)
    print("|---|---|---|---|---|---|---|---|---|---|")
    for tag, m, seconds in rows:
        if isinstance(m, str):
            print("| %s | failed: %s |  |  |  |  |  |  |  |  |" % (tag, m.replace("|", "/")))
            continue
        print("| %s | %d | %.2f | %.1f | %.1f | %.2f | %.2f; %.2f | %.2f%% | %d | %.2f |"
              % (tag, m["triangles"], m["min_angle"], m["max_angle"],
                 m["pct_tris_minangle_ge_30"], m["hausdorff_over_h"],
                 m["deviation_over_local_edge"], m["deviation_not_exempt"],
                 m["max_region_area_error_pct"], m["topology_mismatches"], seconds))
    if args.models:
        ok = [m for _, m, _ in rows if not isinstance(m, str)]
        invalid = sum(m["inverted"] + m["degenerate"] + m["folded_edges"] +
                      m["nonmanifold_edges"] for m in ok)
        angles = sorted(m["min_angle"] for m in ok)
        print("\n%d models, %d failed; min angle >= 25: %d, >= 30: %d (smallest %.2f, median %.2f);"
              " max angle <= 130: %d; area error <= 0.5%%: %d (median %.3f%%, largest %.3f%%);"
              " topology mismatches %d; invalid triangles %d; deviation <= 0.5 local edge"
              " outside regions narrower than %s: %d (largest %.2f); boundary vertices on the"
              " curves (within 1e-9 of the model's size): %d (largest %.2g of the size)"
              % (len(rows), len(rows) - len(ok), sum(a >= 25 for a in angles),
                 sum(a >= 30 for a in angles), angles[0] if angles else float("nan"),
                 float(np.median(angles)) if angles else float("nan"),
                 sum(m["max_angle"] <= 130 for m in ok),
                 sum(m["max_region_area_error_pct"] <= 0.5 for m in ok),
                 float(np.median([m["max_region_area_error_pct"] for m in ok])) if ok else 0.0,
                 max([m["max_region_area_error_pct"] for m in ok] or [0.0]),
                 sum(m["topology_mismatches"] for m in ok), invalid, exempt,
                 sum(m["deviation_not_exempt"] <= 0.5 for m in ok),
                 max([m["deviation_not_exempt"] for m in ok] or [0.0]),
                 sum(m["vertex_off_curves"] <= 1e-9 for m in ok),
                 max([m["vertex_off_curves"] for m in ok] or [0.0])))


if __name__ == "__main__":
    main()
