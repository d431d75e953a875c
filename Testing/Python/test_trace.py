"""A Python trace of a StrataMesh session replays: the traced script, run in a fresh namespace
where the plugin is loaded, rebuilds the same proxies with the same properties and the same
mesh. (ParaView 5.11's trace API is paraview.smtrace.start_trace/stop_trace;
simple.StartTrace/StopTrace only exist in later versions.)"""
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import servermanager, simple, smtrace  # noqa: E402

NS = {}
st.load_plugin(NS)


def property_values(proxy):
    """{name: value} of every property but the input, as Python values."""
    values = {}
    for name in proxy.ListProperties():
        if name == "Input":
            continue
        value = proxy.GetPropertyValue(name)
        values[name] = list(value) if hasattr(value, "__len__") and not isinstance(value, str) \
            else value
    return values


def triangles(proxy):
    return servermanager.Fetch(proxy).GetNumberOfCells()


class TraceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        smtrace.start_trace()
        model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])
        cls.mesh = NS["PhysicalCompressionTriangulation"](Input=model, MaxLevel=11,
                                                          Optimization=0)
        cls.trace = smtrace.stop_trace()
        cls.before = set(simple.GetSources().values())
        # Replay: a fresh namespace, the plugin loaded into it, the trace executed there.
        cls.replay_ns = {}
        st.load_plugin(cls.replay_ns)
        exec(compile(cls.trace, "<trace>", "exec"), cls.replay_ns)
        created = [p for p in simple.GetSources().values() if p not in cls.before]
        meshes = [p for p in created if p.GetXMLName() == "PhysicalCompressionTriangulation"]
        cls.replayed = meshes[0] if len(meshes) == 1 else None

    def test_trace_records_the_filter_and_its_non_default_properties(self):
        self.assertIn("PhysicalCompressionTriangulation(", self.trace)
        self.assertIn(".MaxLevel = 11", self.trace)
        self.assertIn(".Optimization = 0", self.trace)
        self.assertIn("pinch_out.vtp", self.trace)

    def test_replay_creates_one_reader_and_one_triangulation(self):
        created = [p for p in simple.GetSources().values() if p not in self.before]
        self.assertEqual(sorted(p.GetXMLName() for p in created),
                         ["PhysicalCompressionTriangulation", "XMLPolyDataReader"])
        self.assertIsNotNone(self.replayed)

    def test_replayed_proxy_has_the_same_properties(self):
        original = property_values(self.mesh)
        replayed = property_values(self.replayed)
        self.assertEqual(replayed["MaxLevel"], 11)
        self.assertEqual(replayed["Optimization"], 0)
        self.assertEqual(replayed, original)

    def test_replayed_pipeline_gives_the_same_number_of_triangles(self):
        count = triangles(self.mesh)
        self.assertGreater(count, 0)
        self.assertEqual(triangles(self.replayed), count)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
