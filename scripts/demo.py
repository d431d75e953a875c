"""StrataMesh main job (run with pvbatch; scripts/demo.sh does it for you).

Meshes a polyline model with the "Physical Compression Triangulation" filter and writes
under the output folder:
  <model>_mesh.vtu       the triangle mesh (RegionId, quality arrays), binary XML
  <model>_boundary.vtp   the approximated boundary as Shared curves, binary XML
  <model>_mesh.png       the mesh coloured by RegionId, with its edges
and prints a short summary (the quality figures of the mesh's field data).
"""
import argparse
import os
import sys

from paraview.simple import (LoadPlugin, XMLPolyDataReader, Show, GetActiveViewOrCreate,
                             ColorBy, GetColorTransferFunction, SaveData, SaveScreenshot,
                             ResetCamera, Delete, OutputPort)
from paraview import servermanager

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--plugin", required=True, help="path of StrataMesh.so")
parser.add_argument("--model", required=True, help="polyline model (.vtp)")
parser.add_argument("--out", default="out", help="output folder")
parser.add_argument("--max-level", type=int, default=-1, help="MaxLevel (-1: automatic)")
args = parser.parse_args()

# Twelve distinguishable colours (ColorBrewer Set3), for the regions.
PALETTE = [(0.553, 0.827, 0.780), (1.0, 1.0, 0.702), (0.745, 0.729, 0.855),
           (0.984, 0.502, 0.447), (0.502, 0.694, 0.827), (0.992, 0.706, 0.384),
           (0.702, 0.871, 0.412), (0.988, 0.804, 0.898), (0.851, 0.851, 0.851),
           (0.737, 0.502, 0.741), (0.800, 0.922, 0.773), (1.0, 0.929, 0.435)]

LoadPlugin(args.plugin, remote=False, ns=globals())
os.makedirs(args.out, exist_ok=True)
name = os.path.splitext(os.path.basename(args.model))[0]

model = XMLPolyDataReader(FileName=[args.model])
mesh = PhysicalCompressionTriangulation(Input=model,  # noqa: F821 (from the plugin)
                                        MaxLevel=args.max_level)
mesh.UpdatePipeline()
data = servermanager.Fetch(mesh)
if data.GetNumberOfCells() == 0:
    print("StrataMesh demo: no mesh for %s (see the messages above)" % name)
    sys.exit(1)

vtu = os.path.join(args.out, name + "_mesh.vtu")
vtp = os.path.join(args.out, name + "_boundary.vtp")
SaveData(vtu, proxy=OutputPort(mesh, 0), DataMode="Binary")
SaveData(vtp, proxy=OutputPort(mesh, 1), DataMode="Binary")

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 800]
view.OrientationAxesVisibility = 0
display = Show(mesh, view)
display.SetRepresentationType("Surface With Edges")
display.EdgeColor = [0.25, 0.25, 0.3]
ColorBy(display, ("CELLS", "RegionId"))
# Regions as categories: one colour each, named in the legend.
lut = GetColorTransferFunction("RegionId")
regions = data.GetCellData().GetArray("RegionId").GetRange()
ids = list(range(int(regions[0]), int(regions[1]) + 1))
lut.InterpretValuesAsCategories = 1
lut.Annotations = [str(i) for r in ids for i in (r, "region %d" % r)]
lut.IndexedColors = [c for k in range(len(ids)) for c in PALETTE[k % len(PALETTE)]]
display.SetScalarBarVisibility(view, len(ids) > 1)
view.InteractionMode = "2D"
ResetCamera(view)
(x0, x1, y0, y1) = data.GetBounds()[:4]
view.CameraParallelScale = 0.5 * max(y1 - y0, (x1 - x0) * 800.0 / 1200.0) * 1.04
png = os.path.join(args.out, name + "_mesh.png")
SaveScreenshot(png, view, ImageResolution=[1200, 800])

fd = data.GetFieldData()


def field(key):
    return fd.GetArray(key).GetTuple1(0)


print("StrataMesh demo: %s" % name)
print("  mesh:      %d triangles, %d vertices, %d regions"
      % (field("NumberOfTriangles"), field("NumberOfVertices"), int(regions[1]) + 1))
print("  angles:    min %.2f deg, max %.2f deg; %.1f%% of triangles have their smallest"
      " angle in [30, 60]" % (field("MinimumAngle"), field("MaximumAngle"),
                              field("PercentTriangles30To60")))
print("  fidelity:  boundary within %.4g model units of the input curves; region areas"
      " within %.3f%%" % (field("MaxBoundaryDeviation"), 100.0 * field("MaxRegionAreaError")))
print("  time:      %.2f s (%d simulation steps)" % (field("SecondsTotal"), field("Iterations")))
for path in (vtu, vtp, png):
    print("  wrote:     %s" % path)
# Release the render view before the interpreter exits: tearing it down during the
# interpreter's finalisation makes GLX fail under Xvfb.
Delete(view)
del view, display
sys.exit(0)
