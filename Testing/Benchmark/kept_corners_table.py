"""What KeepSharpCorners does to the bundled models, checked from the geometry.

Run by hand (not part of ctest), with Debian's Python:
    /usr/bin/python3 Testing/Benchmark/kept_corners_table.py --tool build/bin/triangulate_to_vtu \
        --meshcheck ../shared/tools/meshcheck.py [--out /tmp/kept] [--models FILE_OR_DIR ...]
Every model is meshed twice with the default settings, without and with
`--keep-sharp-corners`. The table gives, with the option: the model's corners it applies to
and those kept; of the kept corners' wedges (triangles of the corner's region within its
radius whose centroid lies inside its outline, from the tool's `kept_corner_list`), the
smallest input angle kept and the smallest and largest triangle angles; elsewhere (every
other triangle), the smallest and largest angles without -> with the option;
`KeptCornerTriangles`; the triangles and seconds without -> with; and what meshcheck.py
recomputes with the option (inverted or degenerate triangles, worst region area error,
topology mismatches). Angles are recomputed from the points, by meshcheck.py's functions.
"""
import argparse
import importlib.util
import json
import os
import subprocess

import numpy as np
from matplotlib.path import Path

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "Data")
MODELS = ["pinch_out", "faulted_section", "geology_marmousi", "gulf_section", "gulf_section_loops",
          "countries_westeurope", "countries_westeurope_loops", "lake_superior",
          "lake_superior_full"]


def angles(mc, path):
    """Points, triangles, regions and the three angles (degrees) of every triangle of a .vtu,
    read and computed by meshcheck.py (`mc`)."""
    pts, tris, regions, _ = mc.mesh_arrays(mc.read(path), "RegionId")
    return pts, tris, regions, mc.angles_of(pts, tris)[0]


def run(args, model, out, keep):
    cmd = [args.tool, model, out] + (["--keep-sharp-corners"] if keep else [])
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def row(args, mc, model):
    name = os.path.splitext(os.path.basename(model))[0]
    off_vtu = os.path.join(args.out, name + "_off.vtu")
    on_vtu = os.path.join(args.out, name + "_keep.vtu")
    off, on = run(args, model, off_vtu, False), run(args, model, on_vtu, True)
    _, _, _, a_off = angles(mc, off_vtu)
    pts, tris, regions, a_on = angles(mc, on_vtu)
    wedge = np.zeros(len(tris), bool)
    centroids = pts[tris].mean(axis=1)
    for k in on["kept_corner_list"]:
        far = np.linalg.norm(pts[tris] - [k["x"], k["y"]], axis=2).max(axis=1)
        wedge |= ((regions == k["region"]) & (far <= k["radius"] * (1 + 1e-9))
                  & Path(np.array(k["outline"])).contains_points(centroids))
    check = os.path.join(args.out, name + "_keep.json")
    subprocess.run(["/usr/bin/python3", args.meshcheck, model, on_vtu, "--json", check],
                   check=True, capture_output=True)
    mc = json.load(open(check))
    kept = on["kept_corner_list"]
    w = (f"{min(k['angle'] for k in kept):.1f} | {a_on[wedge].min():.2f} | "
         f"{a_on[wedge].max():.1f}") if kept else "- | - | -"
    return (f"| {name} | {on['sharp_corners']} | {on['kept_corners']} | {w} | "
            f"{a_off.min():.2f} -> {a_on[~wedge].min():.2f} | "
            f"{a_off.max():.1f} -> {a_on[~wedge].max():.1f} | {on['kept_corner_triangles']} | "
            f"{off['triangles']} -> {on['triangles']} | {off['seconds']:.2f} -> "
            f"{on['seconds']:.2f} | {mc['inverted'] + mc['degenerate']} | "
            f"{mc['max_region_area_error_pct']:.2f}% | {mc['topology_mismatches']} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshcheck", required=True)
    ap.add_argument("--out", default="/tmp/stratamesh_kept")
    ap.add_argument("--models", nargs="+", help="these .vtp files (or every .vtp of folders)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    spec = importlib.util.spec_from_file_location("meshcheck", args.meshcheck)
    mc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mc)
    models = [os.path.join(DATA, m + ".vtp") for m in MODELS]
    if args.models:
        models = []
        for m in args.models:
            models += sorted(os.path.join(m, f) for f in os.listdir(m) if f.endswith(".vtp")) \
                if os.path.isdir(m) else [m]
    print("| model | sharp corners | kept | smallest kept corner | wedge min angle | "
          "wedge max angle | min angle elsewhere (off -> on) | max angle elsewhere | "
          "KeptCornerTriangles | triangles | seconds | inverted or degenerate | "
          "worst region area error | topology mismatches |")
    print("|" + "---|" * 14)
    for model in models:
        try:
            print(row(args, mc, model), flush=True)
        except (subprocess.CalledProcessError, ValueError, KeyError) as e:
            print(f"| {os.path.basename(model)} | failed: {e} |", flush=True)


if __name__ == "__main__":
    main()
