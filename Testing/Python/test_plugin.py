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


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
