"""Mesh every model (.vtp) of a folder with StrataMesh; bad files are reported and skipped.

    pvpython example_batch.py [--plugin StrataMesh.so] [--data <folder>] [--out out]
                              [--max-level -1]

For each <name>.vtp of --data (sorted by name) prints a progress line, then writes
<out>/<name>_mesh.vtu (binary) or reports why the file could not be meshed (the error VTK
gave: unreadable file, invalid model, ...) and goes on with the next one. Warnings are listed
under their file; a summary ends the run. Defaults come from the environment:
STRATAMESH_PLUGIN (path of StrataMesh.so; not needed when PV_PLUGIN_PATH already loads the
plugin), STRATAMESH_DATA (the folder, else the repository's Data/), STRATAMESH_OUT (output
folder, else out/).

Exit code: 0 when every file was meshed, 1 when some could not be (or none was found),
2 for wrong arguments.
"""
import argparse
import glob
import os
import re
import sys
import time

from paraview import simple
from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow

HERE = os.path.dirname(os.path.abspath(__file__))


def load_stratamesh(plugin):
    """Loads StrataMesh into paraview.simple, unless PV_PLUGIN_PATH already did."""
    if hasattr(simple, "PhysicalCompressionTriangulation"):
        return
    if not plugin:
        sys.exit("error: StrataMesh is not loaded: give --plugin <path of StrataMesh.so> "
                 "or set PV_PLUGIN_PATH to its folder")
    simple.LoadPlugin(plugin, remote=False)


class VtkMessages:
    """Collects what VTK reports while active, instead of printing it (to the output window
    and to the log on stderr)."""

    def __enter__(self):
        self._window = vtkStringOutputWindow()
        self._previous = vtkOutputWindow.GetInstance()
        self._verbosity = vtkLogger.GetCurrentVerbosityCutoff()
        vtkOutputWindow.SetInstance(self._window)
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        return self

    def __exit__(self, *exc):
        vtkOutputWindow.SetInstance(self._previous)
        vtkLogger.SetStderrVerbosity(self._verbosity)
        return False

    def _messages(self, kind):
        """The messages of one kind ("ERROR" or "Warning"), without file/line and object."""
        found = []
        for block in re.split(r"\n(?=ERROR:|Warning:|Generic Warning:)", self._window.GetOutput()):
            if not block.startswith(kind):
                continue
            lines = block.strip().splitlines()
            text = lines[1] if len(lines) > 1 else lines[0]
            text = re.sub(r"^\S+ \(0x[0-9a-fA-F]+\): ", "", text).strip()
            if not text.startswith("Algorithm ") or "returned failure" not in text:
                found.append(text)
        return found

    @property
    def errors(self):
        return self._messages("ERROR")

    @property
    def warnings(self):
        return self._messages("Warning")


def mesh_file(path, out, max_level):
    """Meshes one model; returns (triangles, output path or None, errors, warnings, seconds)."""
    start = time.time()
    with VtkMessages() as messages:
        model = simple.XMLPolyDataReader(FileName=[path])
        mesh = simple.PhysicalCompressionTriangulation(Input=model, MaxLevel=max_level)
        mesh.UpdatePipeline()
        triangles = mesh.GetDataInformation().GetNumberOfCells()
        vtu = None
        if triangles > 0 and not messages.errors:
            vtu = os.path.join(out, os.path.splitext(os.path.basename(path))[0] + "_mesh.vtu")
            simple.SaveData(vtu, proxy=simple.OutputPort(mesh, 0), DataMode="Binary")
        simple.Delete(mesh)
        simple.Delete(model)
    return triangles, vtu, messages.errors, messages.warnings, time.time() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", default=os.environ.get("STRATAMESH_PLUGIN"),
                        help="path of StrataMesh.so (default: $STRATAMESH_PLUGIN)")
    parser.add_argument("--data", default=os.environ.get(
        "STRATAMESH_DATA", os.path.join(HERE, "..", "..", "Data")),
        help="folder of the models (default: $STRATAMESH_DATA, else the repository's Data/)")
    parser.add_argument("--out", default=os.environ.get("STRATAMESH_OUT", "out"),
                        help="output folder (default: $STRATAMESH_OUT, else out/)")
    parser.add_argument("--max-level", type=int, default=-1,
                        help="MaxLevel of the 4-8 grid (-1: automatic)")
    args = parser.parse_args()

    if not os.path.isdir(args.data):
        parser.error("--data %s is not a folder" % args.data)
    load_stratamesh(args.plugin)
    os.makedirs(args.out, exist_ok=True)
    files = sorted(glob.glob(os.path.join(args.data, "*.vtp")))
    if not files:
        print("no .vtp file in %s" % args.data)
        return 1

    failed = []
    for i, path in enumerate(files, 1):
        name = os.path.basename(path)
        triangles, vtu, errors, warnings, seconds = mesh_file(path, args.out, args.max_level)
        if vtu:
            print("[%d/%d] %s: %d triangles -> %s, %.1f s"
                  % (i, len(files), name, triangles, vtu, seconds), flush=True)
            for warning in warnings:
                print("    warning: " + warning)
        else:
            reason = errors[0] if errors else (warnings[0] if warnings else "empty mesh")
            print("[%d/%d] %s: FAILED, skipped: %s" % (i, len(files), name, reason), flush=True)
            failed.append(name)

    print("meshed %d of %d files into %s%s" % (len(files) - len(failed), len(files), args.out,
                                              "; failed: " + ", ".join(failed) if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
