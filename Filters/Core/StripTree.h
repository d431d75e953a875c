// StrataMesh core: strip tree over a set of segments (paper Section 3) and exact nearest-segment
// queries by best-first search (paper Section 4). No VTK.
#ifndef StrataMeshCore_StripTree_h
#define StrataMeshCore_StripTree_h

#include "Geometry.h"

#include <cstdint>
#include <vector>

namespace strata
{

/// Result of a nearest-segment query.
struct NearestSegment
{
  int segment = -1;          ///< index of the closest segment (-1 for an empty tree)
  double distance2 = HUGE_VAL; ///< squared distance to it
  double t = 0.0;            ///< parameter of the closest point on it (0 at its first vertex)
};

/// Scratch memory of a query (the heap); reuse one per thread so queries do not allocate.
struct StripTreeScratch
{
  std::vector<std::pair<double, int>> heap;
};

/// A binary strip tree over segments given as pairs of points. Consecutive segments (in the
/// order given) are grouped: each node covers a run [first, last] of segments, stores the
/// central segment from the run's first vertex to its last vertex and the largest distance
/// of the run's vertices from it; children hold the two halves. Runs need not be connected
/// (rings of one region follow each other): the bound stays valid because the strip around
/// the central segment is convex and contains every vertex of the run.
class StripTree
{
public:
  StripTree() = default;
  /// Segment i goes from a[i] to b[i]. Throws ParameterError when the sizes differ.
  StripTree(std::vector<Vec2> a, std::vector<Vec2> b);

  std::size_t numberOfSegments() const { return this->A.size(); }
  Vec2 segmentStart(int i) const { return this->A[i]; }
  Vec2 segmentEnd(int i) const { return this->B[i]; }

  /// Exact closest segment to p (ties: any of them). Does not allocate once the scratch has
  /// grown to its working size.
  NearestSegment nearest(Vec2 p, StripTreeScratch& scratch) const;

  /// Number of nodes (for tests and memory reports).
  std::size_t numberOfNodes() const { return this->Nodes.size(); }

private:
  struct Node
  {
    Vec2 c0, c1;        // central segment
    double width = 0.0; // max distance of the run's vertices from the central segment
    Box2 box;           // bounding box of the run
    int first = 0;      // first segment of the run
    int last = 0;       // last segment of the run (inclusive)
    int left = -1;      // child nodes, -1 for a leaf
    int right = -1;
  };
  int build(int first, int last);
  double lowerBound2(const Node& n, Vec2 p) const;

  std::vector<Vec2> A, B;
  std::vector<Node> Nodes;
};

} // namespace strata

#endif
