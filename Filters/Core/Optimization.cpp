// StrataMesh core: the optimization after the compression (beyond the paper, optional;
// CompressionParams::optimize), members of the compressor of Compression.cpp (Compressor.h).
//
// The algorithm
// -------------
// It runs on the simulated sub-mesh once the simulation and the face classification are
// over, in this order:
//    (a) Snap: every vertex of the region boundary not on a curve moves to a boundary point
//    near it (its closest point, its push target, or a quarter or half an edge length aside)
//    when the restrain test allows, flipping the edges that block it when valid, as a last
//    resort accepting 0.1% of the rest area; a vertex still heading for a junction hands the
//    junction to a neighbour that can take it; an edge joining two off-curve vertices of
//    different regions that neither can leave is flipped away when valid. (After flips the
//    vertex stars are updated from the flipped triangles only, Compressor::updateStars; after
//    splits and collapses they are rebuilt.)
//    (b) Boundary refinement (the simulation is over: from here on new vertices and edges
//    carry no springs): an edge between faces of different regions whose two ends are on one
//    chain (the chain whose sides carry those two regions, walked in the direction that keeps
//    them on their sides) is compared with the chain between its ends; if a chain point lies
//    farther than boundaryTolerance times the edge's length from it (a corner the compression
//    cut, a bulge between two vertices), the edge and its two faces are split at the farthest
//    chain point (or at the middle of the chain piece), the new vertex is on the curve
//    (pinned on a stop point) and each new face keeps the region of its side; a split whose
//    faces would have an angle below 15 or above 140 degrees is not made. Where the curve
//    runs beyond the face across the edge (an inlet deeper than a face) no split is valid:
//    that face's free vertex, which lies inside the bulge, is placed on the curve instead
//    (farthest point, or its own closest point of the chain) when its faces keep their
//    smallest angle above min(15 degrees, the current one), and its faces are classified
//    again. Up to 8 rounds.
//    (c) Flips: an edge between two faces of one region, one of them with an angle below 30
//    degrees, is flipped when both new faces are valid, keep that region and the pair's
//    smallest angle grows.
//    (d) Smoothing: a vertex whose faces have an angle below 30 degrees moves, if it is free
//    and inside one region, toward the centroid of its neighbours or toward one of them (the
//    candidate with the largest smallest angle, staying in its region), or, if it is on a
//    curve, along its chain (not onto stop points, no face changing region, no boundary edge
//    leaving the boundary tolerance or getting farther out of it unless an angle around the
//    vertex is below 20 degrees), when the smallest angle of its faces grows.
//    (e) Angle refinement: a face with an angle below 30 degrees whose longest edge is shared
//    with a face of its region gets that edge split by a free vertex, placed (on the edge or
//    toward the two faces' centroid) where the four new faces have the largest smallest
//    angle, if that beats the two faces' and the point lies in their region: the fans of
//    needles between a finely sampled curve and a coarse side, which no flip can mend.
//    (f) Collapse: a free or curve vertex inside one region with an angle below 30 degrees
//    around it, closer than 0.3 local edge lengths to a neighbour (squeezed against it: the
//    worst slivers), is merged into that neighbour when the link condition holds, no face
//    inverts and the smallest angle around grows; the edge's two faces disappear.
//    From (c) on, vertices whose push never arrived are free vertices (reported as stuck).
//    Rounds of (c), (d), (f), (e) repeat optimizationPasses times (until nothing changes).
//    Each round looks only at the faces with an angle below 30 degrees at its start, and their
//    corners (collectBad): the first round tests every face, a later one only the faces the
//    rounds before changed (flipped, split, collapsed, or with a corner moved) and the faces
//    they added; the others keep their test.
//    No move, flip, split or collapse of (c)-(f) lowers the local smallest angle, and region
//    boundaries stay on the vertices the compression put on curves.
#include "Compressor.h"

