"""With PV_PLUGIN_PATH pointing at the plugin's folder, pvpython loads StrataMesh by itself:
no LoadPlugin, the filters are in paraview.simple, and they run. (Run with PV_PLUGIN_PATH
set and no other way to find the plugin.)"""
import os
import sys
import unittest

from paraview import servermanager, simple
from paraview.modules.vtkRemotingCore import vtkPVPluginTracker

DATA = os.environ["STRATAMESH_DATA"]


class PluginPathTest(unittest.TestCase):
    def test_plugin_is_loaded_from_PV_PLUGIN_PATH(self):
        folder = os.path.realpath(os.environ["PV_PLUGIN_PATH"])
        tracker = vtkPVPluginTracker.GetInstance()
        found = [i for i in range(tracker.GetNumberOfPlugins())
                 if tracker.GetPluginName(i) == "StrataMesh"]
        self.assertEqual(len(found), 1)
        self.assertTrue(tracker.GetPluginLoaded(found[0]))
        self.assertEqual(os.path.dirname(os.path.realpath(tracker.GetPluginFileName(found[0]))),
                         folder)

    def test_filters_are_in_paraview_simple_without_LoadPlugin(self):
        for name in ("PolylineSignedDistance", "Adaptive48Grid", "Classify48Grid",
                     "PhysicalCompressionTriangulation"):
            self.assertTrue(hasattr(simple, name), name)
            self.assertTrue(hasattr(servermanager.filters, name), name)

    def test_triangulation_runs(self):
        model = simple.XMLPolyDataReader(FileName=[os.path.join(DATA, "pinch_out.vtp")])
        mesh = simple.PhysicalCompressionTriangulation(Input=model)
        self.assertGreater(servermanager.Fetch(mesh).GetNumberOfCells(), 0)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
