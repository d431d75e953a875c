"""PolylineSignedDistance as pvpython users call it."""
import glob
import os
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import simple, servermanager  # noqa: E402
from vtkmodules.numpy_interface import dataset_adapter as dsa  # noqa: E402
import numpy as np  # noqa: E402

NS = {}
st.load_plugin(NS)
PolylineSignedDistance = NS["PolylineSignedDistance"]


def fetch(proxy):
    return dsa.WrapDataObject(servermanager.Fetch(proxy))


class SignedDistanceTest(unittest.TestCase):
    def test_samples_an_image_over_the_lake_with_the_documented_arrays(self):
        lake = simple.XMLPolyDataReader(FileName=[st.data("lake_superior.vtp")])
        distance = PolylineSignedDistance(Input=lake, Source=lake)
        image = fetch(distance)
        self.assertEqual(image.VTKObject.GetClassName(), "vtkImageData")
        self.assertEqual(image.VTKObject.GetDimensions(), (256, 256, 1))
        for name in ("SignedDistance", "RegionId", "NearestCurve"):
            self.assertIn(name, image.PointData.keys())
        d = np.asarray(image.PointData["SignedDistance"])
        r = np.asarray(image.PointData["RegionId"])
        c = np.asarray(image.PointData["NearestCurve"])
        # Positive exactly inside the lake (region 0), negative outside.
        np.testing.assert_array_equal(d > 0, r == 0)
        self.assertTrue(set(np.unique(r)) <= {-1, 0})
        self.assertTrue(((c >= 0) & (c < 46)).all())
        # The image covers the model's bounds padded by 5%, so its border is outside.
        bounds = image.VTKObject.GetBounds()
        lake_bounds = servermanager.Fetch(lake).GetBounds()
        self.assertAlmostEqual(bounds[0], lake_bounds[0] - 0.05 * (lake_bounds[1] - lake_bounds[0]))
        self.assertLess(d.reshape(256, 256)[0, :].max(), 0.0)
        # About a third of the box is water (the lake covers 82,100 km2 of its bounds' 170,600).
        self.assertGreater((r == 0).mean(), 0.25)
        self.assertLess((r == 0).mean(), 0.45)

    def test_probes_the_points_of_a_given_dataset(self):
        lake = simple.XMLPolyDataReader(FileName=[st.data("lake_superior.vtp")])
        plane = simple.Plane(Origin=[-300000, -150000, 0], Point1=[300000, -150000, 0],
                             Point2=[-300000, 150000, 0], XResolution=40, YResolution=20)
        distance = PolylineSignedDistance(Input=plane, Source=lake)
        out = fetch(distance)
        self.assertEqual(out.VTKObject.GetClassName(), "vtkPolyData")
        self.assertEqual(out.GetNumberOfPoints(), 41 * 21)
        d = np.asarray(out.PointData["SignedDistance"])
        # Points far from every shore of a 590 km lake are never farther than its size.
        self.assertTrue((np.abs(d) < 7e5).all())
        self.assertTrue((d > 0).any() and (d < 0).any())

    def test_shared_curves_model_gives_one_region_per_point(self):
        gulf = simple.XMLPolyDataReader(FileName=[st.data("gulf_section.vtp")])
        distance = PolylineSignedDistance(Input=gulf, Source=gulf, SampleDimensions=[128, 64])
        image = fetch(distance)
        self.assertEqual(image.VTKObject.GetDimensions(), (128, 64, 1))
        r = np.asarray(image.PointData["RegionId"])
        d = np.asarray(image.PointData["SignedDistance"])
        np.testing.assert_array_equal(d >= 0, r >= 0)
        # Inside the section's box (the pad excluded) many of the 15 layers are hit.
        self.assertGreaterEqual(len(np.unique(r[r >= 0])), 10)

    def test_properties_are_reachable_by_their_xml_names(self):
        lake = simple.XMLPolyDataReader(FileName=[st.data("lake_superior.vtp")])
        distance = PolylineSignedDistance(Input=lake, Source=lake)
        self.assertEqual(list(distance.SampleDimensions), [256, 256])
        self.assertEqual(distance.Form, "Auto")
        self.assertEqual(distance.RegionArrayName, "RegionId")
        self.assertEqual(distance.LeftRegionArrayName, "LeftRegion")
        self.assertEqual(distance.RightRegionArrayName, "RightRegion")

    def test_bad_models_fail_with_an_error_naming_the_defect(self):
        expected = {
            "nan_coordinate.vtp": "point 5",
            "self_intersecting_loop.vtp": "250",
            "no_region_array.vtp": "region array",
            "unclosed_boundary_shared.vtp": "dangling",
            "inconsistent_labels.vtp": "inconsistent",
        }
        for name, needle in expected.items():
            with self.subTest(name=name):
                model = simple.XMLPolyDataReader(FileName=[st.data("bad_inputs/" + name)])
                distance = PolylineSignedDistance(Input=model, Source=model,
                                                  SampleDimensions=[8, 8])
                with st.ErrorCatcher() as errors:
                    distance.UpdatePipeline()
                self.assertIn("ERROR", errors.text)
                self.assertIn(needle, errors.text)
                self.assertEqual(servermanager.Fetch(distance).GetNumberOfPoints(), 0)
                simple.Delete(distance)
                simple.Delete(model)

    def test_empty_model_gives_empty_output_and_a_warning(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("bad_inputs/empty.vtp")])
        distance = PolylineSignedDistance(Input=model, Source=model)
        with st.ErrorCatcher() as errors:
            distance.UpdatePipeline()
        self.assertIn("Warning", errors.text)
        self.assertNotIn("ERROR", errors.text)
        self.assertEqual(servermanager.Fetch(distance).GetNumberOfPoints(), 0)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