#include "Errors.h"
#include "Quality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace strata
{
namespace detail
{

//------------------------------------------------------------------------------
// Optimization.

// Local vertices on an edge between faces of different regions that are not on a curve.
std::vector<int> Compressor::offCurveBoundaryVertices() const
{
  std::vector<int> off;
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    this->poll(t);
    for (int k = 0; k < 3; ++k)
    {
      if (this->neighbourTag(static_cast<int>(t), k) != this->Tag[t])
      {
        for (int v : { this->Tri[t][k], this->Tri[t][(k + 1) % 3] })
        {
          if (!this->onCurve(v))
          {
            off.push_back(v);
          }
        }
      }
    }
  }
  sortUnique(off);
  return off;
}

// Places vertex i on the rail location `target` if the restrain test allows with
// minFraction of the usual area threshold; triangles that block the move have their edge
// opposite i flipped (when valid) and the move is tried again.
bool Compressor::placeOnCurve(int i, const Location& target, double minFraction)
{
  auto& x = this->positions();
  const Vec2 goal = this->Rails.position(target);
  for (int attempt = 0; attempt < 3; ++attempt)
  {
    std::vector<std::pair<int, int>> blocking;
    for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
    {
      const int t = this->StarItems[s];
      const std::array<int, 3>& tri = this->Tri[t];
      const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
      const Vec2 a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
      const double after = cross(b - a, goal - a);
      if (!(after > 0.0) ||
        (after < minFraction * (kCollapse * this->RestTwice[t]) && after < cross(b - a, x[i] - a)))
      {
        blocking.push_back({ t, (k + 1) % 3 });
      }
    }
    if (blocking.empty())
    {
      x[i] = goal;
      return true;
    }
    bool flipped = false;
    for (const std::pair<int, int>& e : blocking)
    {
      if (this->flipValid(e.first, e.second))
      {
        const int u = this->Nbr[e.first][e.second];
        this->flip(e.first, e.second);
        this->Tag[e.first] = this->faceTag(e.first);
        this->Tag[u] = this->faceTag(u);
        ++this->Result.flips;
        flipped = true;
      }
    }
    if (!flipped)
    {
      return false;
    }
    this->updateStars();
  }
  return false;
}

// Moves the vertices of the region boundary that are off the curves onto a curve.
std::size_t Compressor::snapBoundaryVertices()
{
  std::size_t snapped = 0;
  for (int round = 0; round < 3; ++round)
  {
    const std::vector<int> off = this->offCurveBoundaryVertices();
    std::size_t moved = 0;
    for (int v : off)
    {
      this->poll(static_cast<std::size_t>(&v - off.data()));
      if (!this->active(v))
      {
        continue; // halo vertices do not move
      }
      const Vec2 xv = this->positions()[v];
      const double h = this->H[v];
      // Candidate places: the closest point (or the junction a push was heading for), the
      // push target, and half and a quarter of an edge length beside them; nearest first.
      std::vector<Location> places;
      if (this->St[v] == Pushing && this->junctionBound(v))
      {
        places.push_back(this->Loc[v]);
      }
      else
      {
        const Location c0 = this->Rails.closest(xv, this->RailScratch);
        for (const Location& from : { c0, this->St[v] == Pushing ? this->Loc[v] : c0 })
        {
          for (double f : { 0.0, 0.25, -0.25, 0.5, -0.5 })
          {
            const Location l = this->Rails.slide(from, f * h).location;
            if (!this->nearClaimedStop(l, 0.1 * h))
            {
              places.push_back(l);
            }
          }
        }
        std::stable_sort(places.begin(),
          places.end(),
          [&](const Location& a, const Location& b)
          { return norm2(this->Rails.position(a) - xv) < norm2(this->Rails.position(b) - xv); });
      }
      bool placed = false;
      Location where;
      for (double fraction : { 1.0, kLastResort })
      {
        for (std::size_t k = 0; k < places.size() && !placed; ++k)
        {
          placed = this->placeOnCurve(v, places[k], fraction);
          where = places[k];
        }
        if (placed)
        {
          break;
        }
      }
      if (!placed && this->St[v] == Pushing && this->junctionBound(v))
      {
        // The junction this vertex was heading for: let a neighbour take it instead; the
        // vertex itself is then placed like any other in the next round.
        const Location junction = this->Loc[v];
        std::vector<int> ring;
        for (int s = this->StarStart[v]; s < this->StarStart[v + 1]; ++s)
        {
          for (int w : this->Tri[this->StarItems[s]])
          {
            if (w != v && this->active(w) && (this->St[w] == Free || this->St[w] == Rail))
            {
              ring.push_back(w);
            }
          }
        }
        const Vec2 target = this->pushed(v).target;
        std::sort(ring.begin(),
          ring.end(),
          [&](int a, int b)
          { return norm2(this->positions()[a] - target) < norm2(this->positions()[b] - target); });
        for (int w : ring)
        {
          if (this->placeOnCurve(w, junction, 1.0))
          {
            this->St[w] = Pinned;
            this->Loc[w] = junction;
            this->Sys->setKind(w, ParticleKind::Fixed);
            this->VRegion[w] = kOnCurve;
            this->retagStar(w);
            this->JunctionTarget[this->Global[v]] = -1;
            this->PinOnArrival[v] = 0;
            ++moved;
            break;
          }
        }
        continue;
      }
      if (!placed)
      {
        // Neither end of an edge joining i to an off-curve vertex of another region could be
        // placed: flip that edge away when the flip is valid.
        bool flipped = false;
        for (int s = this->StarStart[v]; s < this->StarStart[v + 1] && !flipped; ++s)
        {
          const int t = this->StarItems[s];
          const std::array<int, 3>& tri = this->Tri[t];
          for (int k = 0; k < 3 && !flipped; ++k)
          {
            const int a = tri[k], b = tri[(k + 1) % 3];
            if ((a == v || b == v) && this->VRegion[a] != kOnCurve &&
              this->VRegion[b] != kOnCurve && this->VRegion[a] != this->VRegion[b] &&
              this->flipValid(t, k))
            {
              const int u = this->Nbr[t][k];
              this->flip(t, k);
              this->Tag[t] = this->faceTag(t);
              this->Tag[u] = this->faceTag(u);
              ++this->Result.flips;
              flipped = true;
            }
          }
        }
        if (flipped)
        {
          this->updateStars();
          ++moved;
        }
        continue;
      }
      const int point = this->Rails.pointAt(where);
      const bool pin = (this->St[v] == Pushing && this->PinOnArrival[v]) ||
        (point >= 0 && this->Rails.isStop(where.chain, point));
      if (point >= 0 && pin)
      {
        this->Claimed[this->Rails.chain(where.chain).nodes[point]] = 1;
      }
      this->St[v] = pin ? Pinned : Rail;
      this->Loc[v] = where;
      this->Sys->setKind(v, pin ? ParticleKind::Fixed : ParticleKind::Driven);
      this->VRegion[v] = kOnCurve;
      this->retagStar(v);
      ++moved;
    }
    snapped += moved;
    if (moved == 0)
    {
      break;
    }
  }
  return snapped;
}

std::size_t Compressor::optimizeFlips()
{
  static const double goodSine = std::sin(kGoodAngle * 3.14159265358979323846 / 180.0);
  std::size_t flips = 0;
  for (int pass = 0; pass < 8; ++pass)
  {
    std::size_t now = 0;
    for (const int t : this->BadFaces)
    {
      this->pollEach(static_cast<std::size_t>(&t - this->BadFaces.data()));
      for (int k = 0; k < 3; ++k)
      {
        const int u = this->Nbr[t][k];
        if (u >= 0 && this->Tag[u] == this->Tag[t] &&
          (this->triMinAngleSine(t) < goodSine || this->triMinAngleSine(u) < goodSine) &&
          this->tryFlip(t, k, false))
        {
          ++now;
          break;
        }
      }
    }
    flips += now;
    if (now == 0)
    {
      break;
    }
  }
  if (flips > 0)
  {
    this->updateStars();
  }
  return flips;
}

double Compressor::starMinAngle(int i, Vec2 p) const
{
  const auto& x = this->positions();
  double m = 1.0;
  for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
  {
    const std::array<int, 3>& tri = this->Tri[this->StarItems[s]];
    m = std::min(m,
      minAngleSine(
        tri[0] == i ? p : x[tri[0]], tri[1] == i ? p : x[tri[1]], tri[2] == i ? p : x[tri[2]]));
  }
  return m; // the sine of the smallest angle
}

std::size_t Compressor::smooth()
{
  static const double skipSine = std::sin(kGoodAngle * 3.14159265358979323846 / 180.0);
  std::size_t moves = 0;
  auto& x = this->positions();
  for (const int& i : this->BadVertices)
  {
    this->pollEach(static_cast<std::size_t>(&i - this->BadVertices.data()));
    const int s0 = this->StarStart[i], s1 = this->StarStart[i + 1];
    if (!this->active(i))
    {
      continue;
    }
    if (s1 == s0 || !(this->St[i] == Free || this->St[i] == Rail))
    {
      continue;
    }
    const double m0 = this->starMinAngle(i, x[i]);
    if (m0 >= skipSine)
    {
      continue;
    }
    if (this->St[i] == Free)
    {
      // Only vertices inside one region (all faces of its region) move.
      bool inside = true;
      for (int s = s0; s < s1 && inside; ++s)
      {
        inside = this->Tag[this->StarItems[s]] == this->VRegion[i];
      }
      if (!inside)
      {
        continue;
      }
      Vec2 c{};
      int count = 0;
      for (int s = s0; s < s1; ++s)
      {
        for (int v : this->Tri[this->StarItems[s]])
        {
          if (v != i)
          {
            c = c + x[v];
            ++count;
          }
        }
      }
      c = (1.0 / count) * c;
      // Candidates: toward the centroid of the neighbours, and toward each neighbour; the one
      // with the largest smallest angle wins if it beats the current position.
      auto& candidates = this->Candidates;
      candidates.clear();
      for (double f : { 1.0, 0.5, 0.25 })
      {
        candidates.push_back(x[i] + f * (c - x[i]));
      }
      for (int s = s0; s < s1; ++s)
      {
        for (int v : this->Tri[this->StarItems[s]])
        {
          if (v != i)
          {
            candidates.push_back(x[i] + 0.3 * (x[v] - x[i]));
            candidates.push_back(x[i] + 0.1 * (x[v] - x[i]));
          }
        }
      }
      double bestM = m0 * (1.0 + 1e-9) + 1e-12;
      Vec2 best = x[i];
      for (const Vec2& p : candidates)
      {
        const double m = this->starMinAngle(i, p);
        if (m > bestM && this->accepts(i, p))
        {
          bestM = m;
          best = p;
        }
      }
      if (best == x[i])
      {
        continue;
      }
      // Same region: within the boundary-free disk around x[i], or by a query.
      double reach = 0.0;
      this->Rails.closest(x[i], this->RailScratch, &reach);
      if (norm(best - x[i]) < reach || this->regionAt(best) == this->VRegion[i])
      {
        this->noteStar(i);
        x[i] = best;
        ++moves;
      }
      continue;
    }
    // A curve vertex slides along its chain (not onto a stop point); faces with every corner
    // on curves take the region of their barycentre and must keep it.
    const double h = this->H[i];
    double bestM = m0 * (1.0 + 1e-9) + 1e-12;
    Location bestLoc;
    bool found = false;
    for (double f : { 0.3, -0.3, 0.15, -0.15, 0.05, -0.05 })
    {
      const BoundaryRails::Slide sl = this->Rails.slide(this->Loc[i], f * h);
      if (sl.stopped)
      {
        continue;
      }
      const Vec2 p = this->Rails.position(sl.location);
      const double m = this->starMinAngle(i, p);
      if (m > bestM && this->accepts(i, p))
      {
        bestM = m;
        bestLoc = sl.location;
        found = true;
      }
    }
    if (!found)
    {
      continue;
    }
    const Vec2 p = this->Rails.position(bestLoc);
    bool kept = this->followsCurves(i, p, bestLoc);
    for (int s = s0; s < s1 && kept; ++s)
    {
      const int t = this->StarItems[s];
      const std::array<int, 3>& tri = this->Tri[t];
      kept = this->faceTag(tri[0],
               tri[1],
               tri[2],
               tri[0] == i ? p : x[tri[0]],
               tri[1] == i ? p : x[tri[1]],
               tri[2] == i ? p : x[tri[2]]) == this->Tag[t];
    }
    if (kept)
    {
      this->noteStar(i);
      x[i] = p;
      this->Loc[i] = bestLoc;
      ++moves;
    }
  }
  return moves;
}

//------------------------------------------------------------------------------
// Boundary refinement.

// Rail locations of curve vertex i: its own, or every location of the chain point it is on
// (a junction lies on several chains).
template<typename F>
void Compressor::forEachLocation(int i, F&& f) const
{
  const Location& l = this->Loc[i];
  const int point = this->Rails.pointAt(l);
  if (point < 0)
  {
    f(l);
    return;
  }
  for (const Location& at : this->Rails.locationsOfNode(this->Rails.chain(l.chain).nodes[point]))
  {
    f(at);
  }
}

// The chain piece that edge k of face t (between two faces of different regions, both ends on
// curves) stands for, with the largest distance of its points to the edge; deviation < 0 when
// no chain joins the two ends with the faces' regions on its sides.
Compressor::ChainPiece Compressor::boundaryPiece(int t, int k) const
{
  ChainPiece best;
  const int u = this->Nbr[t][k];
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3];
  const auto& x = this->positions();
  this->forEachLocation(a,
    [&](const Location& la)
    {
      this->forEachLocation(b,
        [&](const Location& lb)
        {
          if (la.chain != lb.chain)
          {
            return;
          }
          const BoundaryRails::Chain& c = this->Rails.chain(la.chain);
          const int n = static_cast<int>(c.numberOfSegments());
          const double sa = la.segment + la.t, sb = lb.segment + lb.t;
          for (const bool forward : { true, false })
          {
            // Walking a -> b along the chain, face t (left of a -> b) must be on the walk's left.
            const int left = forward ? c.left : c.right, right = forward ? c.right : c.left;
            if (this->Tag[t] != left || this->Tag[u] != right)
            {
              continue;
            }
            double travel = forward ? sb - sa : sa - sb;
            if (c.closed)
            {
              travel = std::fmod(travel + n, static_cast<double>(n));
            }
            if (!(travel > 0.0))
            {
              continue;
            }
            ChainPiece piece;
            piece.chain = la.chain;
            piece.from = sa;
            piece.to = sb;
            piece.forward = forward;
            piece.deviation = 0.0;
            // Chain points strictly between the two ends (at most a bounded number of them).
            const double first = forward ? std::floor(sa) + 1.0 : std::ceil(sa) - 1.0;
            for (int step = 0; step < 100000; ++step)
            {
              const double s = forward ? first + step : first - step;
              if ((forward ? s - sa : sa - s) >= travel)
              {
                break;
              }
              const int p = ((static_cast<int>(s) % n) + n) % n + (!c.closed && s == n ? n : 0);
              const double d = std::sqrt(pointSegmentDistance2(c.points[p], x[a], x[b]));
              if (d > piece.deviation)
              {
                piece.deviation = d;
                piece.farthest = p;
              }
            }
            if (best.deviation < 0.0 || piece.deviation < best.deviation)
            {
              best = piece;
            }
          }
        });
    });
  return best;
}

