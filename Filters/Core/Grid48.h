// StrataMesh core: the adaptive 4-8 grid that subdivides the space around a model (paper
// Sections 2 and 2.1), with its multi-resolution hierarchy. No VTK.
#ifndef StrataMeshCore_Grid48_h
#define StrataMeshCore_Grid48_h

#include "DistanceField.h"
#include "Geometry.h"
#include "LargeArray.h"
#include "Model.h"
#include "Progress.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace strata
{

/// A triangle mesh in local model coordinates (the adapters add Model::origin back).
struct TriangleMesh
{
  LargeVector<Vec2> points;
  /// Counter-clockwise. For a mesh extracted from a Grid48 the first vertex is the right-angle
  /// vertex and triangles[i][1] - triangles[i][2] is the hypotenuse (the refinement edge).
  LargeVector<std::array<int, 3>> triangles;
  LargeVector<int> triangleLevel; ///< grid level of each triangle (may be empty elsewhere)
  /// Level at which each point was created: 0 for the five vertices of level 0, l + 1 for the
  /// midpoint of a level-l hypotenuse, i.e. the first level whose mesh contains the point.
  LargeVector<int> pointLevel;
  LargeVector<int> triangleNode; ///< Grid48 hierarchy node of each triangle (or empty)
  LargeVector<int> pointVertex; ///< Grid48 vertex id of each point, stable across levels (or empty)
  /// Distance from each point to the nearest model boundary when already known (the grid
  /// computed it for its refinement criterion), NaN when not known; empty = none known.
  /// classify() uses the known values instead of querying the distance field again.
  LargeVector<double> pointBoundaryDistance;

  std::size_t numberOfPoints() const { return this->points.size(); }
  std::size_t numberOfTriangles() const { return this->triangles.size(); }
};

/// The model's boundary in a uniform grid of square cells: every distinct boundary segment (a
/// segment shared by two loops counts once) is listed in each cell it crosses, every model
/// vertex in its cell. Boundary curves are the chains of segments between junctions (nodes
/// where the number of segments is not two) and curve ends. Queries take the cells under the
/// query's bounding box and run exact tests on their contents, so their cost does not depend
/// on the size of the model. Queries use an internal stamp array: one index per thread.
class BoundaryIndex
{
public:
  /// Index over the square [origin, origin + side]^2 (points outside it are still handled,
  /// in the border cells). Cells about twice the median segment length (at least 2 sqrt(segments),
  /// at most 1024 per axis).
  BoundaryIndex(const Model& model, Vec2 origin, double side);
  /// Index over the model's bounds (a square around them).
  explicit BoundaryIndex(const Model& model);

  /// Whether some boundary segment is within `tolerance` (closed) of p.
  bool nearPoint(Vec2 p, double tolerance);
  /// Whether some boundary segment is closer than `distance` (open) to p.
  bool closerThan(Vec2 p, double distance);
  /// Whether some boundary segment is within `tolerance` of the segment ab (closed; 0 when
  /// they cross or touch).
  bool nearSegment(Vec2 a, Vec2 b, double tolerance);
  /// Whether the segment ab (closed) meets the segments of two or more different curves.
  bool twoCurvesMeet(Vec2 a, Vec2 b);

  enum TriangleResult
  {
    NothingInside,   ///< no model vertex or segment meets the closed triangle
    SomethingInside, ///< something does, but no requested criterion holds
    CriterionHolds   ///< a requested criterion holds
  };
  /// Grid48's local criteria for the closed counter-clockwise triangle abc. local: two or more
  /// model vertices, or segments of two or more curves. thin: one curve in two or more
  /// separate strands; without `local` also two curves bounding a common region (the
  /// exterior counts as one), or curves of three or more regions.
  TriangleResult testTriangle(Vec2 a, Vec2 b, Vec2 c, bool local, bool thin);
  /// Grid48's thin layer criterion (g) for the closed counter-clockwise triangle abc: whether
  /// a layer with a thickness in [thinnest, thickest) lies across it or beside it.
  /// - Across: two strands of the boundary cross it (two curves, or one curve twice), the
  ///   thickness being the smallest distance from a point of either strand inside the
  ///   triangle (the ends and middles of its segments' parts inside) to the other strand's
  ///   segments: the layer between them is at least that thick everywhere in the triangle.
  /// - Beside: a strand crosses it and another strand of the same curve, within `thickest`
  ///   of it but not meeting it, lies at least `thinnest` and less than `thickest` from each
  ///   of the first one's points inside it (a curve come back along itself, as a tooth, a
  ///   spit or a lens, along an edge of the triangle: its other side lies in the neighbour).
  ///   Strands are then runs of segments joined at nodes within `thickest` of the triangle,
  ///   so that a tooth's end near the triangle is not a layer beside it. Two curves are left
  ///   to the layers across the triangles (beside them too, they refined the slivers between
  ///   faults crossing near one point into worse meshes).
  /// Across, two curves that meet at a common end within twice the triangle's longest edge at
  /// an angle of 30 degrees or more are not a layer (a junction, not a pinch-out).
  bool thinLayer(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest);

  std::size_t numberOfSegments() const { return this->A.size(); }
  std::size_t numberOfCurves() const { return this->ChainBegin.size() - 1; }
  double cellSize() const { return this->CellSize; }
  std::size_t memoryBytes() const;

private:
  void build(const Model& model, Vec2 origin, double side);
  std::size_t strands(Vec2 a, Vec2 b, Vec2 c, double r);
  bool layerAcross(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest);
  bool layerBeside(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest);
  bool junctionNear(int ck, int cm, Vec2 centroid, double longest2) const;
  // Cell column / row of a coordinate, clamped to the grid (monotone in x / y).
  int cellX(double x) const { return this->cellOf((x - this->Origin.x) * this->InvCell); }
  int cellY(double y) const { return this->cellOf((y - this->Origin.y) * this->InvCell); }
  int cellOf(double f) const
  {
    return f <= 0.0 ? 0 : (f >= this->Cells ? this->Cells - 1 : static_cast<int>(f));
  }
  template<typename Visit>
  void forSegmentCells(int s, Visit&& visit) const;
  template<typename Visit>
  bool anySegment(double x0, double y0, double x1, double y1, Visit&& visit);

  // Segments oriented along their curve, curves contiguous: segments s and s + 1 of one
  // curve share the node B[s] == A[s + 1].
  std::vector<Vec2> A, B;
  std::vector<int> ChainOf;
  std::vector<int> ChainBegin;                 // curves + 1 entries
  std::vector<std::array<int, 2>> ChainLabels; // region ids on both sides (-1 exterior)
  std::vector<Vec2> Nodes;                     // distinct model vertices
  Vec2 Origin;
  double CellSize = 1.0;
  double InvCell = 1.0;
  int Cells = 1; // per axis
  LargeVector<int> SegStart, SegItems, NodeStart, NodeItems; // (offsets: 4 MiB at 1024^2 cells)
  std::vector<std::uint32_t> Stamp;
  std::uint32_t CurrentStamp = 0;
  std::vector<int> Hits;
  std::vector<int> StrandEnd;     // thinLayer: one past each strand's last hit
  std::vector<Vec2> StrandPoints; // thinLayer: clipped segment points, per hit
  std::vector<char> HitMeets;     // layerBeside: whether each hit meets the triangle
};

/// Parameters of the grid. Automatic values (-1, 0) are resolved by Grid48::resolveParams;
/// Grid48::params() returns the resolved ones. Out-of-range values throw ParameterError.
struct Grid48Params
{
  /// Global refinement (paper Section 2) stops at this level. Range [0, 60], or -1 for
  /// automatic: the level whose hypotenuse is closest (in log scale) to four times the median
  /// length of the model's boundary segments, clamped to [10, 20]. With the default
  /// localMaxLevel (4 levels finer, hypotenuses 4 times shorter) the finest triangles are then
  /// about as long as a typical boundary segment, so local refinement can separate the
  /// polygon vertices. On the models in Data/ this gives 10 (small synthetic ones) to 16
  /// (gulf_section, guitar) and 1.3e3 to 6.8e4 triangles.
  int maxLevel = -1;
  /// Local refinement (Section 2.1 and thin regions) stops at this level. Range
  /// [maxLevel, 60], or -1 for min(maxLevel + 4, 60). Equal to maxLevel: no local refinement.
  int localMaxLevel = -1;
  /// Global criterion: an edge whose midpoint is within this distance (model units) of the
  /// boundary is not split. Range >= 0 and finite; 0 for automatic: 1e-3 of the hypotenuse
  /// length at maxLevel (which follows from the model's bounds, the margin and maxLevel).
  double tolerance = 0.0;
  /// Section 2.1: split triangles containing two or more polygon vertices or crossed by two
  /// or more boundary curves (up to localMaxLevel). Curves are the chains of distinct
  /// boundary segments between junctions (see BoundaryIndex), so that a border given twice in
  /// the Loops form counts once.
  bool localRefinement = true;
  /// Beyond the paper (thin regions, Section 6.6): also split triangles crossed by one curve
  /// in two or more separate strands (a region or gap bounded on both sides by one curve and
  /// too thin to fill the triangle), up to localMaxLevel. Two curves that bound one region, or
  /// curves of three regions, are already split by localRefinement; with localRefinement off,
  /// this option splits those too.
  bool thinRegionRefinement = true;
  /// Margin of the square domain around the model's bounds, as a fraction of the larger side
  /// of the bounds, added on every side. Range [0, 1].
  double margin = 0.05;
  /// Beyond the paper (close feature points): also split triangles (closed) that contain two
  /// or more model feature points, up to junctionMaxLevel, which may exceed localMaxLevel.
  /// Feature points are the Model::junctions (nodes where the number of boundary segments is
  /// not two: 3+ branches or curve ends) and, when featurePointAngle > 0, the vertices inside
  /// a curve whose angle is below it. Compression puts one mesh vertex on each of them, so two
  /// of them much closer than the local edges (0.7 m apart among 100 m edges) leave slivers;
  /// splitting until they lie in different triangles makes the edges there comparable to
  /// their distance, and the 4-8 grading keeps the triangles around well shaped. Only the
  /// feature points whose nearest other feature point is within a triangle's hypotenuse are
  /// tested, so this costs little (models have few close feature points). A pair that ends
  /// a strip about as wide as their distance that goes on further than the local triangles
  /// (a thin layer ending on the border) is not separated: only its ends would be resolved.
  bool junctionRefinement = true;
  /// Beyond the paper (thin layers): also split triangles from maxLevel up to
  /// junctionMaxLevel (beyond localMaxLevel) that a layer thinner than the triangle's legs
  /// but at least as thick as the legs of junctionMaxLevel crosses or lies beside (two
  /// boundary strands across the triangle, or one across it and one of the same curve
  /// within its legs beside it: see BoundaryIndex::thinLayer), so that such a layer gets
  /// cells about as wide as it is and the compression keeps it. Needs localMaxLevel >
  /// maxLevel.
  bool thinLayerRefinement = false;
  /// A disk (model coordinates).
  struct Zone
  {
    Vec2 centre;
    double radius = 0.0;
  };
  /// With thinLayerRefinement: when not empty, it splits only the triangles whose centroid
  /// lies within a zone (widened by the triangle's hypotenuse): the places where a mesh made
  /// without it lost a piece of a layer (MesherParams::thinLayerRetry), so that the rest of
  /// the grid stays as it was. Empty: everywhere.
  std::vector<Zone> thinLayerZones;
  /// Level cap of junctionRefinement. Range [localMaxLevel, 60], or -1 for
  /// min(localMaxLevel + 8, 60) (hypotenuses 16 times shorter than at localMaxLevel) when
  /// localMaxLevel > maxLevel, else localMaxLevel (no local refinement of any kind). Equal to
  /// localMaxLevel: nothing beyond (b) unless localRefinement is off.
  int junctionMaxLevel = -1;
  /// Vertices inside a curve whose angle (between the two segments, in degrees) is below this
  /// are feature points too (for junctionRefinement). Range [0, 180]; 0: junctions only.
  double featurePointAngle = 0.0;
  /// Sizes in model units: the levels chosen from edge lengths. A level's triangles have
  /// their longest edge, the hypotenuse, of side / 2^(level / 2) (side: the domain's square).
  /// maxEdgeLength > 0: with L the coarsest level whose hypotenuse is <= maxEdgeLength, every
  /// triangle is split at least to level L (minLevel, when automatic, becomes L), so that no
  /// grid edge anywhere is longer than maxEdgeLength; maxLevel becomes L when automatic (the
  /// length overrides the automatic level) and max(maxLevel, L) when set (the finer wins);
  /// localMaxLevel and junctionMaxLevel are raised to at least maxLevel, and their automatic
  /// values follow the new maxLevel. Range 0 (default: no bound) or a finite value >= side /
  /// 2048 (L <= MaxUniformLevel = 22, i.e. at most 16.8 M triangles of uniform refinement).
  double maxEdgeLength = 0.0;
  /// minEdgeLength > 0 caps the refinement: with L the finest level whose hypotenuse is >=
  /// minEdgeLength (0 when even level 0's is shorter), maxLevel, localMaxLevel and
  /// junctionMaxLevel, automatic or set, are lowered to at most max(L, the level of
  /// maxEdgeLength) (the coarser wins; maxEdgeLength wins over it when both cannot hold, which
  /// needs the two within a factor sqrt(2)). No leaf is then finer than that level: every
  /// hypotenuse is >= minEdgeLength, or > minEdgeLength / sqrt(2) in that case. Range 0
  /// (default: no cap) or finite > 0, not above maxEdgeLength when both are > 0.
  double minEdgeLength = 0.0;
  /// Every triangle is split at least to this level (uniform refinement). Range [0,
  /// min(maxLevel, MaxUniformLevel)], or -1 (default) for automatic: the level of
  /// maxEdgeLength when it is > 0, else 0; a level set is raised to that of maxEdgeLength.
  int minLevel = -1;
  /// Optional target edge length field (a sizing function), in model units: called with a
  /// point in *input* coordinates (local + Model::origin, so that the caller can evaluate its
  /// own data there), it returns the wanted length of the triangles' longest edge at that
  /// point; +infinity or NaN mean "no wish here", a finite value <= 0 is a ParameterError.
  /// Empty (default): no field. When set, (f) a leaf is split while its hypotenuse is longer
  /// than the smallest target at its three corners and its centroid (corner values are
  /// evaluated once per grid vertex), up to targetMaxLevel. The 4-8 grid's conformity
  /// (neighbours at most one level apart) grades the result: edge-adjacent triangles' longest
  /// edges differ by at most a factor sqrt(2). With maxLevel automatic (-1, and no
  /// maxEdgeLength), the field can also coarsen: maxLevel becomes the coarser of the usual
  /// automatic level and the coarsest level whose hypotenuse is <= the largest finite target
  /// sampled on a 65 x 65 lattice over the model's bounds (clamped to >= 0, not to [10, 20]);
  /// local, thin-region and junction refinement keep working relative to the levels so
  /// resolved. The function is called from the refining thread only (Grid48 refines on one
  /// thread), never concurrently; the grid keeps a copy in params().
  std::function<double(Vec2)> targetEdgeLength;
  /// Identifies the field of targetEdgeLength for GridSession: two calls with the same
  /// non-zero id promise the same field, so refinement may resume; 0 (default): unknown, a
  /// session with a field is then rebuilt on every refine(). Ignored without a field.
  std::uint64_t targetEdgeLengthId = 0;
  /// Level cap of the target edge length refinement (f), the floor of the field: no leaf is
  /// split by (f) beyond it. Range [localMaxLevel, 60], or -1 (default) for automatic: the
  /// cap of minEdgeLength when it is > 0 (every hypotenuse stays >= minEdgeLength), else
  /// min(localMaxLevel + 4, 60) (hypotenuses 4 times shorter than at localMaxLevel), which
  /// bounds the memory a field asking for tiny edges can take; when the field coarsened an
  /// automatic maxLevel, localMaxLevel is taken as it would be without the field (the usual
  /// automatic level + 4), so that coarsening at depth does not also limit the refinement
  /// where the field asks for small edges. Unused without a field.
  int targetMaxLevel = -1;
};

/// The finest uniform level that maxEdgeLength / minLevel may ask for (4 * 2^22 triangles).
constexpr int MaxUniformLevel = 22;

/// Counters of the work done by the refinement calls so far (summed over calls).
struct Grid48Statistics
{
  std::size_t splits = 0;          ///< triangles bisected (each diamond counts two)
  std::size_t forcedSplits = 0;    ///< of which split only to keep the mesh conforming
  std::size_t distanceQueries = 0; ///< DistanceField::boundaryDistance calls
  std::size_t indexQueries = 0;    ///< global criterion decided with the BoundaryIndex instead
  std::size_t localTests = 0;      ///< triangles tested against the model's segments/vertices
  std::size_t featureTests = 0;    ///< triangles tested against the close feature points
};

/// An adaptive 4-8 mesh over a square domain. Level 0 is the square split into four right
/// isosceles triangles around its centre vertex; a triangle of level l is bisected at the
/// midpoint of its hypotenuse into two triangles of level l + 1 (newest-vertex bisection).
/// Vertices live on an integer lattice of 2^31 x 2^31 cells over the square, mapped to model
/// coordinates by origin + scale * (i, j), so every triangle has angles of exactly 45, 45 and
/// 90 degrees, and each lattice point is one vertex. Refinement is conforming: a triangle is
/// always split together with its neighbour across the hypotenuse (the diamond), after that
/// neighbour, if it is coarser, has been split first; hence no hanging vertices and edge
/// neighbours differ by at most one level. The whole hierarchy is kept (flat arrays of
/// nodes: vertices, neighbours, first child, level; the parent of each pair of children), so
/// that the conforming mesh of any level can be extracted and refinement can resume.
///
/// Node ids: 0..3 are the level-0 triangles; the two children of a node are consecutive ids.
/// Vertex ids: 0..3 the square's corners (counter-clockwise from its lower left), 4 the
/// centre, then in order of creation.
class Grid48
{
public:
  /// The finest level supported (the lattice has 31 bits per axis).
  static constexpr int MaxSupportedLevel = 60;

  /// Level 0 over a square covering `bounds` with `margin` (fraction of the larger side, on
  /// every side; range [0, 1]). An empty box gives the unit square around the origin; a box
  /// of zero size a square of side 1 around it. Throws ParameterError for a bad margin or
  /// non-finite bounds.
  explicit Grid48(const Box2& bounds, double margin = 0.05);

  /// Builds the grid of `model` (local coordinates) with the global and local criteria.
  /// `field` must be the distance field of `model`. Throws ParameterError for parameters out
  /// of range, Aborted when the progress callback asks to stop.
  static Grid48 build(const Model& model,
    const DistanceField& field,
    const Grid48Params& params = {},
    const ProgressReporter& progress = ProgressReporter());

  /// The parameters with the automatic values (-1 / 0) replaced by the rules documented in
  /// Grid48Params, for the domain this model would get. Throws ParameterError when out of range.
  static Grid48Params resolveParams(const Model& model, const Grid48Params& params);

  /// Resumes refinement with (possibly new) parameters: splits leaves until no leaf meets a
  /// criterion. Refinement only adds splits: when every parameter is at least as fine as
  /// before (levels not lower, tolerance not larger, options not turned off), the result is
  /// identical to build() with the new parameters; otherwise it is the coarsest conforming
  /// refinement of the current mesh that meets the new criteria. The grid's domain is kept
  /// (params.margin is ignored); the model's bounds must lie inside it (ParameterError).
  /// After Aborted the grid is valid and conforming, just not fully refined.
  void refine(const Model& model,
    const DistanceField& field,
    const Grid48Params& params,
    const ProgressReporter& progress = ProgressReporter());

  /// Generic conforming refinement: splits every leaf of level < maxLevel for which
  /// split(*this, node) is true, the leaves this creates included, until none is left.
  /// Returns the number of triangles split. maxLevel is clamped to MaxSupportedLevel.
  std::size_t refineWhere(const std::function<bool(const Grid48&, int node)>& split,
    int maxLevel,
    const ProgressReporter& progress = ProgressReporter());

  /// The conforming mesh of level `level`: every node of that level and every leaf coarser
  /// than it; level -1 (or >= maxLeafLevel()) gives all leaves (the finest mesh). The meshes
  /// of levels 0..maxLeafLevel() are nested. Points are numbered in order of first use.
  /// Progress is reported every 64 k triangles (stage "extracting the grid").
  TriangleMesh extract(int level = -1, const ProgressReporter& progress = ProgressReporter()) const;

  // Domain.
  Vec2 origin() const { return this->Origin; } ///< lower left corner of the square (local)
  double side() const { return this->Side; }   ///< side length of the square
  /// Hypotenuse length of the triangles of a level: side / 2^(level / 2).
  double hypotenuseLength(int level) const;

  // Hierarchy.
  std::size_t numberOfNodes() const { return this->Level.size(); }
  std::size_t numberOfLeaves() const { return this->Leaves; }
  std::size_t numberOfVertices() const { return this->Lattice.size(); }
  int maxLeafLevel() const { return this->MaxLeafLevel; }
  int nodeLevel(int node) const { return this->Level[node] & kLevelMask; }
  bool isLeaf(int node) const { return this->Child[node] < 0; }
  int nodeFirstChild(int node) const { return this->Child[node]; } ///< -1 for a leaf
  int nodeParent(int node) const { return node < 4 ? -1 : this->PairParent[(node - 4) / 2]; }
  /// Vertex ids, counter-clockwise, the right-angle vertex first (then the hypotenuse).
  const std::array<int, 3>& nodeVertices(int node) const { return this->Vert[node]; }
  /// Neighbour across the hypotenuse, across (v2, v0) and across (v0, v1); -1 on the domain
  /// border. Maintained for leaves; for inner nodes it is the state when they were split.
  const std::array<int, 3>& nodeNeighbours(int node) const { return this->Nbr[node]; }
  Vec2 vertexPosition(int vertex) const;
  std::array<std::uint32_t, 2> vertexLattice(int vertex) const { return this->Lattice[vertex]; }
  int vertexLevel(int vertex) const { return this->VertexLevel[vertex]; }

  /// Resolved parameters of the last refine()/build() (defaults before any).
  const Grid48Params& params() const { return this->Params; }
  const Grid48Statistics& statistics() const { return this->Stats; }
  /// Bytes the grid's arrays hold (their sizes; see reserveGrowth in LargeArray.h).
  std::size_t memoryBytes() const;

private:
  static constexpr std::uint8_t kLevelMask = 0x3f;

  static Grid48Params resolveParams(const Model& model, const Grid48Params& params, double side);
  int addVertex(std::array<std::uint32_t, 2> lattice, int level, double distance);
  void split(int node, double midpointDistance, LargeVector<int>* pending, bool forced = false);
  void bisect(int node, int midpoint);
  void replaceNeighbour(int node, int from, int to);
  friend class Grid48Refiner;

  Vec2 Origin;
  double Side = 1.0;
  double Scale = 1.0; // Side / 2^31
  Grid48Params Params;
  Grid48Statistics Stats;
  std::size_t Leaves = 0;
  int MaxLeafLevel = 0;

  // Nodes (struct of arrays).
  LargeVector<std::array<int, 3>> Vert;
  LargeVector<std::array<int, 3>> Nbr;
  LargeVector<int> Child;
  LargeVector<std::uint8_t> Level; // level in the low 6 bits, refinement flags above
  LargeVector<int> PairParent;     // parent of nodes 4 + 2k and 5 + 2k

  // Vertices.
  LargeVector<std::array<std::uint32_t, 2>> Lattice;
  LargeVector<std::uint8_t> VertexLevel;
  LargeVector<double> VertexDistance; // boundary distance when computed, else NaN
};

} // namespace strata

#endif
