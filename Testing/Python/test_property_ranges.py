"""What pvpython users get for property values out of range.

ParaView does not enforce the XML range domains: `mesh.MaxLevel = 99` is accepted by the
proxy and sent to the filter. Before StrataMesh checked ranges, the VTK setter then clamped
99 to 60 silently and the update refined the grid to level 60 (which exhausts the memory).
Now the value reaches the filter unchanged and the update fails with an error naming the
property, its value and its range; fixing the value recovers.
Enumerations are different: ParaView refuses unknown names (ValueError) before the filter."""
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import servermanager, simple  # noqa: E402

NS = {}
st.load_plugin(NS)


def update(proxy):
    """Updates the proxy, returning (number of cells, errors printed by VTK)."""
    with st.ErrorCatcher() as errors:
        proxy.UpdatePipeline()
        cells = servermanager.Fetch(proxy).GetNumberOfCells()
    return cells, errors.text


class PropertyRangeTest(unittest.TestCase):
    def setUp(self):
        self.model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])

    def assert_refused_then_recovered(self, mesh, message, name, value):
        """The update fails with `message` and no cells; with `name` set to `value` it
        recovers."""
        cells, errors = update(mesh)
        self.assertIn(message, errors)
        self.assertEqual(cells, 0)
        setattr(mesh, name, value)
        cells, errors = update(mesh)
        self.assertNotIn("out of range", errors)
        self.assertGreater(cells, 0)

    def test_paraview_accepts_out_of_range_values_in_the_proxy(self):
        mesh = NS["PhysicalCompressionTriangulation"](Input=self.model)
        mesh.MaxLevel = 99  # no exception
        self.assertEqual(mesh.MaxLevel, 99)
        domain = mesh.GetProperty("MaxLevel").SMProperty.GetDomain("range")
        self.assertEqual((domain.GetMinimum(0), domain.GetMaximum(0)), (-1, 60))

    def test_out_of_range_max_level_fails_naming_the_property_and_range(self):
        mesh = NS["PhysicalCompressionTriangulation"](Input=self.model, MaxLevel=99)
        self.assert_refused_then_recovered(
            mesh, "MaxLevel = 99 is out of range [-1, 60]", "MaxLevel", 10)

    def test_out_of_range_doubles_fail_naming_the_property_and_range(self):
        mesh = NS["PhysicalCompressionTriangulation"](Input=self.model, SpringStiffness=0.0,
                                                      FeatureAngle=200.0)
        cells, errors = update(mesh)
        self.assertIn("SpringStiffness = 0 is out of range (0, 1000]", errors)
        self.assertIn("FeatureAngle = 200 is out of range [0, 180]", errors)
        self.assertEqual(cells, 0)

    def test_a_minimum_angle_above_33_degrees_is_refused_before_any_refinement(self):
        # Delaunay refinement is known to end only up to about 33 degrees: at 34 it ran for
        # minutes into meshes worse than at 30, so the range ends at 33.
        mesh = NS["PhysicalCompressionTriangulation"](Input=self.model, MinimumAngle=34.0)
        domain = mesh.GetProperty("MinimumAngle").SMProperty.GetDomain("range")
        self.assertEqual((domain.GetMinimum(0), domain.GetMaximum(0)), (0, 33))
        self.assert_refused_then_recovered(
            mesh, "MinimumAngle = 34 is out of range [0, 33]", "MinimumAngle", 33.0)
        self.assertGreaterEqual(servermanager.Fetch(mesh).GetFieldData().GetArray(
            "MinimumAngle").GetValue(0), 30.0)

    def test_grid_and_distance_filters_check_their_ranges_too(self):
        grid = NS["Adaptive48Grid"](Input=self.model, OutputLevel=70)
        cells, errors = update(grid)
        self.assertIn("OutputLevel = 70 is out of range [-1, 60]", errors)
        self.assertEqual(cells, 0)
        distance = NS["PolylineSignedDistance"](Input=self.model, Source=self.model,
                                                SampleDimensions=[1, 64])
        with st.ErrorCatcher() as caught:
            distance.UpdatePipeline()
        self.assertIn("SampleDimensions[0] = 1 is out of range [2, 16384]", caught.text)

    def test_unknown_enumeration_names_are_refused_by_paraview(self):
        mesh = NS["PhysicalCompressionTriangulation"](Input=self.model)
        with self.assertRaises(ValueError):
            mesh.PushCriterion = "Nowhere"


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