// The location half way (in arc length) along a chain piece.
BoundaryRails::Location Compressor::pieceMiddle(const ChainPiece& piece) const
{
  const BoundaryRails::Chain& c = this->Rails.chain(piece.chain);
  const int n = static_cast<int>(c.numberOfSegments());
  const auto at = [&](double s)
  {
    s = c.closed ? std::fmod(std::fmod(s, n) + n, static_cast<double>(n)) : s;
    const int seg = std::min(static_cast<int>(s), n - 1);
    const Vec2 p = c.points[seg], q = c.points[(seg + 1) % c.points.size()];
    return p + (s - seg) * (q - p);
  };
  double travel = piece.forward ? piece.to - piece.from : piece.from - piece.to;
  if (c.closed)
  {
    travel = std::fmod(travel + n, static_cast<double>(n));
  }
  // Break points of the walk: the two ends and the chain points between.
  std::vector<double> params{ piece.from };
  const double first = piece.forward ? std::floor(piece.from) + 1.0 : std::ceil(piece.from) - 1.0;
  for (int step = 0; step < 100000; ++step)
  {
    const double s = piece.forward ? first + step : first - step;
    if ((piece.forward ? s - piece.from : piece.from - s) >= travel)
    {
      break;
    }
    params.push_back(s);
  }
  params.push_back(piece.forward ? piece.from + travel : piece.from - travel);
  double length = 0.0;
  for (std::size_t i = 1; i < params.size(); ++i)
  {
    length += norm(at(params[i]) - at(params[i - 1]));
  }
  double half = 0.5 * length;
  double s = params.back();
  for (std::size_t i = 1; i < params.size(); ++i)
  {
    const double l = norm(at(params[i]) - at(params[i - 1]));
    if (l >= half && l > 0.0)
    {
      s = params[i - 1] + (params[i] - params[i - 1]) * (half / l);
      break;
    }
    half -= l;
  }
  if (c.closed)
  {
    s = std::fmod(std::fmod(s, n) + n, static_cast<double>(n));
  }
  Location l;
  l.chain = piece.chain;
  l.segment = std::min(static_cast<int>(s), n - 1);
  l.t = std::min(1.0, s - l.segment);
  return l;
}

