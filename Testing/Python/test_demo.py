"""The README's main job (scripts/demo.py) writes the mesh, its boundary, a picture and a
summary."""
import os
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEMO = os.path.join(HERE, "..", "..", "scripts", "demo.py")


class DemoTest(unittest.TestCase):
    def test_demo_writes_mesh_boundary_png_and_summary(self):
        from paraview import simple
        # Run in this pvbatch process, as `pvbatch scripts/demo.py` would.
        out = st.OUT
        sys.argv = [DEMO, "--plugin", st.PLUGIN, "--model", st.data("lake_superior.vtp"),
                    "--out", out]
        with open(DEMO) as f:
            code = compile(f.read(), DEMO, "exec")
        try:
            exec(code, {"__name__": "__main__"})
        except SystemExit as e:
            self.assertEqual(e.code, 0)
        vtu = os.path.join(out, "lake_superior_mesh.vtu")
        vtp = os.path.join(out, "lake_superior_boundary.vtp")
        png = os.path.join(out, "lake_superior_mesh.png")
        # Debian's ParaView reads back what the demo wrote (binary, not appended, data).
        mesh = simple.XMLUnstructuredGridReader(FileName=[vtu])
        mesh.UpdatePipeline()
        info = mesh.GetDataInformation()
        self.assertGreater(info.GetNumberOfCells(), 1000)
        self.assertIn("RegionId", mesh.CellData.keys())
        boundary = simple.XMLPolyDataReader(FileName=[vtp])
        boundary.UpdatePipeline()
        self.assertGreater(boundary.GetDataInformation().GetNumberOfCells(), 45)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
