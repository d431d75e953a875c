"""Makes the README's pictures (run with pvbatch; scripts/pictures.sh does it for you).

Every picture is made from the bundled models with the plugin's filters, so they stay true:
  hero.png            the Gulf of Mexico section meshed, coloured by region
  walk_model.png      the salt dome model's curves
  walk_grid.png       its adaptive 4-8 grid (Adaptive 4-8 Grid)
  walk_classified.png the grid's vertices classified (Classify 4-8 Grid)
  walk_mesh.png       the final mesh (Physical Compression Triangulation)
  walk_histogram.png  histogram of the triangles' smallest angles
  lake_distance.png   signed distance to Lake Superior's shores (Polyline Signed Distance)
"""
import argparse
import os
import sys

from paraview.simple import (LoadPlugin, XMLPolyDataReader, Show, Hide, CreateView, ColorBy,
                             GetColorTransferFunction, SaveScreenshot, ResetCamera, Delete,
                             OutputPort, Histogram, Render, GetScalarBar)
from paraview import servermanager

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--plugin", required=True)
parser.add_argument("--data", required=True)
parser.add_argument("--out", required=True)
args = parser.parse_args()
LoadPlugin(args.plugin, remote=False, ns=globals())
os.makedirs(args.out, exist_ok=True)

SIZE = [1200, 700]
PALETTE = [(0.553, 0.827, 0.780), (1.0, 1.0, 0.702), (0.745, 0.729, 0.855),
           (0.984, 0.502, 0.447), (0.502, 0.694, 0.827), (0.992, 0.706, 0.384),
           (0.702, 0.871, 0.412), (0.988, 0.804, 0.898), (0.851, 0.851, 0.851),
           (0.737, 0.502, 0.741), (0.800, 0.922, 0.773), (1.0, 0.929, 0.435)]


def view_2d():
    view = CreateView("RenderView")
    view.ViewSize = SIZE
    view.OrientationAxesVisibility = 0
    view.InteractionMode = "2D"
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    return view


def frame(view, bounds, pad=1.04):
    ResetCamera(view)
    (x0, x1, y0, y1) = bounds[:4]
    view.CameraParallelScale = 0.5 * max(y1 - y0, (x1 - x0) * SIZE[1] / SIZE[0]) * pad


def categorical(display, array, ids, association="CELLS", legend=True, view=None):
    ColorBy(display, (association, array))
    lut = GetColorTransferFunction(array)
    lut.InterpretValuesAsCategories = 1
    lut.Annotations = [str(i) for r in ids for i in (r, str(r))]
    colours = [(0.92, 0.92, 0.92) if r < 0 else PALETTE[r % len(PALETTE)] for r in ids]
    lut.IndexedColors = [c for colour in colours for c in colour]
    display.SetScalarBarVisibility(view, legend)


def dark_legends(view):
    """Legends readable on the white background."""
    for rep in view.Representations:
        lut = getattr(rep, "LookupTable", None)
        # (GetScalarBar makes a visible legend, titled "Name Component", where there is none)
        if (lut is not None and getattr(rep, "Visibility", 0) and
                hasattr(rep, "IsScalarBarVisible") and rep.IsScalarBarVisible(view)):
            bar = GetScalarBar(lut, view)
            bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]


def save(view, name):
    if view.GetXMLName() == "RenderView":
        dark_legends(view)
    Render(view)
    SaveScreenshot(os.path.join(args.out, name), view, ImageResolution=SIZE)
    print("wrote", os.path.join(args.out, name))


def model(name):
    return XMLPolyDataReader(FileName=[os.path.join(args.data, name)])


# Hero: the Gulf of Mexico section.
gulf = model("gulf_section.vtp")
mesh = PhysicalCompressionTriangulation(Input=gulf, MaxLevel=13)  # noqa: F821
view = view_2d()
d = Show(mesh, view)
d.SetRepresentationType("Surface With Edges")
d.EdgeColor = [0.2, 0.2, 0.25]
categorical(d, "RegionId", list(range(15)), view=view, legend=False)
frame(view, servermanager.Fetch(mesh).GetBounds())
save(view, "hero.png")
Delete(view)

# Walk-through on the salt dome.
salt = model("salt_dome.vtp")
view = view_2d()
d = Show(salt, view)
d.LineWidth = 2.0
d.ColorArrayName = ["POINTS", ""]
d.AmbientColor = d.DiffuseColor = [0.1, 0.1, 0.1]
bounds = servermanager.Fetch(salt).GetBounds()
frame(view, bounds, 1.15)
save(view, "walk_model.png")

grid = Adaptive48Grid(Input=salt)  # noqa: F821
g = Show(grid, view)
g.SetRepresentationType("Wireframe")
ColorBy(g, ("CELLS", "Level"))
GetColorTransferFunction("Level").ApplyPreset("Viridis (matplotlib)", True)
g.SetScalarBarVisibility(view, True)
frame(view, bounds, 1.15)
save(view, "walk_grid.png")
Hide(grid, view)

classes = Classify48Grid(Input=salt)  # noqa: F821
c = Show(OutputPort(classes, 0), view)
c.SetRepresentationType("Surface With Edges")
c.EdgeColor = [0.3, 0.3, 0.3]
categorical(c, "CellRegion", list(range(-1, 6)), view=view)
frame(view, bounds, 1.15)
save(view, "walk_classified.png")
Hide(OutputPort(classes, 0), view)

mesh = PhysicalCompressionTriangulation(Input=salt)  # noqa: F821
m = Show(OutputPort(mesh, 0), view)
m.SetRepresentationType("Surface With Edges")
m.EdgeColor = [0.2, 0.2, 0.25]
categorical(m, "RegionId", list(range(6)), view=view)
frame(view, bounds, 1.15)
save(view, "walk_mesh.png")
Delete(view)

histogram = Histogram(Input=mesh, SelectInputArray=["CELLS", "MinimumAngle"], BinCount=30)
chart = CreateView("XYBarChartView")
chart.ViewSize = SIZE
chart.BottomAxisTitle = "smallest angle of a triangle (degrees)"
chart.LeftAxisTitle = "triangles"
bars = Show(histogram, chart)
bars.SeriesVisibility = ["bin_values"]
bars.SeriesColor = ["bin_values", "0.3", "0.45", "0.7"]
chart.ShowLegend = 0
save(chart, "walk_histogram.png")
Delete(chart)

# Signed distance to Lake Superior.
lake = model("lake_superior.vtp")
distance = PolylineSignedDistance(Input=lake, Source=lake, SampleDimensions=[600, 300])  # noqa
view = view_2d()
s = Show(distance, view)
ColorBy(s, ("POINTS", "SignedDistance"))
lut = GetColorTransferFunction("SignedDistance")
lut.ApplyPreset("Cool to Warm", True)
top = servermanager.Fetch(distance).GetPointData().GetArray("SignedDistance").GetRange()[1]
lut.RescaleTransferFunction(-top, top)
s.SetScalarBarVisibility(view, True)
lines = Show(lake, view)
lines.ColorArrayName = ["POINTS", ""]
lines.AmbientColor = lines.DiffuseColor = [0.0, 0.0, 0.0]
frame(view, servermanager.Fetch(distance).GetBounds(), 1.0)
save(view, "lake_distance.png")
Delete(view)
sys.exit(0)