// Splits edge k of face t (a, b) and its neighbour across it at rail location `at`:
// (a, b, c) + (b, a, d) -> (a, w, c) + (w, b, c) + (b, w, d) + (w, a, d), each new face keeping
// the region of its side. Refused (false) when a new face would have an angle below 15
// degrees or above 140 degrees (the optimization that follows could not mend it).
bool Compressor::canSplit(int t, int k, Vec2 w) const
{
  static const double floorSine = std::sin(15.0 * 3.14159265358979323846 / 180.0);
  static const double kMaxCos = std::cos(140.0 * 3.14159265358979323846 / 180.0);
  for (const std::array<Vec2, 3>& f : this->splitFaces(this->quadOf(t, k), w))
  {
    if (!(orient2d(f[0], f[1], f[2]) > 0.0) || minAngleSine(f[0], f[1], f[2]) < floorSine ||
      dot(f[1] - f[0], f[2] - f[0]) < kMaxCos * norm(f[1] - f[0]) * norm(f[2] - f[0]) ||
      dot(f[0] - f[1], f[2] - f[1]) < kMaxCos * norm(f[0] - f[1]) * norm(f[2] - f[1]) ||
      dot(f[0] - f[2], f[1] - f[2]) < kMaxCos * norm(f[0] - f[2]) * norm(f[1] - f[2]))
    {
      return false;
    }
  }
  return true;
}

bool Compressor::splitBoundaryEdge(int t, int k, const Location& at, bool pin)
{
  const Vec2 w = this->Rails.position(at);
  if (!this->canSplit(t, k, w))
  {
    return false;
  }
  this->splitEdge(t, k, w, pin ? Pinned : Rail, at, kOnCurve);
  if (pin)
  {
    const int point = this->Rails.pointAt(at);
    if (point >= 0)
    {
      this->Claimed[this->Rails.chain(at.chain).nodes[point]] = 1;
    }
  }
  return true;
}

