// StrataMesh core: classification of the vertices, edges and faces of a grid against the
// model's regions (paper Section 5). No VTK.
#ifndef StrataMeshCore_Classification_h
#define StrataMeshCore_Classification_h

#include "DistanceField.h"
#include "Grid48.h"
#include "Progress.h"

#include <array>
#include <cstdint>
#include <vector>

namespace strata
{

/// Vertex classes (Classification::vertexClass).
enum VertexClass : std::int8_t
{
  VertexExterior = 0, ///< outside every region
  VertexBoundary = 1, ///< within the boundary tolerance of a boundary
  VertexInterior = 2  ///< inside a region (vertexRegion)
};

/// Edge classes (Classification::edgeClass).
enum EdgeClass : std::int8_t
{
  EdgeExterior = 0,    ///< outside every region, touches no boundary
  EdgeInterior = 1,    ///< inside one region, touches no boundary
  EdgeIntersection = 2 ///< crosses or touches a boundary
};

struct ClassificationParams
{
  /// A vertex within this distance (model units) of a boundary is a boundary vertex, and an
  /// edge that comes this close to a boundary is an intersection edge. Range >= 0 and finite;
  /// 0 for automatic: 1e-6 of the mesh's shortest edge.
  double boundaryTolerance = 0.0;
};

/// The classification of a mesh. Region values are region ids (as in the input), -1 for the
/// exterior.
struct Classification
{
  double boundaryTolerance = 0.0;       ///< the tolerance used (automatic value resolved)
  LargeVector<std::int8_t> vertexClass; ///< VertexClass per point
  /// Region containing each point: for interior points the region, for boundary points the
  /// region DistanceField::query reports (on a boundary shared by regions the one with the
  /// largest signed distance, i.e. the side the point is on; -1 on the exterior side).
  LargeVector<int> vertexRegion;
  /// Unique edges, each once, as (a, b) with a < b, ordered by a then b.
  LargeVector<std::array<int, 2>> edges;
  LargeVector<std::int8_t> edgeClass; ///< EdgeClass per edge
  /// Interior edges: their region. Intersection edges: the region of the first endpoint (a,
  /// then b) that is an interior vertex; if neither is, the first endpoint whose vertexRegion
  /// is not -1; else -1. Exterior edges: -1.
  LargeVector<int> edgeRegion;
  /// Region containing each triangle's barycentre (-1 for none).
  LargeVector<int> cellRegion;
  std::size_t regionQueries = 0; ///< DistanceField::query calls made
};

/// Classifies the points, edges and triangles of `mesh` (local coordinates of `model`);
/// `field` must be the distance field of `model`. Distances known in
/// mesh.pointBoundaryDistance are reused. Throws ParameterError for parameters out of range or
/// a malformed mesh (indices out of range), Aborted when the progress callback asks to stop.
Classification classify(const TriangleMesh& mesh,
  const Model& model,
  const DistanceField& field,
  const ClassificationParams& params = {},
  const ProgressReporter& progress = ProgressReporter());

} // namespace strata

#endif
