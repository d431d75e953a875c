"""Quality table of StrataMesh on the bundled models, checked by the independent mesh checker.

Run by hand (not part of ctest), with Debian's Python:
    /usr/bin/python3 Testing/Benchmark/quality_table.py --tool build/bin/triangulate_to_vtu \
        --meshcheck ../shared/tools/meshcheck.py [--out /tmp/quality]
For every model it meshes with the default settings (automatic levels) and, for the paper's
three models, at the MaxLevel whose triangle count is nearest the paper's; then prints a
Markdown table of what meshcheck.py recomputes from the geometry alone.
"""
import argparse
import json
import os
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "Data")
MODELS = ["lake_superior", "lake_superior_full", "salt_dome", "salt_dome_loops", "gulf_section",
          "gulf_section_loops", "countries_westeurope", "countries_westeurope_loops",
          "geology_marmousi", "guitar", "pinch_out", "thin_layer", "nested_holes",
          "touching_loops"]
# The paper's figures: (MaxLevel giving a similar count, paper triangles, paper min angle).
PAPER = {"lake_superior": (9, 1906, 11.5), "salt_dome": (10, 6183, 10.4),
         "gulf_section": (10, 11015, 5.25)}


def run(args, name, extra):
    model = os.path.join(DATA, name + ".vtp")
    tag = name + ("_L%s" % extra[1] if extra else "")
    vtu = os.path.join(args.out, tag + ".vtu")
    start = time.perf_counter()
    subprocess.run([args.tool, model, vtu] + extra, check=True, capture_output=True)
    seconds = time.perf_counter() - start
    out = subprocess.run(["/usr/bin/python3", args.meshcheck, model, vtu,
                          "--json", os.path.join(args.out, tag + ".json")],
                         check=True, capture_output=True, text=True).stdout
    m = json.loads(out[out.index("{"):])
    return tag, m, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--meshcheck", required=True)
    ap.add_argument("--out", default="/tmp/stratamesh_quality")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in MODELS:
        rows.append(run(args, name, []))
        if name in PAPER:
            rows.append(run(args, name, ["--max-level", str(PAPER[name][0])]))
    print("| model | triangles | min angle | max angle | % triangles min angle >= 30 |"
          " boundary Hausdorff / h | worst region area error | topology mismatches | seconds |")
    print("|---|---|---|---|---|---|---|---|---|")
    for tag, m, seconds in rows:
        print("| %s | %d | %.2f | %.1f | %.1f | %.2f | %.2f%% | %d | %.2f |"
              % (tag, m["triangles"], m["min_angle"], m["max_angle"],
                 m["pct_tris_minangle_ge_30"], m["hausdorff_over_h"],
                 m["max_region_area_error_pct"], m["topology_mismatches"], seconds))


if __name__ == "__main__":
    main()