// Splits edge k of face t (a, b) and its neighbour across it with a new vertex at w, of state
// `state` (rail location `at` for curve vertices, `region` for free ones):
// (a, b, c) + (b, a, d) -> (a, w, c) + (w, b, c) + (b, w, d) + (w, a, d); the new faces keep
// the regions of the faces they come from. The caller checked that all four are valid.
void Compressor::splitEdge(int t, int k, Vec2 w, std::uint8_t state, const Location& at, int region)
{
  auto& x = this->positions();
  const Quad q = this->quadOf(t, k);
  const int u = q.u, j = q.j, a = q.a, b = q.b, c = q.c, d = q.d;
  // The new vertex.
  const int i = static_cast<int>(this->Global.size());
  const int g = static_cast<int>(this->Result.points.size());
  this->Global.push_back(g);
  this->LocalOf.push_back(i);
  this->Result.points.push_back(w);
  this->Result.vertexState.push_back(
    state == Pinned ? VertexPinned : (state == Rail ? VertexOnCurve : VertexFree));
  this->Candidate.push_back(0);
  this->Push.push_back(0);
  this->Distance.push_back(0.0);
  this->JunctionOf.push_back(-1);
  this->JunctionTarget.push_back(-1);
  x.push_back(w);
  this->St.push_back(state);
  this->Loc.push_back(at);
  this->PinOnArrival.push_back(0);
  this->PushOf.push_back(-1); // (never pushed: the simulation is over)
  this->VRegion.push_back(region);
  this->H.push_back(0.5 * (this->H[a] + this->H[b]));
  // The two new faces.
  const int t2 = static_cast<int>(this->Tri.size()), u2 = t2 + 1;
  const int nBC = this->Nbr[t][(k + 1) % 3], nCA = this->Nbr[t][(k + 2) % 3];
  const int nAD = this->Nbr[u][(j + 1) % 3], nDB = this->Nbr[u][(j + 2) % 3];
  this->noteChanged(t); // (t2 and u2 are new faces: collectBad() tests those anyway)
  this->noteChanged(u);
  this->Flipped.push_back(t); // (the stars: updateStars(), which takes t2 and u2 as new)
  this->Flipped.push_back(u);
  this->Tri[t] = { a, i, c };
  this->Nbr[t] = { u2, t2, nCA };
  this->Tri[u] = { b, i, d };
  this->Nbr[u] = { t2, u2, nDB };
  this->Tri.push_back({ i, b, c });
  this->Nbr.push_back({ u, nBC, t });
  this->Tri.push_back({ i, a, d });
  this->Nbr.push_back({ t, nAD, u });
  for (const std::pair<int, int>& relink : { std::make_pair(nBC, t), std::make_pair(nAD, u) })
  {
    if (relink.first >= 0)
    {
      for (int& m : this->Nbr[relink.first])
      {
        m = m == relink.second ? (relink.second == t ? t2 : u2) : m;
      }
    }
  }
  for (const int f : { t, u })
  {
    this->TriEdge[f] = { -1, -1, -1 };
  }
  this->TriEdge.push_back({ -1, -1, -1 });
  this->TriEdge.push_back({ -1, -1, -1 });
  for (const std::pair<int, int>& added : { std::make_pair(t2, t), std::make_pair(u2, u) })
  {
    this->TriGlobal.push_back(static_cast<int>(this->Result.triangles.size()));
    this->Result.triangles.push_back({});
    this->Result.triangleLevel.push_back(this->Level[added.second]);
    this->Result.triangleRegion.push_back(this->Tag[added.second]);
    this->Level.push_back(this->Level[added.second]);
    this->Tag.push_back(this->Tag[added.second]);
    this->RestTwice.push_back(0.0);
  }
  for (const int f : { t, u, t2, u2 })
  {
    this->RestTwice[f] = this->twiceArea(f);
  }
}

// Whether moving curve vertex i to p (rail location l) keeps its boundary edges within the
// boundary tolerance of their chain pieces, or at least no farther out of it than they are.
// Always true without boundary refinement, and for a vertex with an angle below kPoorAngle
// around it (the worst angles come first).
bool Compressor::followsCurves(int i, Vec2 p, const Location& l)
{
  static const double poorSine = std::sin(kPoorAngle * 3.14159265358979323846 / 180.0);
  if (!this->Detached || this->starMinAngle(i, this->positions()[i]) < poorSine)
  {
    return true;
  }
  // Relative deviation of the worst boundary edge at i (0 when none is out of tolerance).
  auto& x = this->positions();
  const auto worst = [&]()
  {
    double w = 0.0;
    for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
    {
      const int t = this->StarItems[s];
      for (int k = 0; k < 3; ++k)
      {
        const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3], u = this->Nbr[t][k];
        if ((a == i || b == i) && u >= 0 && this->Tag[u] != this->Tag[t] && this->onCurve(a) &&
          this->onCurve(b))
        {
          const double relative = this->boundaryPiece(t, k).deviation / norm(x[b] - x[a]);
          w = std::max(w, relative > this->Params.boundaryTolerance ? relative : 0.0);
        }
      }
    }
    return w;
  };
  const double before = worst();
  const Vec2 keepX = x[i];
  const Location keepL = this->Loc[i];
  x[i] = p;
  this->Loc[i] = l;
  const double after = worst();
  x[i] = keepX;
  this->Loc[i] = keepL;
  return after <= before;
}

// Whether edge k of face t is a boundary edge between two curve vertices (each edge once:
// from the face of smaller id, both faces below nt) whose chain piece lies out of tolerance.
bool Compressor::deviatingEdge(int t, int k, int nt, ChainPiece& piece) const
{
  const int u = this->Nbr[t][k];
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3];
  if (u < 0 || u >= nt || u < t || this->Tag[u] == this->Tag[t] || !this->onCurve(a) ||
    !this->onCurve(b))
  {
    return false;
  }
  piece = this->boundaryPiece(t, k);
  const auto& x = this->positions();
  return piece.farthest >= 0 &&
    piece.deviation > this->Params.boundaryTolerance * norm(x[b] - x[a]);
}

BoundaryRails::Location Compressor::farthestLocation(const ChainPiece& piece) const
{
  const BoundaryRails::Chain& c = this->Rails.chain(piece.chain);
  const int p = piece.farthest;
  Location far;
  far.chain = piece.chain;
  far.segment = c.closed || p < static_cast<int>(c.numberOfSegments()) ? p : p - 1;
  far.t = far.segment == p ? 0.0 : 1.0;
  return far;
}

