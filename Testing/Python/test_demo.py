"""The README's main job (scripts/demo.py) writes its image and picture and a summary."""
import os
import subprocess
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEMO = os.path.join(HERE, "..", "..", "scripts", "demo.py")


class DemoTest(unittest.TestCase):
    def test_demo_writes_vti_png_and_summary(self):
        from paraview import simple
        # Run in this pvbatch process, as `pvbatch scripts/demo.py` would.
        out = st.OUT
        sys.argv = [DEMO, "--plugin", st.PLUGIN, "--model", st.data("lake_superior.vtp"),
                    "--out", out, "--samples", "128"]
        with open(DEMO) as f:
            code = compile(f.read(), DEMO, "exec")
        try:
            exec(code, {"__name__": "__main__"})
        except SystemExit as e:
            self.assertEqual(e.code, 0)
        vti = os.path.join(out, "lake_superior_distance.vti")
        png = os.path.join(out, "lake_superior_distance.png")
        self.assertTrue(os.path.getsize(vti) > 1000)
        self.assertTrue(os.path.getsize(png) > 1000)
        # Debian's ParaView reads back what the demo wrote (binary, not appended, data).
        reader = simple.XMLImageDataReader(FileName=[vti])
        reader.UpdatePipeline()
        info = reader.GetDataInformation()
        self.assertEqual(info.GetNumberOfPoints(), 128 * 128)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
