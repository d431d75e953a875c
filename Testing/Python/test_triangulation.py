"""PhysicalCompressionTriangulation as pvpython users call it."""
import math
import sys
import unittest

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import stratamesh_testing as st  # noqa: E402
from paraview import simple, servermanager  # noqa: E402
from vtkmodules.numpy_interface import dataset_adapter as dsa  # noqa: E402
import numpy as np  # noqa: E402

NS = {}
st.load_plugin(NS)
Triangulation = NS["PhysicalCompressionTriangulation"]


def signed_areas(mesh):
    pts = np.asarray(mesh.Points)[:, :2]
    cells = np.asarray(mesh.Cells).reshape(-1, 4)[:, 1:]
    a, b, c = pts[cells[:, 0]], pts[cells[:, 1]], pts[cells[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def min_angles(mesh):
    """Smallest angle of each triangle in degrees, from the points."""
    pts = np.asarray(mesh.Points)[:, :2]
    tri = pts[np.asarray(mesh.Cells).reshape(-1, 4)[:, 1:]]
    angles = []
    for i in range(3):
        u = tri[:, (i + 1) % 3] - tri[:, i]
        v = tri[:, (i + 2) % 3] - tri[:, i]
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        angles.append(np.degrees(np.arctan2(np.abs(cross), (u * v).sum(axis=1))))
    return np.min(angles, axis=0)


def pieces(mesh, region, floor):
    """Pieces of `region` at least `floor` in area: its triangles joined across shared edges."""
    cells = np.asarray(mesh.Cells).reshape(-1, 4)[:, 1:]
    regions = np.asarray(mesh.CellData["RegionId"])
    areas = np.abs(signed_areas(mesh))
    mine = np.nonzero(regions == region)[0]
    parent = {int(t): int(t) for t in mine}

    def find(t):
        while parent[t] != t:
            parent[t] = parent[parent[t]]
            t = parent[t]
        return t

    first = {}
    for t in mine:
        for k in range(3):
            a, b = cells[t, k], cells[t, (k + 1) % 3]
            key = (min(a, b), max(a, b))
            if key in first:
                parent[find(first[key])] = find(int(t))
            else:
                first[key] = int(t)
    sums = {}
    for t in mine:
        root = find(int(t))
        sums[root] = sums.get(root, 0.0) + areas[t]
    return sum(1 for value in sums.values() if value >= floor)


def field(mesh, name):
    """A field data value; fails when the array is missing (dsa gives a silent VTKNoneArray)."""
    array = mesh.VTKObject.GetFieldData().GetArray(name)
    if array is None:
        raise AssertionError("no field data array " + name)
    return array.GetTuple1(0)


def default_and_changed(file_name, **changes):
    """The mesh of a Data model with the default properties, then with `changes` applied."""
    mesh = Triangulation(Input=simple.XMLPolyDataReader(FileName=[st.data(file_name)]))
    default = dsa.WrapDataObject(servermanager.Fetch(mesh))
    for name, value in changes.items():
        setattr(mesh, name, value)
    return default, dsa.WrapDataObject(servermanager.Fetch(mesh))


class TriangulationTest(unittest.TestCase):
    def test_properties_have_the_documented_defaults_and_names(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])
        mesh = Triangulation(Input=model)
        self.assertEqual(mesh.MaxLevel, -1)
        self.assertEqual(mesh.LocalMaxLevel, -1)
        self.assertEqual(mesh.SpringConfiguration, "Edge and projection springs")
        self.assertEqual(mesh.PushCriterion, "One side of the boundary")
        self.assertEqual(mesh.FlipDegenerate, 1)
        self.assertEqual(mesh.Optimization, 1)
        self.assertAlmostEqual(mesh.FeatureAngle, 140.0)
        self.assertAlmostEqual(mesh.BoundaryTolerance, 0.25)
        self.assertAlmostEqual(mesh.MinimumAngle, 30.0)
        self.assertEqual(mesh.CurveRecovery, 1)
        self.assertEqual(mesh.KeepSharpCorners, 0)
        self.assertEqual(mesh.ThinLayerRefinement, 0)
        self.assertEqual(mesh.ThinLayerRetry, 1)
        for name in ("SpringStiffness", "Damping", "TimeStep", "MaxIterations", "PushVelocity",
                     "Tolerance", "Form", "RegionArrayName", "MaximumEdgeLength",
                     "MinimumEdgeLength"):
            self.assertTrue(hasattr(mesh, name), name)

    def test_meshes_a_shared_curves_model_conserving_region_areas(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("salt_dome_loops.vtp")])
        mesh = Triangulation(Input=model, MaxLevel=11)
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        areas = signed_areas(out)
        self.assertTrue((areas > 0).all(), "every triangle counter-clockwise")
        region = np.asarray(out.CellData["RegionId"])
        self.assertEqual(set(np.unique(region)), set(range(6)))
        np.testing.assert_allclose(np.asarray(out.CellData["Area"]), areas, rtol=1e-9)
        # The salt dome section is a 12000 x 6000 box: the regions fill it.
        self.assertAlmostEqual(areas.sum() / (12000.0 * 6000.0), 1.0, delta=0.02)
        for name in ("MinimumAngle", "MaximumAngle", "RadiusRatio", "Level"):
            self.assertIn(name, out.CellData.keys())
        for name in ("VertexClass", "Displacement"):
            self.assertIn(name, out.PointData.keys())
        self.assertGreater(out.FieldData["MinimumAngle"][0], 0.0)

    def test_thin_regions_are_reported_and_boundary_splits_counted(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("thin_layer.vtp")])
        mesh = Triangulation(Input=model, MinimumEdgeLength=4.0)
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        # Region 1 is a layer 1.0 thick and 1000 wide (area ~1000): with no edge shorter than 4,
        # thinner than any triangle (at the default sizes the curve recovery keeps it).
        unresolved = np.asarray(out.FieldData["UnresolvedRegions"]).ravel()
        self.assertEqual(list(unresolved), [1])
        region = np.asarray(out.CellData["RegionId"])
        self.assertLess(np.asarray(out.CellData["Area"])[region == 1].sum(), 500.0)
        self.assertGreaterEqual(out.FieldData["BoundarySplits"][0], 0)
        lake = simple.XMLPolyDataReader(FileName=[st.data("lake_superior.vtp")])
        # The compression's boundary refinement alone (the curve recovery also pulls the
        # boundary onto the curves).
        on = dsa.WrapDataObject(servermanager.Fetch(Triangulation(Input=lake, CurveRecovery=0)))
        off = dsa.WrapDataObject(servermanager.Fetch(
            Triangulation(Input=lake, CurveRecovery=0, BoundaryTolerance=0.0)))
        self.assertGreater(on.FieldData["BoundarySplits"][0], 0)
        self.assertEqual(off.FieldData["BoundarySplits"][0], 0)
        self.assertLess(on.FieldData["MaxBoundaryDeviation"][0],
                        off.FieldData["MaxBoundaryDeviation"][0])

    def test_boundary_vertices_off_the_curves_are_measured(self):
        # With Optimization off (the paper's method) two vertices of lake_superior's boundary
        # stay off the curves (the farthest 3251 units, measured); the default settings put
        # every one on a curve (issue 4: within 1e-9 of the model's size).
        reader = simple.XMLPolyDataReader(FileName=[st.data("lake_superior.vtp")])
        bounds = servermanager.Fetch(reader).GetBounds()
        size = math.hypot(bounds[1] - bounds[0], bounds[3] - bounds[2])
        default, paper = default_and_changed("lake_superior.vtp", Optimization=0)
        self.assertLessEqual(field(default, "MaxBoundaryVertexDistance"), 1e-9 * size)
        self.assertGreater(field(paper, "MaxBoundaryVertexDistance"), 1e-3 * size)

    def test_boundary_port_gives_shared_curves(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])
        mesh = Triangulation(Input=model)
        boundary = dsa.WrapDataObject(servermanager.Fetch(mesh, idx=1))
        left = np.asarray(boundary.CellData["LeftRegion"])
        right = np.asarray(boundary.CellData["RightRegion"])
        self.assertGreater(len(left), 0)
        self.assertTrue((left != right).all())
        self.assertEqual(set(np.unique(np.concatenate([left, right]))), {-1, 0, 1, 2})

    def test_edge_lengths_in_model_units_choose_the_levels(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])
        mesh = Triangulation(Input=model)
        self.assertEqual(mesh.MaximumEdgeLength, 0.0)
        self.assertEqual(mesh.MinimumEdgeLength, 0.0)
        # pinch_out is 1000 x 100: the grid's square has side 1100, hypotenuses 1100 / 2^(l/2).
        mesh.MaximumEdgeLength = 50.0
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        level = np.asarray(out.CellData["Level"])
        self.assertGreaterEqual(level.min(), 9)  # level 9: 48.6, the coarsest <= 50
        pts = np.asarray(out.Points)[:, :2]
        cells = np.asarray(out.Cells).reshape(-1, 4)[:, 1:]
        edges = [np.linalg.norm(pts[cells[:, i]] - pts[cells[:, (i + 1) % 3]], axis=1)
                 for i in range(3)]
        longest = max(e.max() for e in edges)
        self.assertLessEqual(longest, 50.0 * (1 + 1e-9))  # no mesh edge is longer
        # MinimumEdgeLength caps every level: here at level 12 (hypotenuse 17.2 >= 15).
        mesh.MaximumEdgeLength = 0.0
        mesh.MinimumEdgeLength = 15.0
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        self.assertLessEqual(np.asarray(out.CellData["Level"]).max(), 12)
        self.assertGreater(out.GetNumberOfCells(), 0)
        # The field data says the finest edge length the mesh aimed at: the user's.
        self.assertEqual(field(out, "FinestEdgeLength"), 15.0)

    def test_maximum_edge_length_bounds_every_mesh_edge(self):
        # On the salt dome at 206.25 the compression stretches edges to 1.3 times that; the
        # refinement splits them (boundary ones on their curves) and the areas are kept.
        default, mesh = default_and_changed("salt_dome.vtp", MaximumEdgeLength=206.25)
        pts = np.asarray(mesh.Points)[:, :2]
        cells = np.asarray(mesh.Cells).reshape(-1, 4)[:, 1:]
        longest = max(np.linalg.norm(pts[cells[:, i]] - pts[cells[:, (i + 1) % 3]], axis=1).max()
                      for i in range(3))
        self.assertLessEqual(longest, 206.25 * (1 + 1e-9))
        self.assertGreaterEqual(min_angles(mesh).min(), 30.0 - 1e-6)
        self.assertTrue(np.all(signed_areas(mesh) > 0))
        self.assertAlmostEqual(signed_areas(mesh).sum() / signed_areas(default).sum(), 1.0, 3)

    def test_minimum_angle_refines_to_the_bound_and_zero_turns_it_off(self):
        on, off = default_and_changed("salt_dome.vtp", MinimumAngle=0.0)
        self.assertGreater(on.FieldData["RefinementVertices"][0], 0)
        self.assertEqual(off.FieldData["RefinementVertices"][0], 0)
        # Recomputed from the points, not taken from the filter's arrays.
        for out in (on, off):
            self.assertTrue((signed_areas(out) > 0).all())
        smallest = min_angles(on).min()
        self.assertGreaterEqual(smallest, 30.0 - 1e-6)
        self.assertGreater(smallest, min_angles(off).min())

    def test_keep_sharp_corners_meshes_the_pinch_out_to_its_apex(self):
        off, on = default_and_changed("pinch_out.vtp", KeepSharpCorners=1)
        self.assertIsNone(off.VTKObject.GetFieldData().GetArray("KeptCorners"))
        self.assertEqual(field(on, "KeptCorners"), 1)
        self.assertGreater(field(on, "KeptCornerTriangles"), 0)
        # The kept wedge keeps the input's 1 degree; away from it the bound holds.
        self.assertLess(field(on, "MinimumAngle"), 25.0)
        self.assertGreaterEqual(field(on, "MinimumAngleUnforced"), 29.95)
        self.assertEqual(field(off, "MinimumAngleUnforced"), field(off, "MinimumAngle"))
        # Region 1 pinches out at (600, 40) at 1 degree: with the option its triangles reach
        # the apex and keep the input's angle there; without, they end well before it.
        apex = np.array([600.0, 40.0])
        for out, reaches in ((off, False), (on, True)):
            pts = np.asarray(out.Points)[:, :2]
            cells = np.asarray(out.Cells).reshape(-1, 4)[:, 1:]
            layer = cells[np.asarray(out.CellData["RegionId"]) == 1]
            at_apex = np.linalg.norm(pts[layer] - apex, axis=2) < 1e-9
            self.assertEqual(bool(at_apex.any()), reaches)
            self.assertTrue((signed_areas(out) > 0).all())
        pts = np.asarray(on.Points)[:, :2]
        cells = np.asarray(on.Cells).reshape(-1, 4)[:, 1:]
        layer = cells[np.asarray(on.CellData["RegionId"]) == 1]
        total = 0.0
        for tri in layer:
            for i in range(3):
                if np.linalg.norm(pts[tri[i]] - apex) < 1e-9:
                    u, v = pts[tri[(i + 1) % 3]] - apex, pts[tri[(i + 2) % 3]] - apex
                    total += np.degrees(np.arctan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v))
        self.assertAlmostEqual(total, 1.0, delta=0.05)

    def test_curve_recovery_brings_back_the_thin_layer(self):
        # (Without ThinLayerRetry: the mesh without the recovery misses the area bound, and the
        # retry's thin layer refinement would bring the layer back by itself.)
        on, off = default_and_changed("thin_layer.vtp", CurveRecovery=0, ThinLayerRetry=0)
        self.assertEqual(field(off, "CurveVertices"), 0)
        self.assertGreater(field(on, "CurveVertices"), 0)
        layer = [np.abs(signed_areas(out))[np.asarray(out.CellData["RegionId"]) == 1].sum()
                 for out in (off, on)]
        # The layer is 1.0 thick and 1000 long: about 8% of it without, most of it with.
        self.assertLess(layer[0], 200.0)
        self.assertGreater(layer[1], 500.0)
        self.assertTrue((signed_areas(on) > 0).all())

    def test_the_corners_of_a_sections_box_are_mesh_vertices(self):
        # thin_layer's box, 1000 x 100: its corner (1000, 0) lies between two junctions on
        # its border, where the compression used to leave a chord across it.
        reader = simple.XMLPolyDataReader(FileName=[st.data("thin_layer.vtp")])
        model = dsa.WrapDataObject(servermanager.Fetch(reader))
        mesh = dsa.WrapDataObject(servermanager.Fetch(Triangulation(Input=reader)))
        curve_points = np.asarray(model.Points)[:, :2]
        lo, hi = curve_points.min(axis=0), curve_points.max(axis=0)
        size = np.linalg.norm(hi - lo)
        mesh_points = np.asarray(mesh.Points)[:, :2]
        for corner in ([lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]):
            self.assertLess(np.linalg.norm(curve_points - corner, axis=1).min(), 1e-12 * size)
            self.assertLessEqual(np.linalg.norm(mesh_points - corner, axis=1).min(), 1e-9 * size,
                                 "box corner %s" % corner)

    def test_thin_layer_refinement_refines_the_thin_layers_and_keeps_the_bounds(self):
        default, thin = default_and_changed("faulted_thin_layers.vtp", ThinLayerRefinement=1)
        self.assertEqual(field(default, "ThinLayerMesh"), 0)  # it meets the bounds: made once
        self.assertEqual(field(thin, "ThinLayerMesh"), 1)
        # Cells as wide as the layers one to two finest edges thick: triangles from grid
        # levels finer than the default mesh's finest, and no bound lost.
        levels = [np.asarray(out.CellData["Level"]).max() for out in (default, thin)]
        self.assertGreater(levels[1], levels[0])
        self.assertGreaterEqual(field(thin, "MinimumAngle"), 29.95)
        self.assertLessEqual(field(thin, "MaximumAngle"), 130.0)
        self.assertLessEqual(field(thin, "MaxRegionAreaError"), 0.005)
        self.assertTrue((signed_areas(thin) > 0).all())

    def test_triangles_below_the_bound_are_counted_and_a_finer_level_mends_them(self):
        # Layers a finest edge thick where they end in each other: made once, triangles stay
        # below 25 degrees and are counted (those at model corners sharper than 25 degrees
        # apart, as forced by the input); by default (ThinLayerRetry) the mesh is made again 4
        # levels finer (28.3 degrees: one triangle left below 30, counted).
        default, once = default_and_changed("aliased_layers_section.vtp", ThinLayerRetry=0)
        self.assertLess(field(once, "MinimumAngle"), 25.0)
        below = (np.asarray(once.CellData["MinimumAngle"]) < 29.95).sum()
        self.assertLessEqual(field(once, "TrianglesAtSharpCorners"), below)
        below -= field(once, "TrianglesAtSharpCorners")
        self.assertGreater(below, 0)
        self.assertEqual(field(once, "TrianglesBelowMinimumAngle"), below)
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel") + 4)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 28.0)
        default_below = (np.asarray(default.CellData["MinimumAngle"]) < 29.95).sum()
        self.assertLess(default_below, below)
        self.assertEqual(field(default, "TrianglesBelowMinimumAngle"), default_below)

    def test_a_region_off_its_area_is_made_again_at_a_finer_level(self):
        # A piece of a layer lost at the automatic levels (area 10.8% short): by default the
        # mesh is made again 4 levels finer, and, as that one still cuts the layer where it is
        # thinner than its finest triangles, 2 levels finer again: every region within 0.5% of
        # its area and in one piece.
        default, once = default_and_changed("thin_layered_section.vtp", ThinLayerRetry=0)
        self.assertGreater(field(once, "MaxRegionAreaError"), 0.02)
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel") + 6)
        self.assertLessEqual(field(default, "MaxRegionAreaError"), 0.005)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 29.95)
        broken = default.VTKObject.GetFieldData().GetArray("BrokenRegions")
        self.assertEqual(broken.GetNumberOfTuples(), 0)

    def test_a_finer_mesh_still_below_the_angle_goal_is_made_finer_again(self):
        # A layer narrower than the refinement's floor where it thins: made once (ThinLayerRetry
        # off), a region's area is off by 3.8%; by default the mesh 4 levels finer mends the
        # area but keeps a triangle at 27 degrees, so it is made 2 levels finer again, at 30.
        default, once = default_and_changed("narrow_layer_section.vtp", ThinLayerRetry=0)
        self.assertGreater(field(once, "MaxRegionAreaError"), 0.02)
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel") + 6)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 30.0 - 1e-6)
        self.assertGreaterEqual(np.asarray(default.CellData["MinimumAngle"]).min(), 30.0 - 1e-6)
        self.assertEqual(field(default, "TrianglesBelowMinimumAngle"), 0)
        self.assertLessEqual(field(default, "MaxRegionAreaError"), 0.005)

    def test_a_region_whose_loss_and_gain_cancel_out_is_made_finer(self):
        # A layer's tip about a finest edge thick: the mesh with ThinLayerRefinement, made once,
        # loses it (0.54% of the region) and adds 0.10% elsewhere, 0.44% net, within 0.5%; its
        # misplaced area (lost plus added) is 0.63%. By default that is a miss too: the mesh
        # is made 4 levels finer, where both are within 0.5%.
        default, once = default_and_changed(
            "pinchout_tip_section.vtp", ThinLayerRetry=0, ThinLayerRefinement=1)
        self.assertLessEqual(field(once, "MaxRegionAreaError"), 0.005)
        self.assertGreater(field(once, "MaxRegionMisplacedArea"), 0.006)
        # Per region: the worst is region 1, whose loss and gain cancel out in the net area.
        ids, model, mesh, misplaced = (
            np.asarray(once.FieldData[name]).ravel()
            for name in ("RegionIds", "RegionModelArea", "RegionMeshArea", "RegionMisplacedArea"))
        worst = int(np.argmax(misplaced / model))
        self.assertEqual(ids[worst], 1)
        self.assertAlmostEqual(
            misplaced[worst] / model[worst], field(once, "MaxRegionMisplacedArea"), places=12)
        self.assertGreater(misplaced[worst], 1.3 * abs(mesh[worst] - model[worst]))
        self.assertTrue(np.all(misplaced >= np.abs(mesh - model) * (1.0 - 1e-9)))
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel") + 4)
        self.assertLessEqual(field(default, "MaxRegionMisplacedArea"), 0.005)
        self.assertGreaterEqual(
            field(default, "MaxRegionMisplacedArea"), field(default, "MaxRegionAreaError"))
        self.assertGreaterEqual(field(default, "MinimumAngle"), 30.0 - 1e-6)

    def test_a_triangle_at_a_sharp_corner_does_not_hide_the_angle_misses_beside_it(self):
        # Ten layers pinching out at one point: at LocalMaxLevel 18 the mesh has a triangle on
        # that apex (a sharp input corner forces it) and triangles beside it down to 15.88
        # degrees that no corner forces. By default those still count as an angle miss, and the
        # mesh 2 levels finer is kept (18.96 degrees off the corner, the boundary within half a
        # local edge).
        default, at18 = default_and_changed(
            "fan_apex_section.vtp", LocalMaxLevel=18, ThinLayerRetry=0)
        self.assertGreater(field(at18, "TrianglesAtSharpCorners"), 0)
        self.assertGreater(field(at18, "TrianglesBelowMinimumAngle"), 0)
        self.assertLess(field(at18, "MinimumAngleUnforced"), 16.0)
        self.assertGreater(field(at18, "MaxRelativeBoundaryDeviation"), 0.5)
        self.assertEqual(field(default, "LocalMaxLevel"), 20)
        self.assertGreater(field(default, "MinimumAngleUnforced"), 18.0)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 0.5)

    def test_a_larger_smallest_angle_does_not_buy_a_piece_of_a_layer_lost(self):
        # Nine horizons fanning out from one point: at LocalMaxLevel 20 the mesh made without
        # the thin layer refinement gives a piece of a layer about 6 finest edges wide to its
        # neighbour (its boundary more than a local edge off, issue 4's bound) for a larger
        # smallest angle. By default the mesh with the thin layer refinement, which keeps the
        # piece, is kept.
        default, once = default_and_changed(
            "fanned_pinch_outs_section.vtp", LocalMaxLevel=20, ThinLayerRetry=0)
        self.assertEqual(field(once, "ThinLayerMesh"), 0)
        self.assertGreater(field(once, "MaxRelativeBoundaryDeviation"), 1.0)
        self.assertEqual(field(default, "LocalMaxLevel"), 20)
        self.assertEqual(field(default, "ThinLayerMesh"), 1)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 1.0)
        self.assertGreater(field(default, "MinimumAngleUnforced"), 19.0)
        self.assertLess(field(default, "MinimumAngleUnforced"), field(once, "MinimumAngleUnforced"))

    def test_the_boundary_figure_and_the_levels_past_a_finer_mesh_not_kept(self):
        # A disc cut into 11 sectors at its centre, six of them 1.8 to 4.2 degrees wide. Made
        # once (its automatic LocalMaxLevel, 17) the mesh loses pieces of the narrow sectors
        # near the centre: 1.27 local edges off by the mesher (the quality table: 1.38; until
        # 2026-12-07 the mesher said 0.91). By default the mesh 4 levels finer is not kept,
        # but the kept one still misses half a local edge, so the levels go on: 2 levels finer
        # again is kept, within half a local edge.
        default, once = default_and_changed("eleven_sector_pie.vtp", ThinLayerRetry=0)
        self.assertEqual(field(once, "LocalMaxLevel"), 17)
        self.assertGreater(field(once, "MaxRelativeBoundaryDeviation"), 1.2)
        self.assertEqual(field(default, "LocalMaxLevel"), 23)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 0.5)
        self.assertGreater(field(default, "MinimumAngleUnforced"), 29.0)

    def test_a_boundary_still_more_than_a_local_edge_off_leads_to_one_level_more(self):
        # Eight horizons fanning out from one point: at LocalMaxLevel 18 the boundary lies more
        # than a local edge off near the point (issue 4's bound), and 2 levels finer it still
        # does. By default one level more is made, 2 levels finer again, and kept: its boundary
        # within half a local edge, no triangle below 25 degrees.
        default, at18 = default_and_changed("eight_horizon_fan_section.vtp", LocalMaxLevel=18)
        self.assertGreater(field(at18, "MaxRelativeBoundaryDeviation"), 1.0)
        self.assertEqual(field(default, "LocalMaxLevel"), 22)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 0.5)
        self.assertGreater(field(default, "MinimumAngleUnforced"), 25.0)

    def test_a_vertex_left_outside_the_model_goes_into_the_exterior(self):
        # A layer 3e-6 of the section's width thick ends at its sides: the compression left a
        # vertex 4.3 units outside the section, with three triangles; after the refinement
        # they go into the exterior, and the mesh lies within the section.
        mesh = Triangulation(Input=simple.XMLPolyDataReader(
            FileName=[st.data("vanishing_layer_section.vtp")]))
        out = dsa.WrapDataObject(servermanager.Fetch(mesh))
        xmin, xmax, ymin, ymax = out.VTKObject.GetBounds()[:4]
        self.assertGreaterEqual(xmin, 0.0)
        self.assertLessEqual(xmax, 1000.0)
        self.assertGreaterEqual(ymin, 0.0)
        self.assertLessEqual(ymax, 100.0)
        self.assertLessEqual(field(out, "MaxBoundaryVertexDistance"), 1e-9 * 1000.0)
        self.assertGreaterEqual(field(out, "MinimumAngle"), 30.0 - 0.05)

    def test_a_region_still_cut_at_the_finer_level_is_made_finer_again(self):
        # Region 3 is joined across a fault by a neck an eighth of the finest edge wide: made
        # once it is cut (BrokenRegions); by default the meshes 4 and 6 levels finer cut it too,
        # and the one 8 levels finer keeps it whole.
        default, once = default_and_changed("fault_neck_section.vtp", ThinLayerRetry=0)
        broken = once.VTKObject.GetFieldData().GetArray("BrokenRegions")
        self.assertEqual([broken.GetValue(i) for i in range(broken.GetNumberOfTuples())], [3])
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel") + 8)
        broken = default.VTKObject.GetFieldData().GetArray("BrokenRegions")
        self.assertEqual(broken.GetNumberOfTuples(), 0)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 30.0 - 1e-6)

    def test_a_layer_the_mesh_cuts_is_named_and_made_whole_again(self):
        # Region 3 is one piece in the model; made once, the mesh cuts it in two where it is
        # about 1.3 finest edges thick and names it in BrokenRegions; by default the mesh is made
        # again, with ThinLayerRefinement around the boundary's misses at the same level (4
        # levels finer before 2026-12-06, when the cut was not yet seen as a boundary miss),
        # where it is one piece.
        default, once = default_and_changed("broken_layer_section.vtp", ThinLayerRetry=0)
        finest = field(once, "FinestEdgeLength")
        self.assertEqual(pieces(once, 3, 4 * finest * finest), 2)
        self.assertEqual(list(np.asarray(once.FieldData["BrokenRegions"]).ravel()), [3])
        self.assertEqual(field(default, "LocalMaxLevel"), field(once, "LocalMaxLevel"))
        self.assertEqual(field(default, "ThinLayerMesh"), 1)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 0.5)
        self.assertEqual(pieces(default, 3, 4 * finest * finest), 1)
        broken = default.VTKObject.GetFieldData().GetArray("BrokenRegions")
        self.assertEqual(broken.GetNumberOfTuples(), 0)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 29.95)

    def test_a_mesh_that_gives_a_piece_of_a_layer_away_is_made_again(self):
        # Made once, the mesh gives a piece of a layer 3.7 finest edges thick (where a fault cuts
        # it) to its neighbour: every angle and area within the bounds, but the boundary more
        # than half the local edge off its curve. By default the mesh is made again with the
        # thin layer refinement, which keeps the piece, and that one is kept.
        default, once = default_and_changed("lost_layer_piece_section.vtp", ThinLayerRetry=0)
        self.assertGreaterEqual(field(once, "MinimumAngle"), 29.95)
        self.assertLessEqual(field(once, "MaxRegionAreaError"), 0.005)
        self.assertGreater(field(once, "MaxRelativeBoundaryDeviation"), 0.6)
        self.assertEqual(field(once, "ThinLayerMesh"), 0)
        self.assertLessEqual(field(default, "MaxRelativeBoundaryDeviation"), 0.5)
        self.assertEqual(field(default, "ThinLayerMesh"), 1)
        self.assertGreaterEqual(field(default, "MinimumAngle"), 29.95)
        self.assertLessEqual(field(default, "MaxRegionAreaError"), 0.005)

    def test_an_angle_above_30_is_not_bought_with_worse_triangles_than_30_gives(self):
        # Above 30 degrees Delaunay refinement may cascade: interior_pair_countries at
        # MinimumAngle 31 is left at 22.37 degrees. The mesh is made again refined toward 30 and
        # kept: the default's mesh, its triangles below 31 counted against 31.
        default, high = default_and_changed("interior_pair_countries.vtp", MinimumAngle=31.0)
        self.assertGreaterEqual(field(high, "MinimumAngle"), 29.95)
        self.assertEqual(high.GetNumberOfCells(), default.GetNumberOfCells())
        self.assertTrue(np.array_equal(np.asarray(high.Points), np.asarray(default.Points)))
        self.assertEqual(field(default, "TrianglesBelowMinimumAngle"), 0)
        below = (np.asarray(high.CellData["MinimumAngle"]) < 30.95).sum()
        self.assertGreater(field(high, "TrianglesBelowMinimumAngle"), 0)
        self.assertLessEqual(field(high, "TrianglesBelowMinimumAngle"), below)

    def test_out_of_range_values_are_refused_naming_the_property(self):
        model = simple.XMLPolyDataReader(FileName=[st.data("pinch_out.vtp")])
        mesh = Triangulation(Input=model)
        with self.assertRaises(ValueError) as raised:
            mesh.PushCriterion = "Nowhere"
        self.assertIn("Nowhere", str(raised.exception))


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() else 1)