// The curve bulges beyond the face across edge k of t (an inlet deeper than a triangle): the
// free vertex of that face, which lies inside the bulge, is placed on the curve (at the
// farthest point or at its own closest point of the chain), when the restrain test allows;
// its faces are classified again. Needs a current star table.
bool Compressor::pullIntoBulge(int t, int k, const Location& far)
{
  static const double floorSine = std::sin(15.0 * 3.14159265358979323846 / 180.0);
  const auto& x = this->positions();
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3];
  const Vec2 w = this->Rails.position(far);
  const Quad q = this->quadOf(t, k);
  const int v = orient2d(x[a], x[b], w) > 0.0 ? q.c : q.d;
  if (!this->active(v) || this->St[v] != Free)
  {
    return false;
  }
  std::vector<Location> places{ far };
  const Location closest = this->Rails.closest(x[v], this->RailScratch);
  if (closest.chain == far.chain)
  {
    places.push_back(closest);
  }
  for (const Location& l : places)
  {
    const int point = this->Rails.pointAt(l);
    const bool stop = point >= 0 && this->Rails.isStop(l.chain, point);
    if ((stop && this->Claimed[this->Rails.chain(l.chain).nodes[point]]) ||
      (!stop && this->nearClaimedStop(l, 0.1 * this->H[v])) ||
      this->starMinAngle(v, this->Rails.position(l)) <
        std::min(floorSine, this->starMinAngle(v, x[v])))
    {
      continue;
    }
    if (this->placeOnCurve(v, l, 1.0))
    {
      if (stop)
      {
        this->Claimed[this->Rails.chain(l.chain).nodes[point]] = 1;
      }
      this->St[v] = stop ? Pinned : Rail;
      this->Loc[v] = l;
      this->VRegion[v] = kOnCurve;
      this->retagStar(v);
      return true;
    }
  }
  return false;
}

// From here on the springs no longer follow the mesh (no more simulation): vertices and
// faces may be added. The spring system goes, but for its positions (its springs, velocities,
// forces and copy of the mesh: 130 MB at 1 M triangles, which the optimization's arrays and
// the refinement's then reuse instead of new memory).
void Compressor::detach()
{
  if (this->Sys)
  {
    this->X = std::move(this->Sys->positions());
    this->Sys.reset();
  }
  this->fillResult(); // (the splits append to it)
  this->Detached = true;
  if (this->FirstAdded == std::numeric_limits<int>::max())
  {
    this->FirstAdded = static_cast<int>(this->Global.size());
  }
}

// Angle refinement: a face with an angle below kGoodAngle whose longest edge is shared with a
// face of the same region gets that edge split by a free vertex placed where the four new
// faces have the largest smallest angle (on the edge's midpoint, or toward the centroid of
// the two faces), when that is larger than the two faces' smallest angle and the point lies
// in their region. The fans of needles left where a finely sampled curve faces a coarse side
// are mostly mended this way (flips cannot: no edge there gives better faces). One round;
// at most a tenth of the faces are added per round.
std::size_t Compressor::refineAngles()
{
  static const double goodSine = std::sin(kGoodAngle * 3.14159265358979323846 / 180.0);
  this->detach();
  const auto& x = this->positions();
  const int nt = static_cast<int>(this->Tri.size());
  const std::size_t budget = this->Tri.size() / 10 + 16;
  std::size_t added = 0;
  for (std::size_t n = 0; n < this->BadFaces.size() && added < budget; ++n)
  {
    const int t = this->BadFaces[n];
    this->pollEach(n);
    if (t >= nt)
    {
      continue;
    }
    const double m0 = this->triMinAngleSine(t);
    if (m0 >= goodSine)
    {
      continue;
    }
    int k = 0;
    double longest = -1.0;
    for (int e = 0; e < 3; ++e)
    {
      const double l = norm2(x[this->Tri[t][(e + 1) % 3]] - x[this->Tri[t][e]]);
      if (l > longest)
      {
        longest = l;
        k = e;
      }
    }
    const int u = this->Nbr[t][k];
    if (u < 0)
    {
      continue;
    }
    const Quad q = this->quadOf(t, k);
    const int a = q.a, b = q.b, c = q.c, d = q.d;
    // Candidates: inside one region, points on the edge (its middle, the feet of c and d) and
    // toward the two faces' centroid; on a region boundary (two curve vertices), the points
    // of the curve piece closest to those.
    const bool boundary = this->Tag[u] != this->Tag[t];
    ChainPiece piece;
    if (boundary)
    {
      if (!this->onCurve(a) || !this->onCurve(b))
      {
        continue;
      }
      piece = this->boundaryPiece(t, k);
      if (piece.deviation < 0.0)
      {
        continue;
      }
    }
    const Vec2 ab = x[b] - x[a];
    const auto foot = [&](Vec2 p)
    {
      const double f = std::clamp(dot(p - x[a], ab) / norm2(ab), 0.1, 0.9);
      return x[a] + f * ab;
    };
    const Vec2 mid = 0.5 * (x[a] + x[b]);
    const Vec2 centroid = 0.25 * (x[a] + x[b] + x[c] + x[d]);
    std::vector<Vec2> points{ mid, foot(x[c]), foot(x[d]) };
    if (!boundary)
    {
      for (double f : { 0.25, 0.5, 0.75, 1.0 })
      {
        points.push_back(mid + f * (centroid - mid));
      }
    }
    const double before = std::min(m0, this->triMinAngleSine(u));
    const double beforeCos =
      std::min(largestAngleCosine(x[a], x[b], x[c]), largestAngleCosine(x[b], x[a], x[d]));
    // The best candidate: the largest smallest angle; a smaller largest angle breaks ties
    // (a flat face split at the foot of its obtuse corner keeps its small angles).
    double bestM = before * (1.0 + 1e-3) + 1e-9, bestCos = 2.0;
    Vec2 where{};
    Location whereOnCurve;
    bool found = false;
    for (const Vec2& p : points)
    {
      Vec2 w = p;
      Location l;
      if (boundary)
      {
        l = this->Rails.closest(p, this->RailScratch);
        if (!this->insidePiece(piece, l))
        {
          continue;
        }
        w = this->Rails.position(l);
      }
      double m = 1.0, cm = 1.0;
      for (const std::array<Vec2, 3>& g : this->splitFaces(q, w))
      {
        m = orient2d(g[0], g[1], g[2]) > 0.0 ? std::min(m, minAngleSine(g[0], g[1], g[2])) : -1.0;
        cm = std::min(cm, largestAngleCosine(g[0], g[1], g[2]));
      }
      const bool better = m > bestM ||
        (m >= before * (1.0 - 1e-9) && m > 0.0 && cm > beforeCos + 0.02 &&
          (bestCos > 1.5 || cm > bestCos) && !found);
      if (better)
      {
        bestM = std::max(bestM, m);
        bestCos = cm;
        where = w;
        whereOnCurve = l;
        found = true;
      }
    }
    if (!found)
    {
      continue;
    }
    if (boundary)
    {
      const int point = this->Rails.pointAt(whereOnCurve);
      const bool pin = point >= 0 && this->Rails.isStop(whereOnCurve.chain, point);
      if (pin && this->Claimed[this->Rails.chain(whereOnCurve.chain).nodes[point]])
      {
        continue;
      }
      this->splitEdge(t, k, where, pin ? Pinned : Rail, whereOnCurve, kOnCurve);
      if (pin)
      {
        this->Claimed[this->Rails.chain(whereOnCurve.chain).nodes[point]] = 1;
      }
    }
    else
    {
      if (this->regionAt(where) != this->Tag[t])
      {
        continue;
      }
      this->splitEdge(t, k, where, Free, Location{}, this->Tag[t]);
    }
    ++added;
  }
  if (added > 0)
  {
    this->updateStars();
  }
  return added;
}

