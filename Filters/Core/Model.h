// StrataMesh core: the input model. Converts raw polylines (either form of Data/FORMAT.md) into
// validated regions, curves and junctions. No VTK.
#ifndef StrataMeshCore_Model_h
#define StrataMeshCore_Model_h

#include "Geometry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace strata
{

/// The two input forms of Data/FORMAT.md.
enum class ModelForm
{
  Auto,        ///< SharedCurves when left/right labels are given, else Loops
  Loops,       ///< one RegionId per closed cell, even-odd per region
  SharedCurves ///< LeftRegion / RightRegion per cell, curves meet at shared end points
};

/// Kind of an input cell, as far as the model cares.
enum class CellKind : std::uint8_t
{
  Line,    ///< VTK_LINE or VTK_POLY_LINE
  Polygon, ///< VTK_POLYGON: read as a closed loop in the Loops form (with a warning)
  Other    ///< anything else (vertices, triangles, ...): ignored with a warning
};

/// Raw input as an adapter hands it over: points, cells as offsets/connectivity, labels.
struct RawPolylines
{
  std::vector<Vec2> points;                 ///< input points (z dropped)
  std::vector<std::int64_t> offsets;        ///< cells+1 entries; cell c = [offsets[c], offsets[c+1])
  std::vector<std::int64_t> connectivity;   ///< point ids
  std::vector<CellKind> kinds;              ///< one per cell; empty = all Line
  ModelForm form = ModelForm::Auto;
  std::vector<int> regionId;                ///< Loops form: one per cell
  std::vector<int> leftRegion, rightRegion; ///< SharedCurves form: one each per cell
  /// How the caller chose the form and arrays, when that may be the fault: buildModel()
  /// appends it to its InputError messages.
  std::string formNote;
  /// The caller's own warnings about the input (a z dropped): buildModel() puts them first
  /// among the model's warnings.
  std::vector<std::string> notes;

  std::size_t numberOfCells() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

struct ModelParams
{
  /// Points closer than this fraction of the model's bounding-box diagonal are the same point
  /// (closing points of loops, shared curve end points). Range [0, 1e-3].
  double mergeTolerance = 1e-10;
};

/// A cleaned input curve: no repeated consecutive points; closed curves do not repeat their
/// first point at the end. Coordinates are local (input minus Model::origin).
struct Curve
{
  std::vector<Vec2> points;
  std::vector<int> nodes;   ///< id of each point in Model::nodes (merged coordinates)
  bool closed = false;      ///< a loop (Loops form) or a curve whose ends coincide
  int left = -1;            ///< region on the left (SharedCurves), or the loop's region (Loops)
  int right = -1;           ///< region on the right (SharedCurves), -1 in the Loops form
  std::int64_t sourceCell = -1; ///< input cell id
};

/// A closed boundary cycle of one region, oriented so that the region lies on its left.
struct Ring
{
  std::vector<Vec2> points;            ///< local coordinates, first point not repeated
  std::vector<int> nodes;              ///< node ids of the points
  std::vector<std::int64_t> segmentCell; ///< input cell id of segment i (points[i] -> points[i+1])
};

struct Region
{
  int id = -1;
  std::vector<Ring> rings; ///< even-odd: outer boundaries counter-clockwise, holes clockwise
  Box2 bounds;             ///< local coordinates
};

/// A validated model. All geometry is in local coordinates (input minus origin), so that UTM
/// magnitudes (1e7) and tiny scales (1e-6) behave the same as a model around the origin.
struct Model
{
  ModelForm form = ModelForm::Loops;
  Vec2 origin;                      ///< add to local coordinates to get input coordinates
  Box2 bounds;                      ///< local bounds of all curves
  std::vector<Vec2> nodes;          ///< merged distinct points (local)
  std::vector<Curve> curves;        ///< one per kept input cell (a loop with segments that are
                                    ///< no border: one per run of its other segments)
  std::vector<Region> regions;      ///< sorted by id; only ids >= 0
  std::vector<int> junctions;       ///< node ids where 3+ curve branches meet or a curve ends
  std::vector<std::string> warnings;///< repairs made (dropped duplicates, ignored cells, ...)

  bool empty() const { return curves.empty(); }
  /// Index into regions of region id, or -1.
  int regionIndex(int id) const;
  /// A length scale of the model: its bounding-box diagonal (1 for an empty model).
  double size() const;
};

/// Builds and validates a model. Throws InputError naming the cell, point or location at
/// fault for: no region arrays, no line cells, NaN/Inf coordinates, region id < -1, a loop
/// that self-intersects (also after the implied closing edge; the message gives the gap),
/// curves crossing or touching without a shared vertex (the message gives the point),
/// dangling curve ends that leave a region open, inconsistent left/right labels of one
/// face, regions that overlap (two regions on one side of a border, or a region's border
/// inside another region: an island without its hole) and a loop given twice for one region.
/// Repairs with a warning: repeated consecutive points, zero-length and one-point cells,
/// polygon cells in the Loops form, non-line cells, and (Loops form) segments with the same
/// region on both sides (between two of its loops, or where a loop runs back along itself),
/// which are no border by the even-odd rule: they are left out of the rings, the curves and
/// the junctions. Empty input gives an empty model and a warning. Throws ParameterError for
/// parameters out of range.
Model buildModel(const RawPolylines& input, const ModelParams& params = {});

} // namespace strata

#endif
