"""Mesh one cross-section at several resolutions (MaxLevel sweep) and save them as a series.

    pvpython example_multiresolution.py [--plugin StrataMesh.so] [--data Data]
        [--model salt_dome.vtp] [--out out] [--levels 9 10 11 12]

One PhysicalCompressionTriangulation is re-run for every MaxLevel; each mesh is saved as
<out>/<model>_level_<LL>.vtu (binary) and <out>/<model>_levels.pvd lists them with the level as
time, so ParaView's time slider steps through the resolutions. Prints the triangle count of
each level. Defaults come from the environment: STRATAMESH_PLUGIN (path of StrataMesh.so; not
needed when PV_PLUGIN_PATH already loads the plugin), STRATAMESH_DATA (folder of the models,
else the repository's Data/), STRATAMESH_OUT (output folder, else out/). Exit code 0 when
every level was meshed and the counts increase with the level, 1 otherwise.
"""
import argparse
import os
import sys
from xml.sax.saxutils import quoteattr

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


def write_pvd(path, files_by_time):
    """A ParaView collection file: one dataset per time step (here: per MaxLevel)."""
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                '  <Collection>\n')
        for time, name in files_by_time:
            f.write('    <DataSet timestep="%d" part="0" file=%s/>\n' % (time, quoteattr(name)))
        f.write("  </Collection>\n</VTKFile>\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", default=os.environ.get("STRATAMESH_PLUGIN"),
                        help="path of StrataMesh.so (default: $STRATAMESH_PLUGIN)")
    parser.add_argument("--data", default=os.environ.get(
        "STRATAMESH_DATA", os.path.join(HERE, "..", "..", "Data")),
        help="folder of the models (default: $STRATAMESH_DATA, else the repository's Data/)")
    parser.add_argument("--model", default="salt_dome.vtp", help="model file in --data")
    parser.add_argument("--out", default=os.environ.get("STRATAMESH_OUT", "out"),
                        help="output folder (default: $STRATAMESH_OUT, else out/)")
    parser.add_argument("--levels", type=int, nargs="+", default=[9, 10, 11, 12],
                        help="MaxLevel values (default: 9 10 11 12)")
    args = parser.parse_args()

    load_stratamesh(args.plugin)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.splitext(args.model)[0]
    model = simple.XMLPolyDataReader(FileName=[os.path.join(args.data, args.model)])
    mesh = simple.PhysicalCompressionTriangulation(Input=model)

    print("%-9s %10s %10s %10s" % ("MaxLevel", "triangles", "vertices", "min angle"))
    counts, series = [], []
    for level in sorted(set(args.levels)):
        mesh.MaxLevel = level
        mesh.UpdatePipeline()
        info = mesh.GetDataInformation()
        if info.GetNumberOfCells() == 0:
            print("MaxLevel %d: no mesh (see the errors above)" % level)
            return 1
        name = "%s_level_%02d.vtu" % (stem, level)
        simple.SaveData(os.path.join(args.out, name), proxy=simple.OutputPort(mesh, 0),
                        DataMode="Binary")
        counts.append(info.GetNumberOfCells())
        series.append((level, name))
        print("%-9d %10d %10d %10.1f" % (level, info.GetNumberOfCells(),
                                         info.GetNumberOfPoints(),
                                         mesh.CellData["MinimumAngle"].GetRange()[0]),
              flush=True)
    pvd = os.path.join(args.out, stem + "_levels.pvd")
    write_pvd(pvd, series)
    print("series: %s" % pvd)

    if any(b <= a for a, b in zip(counts, counts[1:])):
        print("error: the triangle counts do not increase with MaxLevel: %s" % counts)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