// Whether rail location l lies strictly inside a chain piece (between its two ends).
bool Compressor::insidePiece(const ChainPiece& piece, const Location& l) const
{
  if (l.chain != piece.chain)
  {
    return false;
  }
  const BoundaryRails::Chain& c = this->Rails.chain(piece.chain);
  const double n = static_cast<double>(c.numberOfSegments());
  const double sl = l.segment + l.t;
  double travel = piece.forward ? piece.to - piece.from : piece.from - piece.to;
  double along = piece.forward ? sl - piece.from : piece.from - sl;
  if (c.closed)
  {
    travel = std::fmod(travel + n, n);
    along = std::fmod(along + n, n);
  }
  return along > 1e-9 && along < travel - 1e-9;
}

// Collapses vertex i (free, all its faces in one region, its star closed) into its neighbour
// v: the two faces of edge (i, v) disappear (marked dead: all three corners i, no neighbours,
// region -1; compress() drops them), i's other faces take v instead. Done only when the link
// condition holds (i and v share exactly the two other corners of those faces), every face
// stays counter-clockwise and the smallest angle of the faces around i and v grows. The
// region boundary does not change: the faces around i all had one region.
bool Compressor::collapseInto(int i, int v)
{
  const auto& x = this->positions();
  const int si0 = this->StarStart[i], si1 = this->StarStart[i + 1];
  const int sv0 = this->StarStart[v], sv1 = this->StarStart[v + 1];
  std::array<int, 2> f{ -1, -1 };
  int nf = 0;
  for (int s = si0; s < si1; ++s)
  {
    const int t = this->StarItems[s];
    const std::array<int, 3>& tri = this->Tri[t];
    for (int k = 0; k < 3; ++k)
    {
      if ((tri[k] == i || tri[(k + 1) % 3] == i) && this->Nbr[t][k] < 0)
      {
        return false; // i is on the border of the simulated zone
      }
    }
    if (hasVertex(tri, v))
    {
      if (nf == 2)
      {
        return false;
      }
      f[nf++] = t;
    }
  }
  if (nf != 2)
  {
    return false;
  }
  // Link condition: the common neighbours of i and v are the third corners of f.
  const auto third = [&](int t)
  {
    for (int w : this->Tri[t])
    {
      if (w != i && w != v)
      {
        return w;
      }
    }
    return -1;
  };
  const int p = third(f[0]), q = third(f[1]);
  std::vector<int> ni, nv;
  for (int s = si0; s < si1; ++s)
  {
    for (int w : this->Tri[this->StarItems[s]])
    {
      ni.push_back(w);
    }
  }
  for (int s = sv0; s < sv1; ++s)
  {
    for (int w : this->Tri[this->StarItems[s]])
    {
      nv.push_back(w);
    }
  }
  sortUnique(ni);
  sortUnique(nv);
  std::vector<int> common;
  std::set_intersection(ni.begin(), ni.end(), nv.begin(), nv.end(), std::back_inserter(common));
  common.erase(
    std::remove_if(common.begin(), common.end(), [&](int w) { return w == i || w == v; }),
    common.end());
  if (common.size() != 2 ||
    !((common[0] == p && common[1] == q) || (common[0] == q && common[1] == p)))
  {
    return false;
  }
  // Quality.
  // (v's faces that are not i's do not change: comparing i's faces before with the changed
  // faces after is enough for the smallest angle around i and v not to drop.)
  double before = 1.0, after = 1.0;
  for (int s = si0; s < si1; ++s)
  {
    const int t = this->StarItems[s];
    before = std::min(before, this->triMinAngleSine(t));
    if (t == f[0] || t == f[1])
    {
      continue;
    }
    std::array<Vec2, 3> g;
    for (int k = 0; k < 3; ++k)
    {
      g[k] = x[this->Tri[t][k] == i ? v : this->Tri[t][k]];
    }
    if (!(orient2d(g[0], g[1], g[2]) > 0.0))
    {
      return false;
    }
    after = std::min(after, minAngleSine(g[0], g[1], g[2]));
  }
  if (!(after > before * (1.0 + 1e-9) + 1e-12))
  {
    return false;
  }
  // Relink around the two dying faces: across (v, p) and (p, i) (resp. q) their outer
  // neighbours become neighbours of each other.
  for (const int t : f)
  {
    int kv = -1, ki = -1;
    for (int k = 0; k < 3; ++k)
    {
      const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3];
      if ((a == i || b == i) && (a == v || b == v))
      {
        continue;
      }
      (a == v || b == v ? kv : ki) = k;
    }
    const int nV = this->Nbr[t][kv], nI = this->Nbr[t][ki];
    for (const std::pair<int, int>& link : { std::make_pair(nI, nV), std::make_pair(nV, nI) })
    {
      if (link.first >= 0)
      {
        for (int& m : this->Nbr[link.first])
        {
          m = m == t ? link.second : m;
        }
      }
    }
  }
  this->noteStar(i); // (f's faces among them)
  for (int s = si0; s < si1; ++s)
  {
    const int t = this->StarItems[s];
    this->Flipped.push_back(t); // (the stars: updateStars())
    if (t == f[0] || t == f[1])
    {
      continue;
    }
    for (int& w : this->Tri[t])
    {
      w = w == i ? v : w;
    }
    this->RestTwice[t] = this->twiceArea(t);
  }
  for (const int t : f)
  {
    this->Tri[t] = { i, i, i };
    this->Nbr[t] = { -1, -1, -1 };
    this->Tag[t] = -1;
    this->RestTwice[t] = 0.0;
  }
  this->St[i] = Halo;
  return true;
}

