"""The plugin loads from the build tree and every StrataMesh filter is found by its label."""
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import servermanager  # noqa: E402

# pvpython name -> label in the Filters menu
FILTERS = {
    "PolylineSignedDistance": "Polyline Signed Distance",
    "Adaptive48Grid": "Adaptive 4-8 Grid",
    "Classify48Grid": "Classify 4-8 Grid",
    "PhysicalCompressionTriangulation": "Physical Compression Triangulation",
}


class PluginTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.ns = {}
        st.load_plugin(cls.ns)

    def test_filters_are_functions_in_the_namespace(self):
        for name in FILTERS:
            self.assertIn(name, self.ns, name)

    def test_filters_have_their_menu_labels(self):
        for name, label in FILTERS.items():
            proxy = getattr(servermanager.filters, name)()
            self.assertEqual(proxy.SMProxy.GetXMLLabel(), label)

    def test_filters_are_in_the_stratamesh_menu_category(self):
        definitions = servermanager.ProxyManager().SMProxyManager.GetProxyDefinitionManager()
        for name in FILTERS:
            hints = definitions.GetProxyDefinition("filters", name).FindNestedElementByName("Hints")
            self.assertIsNotNone(hints, name)
            menu = hints.FindNestedElementByName("ShowInMenu")
            self.assertEqual(menu.GetAttribute("category"), "StrataMesh", name)
            self.assertEqual(menu.GetAttribute("icon"), ":/StrataMesh/Icons/stratamesh.svg", name)

    def test_menu_icon_is_compiled_into_the_plugin(self):
        # The Qt resource (Plugin/StrataMesh.qrc) is embedded in the plugin's library.
        with open(st.PLUGIN, "rb") as f:
            self.assertIn(b"stratamesh.svg", f.read())

    def test_region_array_properties_offer_the_inputs_cell_arrays(self):
        from paraview import simple
        for model, expected in (("pinch_out.vtp", ("LeftRegion", "RightRegion")),
                                ("lake_superior.vtp", ("RegionId", "RegionId"))):
            reader = simple.XMLPolyDataReader(FileName=[st.data(model)])
            reader.UpdatePipeline()
            for name in ("PhysicalCompressionTriangulation", "Adaptive48Grid",
                         "Classify48Grid"):
                proxy = self.ns[name](Input=reader)
                domain = proxy.SMProxy.GetProperty("LeftRegionArrayName").GetDomain(
                    "array_list")
                offered = [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]
                self.assertEqual(sorted(set(offered)), sorted(set(expected)), name)
                # The documented default is kept when the input has that array.
                if model == "pinch_out.vtp":
                    self.assertEqual(proxy.LeftRegionArrayName, "LeftRegion")
                    self.assertEqual(proxy.RightRegionArrayName, "RightRegion")
                else:
                    self.assertEqual(proxy.RegionArrayName, "RegionId")
                proxy.UpdatePipeline()
                self.assertGreater(proxy.GetDataInformation().GetNumberOfCells(), 0, name)
                simple.Delete(proxy)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
