"""Helpers shared by the pvpython tests: load the plugin from the build tree, find data."""
import os

from paraview import simple

PLUGIN = os.environ["STRATAMESH_PLUGIN"]
DATA = os.environ["STRATAMESH_DATA"]
OUT = os.environ.get("STRATAMESH_OUT", "out")


def load_plugin(namespace):
    """Loads StrataMesh into `namespace` (the filters become functions there).

    paraview.simple only fills a namespace that is not empty, as globals() never is.
    """
    namespace.setdefault("__name__", "stratamesh_plugin")
    simple.LoadPlugin(PLUGIN, remote=False, ns=namespace)


def data(name):
    return os.path.join(DATA, name)


class ErrorCatcher:
    """Collects what VTK prints as errors and warnings while it is active."""

    def __init__(self):
        from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
        self._window = vtkStringOutputWindow()
        self._previous = vtkOutputWindow.GetInstance()
        self._set = vtkOutputWindow.SetInstance

    def __enter__(self):
        self._set(self._window)
        return self

    def __exit__(self, *exc):
        self._set(self._previous)
        return False

    @property
    def text(self):
        return self._window.GetOutput()