// Free or curve vertices with an angle below kGoodAngle around them, inside one region,
// closer than 0.3 local edge lengths to a neighbour: collapsed into the nearest such
// neighbour when collapseInto() allows (a vertex squeezed against a curve vertex makes the
// worst slivers). Vertices next to a collapse wait for the next round (their stars changed).
std::size_t Compressor::collapseSqueezed()
{
  static const double goodSine = std::sin(kGoodAngle * 3.14159265358979323846 / 180.0);
  const auto& x = this->positions();
  std::vector<std::uint8_t> touched(this->Global.size(), 0);
  std::size_t collapsed = 0;
  for (const int& i : this->BadVertices)
  {
    this->pollEach(static_cast<std::size_t>(&i - this->BadVertices.data()));
    const int s0 = this->StarStart[i], s1 = this->StarStart[i + 1];
    if (touched[i] || !this->active(i) || !(this->St[i] == Free || this->St[i] == Rail) ||
      s0 == s1 || this->starMinAngle(i, x[i]) >= goodSine)
    {
      continue;
    }
    bool inside = true;
    std::vector<int> ring;
    for (int s = s0; s < s1 && inside; ++s)
    {
      const int t = this->StarItems[s];
      inside = this->Tag[t] == this->Tag[this->StarItems[s0]];
      for (int w : this->Tri[t])
      {
        if (w != i)
        {
          ring.push_back(w);
        }
      }
    }
    if (!inside)
    {
      continue;
    }
    std::sort(ring.begin(),
      ring.end(),
      [&](int a, int b) { return norm2(x[a] - x[i]) < norm2(x[b] - x[i]); });
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (int v : ring)
    {
      if (norm(x[v] - x[i]) >= 0.3 * this->H[i])
      {
        break;
      }
      if (touched[v])
      {
        continue;
      }
      if (this->collapseInto(i, v))
      {
        for (int s = s0; s < s1; ++s)
        {
          for (int w : this->Tri[this->StarItems[s]])
          {
            touched[w] = 1;
          }
        }
        touched[i] = touched[v] = 1;
        ++collapsed;
        break;
      }
    }
  }
  if (collapsed > 0)
  {
    this->updateStars();
  }
  return collapsed;
}

void Compressor::collectBad()
{
  static const double goodSine = std::sin(kGoodAngle * 3.14159265358979323846 / 180.0);
  const auto isBad = [&](int t)
  { return this->Tri[t][0] != this->Tri[t][1] && this->triMinAngleSine(t) < goodSine; };
  const std::size_t nt = this->Tri.size();
  if (!this->BadMark.empty())
  {
    // A later round's: the faces changed or added since the last call are tested again, the
    // others keep their test (their corners and positions are as they were).
    const std::size_t before = this->BadMark.size();
    this->BadMark.resize(nt, 0);
    for (const int t : this->Changed)
    {
      this->BadMark[t] = isBad(t) ? 1 : 0;
    }
    for (std::size_t t = before; t < nt; ++t)
    {
      this->BadMark[t] = isBad(static_cast<int>(t)) ? 1 : 0;
    }
  }
  else
  {
    // The first round's: every face (on two threads: the tests only read).
    withRoom(this->BadMark, nt).resize(nt);
    blockwise(
      nt,
      kTwoThreadBlock,
      kTwoThreadItems,
      [&](std::size_t from, std::size_t to, int)
      {
        for (std::size_t t = from; t < to; ++t)
        {
          this->BadMark[t] = isBad(static_cast<int>(t)) ? 1 : 0;
        }
      },
      [&] { this->Progress.report(this->At, this->Stage); });
  }
  this->Changed.clear();
  this->BadFaces.clear();
  this->BadVertices.clear();
  std::vector<std::uint8_t> mark(this->Global.size(), 0);
  for (std::size_t t = 0; t < nt; ++t)
  {
    if (this->BadMark[t])
    {
      this->BadFaces.push_back(static_cast<int>(t));
      for (int v : this->Tri[t])
      {
        if (!mark[v])
        {
          mark[v] = 1;
          this->BadVertices.push_back(v);
        }
      }
    }
  }
  std::sort(this->BadVertices.begin(), this->BadVertices.end());
}

std::size_t Compressor::refineBoundary()
{
  if (!(this->Params.boundaryTolerance > 0.0))
  {
    return 0;
  }
  this->detach();
  std::size_t splits = 0;
  LargeVector<std::uint8_t> deviating; // (see forEachDeviatingEdge())
  for (int round = 0; round < 8; ++round)
  {
    // Splits at the farthest curve point, or at the middle of the curve piece.
    const std::size_t now = this->forEachDeviatingEdge(deviating,
      [&](int t, int k, const ChainPiece& piece)
      {
        const Location far = this->farthestLocation(piece);
        if (this->splitBoundaryEdge(t, k, far, this->Rails.isStop(far.chain, piece.farthest)))
        {
          return true;
        }
        const Location middle = this->pieceMiddle(piece);
        const int point = this->Rails.pointAt(middle);
        return this->splitBoundaryEdge(
          t, k, middle, point >= 0 && this->Rails.isStop(piece.chain, point));
      });
    splits += now;
    // Edges that cannot be split because the curve runs beyond the opposite face: pull that
    // face's free vertex onto the curve (the next round splits what is left). The stars:
    // updated from the round's splits (updateStars()).
    this->updateStars();
    const std::size_t pulled = this->forEachDeviatingEdge(deviating,
      [&](int t, int k, const ChainPiece& piece)
      {
        const Location far = this->farthestLocation(piece);
        return !this->canSplit(t, k, this->Rails.position(far)) &&
          !this->canSplit(t, k, this->Rails.position(this->pieceMiddle(piece))) &&
          this->pullIntoBulge(t, k, far); // (a splittable edge waits for the next round)
      });
    this->Result.bulgeVertices += pulled;
    if (now == 0 && pulled == 0)
    {
      break;
    }
  }
  this->updateStars(); // (updated from the pulls' flips)
  return splits;
}

} // namespace detail
} // namespace strata
