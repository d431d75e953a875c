// StrataMesh core: signed distance to the regions of a model (paper Sections 3-4). No VTK.
#ifndef StrataMeshCore_DistanceField_h
#define StrataMeshCore_DistanceField_h

#include "Model.h"
#include "StripTree.h"

#include <cstdint>
#include <vector>

namespace strata
{

/// What the distance field knows about a point.
struct PointQuery
{
  int region = -1;                ///< id of the region containing the point, -1 for none
  double signedDistance = 0.0;    ///< + distance to that region's boundary inside a region,
                                  ///< - distance to the nearest boundary outside every region
  double boundaryDistance = 0.0;  ///< distance to the nearest boundary of any region (>= 0)
  std::int64_t nearestCurve = -1; ///< input cell id of the nearest boundary segment
};

/// One strip tree per region over its rings, plus one over all boundary segments. The sign of
/// a region's distance is the even-odd rule over the region's rings, decided at the closest
/// boundary point: the side of the closest segment, or, when the closest point is a vertex,
/// the angular sector between the boundary edges incident to that vertex (all of them, so
/// loops that touch at a vertex are handled). Points on a boundary have distance 0 and count
/// as inside. Query points are in local model coordinates (input minus Model::origin).
class DistanceField
{
public:
  explicit DistanceField(const Model& model);

  using Scratch = StripTreeScratch;

  std::size_t numberOfRegions() const { return this->Regions.size(); }
  int regionId(std::size_t regionIndex) const { return this->Regions[regionIndex].id; }

  /// Signed distance to region regionIndex's boundary: > 0 inside, < 0 outside.
  double signedDistance(std::size_t regionIndex, Vec2 p, Scratch& scratch) const;
  /// True when p is inside region regionIndex by the even-odd rule (on the boundary counts).
  bool inside(std::size_t regionIndex, Vec2 p, Scratch& scratch) const;
  /// Unsigned distance to the nearest boundary of any region, and the nearest input cell id.
  double boundaryDistance(Vec2 p, Scratch& scratch, std::int64_t* nearestCurve = nullptr) const;
  /// Everything at once.
  PointQuery query(Vec2 p, Scratch& scratch) const;
  /// query(p, scratch).region alone (faster: no boundary distance).
  int region(Vec2 p, Scratch& scratch) const;

private:
  struct RegionTree
  {
    int id = -1;
    Box2 bounds;
    StripTree tree;              // all segments of all rings, ring after ring
    std::vector<int> prev, next; // neighbouring segment within the ring
    // Vertices shared by several rings (or visited twice by one ring): all segments of the
    // region incident to them, for the sector rule. startStar[s] / endStar[s] index the star
    // of segment s's start / end vertex, -1 when that vertex is not shared. Star k holds
    // starEdges[starOffsets[k] .. starOffsets[k + 1]), each 2 * segment + (1 if the segment
    // leaves the vertex, 0 if it arrives there).
    std::vector<int> startStar, endStar;
    std::vector<int> starOffsets;
    std::vector<int> starEdges;
  };
  double signedDistanceImpl(const RegionTree& r, Vec2 p, Scratch& scratch) const;
  // The containing region (-1 for none) and its signed distance in best.
  int regionImpl(Vec2 p, Scratch& scratch, double& best) const;

  std::vector<RegionTree> Regions;
  StripTree All;
  std::vector<std::int64_t> AllCell;
};

} // namespace strata

#endif
