"""example_batch.py as a user runs it (its own pvpython process) on a folder with three good
models, one invalid model from Data/bad_inputs and one file that is not a model: a progress
line per file, the bad ones reported with their error and skipped, the good ones meshed into
binary .vtu files that read back, exit code 1 (some files failed)."""
import os
import shutil
import subprocess
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import simple  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
GOOD = ["nested_holes.vtp", "pinch_out.vtp", "salt_dome.vtp"]
BAD = {"crossing_curves.vtp": "cross", "not_a_model.vtp": "Error parsing XML"}


class ExampleBatchTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = os.path.join(st.OUT, "models")
        cls.out = os.path.join(st.OUT, "meshes")
        for folder in (cls.folder, cls.out):
            shutil.rmtree(folder, ignore_errors=True)
        os.makedirs(cls.folder)
        for name in GOOD:
            shutil.copy(st.data(name), cls.folder)
        shutil.copy(st.data(os.path.join("bad_inputs", "crossing_curves.vtp")), cls.folder)
        with open(os.path.join(cls.folder, "not_a_model.vtp"), "w") as f:
            f.write("this is not a VTK XML file\n")
        with open(os.path.join(cls.folder, "notes.txt"), "w") as f:
            f.write("not a .vtp: ignored\n")
        cls.proc = subprocess.run(
            [os.environ["STRATAMESH_PVPYTHON"], os.path.join(HERE, "example_batch.py"),
             "--plugin", st.PLUGIN, "--data", cls.folder, "--out", cls.out],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
            timeout=120)
        print(cls.proc.stdout)
        print(cls.proc.stderr, file=sys.stderr)
        cls.lines = cls.proc.stdout.splitlines()

    def test_exit_code_says_some_files_failed(self):
        self.assertEqual(self.proc.returncode, 1)
        self.assertNotIn("Traceback", self.proc.stderr)

    def test_one_progress_line_per_model_in_name_order(self):
        progress = [line for line in self.lines if line.startswith("[")]
        names = sorted(GOOD + list(BAD))
        self.assertEqual(len(progress), len(names))
        for i, (line, name) in enumerate(zip(progress, names), 1):
            self.assertTrue(line.startswith("[%d/%d] %s: " % (i, len(names), name)), line)

    def test_bad_files_are_reported_with_their_error_and_skipped(self):
        for name, reason in BAD.items():
            line = next(line for line in self.lines if "] %s: " % name in line)
            self.assertIn("FAILED, skipped", line)
            self.assertIn(reason, line)
            self.assertFalse(os.path.exists(os.path.join(self.out, name[:-4] + "_mesh.vtu")))
        self.assertIn("meshed 3 of 5 files", self.lines[-1])
        self.assertIn("failed: crossing_curves.vtp, not_a_model.vtp", self.lines[-1])

    def test_good_files_are_meshed_into_binary_vtu_that_reads_back(self):
        for name in GOOD:
            vtu = os.path.join(self.out, name[:-4] + "_mesh.vtu")
            with open(vtu, "rb") as f:
                head = f.read(2000)
            self.assertIn(b'format="binary"', head)
            self.assertNotIn(b'format="appended"', head)
            reader = simple.XMLUnstructuredGridReader(FileName=[vtu])
            reader.UpdatePipeline()
            self.assertGreater(reader.GetDataInformation().GetNumberOfCells(), 0, name)
            self.assertIn("RegionId", reader.CellData.keys())


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
