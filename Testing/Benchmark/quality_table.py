"""Quality table of StrataMesh on the bundled models, checked by the independent mesh checker.

Run by hand (not part of ctest), with Debian's Python:
    /usr/bin/python3 Testing/Benchmark/quality_table.py --tool build/bin/triangulate_to_vtu \
        --meshcheck ../shared/tools/meshcheck.py [--out /tmp/quality] [--tool-args "--no-curve-recovery"]
For every model it meshes with the default settings (automatic levels) and, for the paper's
three models, at the MaxLevel whose triangle count is nearest the paper's; then prints a
Markdown table of what meshcheck.py recomputes from the geometry alone, plus one figure of
its own: the boundary deviation over the *local* edge length (issue 4's "at most one local
edge length"): the same two-way samples as meshcheck's Hausdorff distance, each distance
divided by the mean edge length of the mesh triangle nearest to the sample (by centroid).
With `--models FILE_OR_DIR ...` it meshes those models instead (every .vtp of a folder, e.g.
the output of random_faulted_sections.py), one row each (a failed run or check is a row with
its error), and prints the counts issue 5 asks about under the table.
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
          "touching_loops", "faulted_section"]
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
    subprocess.run([args.tool, model, vtu] + options, check=True, capture_output=True)
    seconds = time.perf_counter() - start
    out = subprocess.run(["/usr/bin/python3", args.meshcheck, model, vtu,
                          "--json", os.path.join(args.out, tag + ".json")],
                         check=True, capture_output=True, text=True).stdout
    m = json.loads(out[out.index("{"):])
    m["deviation_over_local_edge"] = local_deviation(args.checker, model, vtu)
    return tag, m, seconds


def local_deviation(mc, model_path, mesh_path):
    """Largest two-way boundary distance over the local edge length (see the module doc)."""
    model = mc.read(model_path)
    pts, tris, reg, _ = mc.mesh_arrays(mc.read(mesh_path), "RegionId")
    e, key, owner = mc.edges_of(tris)
    faces = {}
    for i, k in enumerate(map(tuple, key)):
        faces.setdefault(k, []).append(owner[i])
    bedges = np.array([k for k, f in faces.items() if len(f) == 1 or reg[f[0]] != reg[f[1]]])
    if len(bedges) == 0:
        return float("nan")
    h = float(np.median(np.linalg.norm(pts[bedges[:, 0]] - pts[bedges[:, 1]], axis=1)))
    curves = mc.model_curves(model)
    p = np.concatenate([c[:-1] for c in curves if len(c) > 1])
    q = np.concatenate([c[1:] for c in curves if len(c) > 1])
    step = h / 4.0
    s_in = mc.sample_segments(p, q, step)
    s_mesh = mc.sample_segments(pts[bedges[:, 0]], pts[bedges[:, 1]], step)
    d1, _ = cKDTree(s_in).query(s_mesh)
    d2, _ = cKDTree(s_mesh).query(s_in)
    tri_pts = pts[tris]
    local = np.mean([np.linalg.norm(tri_pts[:, i] - tri_pts[:, (i + 1) % 3], axis=1)
                     for i in range(3)], axis=0)
    centroids = cKDTree(tri_pts.mean(axis=1))
    worst = 0.0
    for d, samples in ((d1, s_mesh), (d2, s_in)):
        _, nearest = centroids.query(samples)
        worst = max(worst, float((d / local[nearest]).max()))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshcheck", required=True)
    ap.add_argument("--out", default="/tmp/stratamesh_quality")
    ap.add_argument("--tool-args", default="",
                    help="extra options for the tool on every run, e.g. \"--no-curve-recovery\"")
    ap.add_argument("--models", nargs="+", default=None,
                    help="mesh these .vtp files (or every .vtp of these folders) instead")
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
    print("| model | triangles | min angle | max angle | % triangles min angle >= 30 |"
          " boundary Hausdorff / h | deviation / local edge | worst region area error |"
          " topology mismatches | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for tag, m, seconds in rows:
        if isinstance(m, str):
            print("| %s | failed: %s |  |  |  |  |  |  |  |  |" % (tag, m.replace("|", "/")))
            continue
        print("| %s | %d | %.2f | %.1f | %.1f | %.2f | %.2f | %.2f%% | %d | %.2f |"
              % (tag, m["triangles"], m["min_angle"], m["max_angle"],
                 m["pct_tris_minangle_ge_30"], m["hausdorff_over_h"],
                 m["deviation_over_local_edge"], m["max_region_area_error_pct"],
                 m["topology_mismatches"], seconds))
    if args.models:
        ok = [m for _, m, _ in rows if not isinstance(m, str)]
        invalid = sum(m["inverted"] + m["degenerate"] + m["folded_edges"] +
                      m["nonmanifold_edges"] for m in ok)
        angles = sorted(m["min_angle"] for m in ok)
        print("\n%d models, %d failed; min angle >= 25: %d, >= 30: %d (smallest %.2f, median %.2f);"
              " max angle <= 130: %d; area error <= 0.5%%: %d (median %.3f%%, largest %.3f%%);"
              " topology mismatches %d; invalid triangles %d"
              % (len(rows), len(rows) - len(ok), sum(a >= 25 for a in angles),
                 sum(a >= 30 for a in angles), angles[0] if angles else float("nan"),
                 float(np.median(angles)) if angles else float("nan"),
                 sum(m["max_angle"] <= 130 for m in ok),
                 sum(m["max_region_area_error_pct"] <= 0.5 for m in ok),
                 float(np.median([m["max_region_area_error_pct"] for m in ok])) if ok else 0.0,
                 max([m["max_region_area_error_pct"] for m in ok] or [0.0]),
                 sum(m["topology_mismatches"] for m in ok), invalid))


if __name__ == "__main__":
    main()
