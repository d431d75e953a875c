"""Drives the real ParaView GUI for a ctest (run with pvpython, which reads the PNG back):

    pvpython run_gui_test.py --paraview <paraview> [--xvfb <Xvfb>] --load plugins|env
        --plugin-dir <folder of StrataMesh.so> --data <Data> --out <folder> [--timeout 100]

Starts `paraview --dr --script=gui_mesh_screenshot.py --exit` in a private virtual X display
(xvfb.py: Xvfb on a display it picks itself, so parallel tests cannot collide as with
`xvfb-run -a`), with the plugin loaded by `--plugin-search-paths <dir> --plugins StrataMesh`
(--load plugins; --plugins takes names, not paths) or only through PV_PLUGIN_PATH (--load
env). HOME, XDG_CONFIG_HOME and XDG_RUNTIME_DIR point into the output folder and --dr
(disable registry) keeps ParaView from reading or writing user settings, so a fresh CI
machine and a developer's machine behave the same. Then checks what the script wrote and
that the screenshot is a real picture: 800x600, more than 3 distinct colours, and at least
10% of it not background (the mesh is there, not only the orientation axes). Exit code 0 on
success, 1 on failure, 77 (skipped) without Xvfb nor a DISPLAY.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from xvfb import SKIP, VirtualDisplay  # noqa: E402


def picture_statistics(png):
    """(distinct RGB colours, fraction of pixels not of the commonest colour, (width,
    height)) of a PNG, read with VTK's PNG reader."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    import numpy as np
    reader = vtkPNGReader()
    if not reader.CanReadFile(png):
        return 0, 0.0, (0, 0)
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())
    rgb = pixels[:, :3].astype(np.uint32)
    packed = (rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]
    colours, counts = np.unique(packed, return_counts=True)
    foreground = 1.0 - counts.max() / float(len(packed))
    return len(colours), foreground, tuple(image.GetDimensions()[:2])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paraview", required=True)
    parser.add_argument("--xvfb", default="", help="Xvfb (default: the current DISPLAY)")
    parser.add_argument("--load", choices=("plugins", "env"), required=True)
    parser.add_argument("--plugin-dir", required=True)
    parser.add_argument("--data", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--model", default="salt_dome.vtp")
    parser.add_argument("--timeout", type=float, default=100.0)
    args = parser.parse_args()

    out = os.path.abspath(args.out)
    shutil.rmtree(out, ignore_errors=True)
    home = os.path.join(out, "home")
    runtime = os.path.join(out, "runtime")
    os.makedirs(home)
    os.makedirs(runtime, mode=0o700)

    env = dict(os.environ)
    env.update({
        "HOME": home,
        "XDG_CONFIG_HOME": os.path.join(home, ".config"),
        "XDG_RUNTIME_DIR": runtime,
        "STRATAMESH_DATA": os.path.abspath(args.data),
        "STRATAMESH_OUT": out,
        "STRATAMESH_MODEL": args.model,
    })
    env.pop("PV_PLUGIN_PATH", None)
    env.pop("PV_PLUGIN_CONFIG_FILE", None)
    command = [args.paraview, "--dr"]
    if args.load == "plugins":
        command += ["--plugin-search-paths=" + args.plugin_dir, "--plugins=StrataMesh"]
    else:
        env["PV_PLUGIN_PATH"] = args.plugin_dir
    command += ["--script=" + os.path.join(HERE, "gui_mesh_screenshot.py"), "--exit"]

    with VirtualDisplay(args.xvfb or None) as virtual:
        if virtual.display:
            env["DISPLAY"] = virtual.display
            env.pop("XAUTHORITY", None)
        elif not env.get("DISPLAY"):
            print("skipped: no Xvfb and no DISPLAY to run the ParaView GUI in")
            return SKIP
        print("running (DISPLAY=%s): %s" % (env["DISPLAY"], " ".join(command)), flush=True)
        try:
            run = subprocess.run(command, env=env, cwd=out, timeout=args.timeout,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 universal_newlines=True)
        except subprocess.TimeoutExpired as e:
            print(e.output or "")
            print("FAIL: the ParaView GUI did not finish within %g s" % args.timeout)
            return 1
    print(run.stdout)
    print("paraview exit code:", run.returncode)

    failures = []
    result_file = os.path.join(out, "result.json")
    if not os.path.exists(result_file):
        print("FAIL: the GUI script did not finish (no result.json; its error is above)")
        return 1
    with open(result_file) as f:
        result = json.load(f)
    print("result:", json.dumps(result))
    if run.returncode != 0:
        failures.append("paraview exited with %d" % run.returncode)
    if not os.path.basename(result["executable"]).startswith("paraview"):
        failures.append("the script ran in %s, not in the paraview GUI" % result["executable"])
    if result["label"] != "Physical Compression Triangulation":
        failures.append("filter label %r" % result["label"])
    if result["cells"] <= 0:
        failures.append("the mesh has no triangles")
    if "RegionId" not in result["cell_arrays"]:
        failures.append("no RegionId cell array")
    png = result["png"]
    if not os.path.exists(png):
        failures.append("no screenshot " + png)
    else:
        colours, foreground, size = picture_statistics(png)
        print("screenshot %s: %dx%d, %d colours, %.0f%% not background"
              % (png, size[0], size[1], colours, 100.0 * foreground))
        if size != (800, 600):
            failures.append("screenshot size %s, not 800x600" % (size,))
        if colours <= 3:
            failures.append("the screenshot is blank (%d colours)" % colours)
        if foreground < 0.1:
            failures.append("the mesh is missing from the screenshot (%.1f%% not background)"
                            % (100.0 * foreground))
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
