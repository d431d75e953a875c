"""The TargetEdgeLength input (a target edge length field) as pvpython users connect it."""
import os
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import servermanager, simple  # noqa: E402
from vtkmodules.numpy_interface import dataset_adapter as dsa  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataWriter  # noqa: E402
import numpy as np  # noqa: E402

NS = {}
st.load_plugin(NS)
Triangulation = NS["PhysicalCompressionTriangulation"]

# salt_dome.vtp is the box [0, 12000] x [-6000, 0].
CENTRE = (3000.0, -3000.0)
RADIUS = 1000.0
SMALL = 60.0
LARGE = 1500.0


def write(data, name, writer):
    """Writes `data` under STRATAMESH_OUT in binary (readable by Debian's ParaView)."""
    os.makedirs(st.OUT, exist_ok=True)
    path = os.path.join(st.OUT, name)
    w = writer()
    w.SetInputData(data)
    w.SetFileName(path)
    w.SetDataModeToBinary()
    assert w.Write() == 1
    return path


def size_image(values=None, name="TargetEdgeLength"):
    """A 121 x 61 image over the section: SMALL in a disc around CENTRE, LARGE elsewhere."""
    image = vtkImageData()
    image.SetDimensions(121, 61, 1)
    image.SetSpacing(100.0, 100.0, 1.0)
    image.SetOrigin(0.0, -6000.0, 0.0)
    x, y = np.meshgrid(np.arange(121) * 100.0, np.arange(61) * 100.0 - 6000.0)
    if values is None:
        inside = np.hypot(x - CENTRE[0], y - CENTRE[1]) < RADIUS
        values = np.where(inside, SMALL, LARGE).ravel()
    array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
    array.SetName(name)
    image.GetPointData().AddArray(array)
    return image


def longest_edges_and_centroids(mesh):
    pts = np.asarray(mesh.Points)[:, :2]
    cells = np.asarray(mesh.Cells).reshape(-1, 4)[:, 1:]
    a, b, c = pts[cells[:, 0]], pts[cells[:, 1]], pts[cells[:, 2]]
    longest = np.max([np.linalg.norm(a - b, axis=1), np.linalg.norm(b - c, axis=1),
                      np.linalg.norm(c - a, axis=1)], axis=0)
    return longest, (a + b + c) / 3.0


class TargetEdgeLengthTest(unittest.TestCase):
    def setUp(self):
        self.model = simple.XMLPolyDataReader(FileName=[st.data("salt_dome.vtp")])

    def test_properties_have_the_documented_defaults(self):
        mesh = Triangulation(Input=self.model)
        self.assertEqual(mesh.TargetEdgeLengthArray, "TargetEdgeLength")
        self.assertAlmostEqual(mesh.TargetEdgeLengthGrading, 0.5)
        self.assertIsNone(mesh.TargetEdgeLength)
        for proxy in ("Adaptive48Grid", "Classify48Grid"):
            grid = NS[proxy](Input=self.model)
            self.assertEqual(grid.TargetEdgeLengthArray, "TargetEdgeLength", proxy)

    def test_an_image_field_refines_where_it_asks(self):
        path = write(size_image(), "size.vti", vtkXMLImageDataWriter)
        # The documented use (README): a field read from a file, connected as the second input.
        size = simple.XMLImageDataReader(FileName=[path])
        mesh = Triangulation(Input=self.model, TargetEdgeLength=size)
        mesh.UpdatePipeline()
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        plain = dsa.WrapDataObject(servermanager.Fetch(Triangulation(Input=self.model)))
        longest, centroid = longest_edges_and_centroids(out)
        plain_longest, plain_centroid = longest_edges_and_centroids(plain)
        disc = np.hypot(*(centroid - CENTRE).T) < 0.8 * RADIUS
        plain_disc = np.hypot(*(plain_centroid - CENTRE).T) < 0.8 * RADIUS
        self.assertGreater(disc.sum(), 2 * plain_disc.sum())
        self.assertLessEqual(longest[disc].max(), 2.0 * SMALL)
        # Elsewhere the field asks for LARGE: fewer triangles than the automatic levels give.
        far = np.hypot(*(centroid - CENTRE).T) > RADIUS + 2 * LARGE
        plain_far = np.hypot(*(plain_centroid - CENTRE).T) > RADIUS + 2 * LARGE
        self.assertLess(far.sum(), plain_far.sum())
        self.assertEqual(set(np.unique(np.asarray(out.CellData["RegionId"]))), set(range(6)))

    def test_a_points_only_field_uses_its_only_array_and_the_grading(self):
        points = vtkPoints()
        points.InsertNextPoint(CENTRE[0], CENTRE[1], 0.0)
        wells = vtkPolyData()
        wells.SetPoints(points)
        h = numpy_to_vtk(np.array([SMALL]), deep=1)
        h.SetName("h")  # not TargetEdgeLength: the only point array is used
        wells.GetPointData().AddArray(h)
        path = write(wells, "wells.vtp", vtkXMLPolyDataWriter)
        reader = simple.XMLPolyDataReader(FileName=[path])
        grid = NS["Adaptive48Grid"](Input=self.model, TargetEdgeLength=reader,
                                    MaximumEdgeLength=1000.0)
        out = dsa.WrapDataObject(servermanager.Fetch(grid))
        longest, centroid = longest_edges_and_centroids(out)
        distance = np.hypot(*(centroid - CENTRE).T)
        # Every grid triangle is no longer than the law SMALL + 0.5 d at its centroid.
        wanted = SMALL + 0.5 * distance
        self.assertTrue((longest <= wanted * (1 + 1e-9)).all())
        self.assertGreater(out.FieldData["TargetMaxLevel"][0], out.FieldData["MaxLevel"][0])
        near = distance < 2 * SMALL
        self.assertTrue(near.any())
        self.assertLessEqual(longest[near].max(), 2 * SMALL)
        # A steeper grading refines less around the well.
        count = out.GetNumberOfCells()
        grid.TargetEdgeLengthGrading = 2.0
        grid.UpdatePipeline()
        self.assertLess(grid.GetDataInformation().GetNumberOfCells(), count)

    def test_a_bad_value_fails_naming_the_point(self):
        values = np.full(121 * 61, 100.0)
        values[42] = -5.0
        path = write(size_image(values), "bad_size.vti", vtkXMLImageDataWriter)
        size = simple.XMLImageDataReader(FileName=[path])
        mesh = Triangulation(Input=self.model, TargetEdgeLength=size)
        with st.ErrorCatcher() as errors:
            mesh.UpdatePipeline()
            cells = servermanager.Fetch(mesh).GetNumberOfCells()
        self.assertIn("point 42", errors.text)
        self.assertIn("-5", errors.text)
        self.assertEqual(cells, 0)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
