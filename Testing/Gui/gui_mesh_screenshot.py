"""Runs inside the ParaView GUI (paraview --script=<this> --exit), with StrataMesh loaded at
start-up (--plugin-search-paths + --plugins, or PV_PLUGIN_PATH): reads a model, applies
"Physical Compression Triangulation", shows the mesh coloured by RegionId in the GUI's render
view and saves a screenshot. The outcome goes to <out>/result.json (written last), which
run_gui_test.py checks; an exception here leaves no result (the GUI only prints it).

Environment: STRATAMESH_DATA (folder of the models), STRATAMESH_OUT (output folder),
STRATAMESH_MODEL (file name, default salt_dome.vtp).
"""
import json
import os
import sys

import paraview.simple as simple

data = os.environ["STRATAMESH_DATA"]
out = os.environ["STRATAMESH_OUT"]
model_name = os.environ.get("STRATAMESH_MODEL", "salt_dome.vtp")
png = os.path.join(out, os.path.splitext(model_name)[0] + "_gui.png")

# The plugin was loaded by the application at start-up: its filters are in paraview.simple.
if not hasattr(simple, "PhysicalCompressionTriangulation"):
    raise RuntimeError("StrataMesh is not loaded: PhysicalCompressionTriangulation is missing")

model = simple.XMLPolyDataReader(registrationName=model_name,
                                 FileName=[os.path.join(data, model_name)])
mesh = simple.PhysicalCompressionTriangulation(registrationName="Mesh", Input=model)
label = mesh.SMProxy.GetXMLLabel()

view = simple.GetActiveViewOrCreate("RenderView")
display = simple.Show(mesh, view)
simple.ColorBy(display, ("CELLS", "RegionId"))
display.SetRepresentationType("Surface With Edges")
display.RescaleTransferFunctionToDataRange(True, False)
view.ResetCamera()
simple.Render(view)
simple.SaveScreenshot(png, view, ImageResolution=[800, 600])

info = mesh.GetDataInformation()
result = {
    "label": label,
    "cells": info.GetNumberOfCells(),
    "points": info.GetNumberOfPoints(),
    "cell_arrays": list(mesh.CellData.keys()),
    "sources": sorted(name for (name, _id) in simple.GetSources()),
    "png": png,
    # The program this script runs in: the GUI, not pvpython.
    "executable": os.path.realpath("/proc/self/exe") if os.path.exists("/proc/self/exe")
    else sys.executable,
}
with open(os.path.join(out, "result.json"), "w") as f:
    json.dump(result, f, indent=1)
