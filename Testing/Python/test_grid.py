"""Adaptive48Grid and Classify48Grid as pvpython users call them."""
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import simple, servermanager  # noqa: E402
from vtkmodules.numpy_interface import dataset_adapter as dsa  # noqa: E402
import numpy as np  # noqa: E402

NS = {}
st.load_plugin(NS)


class GridTest(unittest.TestCase):
    def setUp(self):
        self.model = simple.XMLPolyDataReader(FileName=[st.data("salt_dome.vtp")])

    def test_grid_has_levels_and_45_90_degree_triangles(self):
        grid = NS["Adaptive48Grid"](Input=self.model, MaxLevel=10)
        out = dsa.WrapDataObject(servermanager.Fetch(grid))
        self.assertIn("Level", out.CellData.keys())
        self.assertIn("Level", out.PointData.keys())
        self.assertEqual(int(out.FieldData["MaxLevel"][0]), 10)
        pts = np.asarray(out.Points)[:, :2]
        cells = np.asarray(out.Cells).reshape(-1, 4)[:, 1:]
        a, b, c = pts[cells[:, 0]], pts[cells[:, 1]], pts[cells[:, 2]]

        def angle(p, q, r):
            u, v = q - p, r - p
            cos = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
            return np.degrees(np.arccos(np.clip(cos, -1, 1)))
        angles = np.concatenate([angle(a, b, c), angle(b, c, a), angle(c, a, b)])
        self.assertTrue(np.allclose(np.minimum(np.abs(angles - 45), np.abs(angles - 90)), 0,
                                    atol=1e-9))

    def test_output_level_changes_the_count_as_the_hierarchy_says(self):
        grid = NS["Adaptive48Grid"](Input=self.model, MaxLevel=10)
        counts = []
        for level in range(0, 11):
            grid.OutputLevel = level
            grid.UpdatePipeline()
            counts.append(grid.GetDataInformation().GetNumberOfCells())
        self.assertEqual(counts[0], 4)
        self.assertEqual(counts[1], 8)  # every level-0 triangle bisected: the grid is refined
        self.assertTrue(all(b >= a for a, b in zip(counts, counts[1:])), counts)
        # A level's mesh has at most twice the triangles of the level before.
        self.assertTrue(all(b <= 2 * a for a, b in zip(counts, counts[1:])), counts)
        grid.OutputLevel = -1
        grid.UpdatePipeline()
        self.assertGreaterEqual(grid.GetDataInformation().GetNumberOfCells(), counts[-1])

    def test_thin_layer_refinement_refines_beyond_the_local_level(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("faulted_thin_layers.vtp")])
        grid = NS["Adaptive48Grid"](Input=model)
        default = dsa.WrapDataObject(servermanager.Fetch(grid))
        grid.ThinLayerRefinement = 1
        thin = dsa.WrapDataObject(servermanager.Fetch(grid))
        local = int(default.FieldData["LocalMaxLevel"][0])
        self.assertLessEqual(int(np.asarray(default.CellData["Level"]).max()), local + 8)
        self.assertGreater(thin.GetNumberOfCells(), default.GetNumberOfCells())
        finer = (np.asarray(thin.CellData["Level"]) > local).sum()
        self.assertGreater(finer, (np.asarray(default.CellData["Level"]) > local).sum())

    def test_classified_grid_has_the_documented_arrays(self):
        classes = NS["Classify48Grid"](Input=self.model, MaxLevel=10)
        grid = dsa.WrapDataObject(servermanager.Fetch(classes, idx=0))
        edges = dsa.WrapDataObject(servermanager.Fetch(classes, idx=1))
        for name in ("VertexClass", "VertexRegion"):
            self.assertIn(name, grid.PointData.keys())
        self.assertIn("CellRegion", grid.CellData.keys())
        for name in ("EdgeClass", "EdgeRegion"):
            self.assertIn(name, edges.CellData.keys())
        vclass = np.asarray(grid.PointData["VertexClass"])
        vregion = np.asarray(grid.PointData["VertexRegion"])
        self.assertTrue(set(np.unique(vclass)) <= {0, 1, 2})
        self.assertTrue((vclass == 0).any() and (vclass == 2).any())
        self.assertTrue((vregion[vclass == 0] == -1).all())
        self.assertEqual(set(np.unique(vregion[vclass == 2])), set(range(6)))
        eclass = np.asarray(edges.CellData["EdgeClass"])
        self.assertTrue((eclass == 2).any() and (eclass == 1).any() and (eclass == 0).any())


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
