"""StrataMesh main job (run with pvbatch; scripts/demo.sh does it for you).

Reads a polyline model, samples its signed distance on an image with the
"Polyline Signed Distance" filter, writes out/<model>_distance.vti and a picture
out/<model>_distance.png, and prints a short summary.
"""
import argparse
import os
import sys
import time

from paraview.simple import (LoadPlugin, XMLPolyDataReader, Show, Hide, GetActiveViewOrCreate,
                             ColorBy, GetColorTransferFunction, SaveData, SaveScreenshot,
                             ResetCamera)
from paraview import servermanager
from vtkmodules.numpy_interface import dataset_adapter as dsa
import numpy as np

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--plugin", required=True, help="path of StrataMesh.so")
parser.add_argument("--model", required=True, help="polyline model (.vtp)")
parser.add_argument("--out", default="out", help="output folder")
parser.add_argument("--samples", type=int, default=512, help="image points along x and y")
args = parser.parse_args()

LoadPlugin(args.plugin, remote=False, ns=globals())
os.makedirs(args.out, exist_ok=True)
name = os.path.splitext(os.path.basename(args.model))[0]

start = time.perf_counter()
model = XMLPolyDataReader(FileName=[args.model])
distance = PolylineSignedDistance(Input=model, Source=model,  # noqa: F821 (from the plugin)
                                  SampleDimensions=[args.samples, args.samples])
distance.UpdatePipeline()
seconds = time.perf_counter() - start

vti = os.path.join(args.out, name + "_distance.vti")
SaveData(vti, proxy=distance, DataMode="Binary")

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 800]
view.OrientationAxesVisibility = 0
display = Show(distance, view)
ColorBy(display, ("POINTS", "SignedDistance"))
lut = GetColorTransferFunction("SignedDistance")
lut.ApplyPreset("Cool to Warm", True)
image = dsa.WrapDataObject(servermanager.Fetch(distance))
values = np.asarray(image.PointData["SignedDistance"])
regions = np.asarray(image.PointData["RegionId"])
# Symmetric about 0 so that the shore is white; outside far from it saturates.
limit = float(values.max()) if values.size and values.max() > 0 else 1.0
lut.RescaleTransferFunction(-limit, limit)
display.SetScalarBarVisibility(view, True)
lines = Show(model, view)
lines.DiffuseColor = [0.0, 0.0, 0.0]
lines.AmbientColor = [0.0, 0.0, 0.0]
lines.LineWidth = 1.5
lines.ColorArrayName = [None, ""]
view.InteractionMode = "2D"
ResetCamera(view)
(x0, x1, y0, y1) = image.VTKObject.GetBounds()[:4]
view.CameraParallelScale = 0.5 * max(y1 - y0, (x1 - x0) * 800.0 / 1200.0) * 1.02
png = os.path.join(args.out, name + "_distance.png")
SaveScreenshot(png, view, ImageResolution=[1200, 800])

model_data = dsa.WrapDataObject(servermanager.Fetch(model))
bounds = model_data.VTKObject.GetBounds()
print("StrataMesh demo: signed distance of %s" % name)
print("  model:    %d cells, %d points, bounds x %.6g..%.6g, y %.6g..%.6g"
      % (model_data.GetNumberOfCells(), model_data.GetNumberOfPoints(), *bounds[:4]))
print("  samples:  %d x %d image, %.2f s" % (args.samples, args.samples, seconds))
print("  distance: min %.6g, max %.6g (model units; + inside a region)"
      % (values.min(), values.max()))
inside = regions >= 0
print("  inside:   %.1f%% of the samples lie in a region (%s)"
      % (100.0 * inside.mean(), ", ".join("region %d: %d" % (r, (regions == r).sum())
                                          for r in np.unique(regions[inside]))))
print("  wrote:    %s" % vti)
print("  wrote:    %s" % png)
# Release the render view before the interpreter exits: tearing it down later, in the
# interpreter's finalisation, makes GLX fail under Xvfb.
from paraview.simple import Delete  # noqa: E402
Delete(view)
del view, display, lines
sys.exit(0)
