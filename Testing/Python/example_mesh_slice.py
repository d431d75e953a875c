"""Mesh one geological cross-section with StrataMesh and save the mesh as a binary .vtu.

    pvpython example_mesh_slice.py [--plugin StrataMesh.so] [--data Data] [--model pinch_out.vtp]
                                   [--out out] [--max-level -1]

Writes <out>/<model>_mesh.vtu (triangles with RegionId and quality arrays) and prints a
summary and each region's areas. Defaults come from the environment: STRATAMESH_PLUGIN (path of StrataMesh.so; not
needed when PV_PLUGIN_PATH already loads the plugin), STRATAMESH_DATA (folder of the models,
else the repository's Data/), STRATAMESH_OUT (output folder, else out/). Exit code 0 when a
mesh was written, 1 otherwise (VTK prints the reason).
"""
import argparse
import os
import sys

from paraview import simple

HERE = os.path.dirname(os.path.abspath(__file__))


def load_stratamesh(plugin):
    """Loads StrataMesh into paraview.simple, unless PV_PLUGIN_PATH already did."""
    if hasattr(simple, "PhysicalCompressionTriangulation"):
        return
    if not plugin:
        sys.exit("error: StrataMesh is not loaded: give --plugin <path of StrataMesh.so> "
                 "or set PV_PLUGIN_PATH to its folder")
    simple.LoadPlugin(plugin, remote=False)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", default=os.environ.get("STRATAMESH_PLUGIN"),
                        help="path of StrataMesh.so (default: $STRATAMESH_PLUGIN)")
    parser.add_argument("--data", default=os.environ.get(
        "STRATAMESH_DATA", os.path.join(HERE, "..", "..", "Data")),
        help="folder of the models (default: $STRATAMESH_DATA, else the repository's Data/)")
    parser.add_argument("--model", default="pinch_out.vtp", help="model file in --data")
    parser.add_argument("--out", default=os.environ.get("STRATAMESH_OUT", "out"),
                        help="output folder (default: $STRATAMESH_OUT, else out/)")
    parser.add_argument("--max-level", type=int, default=-1,
                        help="MaxLevel of the 4-8 grid (-1: automatic)")
    args = parser.parse_args()

    load_stratamesh(args.plugin)
    model = simple.XMLPolyDataReader(FileName=[os.path.join(args.data, args.model)])
    mesh = simple.PhysicalCompressionTriangulation(Input=model, MaxLevel=args.max_level)
    mesh.UpdatePipeline()

    info = mesh.GetDataInformation()
    if info.GetNumberOfCells() == 0:
        print("%s: no mesh (see the errors above)" % args.model)
        return 1
    os.makedirs(args.out, exist_ok=True)
    vtu = os.path.join(args.out, os.path.splitext(args.model)[0] + "_mesh.vtu")
    # Binary, not appended: Debian's ParaView reads back only that.
    simple.SaveData(vtu, proxy=simple.OutputPort(mesh, 0), DataMode="Binary")

    regions = mesh.CellData["RegionId"].GetRange()
    angles = mesh.CellData["MinimumAngle"].GetRange()
    print("%s -> %s: %d triangles, %d vertices, regions %d..%d, smallest angle %.1f deg"
          % (args.model, vtu, info.GetNumberOfCells(), info.GetNumberOfPoints(),
             regions[0], regions[1], angles[0]))
    # Each region's area in the model and in the mesh, and its misplaced area (lost plus
    # added, which a loss at one place and a gain at another do not cancel).
    fd = simple.servermanager.Fetch(mesh).GetFieldData()
    columns = [fd.GetArray(name) for name in
               ("RegionIds", "RegionModelArea", "RegionMeshArea", "RegionMisplacedArea")]
    print("region  model area      mesh area       net      misplaced")
    for i in range(columns[0].GetNumberOfTuples()):
        rid, area, meshed, misplaced = (c.GetTuple1(i) for c in columns)
        print("%6d  %-14.6g  %-14.6g  %+7.3f%%  %7.3f%%"
              % (rid, area, meshed, 100.0 * (meshed - area) / area, 100.0 * misplaced / area))
    return 0


if __name__ == "__main__":
    sys.exit(main())
