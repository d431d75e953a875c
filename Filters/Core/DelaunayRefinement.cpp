// StrataMesh core: constrained Delaunay refinement of the compressed mesh.
//
// The algorithm
// -------------
// The compression leaves a region-tagged mesh whose region boundaries follow the curves and
// whose triangles are mostly good; what is left below the angle bound are strips between
// curves closer than the triangles, caps on wiggly curves and fans around boundary vertices.
// Delaunay refinement (Ruppert 1995; Shewchuk's Triangle; off-centres after Ungor 2004)
// mends those while keeping every region boundary edge:
// 1. Constrained edges. An edge is constrained when its two triangles have different regions,
//    it has one triangle, or a triangle beside it has no positive area. Only the other edges
//    are ever flipped, so every triangle keeps its region.
// 2. Constrained Delaunay. Lawson's flips: an unconstrained edge whose opposite vertex lies
//    inside the other triangle's circumcircle is flipped, until none is left. This maximises
//    the smallest angle over all triangulations with the same vertices and constrained edges,
//    so it never lowers the minimum angle of the compressed mesh.
// 2b. Curve recovery (optional: RefinementParams::curvePoint and regionAt). Every triangle at
//    least minimumEdgeLength short-side through which a model curve runs (curvePoint gives a
//    curve point strictly inside) gets that point inserted (split in three, flips back to
//    Delaunay), and the triangles around it take the region at their centroid, unless that
//    gives one a region boundary edge with an end off the curves (onCurve); the new triangles
//    are probed in turn, up to the insertion budget; then the flips of 2 once more, since
//    the constrained edges changed. It brings back layers and islands the compression lost.
//    Before the probes, every triangle within its longest edge of a curve (curveDistance)
//    takes the region at its centroid under the same rule (the paper's barycentre
//    classification, on the compressed mesh). Everything below then starts from this mesh.
// 2b'. Curve fidelity (optional: RefinementParams::curveDeviation). A region boundary edge at
//    least minimumEdgeLength long that cuts off more than 0.05% of the smaller of its two
//    regions' (mesh) areas from the curve stretch it stands for is split at that stretch's
//    point farthest from it, without the transactions of 4 (the refinement mends the
//    triangles after); the halves are checked in turn (up to 8 rounds, within the insertion
//    budget). The threshold is relative to the region, so that only small regions (islands,
//    small countries, whose area a chord across a bend is a sizeable part of) get such
//    splits: a large region's boundary keeps the edges the refinement gives it. Whatever the
//    area, an edge whose stretch's farthest point lies more than kSnapChord of its length
//    from it, with the opposite vertex of its region triangle a free vertex within half
//    minimumEdgeLength of that point, has that vertex moved onto the point (when no triangle
//    around it turns) and the triangle retagged by its centroid (snapOpposite()): the
//    compression left the vertex beside a model corner, off the curve, so no split fits there
//    and 2b's retag refused the triangle (a lake's shore cut by a chord across its 88-degree
//    corner of land, and another across a bay's bend: 0.57 and 0.67 -> 0.47 and 0.49 local
//    edges). Whatever the area too, an edge whose stretch's farthest point lies more than
//    kChordLocal local edges from it (the mean edge of its triangles, or its length when
//    shorter) and more than minimumEdgeLength is split there: issue 5's boundary bound, which
//    a region-relative area never sees on a large region's shore (a lake's island whose bulge,
//    two finest edges deep, a chord cut off: 0.52 -> 0.49 local edges). An edge whose
//    stretch's farthest point is a model corner (RefinementParams::modelCorner: sharper than
//    FeatureAngle) with straight sides (their stretches within
//    kCornerStraight of their lengths: without that check the corners of wiggly shores were
//    split too, at coarse levels down to 28.5 degrees) is split there whatever the area when
//    the corner lies more than kSnapChord of its length from it; else, or when the split is refused
//    (an end too near the corner, a triangle that cannot take it), the edge's nearer end slides
//    onto the corner along its curve (slideOnto(): no triangle around it turns, its boundary
//    edges stay on the curves). The compression leaves such chords across the corners of a
//    section's box between two junctions: 30 of the 192 box corners of the 48 random faulted
//    sections had no vertex (the nearest 1e-4 to 7e-4 of the diagonal away), none now. The
//    collapses of 6 keep a model corner's vertex.
// 2c. Sharp corners (with the curve recovery). A recovered layer ends where it gets thinner
//    than the triangles, often in a spike: a triangle whose smallest angle lies between two
//    region boundary edges. A region triangle with such a corner below minimumAngle, no longer
//    than 16 minimumEdgeLength, takes the region of the triangle across one of its boundary
//    edges (not beyond the mesh's outer border; the exterior's triangles only when no
//    region's raises it) when that raises the smallest such corner angle of
//    it and its neighbours (new boundary edges must join vertices on curves; no region loses
//    its last triangle). The layer then ends where it is about as thick as its triangles,
//    cleanly. A speck (a triangle with no neighbour of its own region and an inradius below
//    minimumEdgeLength, or with one and an inradius below half of it: a sliver a retag left
//    between other regions, or hanging from its region into another) is treated so whatever
//    its length, and may also go beyond the mesh's outer border, when no region beside it
//    raises its angle (the border stays where it is). A longer triangle is treated
//    so when its area is at most 0.05% of its region's and it does not join two pieces of the
//    region it joins: where the mesh is coarse, a wedge's tip between two curves meeting at
//    a small angle is a triangle longer than that (Marmousi's 19-degree junctions, in
//    triangles 30 long, 17 times its finest edge; country borders meeting a coast at 10-20
//    degrees), and what the tip hides lies within its shortest edge of the mesh's boundary.
//    A longer triangle whose area is a larger share has its tip cut first: both edges of the
//    corner are split on their curves at the distance d from it at which the tip's third
//    edge is 1.5 minimumEdgeLength long (long enough for the refinement), when d is below
//    0.45 of both edges and the tip's area at most 0.05% of the region's; the tip is then a
//    small triangle given away as above (a fault block's layer pinching out at 15 degrees in
//    a triangle longer than 16 finest edges; Marmousi 26.6 -> 30.0 degrees). In the curve
//    recovery's last pass every such corner's tip is cut so, whatever the triangle's size,
//    with a third edge of one minimumEdgeLength: the region then ends where it is about one
//    finest edge wide rather than where a whole triangle ends (country borders meeting a
//    coast at a small angle, whose tips were cut where their triangles were two or three
//    finest edges across).
//    Neither is done to a spike of the mesh's own (with RefinementParams::sharpModelCorner):
//    a sharp corner between two triangles of one other region (or the outer border), with no
//    corner of its region in the model sharper than the bound (plus a margin) within 4 times
//    the triangle's longest edge. Its region is wider there in the model (a country's
//    peninsula whose tip, 38 degrees, the coarse mesh reaches with a chord from a vertex
//    short of it); giving the triangle away would cut the peninsula back by whole triangles,
//    so the refinement of 3 splits its sides on their curves instead.
//    Before the corners, a piece of a region (triangles joined across unconstrained edges)
//    thinner than half minimumEdgeLength everywhere (every inradius below a quarter of it),
//    whose area is at most 0.05% of its region's, goes whole to the neighbouring region it
//    shares the longest boundary with: a sliver of a layer a fault cut off where the layer is
//    thinner than the finest triangles, meshed as a strip of flat triangles that no insertion
//    can mend (a random faulted section's 1-degree pinch-out: 8.5 -> 25.0 degrees); the
//    collapses of 6 then take the vertices left inside its new region.
// 2d. Size (RefinementParams::maximumEdgeLength > 0). Every region edge longer than it is
//    split, longest first: an unconstrained one in its middle, a constrained one at the point
//    the BoundarySplitter gives (on its curve), with the flips of 3 around the new vertex;
//    rounds until none is left (or the splitter or a piece's orientation refuses, or the
//    budget ends). The runs of 3 then mend the angles; after the last pass it is done once
//    more for what the smoothing and the collapses lengthened. Insertions never lengthen an
//    edge, but Lawson's flips can.
// 3. Refinement. A queue holds the region triangles whose smallest angle is below
//    minimumAngle. For each (still bad) triangle with shortest edge pq:
//    - if its smallest angle lies between two constrained edges (a corner of the region), or
//      pq is shorter than the floor, it is left (counted at the end), unless that corner is
//      a spike of the mesh's own (2c): then the longer of its two sides is split at the
//      point the BoundarySplitter gives, and the triangle queued again. The floor is half
//      minimumEdgeLength, except within one minimumEdgeLength of a constrained edge shorter
//      than 0.4 of it in the pass's mesh before its runs, between two points where a vertex
//      stays (RefinementParams::stopPoint, when given: two junctions close together, an edge
//      no split may shorten, so the triangles beside it are only good when they are about
//      as small): there it is half that edge, and at least a twentieth of minimumEdgeLength
//      (random faulted sections' junction pairs 0.2 finest edges apart: 27.1 and 28.3 ->
//      30.0 degrees; the gulf at MaxLevel 6, 25.6 -> 29.9). Beside any short edge, a curve
//      point beside a junction too, it let the bold runs' cascades cut the gulf's layers at
//      coarse levels (2026-12-04: at MaxLevel 6 a layer lost over a stretch);
//    - the point to insert is its circumcentre, or, when that lies farther from pq, the
//      off-centre: the point on pq's bisector whose triangle with pq has an apex angle
//      slightly above minimumAngle (fewer, better graded vertices than circumcentres);
//    - the point is located by a walk from the triangle; if the walk meets a constrained edge,
//      the point lies beyond it and that edge is split; otherwise the triangles whose
//      circumcircle contains the point (grown from the one holding it, across unconstrained
//      edges) are its Bowyer-Watson cavity, and if a constrained edge of the cavity has the
//      point inside its diametral circle (the point encroaches it), that edge is split
//      instead;
//    - otherwise the point is inserted (its triangle split in three, or its edge in four when
//      it lies on one) and the edges opposite it are flipped back to Delaunay (Lawson).
//    A constrained edge ab is split at the point the BoundarySplitter gives (the curve point
//    nearest its middle: new boundary vertices lie on the model's curves), unless it is
//    shorter than twice the floor at its middle, the splitter refuses, or a piece would not be
//    counter-clockwise; the bad triangle is queued again. Every triangle a change creates is
//    queued when bad. The number of insertions is capped by insertionBudget.
// 4. Transactions. Each insertion (with its flips) is recorded and undone when the triangles
//    it made have a smaller smallest angle than min(floor, the smallest angle of the triangles
//    it replaced). Ruppert's refinement needs such temporary losses away from the boundary,
//    but where the mesh's boundary edges meet at small angles (a layer thinner than its
//    triangles, a boundary cut short near a junction) it cascades into slivers. Hence several
//    runs from the same mesh, the one with the largest smallest angle kept:
//    - a cautious run, floor = minimumAngle: no insertion ever lowers a local smallest angle,
//      so its result is never worse than the compressed mesh;
//    - up to three bold runs, floor = minimumAngle / 4, which reach the bound where the
//      boundary allows it; each run after the first is cautious inside disks (radius twice
//      the longest edge) around the triangles where the runs before ended below the best
//      smallest angle so far. The runs stop once one reaches minimumAngle.
//    The run kept is the one with the largest smallest angle, and of equal ones the one with
//    the fewest triangles below minimumAngle (the smallest angle is often one corner no run
//    can mend, while the bold runs mend hundreds of triangles elsewhere).
// 5. Smoothing. The vertices of the triangles still below minimumAngle move where that raises
//    the smallest angle of their star (never inverting a triangle): a free vertex (one region
//    around it, no boundary edge) toward the centroid of its neighbours (full, half or quarter
//    way); a vertex with exactly two boundary edges and two regions around it slides along
//    its curve (RefinementParams::curveSlide) toward the middle of its two boundary
//    neighbours or toward that centroid, unless the middle of one of its boundary edges would
//    get farther from the curves than 5% of the edge's length (or than it was); no move makes
//    an angle above max(120 degrees, the largest before). Junctions and feature points stay.
//    Up to 4 rounds, each followed by the flips of 2; then the corners of 2c once more, and
//    after the last pass 6 and a cautious run of 3 (a wedge's tip given to its neighbour
//    leaves the tip's sharp corner between edges that are no longer constrained, which
//    insertions can now widen; the smoothing's moves are mended too). When that run leaves
//    triangles below minimumAngle, a bold run follows on a copy, bold only inside the disks
//    of 4 around them and cautious elsewhere, kept when its smallest angle is larger (a
//    sliver at a lake's shore whose boundary split the cautious run refused: 27.3 -> 30.0
//    degrees; the bold floor anywhere else would let its cascades spread).
// 6. Short edge collapses (after the last pass, with the smoothing's callbacks and onCurve).
//    Where a tip was cut, the cut is often an edge shorter than the floor of 3, across the
//    wedge between its two curves (Marmousi: 0.80 long against a floor of 0.875, its apex at
//    16 degrees), and no insertion may mend the triangles on it. The shortest edge uv of such
//    a bad triangle is collapsed: v is merged into u (either way, the better one) when v is a free
//    vertex, or one that may slide on its curve (curveSlide: no junction, no feature point) and u
//    lies on the curves; when both are free, a third way, the best of the three when it is better,
//    merges them at the edge's middle (two free vertices closer than the floor inside a country,
//    their triangles at 27.3 degrees, which neither merge into an end raised: countries159 of
//    random_lakes_countries.py 154 166, 30.0 degrees now). The link condition holds (no fold); no
//    triangle of the new star is inverted, its smallest angle is above the old stars' and its
//    largest below max(120 degrees, the largest before); u gets no more boundary edges or regions
//    than u or v had, and each new boundary edge joins vertices on curves with its middle within
//    max(5% of its length, a quarter of minimumEdgeLength) of them (the tip is cut where the wedge
//    is a little wider); no region loses its last triangle. Up to 4 sweeps; the vertex
//    left is no longer referenced.
// 7. Kept corners (RefinementParams::keptCorners, with the curve recovery's callbacks; in the
//    last pass, after 2d and before the runs of 3). A region corner of the model sharper than
//    minimumAngle (a pinch-out's apex, a sharp junction) ends, after 2c, where its layer is
//    about as thick as the triangles. For each corner asked for, its region's wedge from the
//    apex to the region's nearest vertices on its two sides (the sides: the region's ring
//    from the apex both ways) is rebuilt as rungs:
//    - a vertex is put on the apex (there already for junctions and feature points), and on
//      both sides at the same distances from it, minimumEdgeLength apart, or the wedge's
//      width apart where that is more, plus the sides' own points, but not within half that
//      of a vertex already on the side (each inserted with the flips of 2, or splitting the
//      edge it lies on);
//    - each side between consecutive vertices is made a mesh edge: the edges crossing it are
//      flipped (Sloan's edge recovery), a vertex on it splits it, and what no flip clears is
//      split where the side crosses it;
//    - the triangles inside the outline (apex, first side, second side back) take the
//      corner's region, and those around whose region the sides cut take the region at their
//      centroid (the retag of 2b); then the flips of 2.
//    The corner is kept when every new region boundary edge joins vertices on the curves, the
//    wedge joins the region's triangles beyond it and reaches the apex, no triangle around is
//    nearly flat, and the wedge's triangles have no angle below a quarter of the corner's nor
//    above kKeptLargest (rungs across a thin wedge: about the corner's angle and 90 degrees);
//    otherwise everything is undone and the corner stays as 2c left it. The kept wedges'
//    triangles are then exempt: not refined (bad() is false), not counted by the
//    transactions of 4, left by 2c and 6 (no collapse within their reach), and no point is
//    inserted in them (3, 2d); a side of a wedge is split (3) only when the wedge's triangles
//    keep those shapes. The smoothing (5) may slide their sides' vertices along the curves. What
//    the runs cannot mend beside a wedge is counted by the mesher, with the wedge's triangles, as
//    what keeping the corner costs.
// 7'. Inlets and lost tips (RefinementParams::wedgeCorners; in the last pass, before 7).
//    - A wedge of the exterior sharper than minimumAngle (a coast's narrow bay) ends, in the
//      compressed mesh, where it is two or three finest edges wide: the probes of 2b need a
//      margin on both sides of a curve. Where its exterior triangles end farther from the
//      apex than the distance d0 at which the wedge is kWedgeCut minimumEdgeLength wide, it is
//      rebuilt as in 7 from there (not from the apex): vertices on one side at d0, on the
//      other (where the wedge's triangles end nearer the apex) kWedgeSlant times that width
//      nearer the apex (at most d0 / 2), and outward from those at the same spacing; the sides
//      and the cut between the two made mesh edges; the triangles inside made exterior (but
//      islands; the tip beyond the cut keeps the region around it), with the same checks but
//      for the wedge's shapes (its triangles are dropped). (Lake Superior's 10-degree bay:
//      deviation 1.16 -> 0.52 local edges.) The cut is slanted: its middle lies half the
//      wedge's width from the sides, as a cut straight across would, but it is longer, and so
//      are the triangles beside it, while the tip it leaves out is narrower than a finest edge
//      (straight cuts, beside triangles shorter than them, were up to 0.59 local edges from
//      the curves: Marmousi's lens of region 4; the 48 random faulted sections 38 -> 47 within
//      half the local edge, the largest 0.56 -> 0.52). So
//      is a spit of a region into the exterior sharper than minimumAngle (the exterior on
//      both its sides): its region is extended so, the tip beyond the cut left to the
//      exterior, its triangles refined after; the triangles on its sides take the region at
//      their centroid whatever their reach, so that no region triangle is left beyond a side
//      (lake_superior_full's 9-degree spit: deviation 0.80 -> 0.63 local edges). So is a
//      lens's tip in another region, or a layer's pinch-out at a junction (other regions on
//      both its sides), the tip left to the triangles it had (Marmousi's lenses: deviation
//      2.02 -> 0.59 local edges; the gulf's 1-degree pinch-outs: 0.63 -> 0.50). Where the
//      tip is left to a region, vertices of its old mesh may sit a fraction of a
//      minimumEdgeLength from the new vertices on the sides, in triangles no insertion mends:
//      after the runs, the short edges of bad triangles within one minimumEdgeLength of a
//      side's vertex are collapsed as in 6, before the smoothing moves them apart (Marmousi:
//      25.9 -> 30.0 degrees; the gulf's first mesh 28.0 -> 30.0).
//      Where the region's triangles end is read on its body, the pieces of it that reach the
//      end of the wedge's sides (or, if none does, the one reaching farthest): a piece left
//      inside the wedge, cut off from the body by its neighbour's triangles, is no end of it
//      and is rebuilt over (Marmousi's 19-degree lens tip: the compression gave its neighbour
//      the lens's seven finest edges before the cut but for two such pieces; the mesh's
//      largest boundary deviation 0.62 -> 0.50 local edges, 0.40 with the thin layers refined
//      there).
//      When a triangle below minimumAngle is left within twice the reach of wedges among
//      regions (SharpCorner::amongRegions), the last pass is made again without those wedges,
//      and kept when its smallest angle is larger (Marmousi at MaxLevel 7: a 20-degree
//      pinch-out's tip, left to a neighbour, was a 19.7-degree triangle; its other wedges stay
//      extended).
//    - A region corner of minimumAngle to 100 degrees (as the mesher lists them: right angles
//      and a little wider) whose tip the mesh lost (its region's triangles have no vertex on
//      the apex and end, on both sides, farther from it than where the wedge is one
//      minimumEdgeLength wide, plus kRestoredMargin of that: a margin of a half left the
//      52-degree tip of a spit in lake006 of the random lakes lost 1.4 finest edges from its
//      apex, 0.53 local edges from the mesh; with none, Marmousi's 38-degree lens end, lost
//      within its last finest edge, came back with a 29.2-degree triangle) is rebuilt as in 7
//      to its apex, with rungs two minimumEdgeLength apart at least (nearer ones leave edges
//      too short for the refinement beside the apex) and all of 7's checks, but not kept: its
//      triangles are refined as any others (a country's 45-degree cape the compressed mesh
//      cut 2.3 finest edges short, where its triangles are 2.4 finest edges long).
//    The runs of 3 then mend the triangles beside them. Each wedge looks only at the
//    triangles with a vertex within twice its sides' reach (found for all wedges in one
//    sweep), and its flips of 2 start from those.
// With the curve recovery, 2b to 5 run twice: the second recovery probes the refined
// triangles, which are smaller than the compressed ones, so layers that ran through the edges
// of big triangles are found. Most triangles are left as they were by the first pass, and 2b's
// queries depend on a triangle's corners only: the second recovery takes the first's answers
// for those (RecoveryMemo), and asks about the others; the first takes the caller's answers
// about the centroids (KnownCentroidRegions) the same way.
// Outside the smoothing and 6 no step moves or removes an existing vertex, and no step inverts
// a triangle; outside the curve recovery, 2c and 7 no triangle changes region, and the
// regions' areas change only where a boundary edge is split onto its curve (3, 2b', 7) or a
// boundary vertex slides or is collapsed (6).
// Two threads: the sweeps over the whole mesh (the neighbours, the frozen triangles, those
// without positive area, the first test of 2's flips, which then stack only the edges that
// need one, the bad triangles of 3, the smallest angle, the short boundary edges of 3's floor
// and the bad triangles with a short edge of 6, which are then taken in order) run in blocks,
// each block's halves at once, and the probes of 2b may be asked in blocks
// (RefinementParams::curvePoints); every result is the serial one.
// The refiners of one pass hand their mesh on (Handover): the next takes its neighbours, and
// looks for 2's flips only at the edges the one before left needing one (a flip refused, an
// edge from a vertex it inserted off an edge or moved, a retagged triangle's) and at the
// triangles whose frozen flag changed: the flips a sweep of every edge would find, in its
// order. The curve recovery's and the corners' flips after their retags look there too. Only
// the first preparation tests every edge (checked on the 548 bundled and unseen models; at 1 M
// seven of eight such tests spared).
#include "DelaunayRefinement.h"

#include "ArcIndex.h"
#include "CallTables.h"

#include "Errors.h"
#include "Parallel.h"
#include "Quality.h"
#include "Rows.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <queue>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>

namespace strata
{

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr const char* kRefiningStage = "refining toward the minimum angle"; // (progress)
constexpr int kMaxWalk = 1 << 16;        // steps of a point location walk
constexpr std::size_t kNearSearch = 256; // triangles holding() looks at before the whole mesh
constexpr std::size_t kMaxCavity = 256;  // triangles of a cavity looked at for encroachment
constexpr double kBoldFloor = 0.25;      // the bold runs' floor, relative to minimumAngle
constexpr int kBoldRuns = 3;             // bold runs at most
constexpr int kFinisherTries = 3;        // the finisher's runs at most (5, after the last pass)
constexpr double kDissolveLength = 16.0; // corners dissolved in triangles up to this long
                                         // (relative to minimumEdgeLength)
constexpr int kDissolveSweeps = 16;      // sweeps of the corner dissolving at most
constexpr double kSpikeReach = 4.0;      // 2c: a model corner this many longest edges away
                                         // from a spike makes it the model's
constexpr double kTipCut = 1.5;          // 2c: a cut tip's far edge, in minimumEdgeLength
constexpr double kEveryTipCut = 1.0;     // 2c, the recovery's last pass: every tip's far edge
constexpr double kFlat = 1e-4;           // 7: no flip makes a triangle with a smaller sine
constexpr double kSnap = 1e-3;           // 7: a side crossing an edge this close (relative) to an
                                         // end on the curves passes through that end
constexpr int kRecoveryFlips = 256;      // 7: flips tried per side edge before conforming
constexpr double kWedgeCut = 1.0;        // 7': an extended wedge ends this many finest edges wide
constexpr double kWedgeSlant = 1.0;      // 7': ... on one side, on the other this many nearer
constexpr double kRestoredSpacing = 2.0; // 7': a lost tip's rungs, in minimumEdgeLength at least
constexpr double kRestoredMargin = 0.25; // 7': a lost tip is rebuilt where its region ends this
                                         // many of its width farther than where it is that wide
constexpr double kKeptSpacing = 1.0;     // 7: a kept wedge's vertices along its sides, in
                                         // minimumEdgeLength
constexpr double kKeptLargest = 150.0;   // 7: a kept wedge's triangles have no angle above this
constexpr int kSmoothingRounds = 4;      // rounds of the smoothing at most
// A smoothing move makes no angle above max(120 degrees, the largest before).
const double kSmoothingLargestCosine = std::cos(120.0 * kPi / 180.0);
constexpr double kSlideDeviation = 0.05;    // a slid boundary edge's middle stays this close to
                                            // the curves (relative to its length)
constexpr double kDeviationFraction = 5e-4; // 2b': area a boundary edge may cut off
constexpr int kFollowRounds = 8;            // rounds of 2b' at most
constexpr int kSizeRounds = 32;             // rounds of 2d at most
constexpr int kCollapseSweeps = 4;          // sweeps of the short edge collapses (6) at most
constexpr int kRecoveryPasses = 2;          // passes of 2b-5 with the curve recovery
// The refinement of 3 goes down to this much of minimumEdgeLength: a junction pair, a curve
// vertex or a recovered layer often leaves a boundary edge a little shorter than the finest
// triangles, and the triangles beside it are only mended below it (Gulf: a 22.7-degree triangle
// on a 0.70 long edge between two junctions, the finest legs 0.95 long). The probes of 2b and the
// corners of 2c keep minimumEdgeLength: recovering thinner layers costs angles where they end.
constexpr double kFloor = 0.5;
// ... except within one minimumEdgeLength of a region boundary edge shorter than kShortFeature
// of it between two stop points (RefinementParams::stopPoint: two junctions close together):
// there it goes down to half that edge, and at least to kLowestFloor of minimumEdgeLength.
// (Elsewhere the refinement's own splits make no such edge: their pieces are about half
// minimumEdgeLength long at least.)
constexpr double kShortFeature = 0.4;
constexpr double kLowestFloor = 0.05;
constexpr double kCornerOff = 1e-6; // 2b': a model corner this many of a chord's lengths off it
                                    // is not on it
constexpr double kCornerStraight = 0.05; // 2b': ... and its sides' stretches this close to
                                         // straight (relative to their lengths)
constexpr double kSnapChord = 0.25; // 2b': a chord whose curve point lies this many of its
                                    // lengths from it, with a free vertex beside that point
constexpr double kChordLocal = 0.4; // 2b': a chord whose curve point lies this many local
                                    // edges from it (and a finest edge) is split there
constexpr std::size_t kManyChanged = 8; // flipToDelaunayNear(): more changed triangles than
                                        // the mesh's over this are flagged, not sorted

// > 0 when d lies strictly inside the circumcircle of the counter-clockwise triangle abc,
// beyond a relative rounding margin.
bool inCircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d)
{
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
  const double ab = adx * bdy - bdx * ady, bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy;
  const double det = al * bc + bl * ca + cl * ab;
  const double mag = al * std::fabs(bc) + bl * std::fabs(ca) + cl * std::fabs(ab);
  return det > 1e-10 * mag;
}

Vec2 circumcenter(Vec2 a, Vec2 b, Vec2 c)
{
  const Vec2 ba = b - a, ca = c - a;
  const double d = 2.0 * cross(ba, ca);
  const double lb = norm2(ba), lc = norm2(ca);
  return a + Vec2{ (ca.y * lb - ba.y * lc) / d, (ba.x * lc - ca.x * lb) / d };
}

// Whether p lies inside the polygon (even-odd crossings).
bool insidePolygon(const std::vector<Vec2>& polygon, Vec2 p)
{
  bool in = false;
  for (std::size_t j = 0, n = polygon.size(); j < n; ++j)
  {
    const Vec2 a = polygon[j], b = polygon[(j + 1) % n];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x))
    {
      in = !in;
    }
  }
  return in;
}

// The point of a polyline at arc length d from its start (its end beyond).
Vec2 pointAlong(const std::vector<Vec2>& line, double d)
{
  for (std::size_t j = 1; j < line.size(); ++j)
  {
    const double l = norm(line[j] - line[j - 1]);
    if (d <= l && l > 0.0)
    {
      return line[j - 1] + (d / l) * (line[j] - line[j - 1]);
    }
    d -= l;
  }
  return line.back();
}

// The polyline's length.
double polylineLength(const std::vector<Vec2>& line)
{
  double sum = 0.0;
  for (std::size_t j = 1; j < line.size(); ++j)
  {
    sum += norm(line[j] - line[j - 1]);
  }
  return sum;
}

// Disks (centre, radius) in a uniform grid, to find those a box may meet: each disk is listed
// in the cells its bounding box meets, or, when that is more than kMostDiskCells cells, apart
// (asked about by every box). The cells are about as wide as the median disk, at most
// kCellsPerDisk per disk and kMostGridCells in all.
class DiskGrid
{
public:
  DiskGrid(const std::vector<Vec2>& centre, const std::vector<double>& radius)
    : Seen(centre.size(), 0)
  {
    const std::size_t n = centre.size();
    if (n == 0)
    {
      return;
    }
    Vec2 lo{ HUGE_VAL, HUGE_VAL }, hi{ -HUGE_VAL, -HUGE_VAL };
    for (std::size_t i = 0; i < n; ++i)
    {
      lo = { std::min(lo.x, centre[i].x - radius[i]), std::min(lo.y, centre[i].y - radius[i]) };
      hi = { std::max(hi.x, centre[i].x + radius[i]), std::max(hi.y, centre[i].y + radius[i]) };
    }
    std::vector<double> sizes(radius);
    std::nth_element(sizes.begin(), sizes.begin() + n / 2, sizes.end());
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    this->Cell = std::max({ 2.0 * sizes[n / 2], extent / 1024.0, 1e-300 });
    // (At most kCellsPerDisk cells a disk: a larger grid's offsets leave the cache, and each
    // box's look at them costs more than the disks it spares.)
    const double most =
      static_cast<double>(std::min(kMostGridCells, kCellsPerDisk * n + kCellsPerDisk));
    while ((std::floor((hi.x - lo.x) / this->Cell) + 1.0) *
        (std::floor((hi.y - lo.y) / this->Cell) + 1.0) >
      most)
    {
      this->Cell *= 2.0;
    }
    this->Origin = lo;
    this->Nx = static_cast<int>(std::floor((hi.x - lo.x) / this->Cell)) + 1;
    this->Ny = static_cast<int>(std::floor((hi.y - lo.y) / this->Cell)) + 1;
    // Each disk's cells (x0, x1, y0, y1).
    std::vector<std::array<int, 4>> cells(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      std::array<int, 4>& b = cells[i];
      const Vec2 r{ radius[i], radius[i] };
      this->range(centre[i] - r, centre[i] + r, b[0], b[1], b[2], b[3]);
      if ((static_cast<std::size_t>(b[1] - b[0]) + 1) *
          (static_cast<std::size_t>(b[3] - b[2]) + 1) >
        kMostDiskCells)
      {
        this->Apart.push_back(static_cast<int>(i));
        b = { 0, -1, 0, -1 }; // (in no cell)
      }
    }
    groupIntoRows(static_cast<std::size_t>(this->Nx) * this->Ny,
      this->Start,
      this->Items,
      [&](auto&& emit)
      {
        for (std::size_t i = 0; i < n; ++i)
        {
          for (int y = cells[i][2]; y <= cells[i][3]; ++y)
          {
            for (int x = cells[i][0]; x <= cells[i][1]; ++x)
            {
              emit(static_cast<std::size_t>(y) * this->Nx + x, static_cast<int>(i));
            }
          }
        }
      });
  }

  // Whether a disk's bounding box may hold p (false: none does): p's cell lists a disk, or a
  // disk is listed apart.
  bool mayHold(Vec2 p) const
  {
    if (!this->Apart.empty())
    {
      return true;
    }
    if (this->Start.empty())
    {
      return false;
    }
    const std::size_t c =
      static_cast<std::size_t>(this->cellOf(p.y, this->Origin.y, this->Ny)) * this->Nx +
      this->cellOf(p.x, this->Origin.x, this->Nx);
    return this->Start[c + 1] > this->Start[c];
  }

  // Calls f(i) once for each disk whose bounding box may meet the box [lo, hi] (every disk
  // that does, and perhaps others).
  template<typename F>
  void forEachNear(Vec2 lo, Vec2 hi, F&& f)
  {
    ++this->Stamp;
    if (!this->Start.empty())
    {
      int x0, x1, y0, y1;
      this->range(lo, hi, x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
      {
        for (int x = x0; x <= x1; ++x)
        {
          const std::size_t c = static_cast<std::size_t>(y) * this->Nx + x;
          for (std::size_t k = this->Start[c]; k < this->Start[c + 1]; ++k)
          {
            const int i = this->Items[k];
            if (this->Seen[i] != this->Stamp)
            {
              this->Seen[i] = this->Stamp;
              f(i);
            }
          }
        }
      }
    }
    for (const int i : this->Apart)
    {
      f(i);
    }
  }

private:
  static constexpr std::size_t kMostGridCells = std::size_t(1) << 20;
  static constexpr std::size_t kCellsPerDisk = 4;
  static constexpr std::size_t kMostDiskCells = 64;

  int cellOf(double v, double origin, int count) const
  {
    return clampedCell((v - origin) / this->Cell, count);
  }
  // The cells of the box, clamped to the grid (a box beside the grid meets its border cells:
  // more candidates, never fewer).
  void range(Vec2 lo, Vec2 hi, int& x0, int& x1, int& y0, int& y1) const
  {
    x0 = this->cellOf(lo.x, this->Origin.x, this->Nx);
    x1 = this->cellOf(hi.x, this->Origin.x, this->Nx);
    y0 = this->cellOf(lo.y, this->Origin.y, this->Ny);
    y1 = this->cellOf(hi.y, this->Origin.y, this->Ny);
  }

  double Cell = 1.0;
  Vec2 Origin{ 0.0, 0.0 };
  int Nx = 0, Ny = 0;
  std::vector<std::size_t> Start;
  std::vector<int> Items, Apart;
  std::vector<std::size_t> Seen;
  std::size_t Stamp = 0;
};

// A disk where insertions must not lower the local smallest angle (see refineDelaunay()).
struct Zone
{
  Vec2 center;
  double radius2;
};

// The answers of 2b's queries that depend on a triangle's corners only (its centroid's region
// near a curve, centroidRegionsNear(); its probe, curvePoint), as one recovery asked them, for
// the next (the second pass's mesh is mostly the first's): a triangle whose corners lie where
// those of the triangle of the same index lay then, in the same order, has the same answers.
struct RecoveryMemo
{
  LargeVector<std::array<int, 3>> triangles; // as they were when asked
  LargeVector<Vec2> points;                  // as they were when asked
  LargeVector<int> near;                     // centroidRegionsNear() (empty: not asked)
  LargeVector<std::uint8_t> probe;           // kNotProbed, kNoPoint or kPoint (at)
  std::unordered_map<int, Vec2> at;          // the point a probe found inside
  static constexpr std::uint8_t kNotProbed = 0, kNoPoint = 1, kPoint = 2;

  // Whether t of `mesh` has the corners of the triangle t asked about.
  bool same(std::size_t t, const RegionMesh& mesh) const
  {
    if (t >= this->triangles.size())
    {
      return false;
    }
    const auto& now = mesh.triangles[t];
    const auto& then = this->triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      if (!(mesh.points[now[k]] == this->points[then[k]]))
      {
        return false;
      }
    }
    return true;
  }
};

std::size_t collapseShortEdgesAvoiding(RegionMesh& m,
  const RefinementParams& P,
  const std::vector<Zone>& avoid,
  const std::vector<Zone>& within = {});
bool turnsLeft(Vec2 a, Vec2 b, Vec2 c);
double smallestCosine(Vec2 a, Vec2 b, Vec2 c);
double shapeCosine(Vec2 a, Vec2 b, Vec2 c);
double shapeCosine(Vec2 a, Vec2 b, Vec2 c, double& largest);

// What a refiner that is done hands the next refiner of its mesh (Refiner::takeHandover(),
// prepare()): its neighbours, the triangles with an edge its flips left needing one or whose
// edges a change no flip followed may have left so (Unsettled), and its frozen flags.
struct Handover
{
  LargeVector<std::array<int, 3>> neighbours;
  std::vector<int> unsettled;
  LargeVector<std::uint8_t> live;
};

class Refiner
{
public:
  Refiner(RegionMesh& mesh,
    const BoundarySplitter& splitter,
    const RefinementParams& params,
    double floorFraction,
    const std::vector<Zone>& cautious,
    const ProgressReporter& progress)
    : M(mesh)
    , Split(splitter)
    , P(params)
    , Progress(progress)
    , Cautious(cautious)
  {
    const double theta = params.minimumAngle * kPi / 180.0;
    this->CosBad = std::cos(theta);
    this->CosFloor = std::cos(floorFraction * theta);
    // Off-centre apex angle: 10% above the bound, so the new triangle is not bad itself.
    this->OffDistance = 0.5 / std::tan(0.5 * std::min(1.1 * theta, kPi / 3.0));
    this->Budget = static_cast<std::size_t>(
                     params.insertionBudget * static_cast<double>(mesh.triangles.size())) +
      1000;
  }

  /// Neighbours, frozen triangles, then Lawson's flips to constrained Delaunay (counted in
  /// the result's delaunayFlips). With `handed`, what the refiner that changed this mesh last
  /// handed over (takeHandover()): its neighbours are taken instead of found again (the same
  /// ones), and since its mesh is constrained Delaunay but for the edges of its unsettled
  /// triangles and of those whose frozen flag the sweep here changes, the flips look there
  /// only (flipToDelaunayNear(): the same flips, in the same order, without a sweep of every
  /// edge).
  void prepare(Handover* handed = nullptr);
  /// For prepare() of the next refiner of this mesh (this one is done).
  Handover takeHandover()
  {
    return { std::move(this->Nbr), std::move(this->Unsettled), std::move(this->Live) };
  }
  /// From here on the zones given at construction are the only places where insertions may
  /// go down to the floor; elsewhere they are cautious (never below the bound, or the old
  /// smallest angle there).
  void boldInside() { this->BoldInside = true; }
  void flipToDelaunay(const std::vector<int>* seeds = nullptr);
  /// flipToDelaunay() when only the edges of `changed` (the triangles whose corners moved or
  /// that changed otherwise since the last call) and those recorded since (Unsettled) may
  /// need a flip: the same flips, in the same order, without the sweep.
  void flipToDelaunayNear(std::vector<int> changed);
  /// Curve recovery (RefinementParams::curvePoint): returns the vertices inserted. With a
  /// memo, the answers kept there by the recovery before are taken for the triangles it asked
  /// about that are unchanged, and this recovery's answers are kept in `after` (when given).
  std::size_t recoverCurves(const RecoveryMemo* before = nullptr, RecoveryMemo* after = nullptr);
  /// Curve fidelity (RefinementParams::curveDeviation): returns the boundary edges split.
  std::size_t followCurves();
  /// Region corners sharper than the bound in small triangles given a neighbour's region
  /// (with the curve recovery's callbacks): returns the triangles retagged.
  std::size_t dissolveCorners();
  /// The tips of the region corners sharper than the bound in triangles too long and too
  /// large to be given away whole (or in every triangle, after cutEveryTip()), split off on
  /// their curves (2c): returns the splits. `sharp`: the triangles with a sharp region corner
  /// now, increasing (until a cut changes the mesh, the only ones looked at);
  /// `regionTwice(region)`: twice the region's (mesh) area, asked for before any cut.
  std::size_t cutTips(const std::function<double(int)>& regionTwice, const std::vector<int>& sharp);
  /// From here on, dissolveCorners() cuts the tip of every sharp region corner (2c: the
  /// curve recovery's last pass).
  void cutEveryTip() { this->EveryTip = true; }
  std::size_t dissolveThinPieces(LargeVector<int>& piece,
    std::map<int, double>& regionTwice,
    std::map<int, std::size_t>& count);
  /// The vertices cutTips inserted (on boundary edges) since construction.
  std::size_t tipVertices() const { return this->TipVertices; }
  /// Region edges longer than maximumEdgeLength split (2d): returns the vertices inserted.
  std::size_t splitLongEdges();
  LargeVector<int> pieces() const;
  bool hasThinPiece() const;
  /// Smoothing of the vertices of the triangles below the bound: returns the moves.
  std::size_t smoothBad();
  /// Takes the neighbours of a prepared refiner of the same mesh (instead of prepare()).
  void adopt(const Refiner& prepared);
  /// The refinement of a prepared mesh; `bad`, when given, lists its bad triangles
  /// (badTriangles() of a refiner of the same mesh, before any change).
  RefinementResult run(const std::vector<int>* bad = nullptr);
  /// The bad triangles, increasing.
  std::vector<int> badTriangles() const
  {
    return this->selectTriangles([this](int t) { return this->bad(t); });
  }
  /// The bad triangles whose smallest angle is not a corner of the region (between two
  /// constrained edges) unless a spike of the mesh's own: those an insertion may mend.
  std::vector<int> mendableBad() const
  {
    std::vector<int> list = this->badTriangles();
    list.erase(std::remove_if(list.begin(),
                 list.end(),
                 [this](int t)
                 {
                   const int c = this->smallestCorner(t);
                   return this->constrained(t, c) && this->constrained(t, (c + 2) % 3) &&
                     !this->meshSpike(t);
                 }),
      list.end());
    return list;
  }
  /// Sets the result's counts of bad triangles (and of those at region corners); returns the
  /// smallest angle (degrees) of the region triangles outside the kept wedges. The bad
  /// triangles, increasing, are left in `bad` when given.
  double countBad(RefinementResult& result, std::vector<int>* bad = nullptr) const;
  /// The smallest angle (degrees) of the region triangles outside the kept wedges at the end
  /// of run() (countBad()).
  double angleAfterRun() const { return this->AngleAfterRun; }
  std::size_t flips() const { return this->R.delaunayFlips; }
  /// Insertions allowed (insertionBudget x the triangles at construction + 1000), and a
  /// smaller allowance for a run that continues another's.
  std::size_t budget() const { return this->Budget; }
  void limitBudget(std::size_t budget) { this->Budget = std::min(this->Budget, budget); }
  /// Disks around the region triangles whose smallest angle is below `angle` degrees (radius:
  /// twice the longest edge), appended to `zones`.
  void zonesBelow(double angle, std::vector<Zone>& zones) const;
  /// The disk around triangle t's centroid of radius twice its longest edge.
  Zone zoneAround(int t) const
  {
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    return { (1.0 / 3.0) * (a + b + c),
      4.0 * std::max({ norm2(b - a), norm2(c - b), norm2(a - c) }) };
  }
  /// Step 7: the kept corners (RefinementParams::keptCorners) meshed to their apex, each
  /// with the flips of 2. Sets `radii` and `outlines` (one per corner; 0 and empty when not
  /// kept) and returns the corners kept. Their wedges' triangles are no longer bad for this
  /// refiner.
  std::size_t keepCorners(std::vector<double>& radii, std::vector<std::vector<Vec2>>& outlines);
  /// Step 7': the wedges of RefinementParams::wedgeCorners extended to where they are
  /// kWedgeCut minimumEdgeLength wide (the exterior's) or rebuilt to their apex (a region's
  /// lost tip). Returns the wedges changed.
  std::size_t extendWedges();
  /// Of the (sorted) triangles `list`, those of `region` in pieces (joined across edges within
  /// the list) with a vertex at least `reach` from `apex`, or, when no piece reaches so far,
  /// in the piece reaching farthest; sorted.
  std::vector<int> regionBody(const std::vector<int>& list,
    int region,
    Vec2 apex,
    double reach) const;
  /// The vertices keepCorners inserted (on the kept corners' sides) since construction.
  std::size_t keptVertices() const { return this->KeptVertices; }
  /// The region triangles within kept corners' wedges below minimumAngle.
  std::size_t keptBad() const;
  /// Takes the kept corners' wedges of another refiner of the same mesh.
  void keepWedges(const Refiner& other)
  {
    this->Kept = other.Kept;
    this->KeepRan = other.KeepRan;
  }
  /// Step 3's local floors: the region boundary edges of this mesh shorter than
  /// kShortFeature minimumEdgeLength, between two stop points when RefinementParams::stopPoint
  /// is given (see the top of this file). Called on a pass's mesh before its runs, which take
  /// them (adopt(), takeShortEdges()).
  void findShortEdges();
  void takeShortEdges(const Refiner& other)
  {
    this->Shorts = other.Shorts;
    this->ShortCells = other.ShortCells;
  }
  /// Disks around the kept corners (their wedges' reach).
  std::vector<Zone> keptDisks() const
  {
    std::vector<Zone> disks;
    for (const Wedge& w : this->Kept)
    {
      disks.push_back({ w.apex, w.radius2 });
    }
    return disks;
  }
  /// The vertices on the sides of 7''s extended wedges (from the cut out), each with a disk
  /// of one minimumEdgeLength around it.
  const std::vector<Zone>& extendedSides() const { return this->ExtendedSides; }

private:
  Vec2 X(int v) const { return this->M.points[v]; }
  bool positive(int t) const
  {
    const auto& tri = this->M.triangles[t];
    return orient2d(this->X(tri[0]), this->X(tri[1]), this->X(tri[2])) > 0.0;
  }
  // Positive beyond a margin of 1e-9 of its longest side squared (a vertex moved onto a
  // curve point turns no triangle around it: snapOpposite(), slideOnto()).
  bool clearlyPositive(int t) const
  {
    const auto& tri = this->M.triangles[t];
    const Vec2 p = this->X(tri[0]), q = this->X(tri[1]), r = this->X(tri[2]);
    return orient2d(p, q, r) > 1e-9 * std::max({ norm2(q - p), norm2(r - q), norm2(p - r) });
  }
  bool constrained(int t, int k) const
  {
    const int u = this->Nbr[t][k];
    return u < 0 || this->M.region[u] != this->M.region[t] || !this->Live[t] || !this->Live[u];
  }
  void buildNeighbours();
  // Transactions: every slot an insertion changes is saved first, so that an insertion that
  // would lower the local smallest angle can be undone.
  void begin()
  {
    this->Journal.clear();
    ++this->Tx;
    this->Recording = true;
    this->Tri0 = this->M.triangles.size();
    this->Points0 = this->M.points.size();
    this->Flips0 = this->R.delaunayFlips;
  }
  void save(int t)
  {
    if (this->Recording && static_cast<std::size_t>(t) < this->Tri0 && this->Saved[t] != this->Tx)
    {
      this->Saved[t] = this->Tx;
      this->Journal.push_back({ t, this->M.triangles[t], this->Nbr[t], this->M.level[t] });
    }
  }
  bool commit();
  void undo(); // of the transaction begun last
  void replaceNeighbour(int n, int from, int to)
  {
    if (n >= 0)
    {
      this->save(n);
      for (int& x : this->Nbr[n])
      {
        x = x == from ? to : x;
      }
    }
  }
  int addTriangle(std::array<int, 3> tri, int region, int level)
  {
    this->Saved.push_back(0);
    this->M.triangles.push_back(tri);
    this->M.region.push_back(region);
    this->M.level.push_back(level);
    this->Nbr.push_back({ -1, -1, -1 });
    this->Live.push_back(1);
    return static_cast<int>(this->M.triangles.size()) - 1;
  }
  // visit(t, part) for every triangle, in blocks of kTwoThreadBlock, each block's two halves at
  // once (parts 0 and 1) for large meshes (visit reads only, or writes its own part's data);
  // after each block merge() and a progress report, on this thread.
  template<class Visit, class Merge>
  void sweepTriangles(Visit&& visit, Merge&& merge) const
  {
    blockwise(
      this->M.triangles.size(),
      kTwoThreadBlock,
      kTwoThreadItems,
      [&](std::size_t from, std::size_t to, int part)
      {
        for (std::size_t t = from; t < to; ++t)
        {
          visit(static_cast<int>(t), part);
        }
      },
      [&]
      {
        merge();
        this->report();
      });
  }
  // The triangles t, increasing, for which pred(t) holds (as sweepTriangles, gatherInOrder).
  template<class Pred>
  std::vector<int> selectTriangles(Pred&& pred) const
  {
    std::vector<int> list;
    gatherInOrder<int>(
      this->M.triangles.size(),
      kTwoThreadBlock,
      kTwoThreadItems,
      [&](std::size_t t, std::vector<int>& found)
      {
        if (pred(static_cast<int>(t)))
        {
          found.push_back(static_cast<int>(t));
        }
      },
      [&](int t) { list.push_back(t); },
      [&] { this->report(); });
    return list;
  }
  bool needsFlip(int t, int k) const;
  void flipStacked(LargeVector<std::array<int, 2>>& stack); // (flipToDelaunay()'s flips)
  bool flip(int t, int k);
  void legalize(int p, std::vector<int>& around);
  bool bad(int t) const;
  double smallestAngleCosine(const std::array<int, 3>& tri) const;
  int smallestCorner(int t) const;
  bool splitEdge(int t, int k, Vec2 w, std::vector<int>& created);
  void insertIn(int t, Vec2 w, std::vector<int>& created);
  bool splitBoundary(int t, int k);
  bool retag(int t, char* far = nullptr, const int* near = nullptr);
  /// 2b': moves the free vertex of t opposite its edge k onto the curve point w beside it and
  /// retags t; false (nothing changed) when that vertex is not free, the move would turn a
  /// triangle around it, or t keeps its region.
  bool snapOpposite(int t, int k, Vec2 w);
  /// 2b': moves vertex v of t, on the curve of a region boundary edge of t between regions
  /// `left` and `right`, along that curve onto the model corner w (RefinementParams::
  /// modelCorner) when curveSlide takes it exactly there, no triangle around it turns and its
  /// region boundary edges stay on the curves; false (nothing changed) otherwise.
  bool slideOnto(int t, int v, Vec2 w, int left, int right);
  /// Whether the curve stretch from a to b (curveDeviation) lies within kCornerStraight of
  /// their distance from the segment ab: a side of a model corner with no other corner on it.
  bool straightTo(Vec2 a, Vec2 b, int left, int right) const
  {
    double area = 0.0;
    Vec2 w;
    return !this->P.curveDeviation(a, b, left, right, area, w) ||
      std::fabs(cross(b - a, w - a)) <= kCornerStraight * norm2(b - a);
  }
  LargeVector<int> centroidRegionsNear(const RecoveryMemo* before);
  template<class List>
  void appendNeighbours(int t, List& list) const
  {
    for (int n : this->Nbr[t])
    {
      if (n >= 0)
      {
        list.push_back(n);
      }
    }
  }
  double cornerAngle(int t) const;
  // Whether t is a live region triangle whose inradius (2 area / perimeter) is below a quarter
  // of minimumEdgeLength: a thin triangle, of which a thin piece is made (dissolveThinPieces()).
  bool thin(int t) const
  {
    if (this->M.region[t] < 0 || !this->Live[t])
    {
      return false;
    }
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    return orient2d(a, b, c) <
      0.25 * this->P.minimumEdgeLength * (norm(b - a) + norm(c - b) + norm(a - c));
  }
  int sharpestRegionCorner(int t, const std::array<double, 3>& angles) const;
  bool meshSpike(int t) const;
  bool inKept(int t) const;
  bool inKept(const std::array<int, 3>& tri, int region) const;
  bool keptShapes(const std::vector<int>& tris) const;
  struct Wedge;
  const Wedge* wedgeOf(const std::array<int, 3>& tri, int region) const;
  int conform(int v, int& t, Vec2 e, double tol, std::vector<int>& path);
  int around(int v, int t, Vec2 e, int& kv) const;
  int holding(int v, int t) const;
  int nearEdge(const std::array<int, 3>& tri, Vec2 e, double tol) const;
  int walkTo(int v, int t, Vec2 e) const;
  int vertexAt(int v, int& t, Vec2 e, double tol);
  int newVertex(int s, int edge, Vec2 w, bool orInside, int& t);
  bool recoverEdge(int p, int q, double tol, std::vector<int>& path);
  bool keepCorner(const SharpCorner& c,
    double& radius2,
    std::vector<Vec2>& outline,
    double cutWidth = 0.0,
    const std::vector<int>* local = nullptr);
  std::vector<int> scope(const std::vector<int>* local, bool changed) const;
  double starCosine(const int* first, const int* last, double& largest) const;
  int locate(int start, Vec2 p, int& crossT, int& crossK) const;
  bool encroached(int start, Vec2 p, int& segT, int& segK);
  void queueBad(const std::vector<int>& tris);
  void report() const // poll() now
  {
    this->Ticks |= 1023;
    this->poll();
  }
  void poll() const
  {
    if ((++this->Ticks & 1023) == 0)
    {
      this->Progress.report(
        std::min(0.99, static_cast<double>(this->Inserted) / static_cast<double>(this->Budget)),
        kRefiningStage);
    }
  }

  RegionMesh& M;
  const BoundarySplitter& Split;
  const RefinementParams& P;
  const ProgressReporter Progress; // a copy: callers pass sub-ranges by value
  double CosBad = 1.0;
  double OffDistance = 0.0;
  std::size_t Budget = 0;
  std::size_t Inserted = 0;
  std::size_t TipVertices = 0;  // (cutTips)
  bool EveryTip = false;        // (cutTips)
  std::size_t KeptVertices = 0; // (keepCorners)
  mutable std::size_t Ticks = 0;
  LargeVector<std::array<int, 3>> Nbr; // across edge k = (tri[k], tri[k + 1])
  LargeVector<std::uint8_t> Live;      // positive area at the start (others are frozen)
  std::deque<int> Queue;
  LargeVector<int> Cavity, Mark;
  int Stamp = 0;
  struct Entry
  {
    int t;
    std::array<int, 3> tri, nbr;
    int level;
  };
  std::vector<Entry> Journal;
  LargeVector<int> Saved; // transaction that saved each slot
  int Tx = 0;
  bool Recording = false;
  std::size_t Tri0 = 0, Points0 = 0, Flips0 = 0;
  double CosFloor = 1.0; // an insertion may not leave an angle below min(this, the old smallest)
  const std::vector<Zone>& Cautious;
  bool BoldInside = false; // (boldInside()): the zones are where it is bold, not cautious
  std::vector<int> Changed;
  // Triangles with an edge that may need a flip no flip has looked at since: one the flips
  // left (refused, or a new diagonal that needs one by rounding), one from a vertex inserted
  // or moved, a retagged triangle's. What flipToDelaunayNear() looks at besides the changed
  // triangles, and what a refiner hands the next (Handover); a sweep of every edge clears it.
  std::vector<int> Unsettled;
  std::vector<int>* FlipLog = nullptr; // flip() appends the two triangles it changes here
  RefinementResult R;
  double AngleAfterRun = 0.0;
  std::vector<int> BadAfterRun; // (zonesBelow(): after run(), the bad triangles)
  bool Ran = false;             // run() ran
  bool Legalize = true;      // false while the kept corners' sides are conformed
  std::vector<Zone> ExtendedSides; // extendedSides()
  mutable int LastAround = -1;     // around()'s last triangle: where holding() looks first
  mutable PlaceTable BodyPlaces;   // regionBody(): its region triangles' places in its list
  VertexMemo SideArcs;             // keepCorner(): the arcs of the vertices within reach
  bool Keeping = false;      // in keepCorners()
  bool KeepRan = false;      // keepCorners() ran (on this mesh)
  struct Wedge
  {
    Vec2 apex;
    int region;
    double radius2;
    double angle;              // the corner's, degrees
    std::vector<Vec2> outline; // apex, first side, second side back
  };
  std::vector<Wedge> Kept; // the kept corners' wedges (their triangles are not bad)
  struct ShortEdge
  {
    Vec2 middle;
    double length;
  };
  std::vector<ShortEdge> Shorts; // (findShortEdges())
  // Shorts by cell of a grid of cells minimumEdgeLength wide (a hash of the cell's indices).
  std::unordered_map<std::int64_t, std::vector<int>> ShortCells;
  static std::int64_t shortCell(std::int64_t i, std::int64_t j)
  {
    return i * 73856093LL ^ j * 19349663LL;
  }
  double floorAt(Vec2 x) const;
};

void Refiner::buildNeighbours()
{
  const std::size_t nt = this->M.triangles.size();
  const PointStars stars =
    pointStars(this->M.points.size(), this->M.triangles, nullptr, [this] { this->report(); });
  this->report(); // (between first writes: 0.02-0.04 s each at 1 M)
  withRoom(this->Nbr, nt).assign(nt, { -1, -1, -1 });
  this->report();
  // Each directed edge a -> b of a triangle is matched at a, in a's star: its neighbour is the
  // star's triangle with the edge b -> a. A second triangle with either is not a manifold,
  // consistently oriented mesh. Each point writes its own corners' slots only, so the points
  // are matched in two halves at once (large meshes); the first point at fault is reported.
  struct Corner
  {
    int triangle, k, next, prev; // triangle[k] = a; its edge k runs a -> next, edge k+2 prev -> a
  };
  struct Fault
  {
    std::size_t point, next, triangle;
  };
  std::optional<Fault> fault, faults[2];
  const auto match = [&](std::size_t from, std::size_t to, int part)
  {
    std::vector<Corner> star;
    for (std::size_t a = from; a < to && !faults[part]; ++a)
    {
      star.clear();
      for (int s = stars.start[a]; s < stars.start[a + 1]; ++s)
      {
        const int t = stars.items[s];
        const auto& tri = this->M.triangles[t];
        const int k = tri[0] == static_cast<int>(a) ? 0 : (tri[1] == static_cast<int>(a) ? 1 : 2);
        star.push_back({ t, k, tri[(k + 1) % 3], tri[(k + 2) % 3] });
      }
      for (std::size_t i = 0; i < star.size() && !faults[part]; ++i)
      {
        int found = 0, same = 0;
        for (const Corner& c : star)
        {
          found += c.prev == star[i].next;
          same += c.next == star[i].next;
          if (c.prev == star[i].next)
          {
            this->Nbr[star[i].triangle][star[i].k] = c.triangle;
          }
        }
        if (found > 1 || same > 1)
        {
          faults[part] = Fault{
            a, static_cast<std::size_t>(star[i].next), static_cast<std::size_t>(star[i].triangle)
          };
        }
      }
    }
  };
  const std::size_t np = stars.start.empty() ? 0 : stars.start.size() - 1;
  blockwise(np,
    kTwoThreadBlock,
    kTwoThreadItems,
    match,
    [&]
    {
      fault = fault ? fault : (faults[0] ? faults[0] : faults[1]);
      if (!fault)
      {
        this->report();
      }
    });
  if (fault)
  {
    throw ParameterError("refineDelaunay: the edge from point " + std::to_string(fault->point) +
      " to point " + std::to_string(fault->next) +
      " belongs to more than two triangles or twice to one side (triangle " +
      std::to_string(fault->triangle) + "): not a manifold, consistently oriented mesh");
  }
}

bool Refiner::needsFlip(int t, int k) const
{
  if (this->constrained(t, k))
  {
    return false;
  }
  const int u = this->Nbr[t][k];
  const auto& tt = this->M.triangles[t];
  const auto& tu = this->M.triangles[u];
  int d = -1;
  for (int j = 0; j < 3; ++j)
  {
    if (tu[j] == tt[(k + 1) % 3])
    {
      d = tu[(j + 2) % 3];
    }
  }
  return d >= 0 && inCircle(this->X(tt[0]), this->X(tt[1]), this->X(tt[2]), this->X(d));
}

// Flips edge k of t, (a, b) with c opposite in t and d in the neighbour u, into (c, d): t
// becomes (c, a, d), u becomes (d, b, c). Refused when a new triangle would not be positive.
bool Refiner::flip(int t, int k)
{
  const int u = this->Nbr[t][k];
  auto& tt = this->M.triangles[t];
  auto& tu = this->M.triangles[u];
  const int a = tt[k], b = tt[(k + 1) % 3], c = tt[(k + 2) % 3];
  int j = 0;
  while (tu[j] != b)
  {
    ++j;
  }
  const int d = tu[(j + 2) % 3];
  // Both new triangles counter-clockwise, and, with kept corners, not nearly flat (a kept
  // corner's sides are nearly parallel lines: three vertices on one are collinear but for the
  // curves' tolerance).
  const Vec2 pa = this->X(a), pb = this->X(b), pc = this->X(c), pd = this->X(d);
  const double flat = this->Kept.empty() && !this->Keeping ? 0.0 : kFlat;
  if (!(orient2d(pc, pa, pd) > flat * norm(pa - pc) * norm(pd - pc)) ||
    !(orient2d(pd, pb, pc) > flat * norm(pb - pd) * norm(pc - pd)))
  {
    return false;
  }
  this->save(t);
  this->save(u);
  const int nca = this->Nbr[t][(k + 2) % 3], nbc = this->Nbr[t][(k + 1) % 3];
  const int nad = this->Nbr[u][(j + 1) % 3], ndb = this->Nbr[u][(j + 2) % 3];
  tt = { c, a, d };
  tu = { d, b, c };
  this->Nbr[t] = { nca, nad, u };
  this->Nbr[u] = { ndb, nbc, t };
  this->replaceNeighbour(nad, u, t);
  this->replaceNeighbour(nbc, t, u);
  this->M.level[t] = this->M.level[u] = std::max(this->M.level[t], this->M.level[u]);
  ++this->R.delaunayFlips;
  if (this->FlipLog)
  {
    this->FlipLog->insert(this->FlipLog->end(), { t, u });
  }
  return true;
}

// Lawson: the edges opposite the new vertex p in the triangles `around` are flipped while not
// Delaunay; each flip gives two triangles around p whose opposite edges are checked in turn.
// On return `around` lists the triangles around p.
void Refiner::legalize(int p, std::vector<int>& around)
{
  std::vector<int> stack = this->Legalize ? around : std::vector<int>();
  while (!stack.empty())
  {
    const int t = stack.back();
    stack.pop_back();
    const auto& tri = this->M.triangles[t];
    int k = 0;
    while (k < 3 && tri[k] != p)
    {
      ++k;
    }
    if (k == 3)
    {
      continue;
    }
    const int e = (k + 1) % 3; // the edge opposite p
    const int u = this->Nbr[t][e];
    if (!this->needsFlip(t, e))
    {
      continue;
    }
    if (!this->flip(t, e))
    {
      this->Unsettled.push_back(t); // (refused: left needing one)
      continue;
    }
    stack.push_back(t);
    stack.push_back(u);
    around.push_back(u);
  }
  sortUnique(around);
}

bool Refiner::bad(int t) const
{
  return this->M.region[t] >= 0 && this->Live[t] &&
    this->smallestAngleCosine(this->M.triangles[t]) > this->CosBad &&
    (this->Kept.empty() || !this->inKept(t));
}

// Whether t is a triangle of a kept corner's wedge (wedgeOf()).
bool Refiner::inKept(int t) const
{
  return this->wedgeOf(this->M.triangles[t], this->M.region[t]) != nullptr;
}

bool Refiner::inKept(const std::array<int, 3>& tri, int region) const
{
  return this->wedgeOf(tri, region) != nullptr;
}

// Whether the triangles of kept corners' wedges among `tris` are no sharper than a quarter of
// their corner's angle and have no angle above kKeptLargest (what step 7 makes).
bool Refiner::keptShapes(const std::vector<int>& tris) const
{
  for (int t : tris)
  {
    const auto& tri = this->M.triangles[t];
    const Wedge* w = this->wedgeOf(tri, this->M.region[t]);
    double largest = 0.0;
    if (w &&
      (shapeCosine(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]), largest) >
          std::cos(0.25 * w->angle * kPi / 180.0) ||
        largest < std::cos(kKeptLargest * kPi / 180.0)))
    {
      return false;
    }
  }
  return true;
}

// The kept corner's wedge that a triangle of `region` with these corners lies in (of its
// region, within the wedge's radius, its centroid inside the outline), or none.
const Refiner::Wedge* Refiner::wedgeOf(const std::array<int, 3>& tri, int region) const
{
  for (const Wedge& w : this->Kept)
  {
    if (w.region == region && norm2(this->X(tri[0]) - w.apex) <= w.radius2 &&
      norm2(this->X(tri[1]) - w.apex) <= w.radius2 &&
      norm2(this->X(tri[2]) - w.apex) <= w.radius2 &&
      insidePolygon(w.outline, (1.0 / 3.0) * (this->X(tri[0]) + this->X(tri[1]) + this->X(tri[2]))))
    {
      return &w;
    }
  }
  return nullptr;
}

// Corner (0..2) of the smallest angle: opposite the shortest edge.
int Refiner::smallestCorner(int t) const
{
  const auto& tri = this->M.triangles[t];
  int corner = 0;
  double shortest = HUGE_VAL;
  for (int k = 0; k < 3; ++k)
  {
    const double l = norm2(this->X(tri[(k + 2) % 3]) - this->X(tri[(k + 1) % 3]));
    if (l < shortest)
    {
      shortest = l;
      corner = k;
    }
  }
  return corner;
}

// Splits edge k of t (a, b; c opposite) and the neighbour's (b, a; d opposite) at w: t = (a, w,
// c), new (w, b, c); u = (b, w, d), new (w, a, d). Refused when a piece would not be positive.
bool Refiner::splitEdge(int t, int k, Vec2 w, std::vector<int>& created)
{
  const int u = this->Nbr[t][k];
  const int a = this->M.triangles[t][k], b = this->M.triangles[t][(k + 1) % 3],
            c = this->M.triangles[t][(k + 2) % 3];
  int j = 0, d = -1;
  if (u >= 0)
  {
    while (this->M.triangles[u][j] != b)
    {
      ++j;
    }
    d = this->M.triangles[u][(j + 2) % 3];
  }
  const double scale = norm2(this->X(b) - this->X(a));
  const auto ok = [&](Vec2 p, Vec2 q, Vec2 r) { return orient2d(p, q, r) > 1e-9 * scale; };
  if (!ok(this->X(a), w, this->X(c)) || !ok(w, this->X(b), this->X(c)) ||
    (u >= 0 && (!ok(this->X(b), w, this->X(d)) || !ok(w, this->X(a), this->X(d)))))
  {
    return false;
  }
  this->save(t);
  if (u >= 0)
  {
    this->save(u);
  }
  const int wi = static_cast<int>(this->M.points.size());
  this->M.points.push_back(w);
  const int nbc = this->Nbr[t][(k + 1) % 3], nca = this->Nbr[t][(k + 2) % 3];
  const int t2 = this->addTriangle({ wi, b, c }, this->M.region[t], this->M.level[t]);
  this->M.triangles[t] = { a, wi, c };
  int u2 = -1;
  if (u >= 0)
  {
    const int nad = this->Nbr[u][(j + 1) % 3], ndb = this->Nbr[u][(j + 2) % 3];
    u2 = this->addTriangle({ wi, a, d }, this->M.region[u], this->M.level[u]);
    this->M.triangles[u] = { b, wi, d };
    this->Nbr[u] = { t2, u2, ndb };
    this->Nbr[u2] = { t, nad, u };
    this->replaceNeighbour(nad, u, u2);
  }
  this->Nbr[t] = { u2, t2, nca };
  this->Nbr[t2] = { u, nbc, t };
  this->replaceNeighbour(nbc, t, t2);
  created = { t, t2 };
  if (u >= 0)
  {
    created.push_back(u);
    created.push_back(u2);
  }
  this->legalize(wi, created);
  // (w off the edge, on its curve: an edge from w may need a flip legalize() does not look
  // for, left to the next sweep, or to prepare()'s successor.)
  this->Unsettled.insert(this->Unsettled.end(), created.begin(), created.end());
  return true;
}

// Splits t = (a, b, c) at the interior point w into (a, b, w), (b, c, w), (c, a, w).
void Refiner::insertIn(int t, Vec2 w, std::vector<int>& created)
{
  this->save(t);
  const auto tri = this->M.triangles[t];
  const int wi = static_cast<int>(this->M.points.size());
  this->M.points.push_back(w);
  const int nab = this->Nbr[t][0], nbc = this->Nbr[t][1], nca = this->Nbr[t][2];
  const int t2 = this->addTriangle({ tri[1], tri[2], wi }, this->M.region[t], this->M.level[t]);
  const int t3 = this->addTriangle({ tri[2], tri[0], wi }, this->M.region[t], this->M.level[t]);
  this->M.triangles[t] = { tri[0], tri[1], wi };
  this->Nbr[t] = { nab, t2, t3 };
  this->Nbr[t2] = { nbc, t3, t };
  this->Nbr[t3] = { nca, t, t2 };
  this->replaceNeighbour(nbc, t, t2);
  this->replaceNeighbour(nca, t, t3);
  created = { t, t2, t3 };
  this->legalize(wi, created);
  // (An edge from w may need a flip by rounding, w near a side: as in splitEdge().)
  this->Unsettled.insert(this->Unsettled.end(), created.begin(), created.end());
}

// Cosine of the smallest angle of tri: the angle opposite the shortest edge (law of cosines
// on the squared edge lengths).
double Refiner::smallestAngleCosine(const std::array<int, 3>& tri) const
{
  return smallestCosine(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
}

// Ends the transaction: keeps it when the smallest angle of the triangles it made is not below
// min(CosFloor's angle, the smallest angle of the triangles it replaced), else undoes it.
// Changed lists the triangles made (when kept).
bool Refiner::commit()
{
  this->Recording = false;
  double before = -1.0, after = -1.0; // cosines of the smallest angles (larger = worse)
  // (The kept corners' wedges do not count: their angles are the input's.)
  for (const Entry& e : this->Journal)
  {
    if (this->M.region[e.t] >= 0 &&
      (this->Kept.empty() || !this->inKept(e.tri, this->M.region[e.t])))
    {
      before = std::max(before, this->smallestAngleCosine(e.tri));
    }
  }
  this->Changed.clear();
  for (const Entry& e : this->Journal)
  {
    this->Changed.push_back(e.t);
  }
  for (std::size_t t = this->Tri0; t < this->M.triangles.size(); ++t)
  {
    this->Changed.push_back(static_cast<int>(t));
  }
  for (int t : this->Changed)
  {
    if (this->M.region[t] >= 0 && (this->Kept.empty() || !this->inKept(t)))
    {
      after = std::max(after, this->smallestAngleCosine(this->M.triangles[t]));
    }
  }
  double floor = this->BoldInside ? this->CosBad : this->CosFloor;
  const Vec2 w = this->M.points.back(); // the vertex this transaction inserted
  for (const Zone& z : this->Cautious)
  {
    // (cautious: the bound; with boldInside(), bold: the floor)
    floor =
      norm2(w - z.center) < z.radius2 ? (this->BoldInside ? this->CosFloor : this->CosBad) : floor;
  }
  if (after <= std::max(std::min(before, 1.0), floor) + 1e-12)
  {
    return true;
  }
  this->undo();
  return false;
}

void Refiner::undo()
{
  this->Recording = false;
  for (auto e = this->Journal.rbegin(); e != this->Journal.rend(); ++e)
  {
    this->M.triangles[e->t] = e->tri;
    this->Nbr[e->t] = e->nbr;
    this->M.level[e->t] = e->level;
  }
  this->M.triangles.resize(this->Tri0);
  this->M.region.resize(this->Tri0);
  this->M.level.resize(this->Tri0);
  this->Nbr.resize(this->Tri0);
  this->Live.resize(this->Tri0);
  this->Saved.resize(this->Tri0);
  this->M.points.resize(this->Points0);
  this->R.delaunayFlips = this->Flips0;
  this->Changed.clear();
}

// Splits the constrained edge k of t on its curve.
bool Refiner::splitBoundary(int t, int k)
{
  const int u = this->Nbr[t][k];
  if (!this->Live[t] || (u >= 0 && !this->Live[u]))
  {
    return false; // beside a frozen triangle
  }
  const bool side = !this->Kept.empty() && (this->inKept(t) || (u >= 0 && this->inKept(u)));
  const Vec2 a = this->X(this->M.triangles[t][k]), b = this->X(this->M.triangles[t][(k + 1) % 3]);
  const double l = norm(b - a);
  if (l < 2.0 * kFloor * this->P.minimumEdgeLength && l < 2.0 * this->floorAt(0.5 * (a + b)))
  {
    return false;
  }
  Vec2 w;
  if (!this->Split(a, b, this->M.region[t], u >= 0 ? this->M.region[u] : -1, w) ||
    !(norm(w - a) > 1e-6 * l && norm(w - b) > 1e-6 * l))
  {
    return false;
  }
  std::vector<int> created;
  this->begin();
  if (!this->splitEdge(t, k, w, created) || (side && !this->keptShapes(created)))
  {
    this->undo(); // (a kept corner's side is split only when its wedge keeps its shapes)
    return false;
  }
  if (!this->commit())
  {
    this->Recording = false;
    return false;
  }
  ++this->R.boundaryVertices;
  ++this->Inserted;
  this->queueBad(this->Changed);
  return true;
}

// Walks from `start` toward p. Returns the triangle holding p, or -1 with (crossT, crossK) the
// constrained edge the walk would cross (-1 when the walk did not end).
int Refiner::locate(int start, Vec2 p, int& crossT, int& crossK) const
{
  int t = start;
  crossT = crossK = -1;
  for (int step = 0; step < kMaxWalk; ++step)
  {
    const auto& tri = this->M.triangles[t];
    int next = -1;
    for (int i = 0; i < 3 && next < 0; ++i)
    {
      const int k = (i + step) % 3; // rotate the first edge tried: no cycling on ties
      const Vec2 a = this->X(tri[k]), b = this->X(tri[(k + 1) % 3]);
      if (orient2d(a, b, p) < -1e-12 * norm2(b - a))
      {
        next = k;
      }
    }
    if (next < 0)
    {
      return t;
    }
    if (this->constrained(t, next))
    {
      crossT = t;
      crossK = next;
      return -1;
    }
    t = this->Nbr[t][next];
  }
  return -1;
}

// Whether p encroaches a constrained edge of its Bowyer-Watson cavity (grown from `start`, the
// triangle holding p): then (segT, segK) is that edge.
bool Refiner::encroached(int start, Vec2 p, int& segT, int& segK)
{
  if (this->Mark.size() < this->M.triangles.size())
  {
    if (this->Mark.capacity() < this->M.triangles.size())
    {
      withRoom(this->Mark, this->M.triangles.size());
    }
    this->Mark.resize(this->M.triangles.size(), 0);
  }
  ++this->Stamp;
  this->Cavity.assign(1, start);
  this->Mark[start] = this->Stamp;
  for (std::size_t n = 0; n < this->Cavity.size() && n < kMaxCavity; ++n)
  {
    const int t = this->Cavity[n];
    const auto& tri = this->M.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      const Vec2 a = this->X(tri[k]), b = this->X(tri[(k + 1) % 3]);
      if (this->constrained(t, k))
      {
        if (dot(a - p, b - p) < 0.0)
        {
          segT = t;
          segK = k;
          return true;
        }
        continue;
      }
      const int u = this->Nbr[t][k];
      if (this->Mark[u] != this->Stamp)
      {
        const auto& tu = this->M.triangles[u];
        if (inCircle(this->X(tu[0]), this->X(tu[1]), this->X(tu[2]), p))
        {
          this->Mark[u] = this->Stamp;
          this->Cavity.push_back(u);
        }
      }
    }
  }
  return false;
}

void Refiner::queueBad(const std::vector<int>& tris)
{
  for (int t : tris)
  {
    if (this->bad(t))
    {
      this->Queue.push_back(t);
    }
  }
}

void Refiner::prepare(Handover* handed)
{
  const std::size_t nt = this->M.triangles.size();
  const bool taken = handed && handed->neighbours.size() == nt;
  if (taken)
  {
    this->Nbr = std::move(handed->neighbours);
  }
  else
  {
    this->buildNeighbours();
  }
  withRoom(this->Live, nt).resize(nt);
  withRoom(this->Saved, nt).assign(nt, 0);
  // (Each triangle writes its own flag: a block's two halves at once.)
  this->sweepTriangles([this](int t, int) { this->Live[t] = this->positive(t); }, [] {});
  if (!taken || handed->live.size() != nt)
  {
    this->flipToDelaunay();
    return;
  }
  // The handed unsettled triangles (an undone insertion's are gone), and those whose flag
  // changed: their edges' constraints did (a vertex moved since the flags were made).
  std::vector<int> near;
  for (const int t : handed->unsettled)
  {
    if (t >= 0 && static_cast<std::size_t>(t) < nt)
    {
      near.push_back(t);
    }
  }
  for (std::size_t t = 0; t < nt; ++t)
  {
    if (handed->live[t] != this->Live[t])
    {
      near.push_back(static_cast<int>(t));
    }
  }
  this->Unsettled.clear();
  this->flipToDelaunayNear(std::move(near));
}

// Lawson's flips until every unconstrained edge is Delaunay (with `seeds`: starting from the
// edges of those triangles only, when the others are known to be Delaunay).
void Refiner::flipToDelaunay(const std::vector<int>* seeds)
{
  // Every interior edge once, in order, would be stacked; only those that need a flip now are
  // (each block's two halves tested at once for large meshes): the others are Delaunay, and
  // one that a flip changes is stacked by that flip, so the flips are those of the full stack.
  LargeVector<std::array<int, 2>> stack, parts[2];
  for (std::size_t i = 0; seeds && i < seeds->size(); ++i)
  {
    const int t = (*seeds)[i];
    for (int k = 0; k < 3 && this->Live[t]; ++k)
    {
      const int u = this->Nbr[t][k];
      // (each edge once: from the lower-numbered triangle when both are seeds)
      if (u >= 0 && this->needsFlip(t, k) &&
        (u > t || !std::binary_search(seeds->begin(), seeds->end(), u)))
      {
        stack.push_back({ t, k });
      }
    }
  }
  if (!seeds)
  {
    this->sweepTriangles(
      [&](int t, int part)
      {
        for (int k = 0; k < 3; ++k)
        {
          if (this->Nbr[t][k] > t && this->needsFlip(t, k))
          {
            parts[part].push_back({ t, k });
          }
        }
      },
      [&]
      {
        for (auto& list : parts)
        {
          stack.insert(stack.end(), list.begin(), list.end());
          list.clear();
        }
      });
  }
  if (!seeds)
  {
    this->Unsettled.clear();
  }
  this->flipStacked(stack);
}

void Refiner::flipToDelaunayNear(std::vector<int> changed)
{
  changed.insert(changed.end(), this->Unsettled.begin(), this->Unsettled.end());
  this->Unsettled.clear();
  // Their edges as the sweep of flipToDelaunay() names them (from the lower-numbered triangle),
  // in its order, those that need a flip.
  const auto owned = [this](int t, int k, auto&& take)
  {
    const int u = this->Nbr[t][k];
    if (u > t)
    {
      take(t, k);
    }
    else if (u >= 0)
    {
      const auto& nu = this->Nbr[u];
      take(u, nu[0] == t ? 0 : (nu[1] == t ? 1 : 2));
    }
  };
  LargeVector<std::array<int, 2>> stack;
  const std::size_t nt = this->M.triangles.size();
  if (changed.size() > nt / kManyChanged)
  {
    // Many (a pass's recovery changed much of the mesh): the edges flagged per triangle and
    // read in increasing order, with progress reports, instead of sorted (the same edges in
    // the same order; with tens of thousands of input points two sorts here took 0.5 s at 1 M
    // triangles without a report).
    LargeVector<std::uint8_t> edges(nt, 0);
    for (const int t : changed)
    {
      this->poll();
      for (int k = 0; k < 3; ++k)
      {
        owned(t, k, [&](int o, int ok) { edges[o] |= static_cast<std::uint8_t>(1 << ok); });
      }
    }
    for (std::size_t t = 0; t < nt; ++t)
    {
      this->poll();
      for (int k = 0; k < 3; ++k)
      {
        const int ti = static_cast<int>(t);
        if ((edges[t] >> k & 1) && this->needsFlip(ti, k))
        {
          stack.push_back({ ti, k });
        }
      }
    }
  }
  else
  {
    sortUnique(changed);
    for (const int t : changed)
    {
      for (int k = 0; k < 3; ++k)
      {
        owned(t, k, [&](int o, int ok) { stack.push_back({ o, ok }); });
      }
    }
    sortUnique(stack);
    stack.erase(std::remove_if(stack.begin(),
                  stack.end(),
                  [this](const std::array<int, 2>& e) { return !this->needsFlip(e[0], e[1]); }),
      stack.end());
  }
  this->flipStacked(stack);
}

void Refiner::flipStacked(LargeVector<std::array<int, 2>>& stack)
{
  while (!stack.empty())
  {
    this->poll();
    const auto [t, k] = stack.back();
    stack.pop_back();
    const int u = this->Nbr[t][k];
    if (!this->needsFlip(t, k))
    {
      continue;
    }
    if (!this->flip(t, k))
    {
      this->Unsettled.push_back(t);
      continue;
    }
    // t = (c, a, d), u = (d, b, c): their outer edges are 0 and 1, the new diagonal t's 2.
    stack.push_back({ t, 0 });
    stack.push_back({ t, 1 });
    stack.push_back({ u, 0 });
    stack.push_back({ u, 1 });
    if (this->needsFlip(t, 2))
    {
      this->Unsettled.push_back(t);
    }
  }
}

std::size_t Refiner::recoverCurves(const RecoveryMemo* before, RecoveryMemo* after)
{
  if (!this->P.curvePoint || !this->P.regionAt)
  {
    return 0;
  }
  std::deque<int> queue;
  for (std::size_t t = 0; t < this->M.triangles.size(); ++t)
  {
    queue.push_back(static_cast<int>(t));
  }
  // Every triangle takes the region at its centroid first; a retag can allow its neighbours'
  // (a few rounds). A triangle with no curve within its longest edge of its centroid is marked
  // far: while it stays as it is, no curve point lies inside it (none lies farther from the
  // centroid than its farthest corner, 2/3 of a median, less than the longest edge), so it is
  // not probed. Insertions change only the triangles they report (the new vertex's star).
  // The centroids' curve queries (geometry only: the rounds change regions, not positions)
  // are asked all at once first when the caller can answer them so.
  LargeVector<int> near = this->centroidRegionsNear(before);
  const std::size_t nt = this->M.triangles.size();
  LargeVector<int> todo, next; // (the first round: every triangle, in order)
  LargeVector<char> far(nt, 0);
  for (int round = 0; round < 4 && (round == 0 ? nt > 0 : !todo.empty()); ++round)
  {
    next.clear();
    const std::size_t count = round == 0 ? nt : todo.size();
    for (std::size_t i = 0; i < count; ++i)
    {
      const int t = round == 0 ? static_cast<int>(i) : todo[i];
      this->poll();
      if (this->retag(t, &far[t], near.empty() ? nullptr : &near[t]))
      {
        this->appendNeighbours(t, next);
      }
    }
    sortUnique(next);
    todo.swap(next);
  }
  const std::size_t inserted = this->Inserted;
  const auto probed = [&](int t, const std::array<int, 3>& tri)
  {
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    const double shortest = std::sqrt(std::min({ norm2(b - a), norm2(c - b), norm2(a - c) }));
    return this->Live[t] && shortest >= this->P.minimumEdgeLength;
  };
  // The probes of the triangles as they are now, asked all at once (in blocks) when the
  // caller can answer them so: a triangle's answer holds while no insertion changed it (points
  // never move here; an insertion reports every triangle it changes).
  LargeVector<int> probeT; // the triangles probed in advance, increasing
  LargeVector<char> probeFound, changed;
  LargeVector<Vec2> probeAt;
  if (this->P.curvePoints)
  {
    for (std::size_t t = 0; t < nt; ++t)
    {
      if (!far[t] && probed(static_cast<int>(t), this->M.triangles[t]))
      {
        probeT.push_back(static_cast<int>(t));
      }
    }
    probeFound.assign(probeT.size(), 0);
    probeAt.resize(probeT.size());
    // The triangles the recovery before probed, unchanged, take its answers; the others are
    // asked (by their places in probeT).
    LargeVector<std::size_t> ask;
    for (std::size_t i = 0; i < probeT.size(); ++i)
    {
      const int t = probeT[i];
      const std::uint8_t known = before && static_cast<std::size_t>(t) < before->probe.size()
        ? before->probe[t]
        : RecoveryMemo::kNotProbed;
      if (known != RecoveryMemo::kNotProbed && before->same(t, this->M))
      {
        probeFound[i] = known == RecoveryMemo::kPoint;
        if (probeFound[i])
        {
          probeAt[i] = before->at.at(t);
        }
      }
      else
      {
        ask.push_back(i);
      }
    }
    LargeVector<Vec2> corners, at;
    LargeVector<char> found;
    for (std::size_t begin = 0; begin < ask.size(); begin += kTwoThreadBlock)
    {
      this->report();
      const std::size_t n = std::min(kTwoThreadBlock, ask.size() - begin);
      corners.clear();
      for (std::size_t i = begin; i < begin + n; ++i)
      {
        const auto& tri = this->M.triangles[probeT[ask[i]]];
        corners.insert(corners.end(), { this->X(tri[0]), this->X(tri[1]), this->X(tri[2]) });
      }
      found.assign(n, 0);
      at.resize(n);
      this->P.curvePoints(corners.data(), n, found.data(), at.data());
      for (std::size_t i = 0; i < n; ++i)
      {
        probeFound[ask[begin + i]] = found[i];
        probeAt[ask[begin + i]] = at[i];
      }
    }
    changed.assign(nt, 0);
  }
  if (after)
  {
    // This recovery's answers, for the next (the mesh as it was asked about).
    after->triangles = this->M.triangles;
    after->points = this->M.points;
    after->near = std::move(near); // (not needed here any more)
    after->probe.assign(this->M.triangles.size(), RecoveryMemo::kNotProbed);
    after->at.clear();
    for (std::size_t i = 0; i < probeT.size(); ++i)
    {
      after->probe[probeT[i]] = probeFound[i] ? RecoveryMemo::kPoint : RecoveryMemo::kNoPoint;
      if (probeFound[i])
      {
        after->at.emplace(probeT[i], probeAt[i]);
      }
    }
  }
  // The answer asked in advance for t, if any and still valid (lookups mostly in increasing
  // order: the triangles of the first queue, unchanged, come in order).
  std::size_t cursor = 0;
  const auto askedBefore = [&](int t) -> int
  {
    if (static_cast<std::size_t>(t) >= changed.size() || changed[t])
    {
      return -1;
    }
    if (cursor > 0 && probeT[cursor - 1] >= t)
    {
      cursor = static_cast<std::size_t>(
        std::lower_bound(probeT.begin(), probeT.end(), t) - probeT.begin());
    }
    while (cursor < probeT.size() && probeT[cursor] < t)
    {
      ++cursor;
    }
    return cursor < probeT.size() && probeT[cursor] == t ? static_cast<int>(cursor++) : -1;
  };
  std::vector<int> created;
  while (!queue.empty() && this->Inserted < this->Budget)
  {
    this->poll();
    const int t = queue.front();
    queue.pop_front();
    if (static_cast<std::size_t>(t) < far.size() && far[t])
    {
      continue; // no curve comes into it (see above)
    }
    const auto tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    if (!probed(t, tri))
    {
      continue;
    }
    Vec2 w;
    const int known = askedBefore(t);
    const bool found =
      known >= 0 ? (w = probeAt[known], probeFound[known] != 0) : this->P.curvePoint(a, b, c, w);
    if (!found || !(orient2d(a, b, w) > 0.0 && orient2d(b, c, w) > 0.0 && orient2d(c, a, w) > 0.0))
    {
      continue;
    }
    this->insertIn(t, w, created);
    ++this->Inserted; // (also what poll() reports)
    for (int u : created)
    {
      if (static_cast<std::size_t>(u) < far.size())
      {
        far[u] = 0; // changed
      }
      if (static_cast<std::size_t>(u) < changed.size())
      {
        changed[u] = 1;
      }
      this->retag(u);
      queue.push_back(u);
    }
  }
  // Regions changed, so did the constrained edges: the retagged triangles and the insertions
  // are recorded (Unsettled), so the flips look at their edges only.
  this->flipToDelaunayNear({});
  return this->Inserted - inserted;
}

std::size_t Refiner::splitLongEdges()
{
  const double limit2 = this->P.maximumEdgeLength * this->P.maximumEdgeLength;
  if (!(limit2 > 0.0))
  {
    return 0;
  }
  std::size_t splits = 0;
  std::vector<std::tuple<double, int, int>> todo; // (-squared length, triangle, edge)
  std::vector<int> created;
  for (int round = 0; round < kSizeRounds; ++round)
  {
    todo.clear();
    for (std::size_t i = 0; i < this->M.triangles.size(); ++i)
    {
      this->poll();
      const int t = static_cast<int>(i);
      for (int k = 0; k < 3 && this->M.region[t] >= 0 && this->Live[t]; ++k)
      {
        const int u = this->Nbr[t][k];
        const double l2 =
          norm2(this->X(this->M.triangles[t][(k + 1) % 3]) - this->X(this->M.triangles[t][k]));
        if (l2 > limit2 && !(u >= 0 && u < t && this->M.region[u] >= 0 && this->Live[u]))
        {
          todo.emplace_back(-l2, t, k); // (each edge once)
        }
      }
    }
    std::sort(todo.begin(), todo.end());
    const std::size_t before = splits;
    for (const auto& [negative, t, k] : todo)
    {
      this->poll();
      const int u = this->Nbr[t][k];
      const Vec2 a = this->X(this->M.triangles[t][k]),
                 b = this->X(this->M.triangles[t][(k + 1) % 3]);
      const double l = norm(b - a);
      if (this->Inserted >= this->Budget || !(l * l > limit2) || (u >= 0 && !this->Live[u]))
      {
        continue; // (a split before may have changed the slot)
      }
      if (!this->Kept.empty() && (this->inKept(t) || (u >= 0 && this->inKept(u))))
      {
        continue; // a kept corner's wedge stays as step 7 made it
      }
      Vec2 w = 0.5 * (a + b);
      if (this->constrained(t, k) &&
        (!this->Split(a, b, this->M.region[t], u >= 0 ? this->M.region[u] : -1, w) ||
          !(norm(w - a) > 1e-6 * l && norm(w - b) > 1e-6 * l)))
      {
        continue; // no curve point to split it at
      }
      if (this->splitEdge(t, k, w, created))
      {
        ++splits;
        ++this->Inserted;
      }
    }
    if (splits == before)
    {
      break;
    }
  }
  return splits;
}

// The pieces of the regions (triangles joined across edges that are not constrained): the
// piece of each triangle.
LargeVector<int> Refiner::pieces() const
{
  const std::size_t nt = this->M.triangles.size();
  LargeVector<int> piece(nt, -1);
  std::vector<int> stack;
  int id = 0;
  for (std::size_t t0 = 0; t0 < nt; ++t0)
  {
    if (piece[t0] >= 0)
    {
      continue;
    }
    piece[t0] = ++id;
    stack.assign(1, static_cast<int>(t0));
    while (!stack.empty())
    {
      this->poll(); // (once per triangle: 0.06-0.10 s in all at 1.5-2 M triangles)
      const int t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k)
      {
        const int n = this->Nbr[t][k];
        if (!this->constrained(t, k) && piece[n] < 0)
        {
          piece[n] = id;
          stack.push_back(n);
        }
      }
    }
  }
  return piece;
}

// Whether a piece of a region (pieces()) has only thin triangles (thin()): what
// dissolveThinPieces() looks for. Searched from the thin triangles (selectTriangles()), a
// piece left at its first triangle that is not thin. (A piece left so may be searched again
// from a thin triangle not reached yet and then taken for thin: never the other way round.)
bool Refiner::hasThinPiece() const
{
  const std::size_t nt = this->M.triangles.size();
  const std::vector<int> seeds = this->selectTriangles([this](int t) { return this->thin(t); });
  std::vector<std::uint8_t> seen(seeds.empty() ? 0 : nt, 0);
  std::vector<int> stack;
  for (const int seed : seeds)
  {
    if (seen[seed])
    {
      continue;
    }
    seen[seed] = 1;
    stack.assign(1, seed);
    bool allThin = true;
    while (!stack.empty() && allThin)
    {
      const int t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3 && allThin; ++k)
      {
        const int n = this->Nbr[t][k];
        if (!this->constrained(t, k) && !seen[n])
        {
          seen[n] = 1;
          allThin = this->thin(n);
          stack.push_back(n);
        }
      }
    }
    if (allThin)
    {
      return true;
    }
  }
  return false;
}

std::size_t Refiner::followCurves()
{
  if (!this->P.curveDeviation)
  {
    return 0;
  }
  // The region boundary edges of t, each once (from its region side), to todo.
  std::vector<std::pair<int, int>> todo;
  const auto edgesOf = [&](int t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int u = this->Nbr[t][k];
      if (this->M.region[t] >= 0 && this->Live[t] && this->constrained(t, k) &&
        (u < 0 || this->M.region[u] < 0 || (this->Live[u] && t < u)))
      {
        todo.emplace_back(t, k);
      }
    }
  };
  // Those of every triangle (in order: sorted), and the mesh area per region.
  std::vector<double> area;
  for (std::size_t t = 0; t < this->M.triangles.size(); ++t)
  {
    this->poll(); // (0.1 s in all at 1.5 M triangles)
    const int r = this->M.region[t];
    if (r >= 0 && this->Live[t])
    {
      area.resize(std::max(area.size(), static_cast<std::size_t>(r) + 1), 0.0);
      const auto& tri = this->M.triangles[t];
      area[r] += 0.5 * orient2d(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
    }
    edgesOf(static_cast<int>(t));
  }
  // A region whose boundary edges cut off more than curveAreaBudget of its area in all (a
  // thin, bending layer: each edge under the per-edge bound, their sum not) also has its edges
  // that cut off more than an even share of that budget split: limit[r], else no limit.
  const double budget = this->P.curveAreaBudget;
  std::vector<double> limit(area.size(), HUGE_VAL);
  if (budget > 0.0)
  {
    std::vector<double> cut(area.size(), 0.0);
    std::vector<int> edges(area.size(), 0);
    for (const auto& [t, k] : todo)
    {
      this->poll();
      const int u = this->Nbr[t][k];
      if (u >= 0 && !this->Live[u])
      {
        continue;
      }
      const Vec2 a = this->X(this->M.triangles[t][k]),
                 b = this->X(this->M.triangles[t][(k + 1) % 3]);
      const int left = this->M.region[t], right = u >= 0 ? this->M.region[u] : -1;
      double deviation = 0.0;
      Vec2 w;
      if (!this->P.curveDeviation(a, b, left, right, deviation, w))
      {
        deviation = 0.0;
      }
      for (int r : { left, right })
      {
        if (r >= 0)
        {
          cut[r] += deviation;
          ++edges[r];
        }
      }
    }
    for (std::size_t r = 0; r < area.size(); ++r)
    {
      if (edges[r] > 0 && cut[r] > budget * area[r])
      {
        limit[r] = budget * area[r] / edges[r];
      }
    }
  }
  const auto meanEdge = [&](int t)
  {
    const auto& tri = this->M.triangles[t];
    return meanEdgeLength(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
  };
  std::size_t splits = 0;
  std::vector<int> created, touched;
  for (int round = 0; round < kFollowRounds && !todo.empty(); ++round)
  {
    touched.clear();
    for (const auto& [t, k] : todo)
    {
      this->poll();
      const int u = this->Nbr[t][k];
      if (this->Inserted >= this->Budget || !this->Live[t] || this->M.region[t] < 0 ||
        !this->constrained(t, k) || (u >= 0 && !this->Live[u]))
      {
        continue; // (a split before may have changed the slot)
      }
      const Vec2 a = this->X(this->M.triangles[t][k]),
                 b = this->X(this->M.triangles[t][(k + 1) % 3]);
      const double l = norm(b - a);
      const int left = this->M.region[t], right = u >= 0 ? this->M.region[u] : -1;
      double deviation = 0.0;
      Vec2 w;
      if (l < this->P.minimumEdgeLength || !this->P.curveDeviation(a, b, left, right, deviation, w))
      {
        continue;
      }
      const double off = std::fabs(cross(b - a, w - a)); // (w's distance from the edge x l)
      // A chord across a model corner with a free vertex of t beside the corner (the
      // compression left it there, off the curve): that vertex is moved onto the corner (no
      // vertex made: not counted).
      if (off > kSnapChord * l * l &&
        norm(this->X(this->M.triangles[t][(k + 2) % 3]) - w) < kFloor * this->P.minimumEdgeLength &&
        this->snapOpposite(t, k, w))
      {
        touched.push_back(t);
        continue;
      }
      const double smaller = right >= 0 ? std::min(area[left], area[right]) : area[left];
      const double bound = std::min(
        { kDeviationFraction * smaller, limit[left], right >= 0 ? limit[right] : HUGE_VAL });
      // A chord across a model corner (RefinementParams::modelCorner): split at the corner
      // when that lies more than kSnapChord of the chord's length from it, whatever the area;
      // else, or when the split is refused, the chord's nearer end slides onto the corner.
      const bool corner = off > kCornerOff * l * l && this->P.modelCorner &&
        this->P.modelCorner(w) && this->straightTo(a, w, left, right) &&
        this->straightTo(w, b, left, right);
      // A chord whose stretch lies farther than kChordLocal local edges from it (the mean
      // edge of the triangles beside it, or its length when shorter: the refinement makes
      // them about as long as the chord) and than a finest edge: issue 5's boundary bound,
      // which no area bound sees on a large region's shore (a lake's island whose bulge a
      // chord cut off, 0.52 local edges).
      const double local = std::min(
        l, u >= 0 && this->M.region[u] >= 0 ? 0.5 * (meanEdge(t) + meanEdge(u)) : meanEdge(t));
      const bool far = off > l * std::max(kChordLocal * local, this->P.minimumEdgeLength);
      if ((deviation > bound || far || (corner && off > kSnapChord * l * l)) &&
        std::min(norm(w - a), norm(w - b)) >= kFloor * this->P.minimumEdgeLength &&
        this->splitEdge(t, k, w, created))
      {
        ++splits;
        ++this->Inserted;
        touched.insert(touched.end(), created.begin(), created.end());
      }
      else if (corner &&
        this->slideOnto(
          t, this->M.triangles[t][norm2(w - a) <= norm2(w - b) ? k : (k + 1) % 3], w, left, right))
      {
        touched.push_back(t);
      }
    }
    sortUnique(touched);
    todo.clear();
    for (const int t : touched)
    {
      edgesOf(t);
    }
    sortUnique(todo);
  }
  return splits;
}

bool Refiner::snapOpposite(int t, int k, Vec2 w)
{
  const int c = this->M.triangles[t][(k + 2) % 3];
  const int region = this->M.region[t];
  // c's star, turning from t; a free vertex's is closed, of t's region, with no constrained edge.
  std::vector<int> star;
  int cur = t;
  for (int turn = 0; turn < kMaxWalk; ++turn)
  {
    const auto& tri = this->M.triangles[cur];
    const int kc = tri[0] == c ? 0 : (tri[1] == c ? 1 : 2);
    if (!this->Live[cur] || this->M.region[cur] != region || this->constrained(cur, kc) ||
      this->constrained(cur, (kc + 2) % 3))
    {
      return false;
    }
    star.push_back(cur);
    cur = this->Nbr[cur][kc];
    if (cur < 0)
    {
      return false;
    }
    if (cur == t)
    {
      break;
    }
  }
  if (cur != t)
  {
    return false;
  }
  const Vec2 before = this->M.points[c];
  this->M.points[c] = w;
  const bool turned =
    std::any_of(star.begin(), star.end(), [&](int x) { return !this->clearlyPositive(x); });
  if (turned || !this->retag(t))
  {
    this->M.points[c] = before;
    return false;
  }
  this->legalize(c, star);
  // (c moved: an edge between two of its triangles may need a flip legalize() does not look
  // for, left to the next sweep, or to prepare()'s successor.)
  this->Unsettled.insert(this->Unsettled.end(), star.begin(), star.end());
  return true;
}

bool Refiner::slideOnto(int t, int v, Vec2 w, int left, int right)
{
  Vec2 at;
  if (!this->P.curveSlide || !this->P.onCurve || !this->P.curveDistance ||
    !this->P.curveSlide(this->X(v), w, left, right, at) ||
    !(norm(at - w) <= 1e-9 * norm(w - this->X(v)))) // (at w: the slide stopped there)
  {
    return false;
  }
  // v's star: turning both ways from t, to the mesh's border or round.
  std::vector<int> star{ t };
  for (const int way : { 0, 2 })
  {
    int cur = t;
    for (int turn = 0; turn < kMaxWalk; ++turn)
    {
      const auto& tri = this->M.triangles[cur];
      const int kv = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      cur = this->Nbr[cur][(kv + way) % 3];
      if (cur < 0 || cur == t)
      {
        break;
      }
      if (!this->Live[cur])
      {
        return false;
      }
      star.push_back(cur);
    }
    if (cur == t)
    {
      break; // (round: every triangle once)
    }
  }
  const Vec2 before = this->M.points[v];
  this->M.points[v] = w;
  bool ok = true;
  for (const int x : star)
  {
    const auto& tri = this->M.triangles[x];
    ok = ok && this->clearlyPositive(x);
    const int kv = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    for (const int k : { kv, (kv + 2) % 3 })
    {
      const int o = tri[k == kv ? (kv + 1) % 3 : k];
      if (ok && this->constrained(x, k))
      {
        const double length = norm(this->X(o) - w);
        ok = this->P.onCurve(this->X(o)) &&
          this->P.curveDistance(0.5 * (w + this->X(o)), HUGE_VAL) <= kSlideDeviation * length;
      }
    }
  }
  if (!ok)
  {
    this->M.points[v] = before;
    return false;
  }
  this->legalize(v, star);
  this->Unsettled.insert(this->Unsettled.end(), star.begin(), star.end()); // (as in snapOpposite())
  return true;
}

// For every live triangle, the region at its centroid when a curve lies nearer to it than
// its longest edge, else kNoCurveNear (RefinementParams::regionsNear, in blocks between
// polls); empty without regionsNear or curveDistance.
LargeVector<int> Refiner::centroidRegionsNear(const RecoveryMemo* before)
{
  LargeVector<int> region;
  if (!this->P.regionsNear || !this->P.curveDistance)
  {
    return region;
  }
  const std::size_t n = this->M.triangles.size();
  region.assign(n, kNoCurveNear);
  std::vector<Vec2> points;
  std::vector<double> reach;
  std::vector<int> ids, answers;
  constexpr std::size_t kBlock = std::size_t(1) << 15;
  for (std::size_t begin = 0; begin < n; begin += kBlock)
  {
    this->report();
    points.clear();
    reach.clear();
    ids.clear();
    for (std::size_t t = begin; t < std::min(n, begin + kBlock); ++t)
    {
      if (this->Live[t] && before && t < before->near.size() && before->same(t, this->M))
      {
        region[t] = before->near[t]; // (unchanged: the same answer)
      }
      else if (this->Live[t])
      {
        const auto& tri = this->M.triangles[t];
        const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
        points.push_back((1.0 / 3.0) * (a + b + c));
        reach.push_back(std::sqrt(std::max({ norm2(b - a), norm2(c - b), norm2(a - c) })));
        ids.push_back(static_cast<int>(t));
      }
    }
    answers.resize(ids.size());
    this->P.regionsNear(points.data(), reach.data(), ids.size(), answers.data());
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      region[ids[i]] = answers[i];
    }
  }
  return region;
}

// Gives t the region at its centroid unless that gives it a region boundary edge with an end
// off the curves. Returns whether its region changed; sets *far (when given) for a live
// triangle with no curve within its longest edge of its centroid (see recoverCurves). *near,
// when given, is t's entry of centroidRegionsNear() (t unchanged since): no query is asked.
bool Refiner::retag(int t, char* far, const int* near)
{
  const auto& tri = this->M.triangles[t];
  // (The centroid g and the longest edge only for the queries: with `near`, at 1 M every
  // triangle of the first round, none is asked.)
  Vec2 g{};
  const auto farFromCurves = [&]
  {
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    g = (1.0 / 3.0) * (a + b + c);
    const double longest = std::sqrt(std::max({ norm2(b - a), norm2(c - b), norm2(a - c) }));
    return this->P.curveDistance && this->P.curveDistance(g, longest) >= longest;
  };
  if (!this->Live[t] || (near ? *near == kNoCurveNear : farFromCurves()))
  {
    if (far && this->Live[t])
    {
      *far = 1;
    }
    return false; // no curve runs near it: its region is its neighbours'
  }
  const int r = near ? *near : this->P.regionAt(g); // (g: set by farFromCurves() without near)
  if (r == this->M.region[t])
  {
    return false;
  }
  for (int k = 0; k < 3 && this->P.onCurve; ++k)
  {
    const int n = this->Nbr[t][k];
    if ((n >= 0 ? this->M.region[n] : -2) != r &&
      !(this->P.onCurve(this->X(tri[k])) && this->P.onCurve(this->X(tri[(k + 1) % 3]))))
    {
      return false;
    }
  }
  this->M.region[t] = r;
  this->Unsettled.push_back(t); // (its edges' constraints changed)
  return true;
}

// The smallest angle (degrees) of t at a corner between two of its constrained edges (a
// corner of its region); 180 when it has none or is not a region triangle.
double Refiner::cornerAngle(int t) const
{
  if (this->M.region[t] < 0 || !this->Live[t] || (!this->Kept.empty() && this->inKept(t)))
  {
    return 180.0;
  }
  bool corner = false;
  for (int i = 0; i < 3 && !corner; ++i)
  {
    corner = this->constrained(t, i) && this->constrained(t, (i + 2) % 3);
  }
  if (!corner)
  {
    return 180.0; // (most triangles: no angle to compute)
  }
  double angle = 180.0;
  const auto& tri = this->M.triangles[t];
  const auto angles = triangleAngles(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
  for (int i = 0; i < 3; ++i)
  {
    if (this->constrained(t, i) && this->constrained(t, (i + 2) % 3))
    {
      angle = std::min(angle, angles[i]);
    }
  }
  return angle;
}

// The corner of t between two region boundary edges with the smallest of the given angles
// (t's, by corner), or -1 when t has no such corner.
int Refiner::sharpestRegionCorner(int t, const std::array<double, 3>& angles) const
{
  int k = -1;
  for (int j = 0; j < 3; ++j)
  {
    if (this->constrained(t, j) && this->constrained(t, (j + 2) % 3) &&
      (k < 0 || angles[j] < angles[k]))
    {
      k = j;
    }
  }
  return k;
}

// Whether t's sharpest region corner is a spike of its region between two triangles of one
// other region (or the outer border) with no corner of the model's region sharper than the
// bound within kSpikeReach times t's longest edge of it (RefinementParams::sharpModelCorner): the
// mesh's doing.
bool Refiner::meshSpike(int t) const
{
  if (!this->P.sharpModelCorner)
  {
    return false;
  }
  const auto& tri = this->M.triangles[t];
  const Vec2 p[3] = { this->X(tri[0]), this->X(tri[1]), this->X(tri[2]) };
  const int k = this->sharpestRegionCorner(t, triangleAngles(p[0], p[1], p[2]));
  if (k < 0)
  {
    return false;
  }
  const int n1 = this->Nbr[t][k], n2 = this->Nbr[t][(k + 2) % 3];
  if ((n1 >= 0 ? this->M.region[n1] : -1) != (n2 >= 0 ? this->M.region[n2] : -1))
  {
    return false;
  }
  const double longest =
    std::sqrt(std::max({ norm2(p[1] - p[0]), norm2(p[2] - p[1]), norm2(p[0] - p[2]) }));
  return !this->P.sharpModelCorner(this->M.region[t], p[k], kSpikeReach * longest);
}

std::size_t Refiner::dissolveCorners()
{
  if (!this->P.regionAt || !this->P.onCurve || !(this->P.minimumAngle > 0.0))
  {
    return 0;
  }
  // The triangles per region and twice the regions' (mesh) areas are made when first asked
  // for (at 1 M mostly never: 0.003 and 0.006 s a sweep): the counts before the first retag
  // (the first visit below that retags asks for them first), the areas as the mesh was before
  // the retags (journalled below), as when they were made first.
  std::map<int, std::size_t> count;
  bool counted = false;
  const auto counts = [&]() -> std::map<int, std::size_t>&
  {
    if (!counted)
    {
      auto it = count.end(); // neighbouring triangles mostly share a region: one lookup per run
      for (int r : this->M.region)
      {
        this->poll();
        if (it == count.end() || it->first != r)
        {
          it = count.try_emplace(r, 0).first;
        }
        ++it->second;
      }
      counted = true;
    }
    return count;
  };
  const auto around = [&](int t)
  {
    double angle = this->cornerAngle(t);
    for (int n : this->Nbr[t])
    {
      angle = n >= 0 ? std::min(angle, this->cornerAngle(n)) : angle;
    }
    return angle;
  };
  const double longest2 = std::pow(kDissolveLength * this->P.minimumEdgeLength, 2);
  // For longer triangles: twice the regions' (mesh) areas, and the regions' pieces.
  std::map<int, double> regionTwice;
  bool summed = false;
  const auto sumAreas = [&]()
  {
    regionTwice.clear();
    auto it = regionTwice.end();
    for (std::size_t t = 0; t < this->M.triangles.size(); ++t)
    {
      this->poll();
      const auto& tri = this->M.triangles[t];
      const int r = this->M.region[t];
      if (it == regionTwice.end() || it->first != r)
      {
        it = regionTwice.try_emplace(r, 0.0).first;
      }
      it->second += orient2d(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
    }
  };
  // The triangles with a sharp region corner (increasing), and whether a live region triangle
  // with a constrained edge is thinner than dissolveThinPieces() looks for: one sweep, on two
  // threads, made again when the mesh changed. Only such triangles can have a tip cut or be
  // given away (in the first sweep below, until a retag changes a neighbour's corners). A
  // thin piece has such a triangle (a piece is bounded by constrained edges), so with none
  // hasThinPiece() is false; the others' geometry is not read (at 1 M 0.03 s a sweep).
  std::vector<int> sharp;
  bool anyThin = false;
  const auto findSharp = [&]()
  {
    sharp.clear();
    std::vector<int> parts[2];
    bool thinPart[2] = { false, false };
    this->sweepTriangles(
      [&](int t, int part)
      {
        if (this->M.region[t] < 0 || !this->Live[t])
        {
          return;
        }
        if (this->cornerAngle(t) < this->P.minimumAngle)
        {
          parts[part].push_back(t);
        }
        if (!thinPart[part] &&
          (this->constrained(t, 0) || this->constrained(t, 1) || this->constrained(t, 2)))
        {
          thinPart[part] = this->thin(t);
        }
      },
      [&]
      {
        for (std::vector<int>& part : parts)
        {
          sharp.insert(sharp.end(), part.begin(), part.end());
          part.clear();
        }
      });
    anyThin = thinPart[0] || thinPart[1];
  };
  findSharp();
  // The retags of the visits below while the areas or the pieces are not made yet.
  struct Retag
  {
    int t, from, to, beside; // beside: the neighbour whose piece t joins (-1: none)
  };
  std::vector<Retag> journal;
  // make() on the mesh as it was before the journalled retags.
  const auto beforeRetags = [&](auto&& make)
  {
    for (auto it = journal.rbegin(); it != journal.rend(); ++it)
    {
      this->M.region[it->t] = it->from;
    }
    make();
    for (const Retag& r : journal)
    {
      this->M.region[r.t] = r.to;
    }
  };
  const auto areas = [&]() -> std::map<int, double>&
  {
    if (!summed)
    {
      beforeRetags(sumAreas);
      summed = true;
    }
    return regionTwice;
  };
  if (this->cutTips([&](int region) { return areas().at(region); }, sharp) > 0)
  {
    count.clear();
    counted = false;
    regionTwice.clear();
    summed = false;
    findSharp();
  }
  // The pieces (pieces()) only when a thin piece may be dissolved (hasThinPiece()) or a longer
  // triangle asks (at 1 M neither, mostly: 0.04 s a sweep); until then the retags are
  // journalled, so that the pieces are those of the mesh before them, followed by the retags,
  // as if made first.
  LargeVector<int> piece;
  bool havePieces = false;
  const auto makePieces = [&]()
  {
    if (havePieces)
    {
      return;
    }
    beforeRetags([&] { piece = this->pieces(); });
    for (const Retag& r : journal)
    {
      piece[r.t] = r.beside >= 0 ? piece[r.beside] : -1;
    }
    havePieces = true;
  };
  std::size_t total = 0;
  if (anyThin && this->hasThinPiece())
  {
    makePieces();
    total = this->dissolveThinPieces(piece, areas(), counts());
    if (total > 0)
    {
      findSharp();
    }
  }
  std::vector<int> next;
  const auto visit = [&](int t)
  {
    this->poll();
    const int old = this->M.region[t];
    if (old < 0 || !this->Live[t] || this->cornerAngle(t) >= this->P.minimumAngle)
    {
      return; // no sharp corner (most triangles)
    }
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    // A speck: no neighbour of its own region and an inradius below minimumEdgeLength, or
    // one such neighbour and an inradius below half of it (a sliver a retag left between
    // other regions, or hanging from its region into another); any length.
    int own = 0;
    for (int n : this->Nbr[t])
    {
      own += n >= 0 && this->M.region[n] == old;
    }
    const double twiceArea = orient2d(a, b, c), perimeter = norm(b - a) + norm(c - b) + norm(a - c);
    const bool speck = (own == 0 && twiceArea < this->P.minimumEdgeLength * perimeter) ||
      (own == 1 && twiceArea < 0.5 * this->P.minimumEdgeLength * perimeter);
    const bool longer = !speck && std::max({ norm2(b - a), norm2(c - b), norm2(a - c) }) > longest2;
    if (counts()[old] <= 1 || (longer && !(twiceArea <= kDeviationFraction * areas()[old])) ||
      (!speck && this->meshSpike(t)))
    {
      return;
    }
    if (longer)
    {
      makePieces(); // (before the trial retags below)
    }
    // (A region beside it is preferred to the exterior whenever one raises the angle: the
    // mesh's outer border stays where it is; a wedge's tip at a section's side given to the
    // exterior left a notch in it, m110 of random_sections.py 100 112.)
    const double before = around(t) + 1e-9;
    double best = before, bestOutside = before;
    int bestRegion = old, bestBeside = -1;
    for (int k = 0; k < 3; ++k)
    {
      const int n = this->Nbr[t][k];
      if ((n < 0 && !speck) || (n >= 0 && (this->M.region[n] == old || !this->Live[n])))
      {
        continue; // the mesh's outer border: nothing beyond (but a speck goes there)
      }
      const int r = n >= 0 ? this->M.region[n] : -1;
      this->M.region[t] = r;
      // Its new boundary edges join vertices on curves; a longer one joins no two pieces of
      // region r (a wedge's tip between two of them, in a section cut by faults).
      bool keepsCurves = true;
      for (int j = 0; j < 3 && keepsCurves; ++j)
      {
        const int m = this->Nbr[t][j];
        keepsCurves = (m >= 0 ? this->M.region[m] : -1) == r ||
          (this->P.onCurve(this->X(tri[j])) && this->P.onCurve(this->X(tri[(j + 1) % 3])));
        keepsCurves = keepsCurves &&
          !(longer && r >= 0 && m >= 0 && this->M.region[m] == r && piece[m] != piece[n]);
      }
      const double angle = keepsCurves ? around(t) : -1.0;
      this->M.region[t] = old;
      if (r < 0 && angle > bestOutside)
      {
        bestOutside = angle;
      }
      else if (r >= 0 && angle > best)
      {
        best = angle;
        bestRegion = r;
        bestBeside = n;
      }
    }
    if (bestRegion == old && bestOutside > before)
    {
      bestRegion = -1;
      bestBeside = -1;
    }
    if (bestRegion != old)
    {
      if (havePieces)
      {
        piece[t] = bestBeside >= 0 ? piece[bestBeside] : -1;
      }
      if (!havePieces || !summed)
      {
        journal.push_back({ t, old, bestRegion, bestBeside });
      }
      --counts()[old];
      ++counts()[bestRegion];
      this->M.region[t] = bestRegion;
      this->Unsettled.push_back(t); // (its edges' constraints changed: the flips below)
      ++total;
      next.push_back(t); // it may have a sharp corner in its new region
      this->appendNeighbours(t, next);
    }
  };
  // The first sweep visits every triangle in order; those with no sharp region corner (sharp)
  // are skipped unless a retag before them in the sweep changed a corner (a
  // neighbour's). The later sweeps visit the retagged triangles and their neighbours.
  this->report(); // (the tips and the pieces: up to 0.05 s at 1 M)
  std::vector<int> todo = std::move(sharp);
  std::priority_queue<int, std::vector<int>, std::greater<int>> later; // (the first sweep)
  for (int sweep = 0; sweep < kDissolveSweeps && !todo.empty(); ++sweep)
  {
    next.clear();
    std::size_t i = 0;
    while (i < todo.size() || !later.empty())
    {
      const int t =
        later.empty() || (i < todo.size() && todo[i] < later.top()) ? todo[i] : later.top();
      for (; i < todo.size() && todo[i] == t; ++i)
      {
      }
      for (; !later.empty() && later.top() == t; later.pop())
      {
      }
      const std::size_t retagged = next.size();
      visit(t);
      this->poll();
      for (std::size_t k = retagged; sweep == 0 && k < next.size(); ++k)
      {
        if (next[k] > t)
        {
          later.push(next[k]);
        }
      }
    }
    sortUnique(next);
    todo.swap(next);
  }
  this->report(); // (the visits: up to 0.05 s at 1 M)
  if (total > 0)
  {
    this->flipToDelaunayNear({}); // (the retags are recorded, as in recoverCurves())
  }
  return total;
}

// A piece of a region (triangles joined across unconstrained edges) thinner than half
// minimumEdgeLength everywhere (every triangle's inradius below a quarter of it) whose area is
// at most kDeviationFraction of its region's goes whole to the neighbouring region it shares
// the longest boundary with (a sliver of a layer cut off by a fault, thinner than the finest
// triangles: a strip of flat triangles, which no insertion can mend; the collapses of 6 then
// take the vertices left inside its new region). Not within the reach of a corner of its
// region to keep (step 7: before it ran, or when it kept the corner). Returns the triangles
// retagged; `piece`, `regionTwice` and `count` follow.
std::size_t Refiner::dissolveThinPieces(LargeVector<int>& piece,
  std::map<int, double>& regionTwice,
  std::map<int, std::size_t>& count)
{
  // Per piece (ids from 1): thin so far, twice its area; then the thin ones' triangles.
  const int pieces = piece.empty() ? 0 : *std::max_element(piece.begin(), piece.end()) + 1;
  std::vector<std::uint8_t> thinPiece(static_cast<std::size_t>(pieces), 1);
  std::vector<double> pieceTwice(static_cast<std::size_t>(pieces), 0.0);
  for (std::size_t t = 0; t < this->M.triangles.size(); ++t)
  {
    this->poll();
    const auto& tri = this->M.triangles[t];
    if (this->M.region[t] < 0)
    {
      continue;
    }
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    pieceTwice[piece[t]] += orient2d(a, b, c);
    thinPiece[piece[t]] &= this->thin(static_cast<int>(t));
  }
  std::map<int, std::vector<int>> members; // thin piece -> triangles
  for (std::size_t t = 0; t < this->M.triangles.size(); ++t)
  {
    this->poll();
    if (this->M.region[t] >= 0 && thinPiece[piece[t]])
    {
      members[piece[t]].push_back(static_cast<int>(t));
    }
  }
  std::size_t total = 0;
  for (const auto& [id, tris] : members)
  {
    const int old = this->M.region[tris.front()];
    if (!(pieceTwice[id] <= kDeviationFraction * regionTwice[old]) || count[old] <= tris.size())
    {
      continue;
    }
    bool nearKept = false; // (a corner to keep: its thin tip is what step 7 rebuilds)
    for (const SharpCorner& c : this->P.keptCorners)
    {
      bool kept = !this->KeepRan; // before step 7 every corner may be kept, after it those kept
      for (const Wedge& w : this->Kept)
      {
        kept = kept || (w.region == c.region && w.apex == c.apex);
      }
      const double reach = std::max(polylineLength(c.first), polylineLength(c.second));
      for (std::size_t i = 0; i < tris.size() && kept && c.region == old && !nearKept; ++i)
      {
        nearKept = norm2(this->X(this->M.triangles[tris[i]][0]) - c.apex) <= reach * reach;
      }
    }
    if (nearKept)
    {
      continue;
    }
    std::map<int, double> shared; // neighbouring region -> boundary length with it
    for (int t : tris)
    {
      const auto& tri = this->M.triangles[t];
      for (int k = 0; k < 3; ++k)
      {
        const int n = this->Nbr[t][k];
        if (n >= 0 && this->M.region[n] >= 0 && this->M.region[n] != old && this->Live[n])
        {
          shared[this->M.region[n]] += norm(this->X(tri[(k + 1) % 3]) - this->X(tri[k]));
        }
      }
    }
    if (shared.empty())
    {
      continue;
    }
    const int to = std::max_element(shared.begin(),
      shared.end(),
      [](const auto& x, const auto& y) {
        return x.second < y.second;
      })->first;
    for (int t : tris)
    {
      this->M.region[t] = to;
      this->Unsettled.push_back(t); // (as in dissolveCorners())
    }
    regionTwice[old] -= pieceTwice[id];
    regionTwice[to] += pieceTwice[id];
    count[old] -= tris.size();
    count[to] += tris.size();
    total += tris.size();
  }
  if (total > 0)
  {
    piece = this->pieces();
  }
  return total;
}

std::size_t Refiner::cutTips(const std::function<double(int)>& regionTwice,
  const std::vector<int>& sharp)
{
  const double finest = this->P.minimumEdgeLength;
  const double longest2 = std::pow(kDissolveLength * finest, 2);
  std::size_t cuts = 0;
  std::vector<int> created;
  const std::size_t nt = this->M.triangles.size();
  std::size_t next = 0; // in sharp
  for (std::size_t i = 0; i < nt && this->Inserted + 2 <= this->Budget; ++i)
  {
    if (cuts == 0 && this->M.triangles.size() == nt)
    {
      // (Nothing changed yet: the next triangle with a sharp region corner.)
      for (; next < sharp.size() && static_cast<std::size_t>(sharp[next]) < i; ++next)
      {
      }
      if (next == sharp.size())
      {
        break;
      }
      i = static_cast<std::size_t>(sharp[next]);
    }
    this->poll();
    const int t = static_cast<int>(i);
    const int region = this->M.region[t];
    const std::array<int, 3> tri = this->M.triangles[t];
    const Vec2 p[3] = { this->X(tri[0]), this->X(tri[1]), this->X(tri[2]) };
    if (region < 0 || !this->Live[t] || this->cornerAngle(t) >= this->P.minimumAngle ||
      (!this->EveryTip &&
        (std::max({ norm2(p[1] - p[0]), norm2(p[2] - p[1]), norm2(p[0] - p[2]) }) <= longest2 ||
          orient2d(p[0], p[1], p[2]) <= kDeviationFraction * regionTwice(region))) ||
      this->meshSpike(t))
    {
      continue; // 2c gives it away whole, or it has no sharp corner
    }
    const auto angles = triangleAngles(p[0], p[1], p[2]);
    const int k = this->sharpestRegionCorner(t, angles);
    // Its edges are split at distance d from it, on their curves: the far edge of the tip,
    // 2 d sin(angle / 2), is kTipCut finest edges long (long enough for the refinement), or
    // kEveryTipCut in the recovery's last pass.
    const Vec2 v = p[k], a = p[(k + 1) % 3], b = p[(k + 2) % 3];
    const double d = (this->EveryTip ? kEveryTipCut : kTipCut) * finest /
      (2.0 * std::sin(0.5 * angles[k] * kPi / 180.0));
    const double la = norm(a - v), lb = norm(b - v);
    if (!(d < 0.45 * std::min(la, lb)) ||
      !(d * d * std::sin(angles[k] * kPi / 180.0) <= kDeviationFraction * regionTwice(region)))
    {
      continue; // the whole triangle is hardly larger than the tip, or the tip is no small share
    }
    const int na = this->Nbr[t][k], nb = this->Nbr[t][(k + 2) % 3];
    Vec2 wa, wb;
    if (!this->Split(
          v, v + (2.0 * d / la) * (a - v), region, na >= 0 ? this->M.region[na] : -1, wa) ||
      !this->Split(
        v + (2.0 * d / lb) * (b - v), v, region, nb >= 0 ? this->M.region[nb] : -1, wb) ||
      !(norm(wa - v) > 0.5 * d && norm(wa - v) < 1.5 * d && norm(wb - v) > 0.5 * d &&
        norm(wb - v) < 1.5 * d))
    {
      continue;
    }
    // t = (v, a, b): split (v, a) at wa, then (b, v) of t = (v, wa, b) at wb.
    if (!this->splitEdge(t, k, wa, created))
    {
      continue;
    }
    ++cuts;
    ++this->Inserted;
    const int j = static_cast<int>(
      std::find(this->M.triangles[t].begin(), this->M.triangles[t].end(), tri[(k + 2) % 3]) -
      this->M.triangles[t].begin());
    if (j < 3 && this->M.triangles[t][(j + 1) % 3] == tri[k] && this->constrained(t, j) &&
      this->splitEdge(t, j, wb, created))
    {
      ++cuts;
      ++this->Inserted;
    }
  }
  this->TipVertices += cuts;
  return cuts;
}

// Cosine of the smallest angle of the region triangles first..last (2 when one is not
// counter-clockwise), and in `largest` the cosine of their largest angle.
double Refiner::starCosine(const int* first, const int* last, double& largest) const
{
  double worst = -1.0;
  largest = 1.0;
  for (const int* it = first; it != last; ++it)
  {
    const auto& tri = this->M.triangles[*it];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
    if (!turnsLeft(a, b, c))
    {
      return 2.0;
    }
    if (this->M.region[*it] >= 0)
    {
      worst = std::max(worst, this->smallestAngleCosine(tri));
      largest = std::min(largest, largestAngleCosine(a, b, c));
    }
  }
  return worst;
}

std::size_t Refiner::smoothBad()
{
  std::size_t moves = 0;
  // The bad triangles: found in a sweep first, then among those and the triangles a round
  // changed (moved corners, flips), whose flips only are looked for (flipToDelaunayNear()).
  std::vector<int> bad = this->badTriangles(), changed, flipped;
  // (With none, nothing moves: no stars are made, at 1 M a sweep of 0.007-0.009 s.)
  for (int round = 0; round < kSmoothingRounds && !bad.empty(); ++round)
  {
    std::vector<int> todo;
    changed.clear();
    for (const int t : bad)
    {
      todo.insert(todo.end(), this->M.triangles[t].begin(), this->M.triangles[t].end());
    }
    sortUnique(todo);
    std::vector<char> inTodo(this->M.points.size(), 0);
    for (int v : todo)
    {
      inTodo[v] = 1;
    }
    const PointStars stars =
      pointStars(this->M.points.size(), this->M.triangles, &inTodo, [this] { this->report(); });
    std::size_t moved = 0;
    std::vector<int> link, ends, regions;
    std::vector<Vec2> candidates;
    for (int v : todo)
    {
      this->poll();
      const int* first = stars.items.data() + stars.start[v];
      const int* last = stars.items.data() + stars.start[v + 1];
      link.clear();
      ends.clear(); // the other ends of its boundary edges
      regions.clear();
      bool live = first != last;
      for (const int* it = first; it != last && live; ++it)
      {
        const int t = *it;
        const auto& tri = this->M.triangles[t];
        const int i = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
        live = this->Live[t];
        link.push_back(tri[(i + 1) % 3]);
        link.push_back(tri[(i + 2) % 3]);
        regions.push_back(this->M.region[t]);
        for (int k : { i, (i + 2) % 3 })
        {
          if (this->constrained(t, k))
          {
            ends.push_back(k == i ? tri[(i + 1) % 3] : tri[(i + 2) % 3]);
            if (this->Nbr[t][k] < 0)
            {
              regions.push_back(-1); // the mesh's outer border: the exterior beyond
            }
          }
        }
      }
      for (std::vector<int>* list : { &link, &ends, &regions })
      {
        sortUnique(*list);
      }
      const bool free = ends.empty() && regions.size() == 1 && regions[0] >= 0;
      const bool boundary =
        ends.size() == 2 && regions.size() == 2 && this->P.curveSlide && this->P.curveDistance;
      if (!live || (!free && !boundary))
      {
        continue;
      }
      const Vec2 p = this->M.points[v];
      Vec2 centre;
      for (int u : link)
      {
        centre = centre + this->X(u);
      }
      centre = (1.0 / static_cast<double>(link.size())) * centre;
      const auto deviation = [&]()
      {
        double worst = 0.0;
        for (int e : ends)
        {
          worst = std::max(worst,
            this->P.curveDistance(0.5 * (this->X(e) + this->X(v)), HUGE_VAL) /
              norm(this->X(e) - this->X(v)));
        }
        return worst;
      };
      const double allowed = boundary ? std::max(deviation(), kSlideDeviation) : 0.0;
      candidates.clear();
      for (double s : { 1.0, 0.5, 0.25 })
      {
        if (free)
        {
          candidates.push_back(p + s * (centre - p));
          continue;
        }
        const Vec2 middle = 0.5 * (this->X(ends[0]) + this->X(ends[1]));
        for (Vec2 toward : { p + s * (middle - p), p + s * (centre - p) })
        {
          Vec2 at;
          if (this->P.curveSlide(p, toward, regions[0], regions[1], at))
          {
            candidates.push_back(at);
          }
        }
      }
      double largest = 1.0;
      double best = this->starCosine(first, last, largest) - 1e-12;
      const double largestAllowed = std::min(largest, kSmoothingLargestCosine);
      Vec2 bestAt = p;
      for (Vec2 q : candidates)
      {
        this->M.points[v] = q;
        const double c = this->starCosine(first, last, largest);
        if (c < best && largest >= largestAllowed - 1e-12 &&
          (!boundary || deviation() <= allowed + 1e-12))
        {
          best = c;
          bestAt = q;
        }
      }
      this->M.points[v] = bestAt;
      if (!(bestAt == p))
      {
        ++moved;
        changed.insert(changed.end(), first, last);
      }
    }
    moves += moved;
    if (moved == 0)
    {
      break;
    }
    flipped.clear();
    this->FlipLog = &flipped;
    if (round == 0)
    {
      this->flipToDelaunay(); // (no knowing what the caller left unflipped)
    }
    else
    {
      this->flipToDelaunayNear(changed);
    }
    this->FlipLog = nullptr;
    bad.insert(bad.end(), changed.begin(), changed.end());
    bad.insert(bad.end(), flipped.begin(), flipped.end());
    sortUnique(bad);
    bad.erase(
      std::remove_if(bad.begin(), bad.end(), [this](int t) { return !this->bad(t); }), bad.end());
  }
  return moves;
}

void Refiner::adopt(const Refiner& prepared)
{
  // (With room for the run's new triangles, as the mesh's copies have: roomyCopy().)
  withRoom(this->Nbr, prepared.Nbr.size()) = prepared.Nbr;
  withRoom(this->Live, prepared.Live.size()) = prepared.Live;
  this->Kept = prepared.Kept;
  this->KeepRan = prepared.KeepRan;
  this->Unsettled = prepared.Unsettled; // (its mesh's edges the prepared refiner left so)
  this->takeShortEdges(prepared);
  withRoom(this->Saved, this->M.triangles.size()).assign(this->M.triangles.size(), 0);
}

void Refiner::findShortEdges()
{
  this->Shorts.clear();
  this->ShortCells.clear();
  const double h = this->P.minimumEdgeLength;
  if (!(h > 0.0))
  {
    return;
  }
  // The short region boundary edges (t, k) in order, on two threads; then, in that order, those
  // between two stop points (the callback's queries are the caller's: one thread).
  std::vector<std::array<int, 2>> edges;
  gatherInOrder<std::array<int, 2>>(
    this->M.triangles.size(),
    kTwoThreadBlock,
    kTwoThreadItems,
    [&](std::size_t i, std::vector<std::array<int, 2>>& found)
    {
      const int t = static_cast<int>(i);
      if (!this->Live[t] || this->M.region[t] < 0)
      {
        return;
      }
      const auto& tri = this->M.triangles[t];
      for (int k = 0; k < 3; ++k)
      {
        const int u = this->Nbr[t][k];
        // (Each edge once: from the triangle of the smaller index when both are regions'.)
        if (this->constrained(t, k) &&
          !(u >= 0 && u < t && this->M.region[u] >= 0 && this->Live[u]) &&
          norm(this->X(tri[(k + 1) % 3]) - this->X(tri[k])) < kShortFeature * h)
        {
          found.push_back({ t, k });
        }
      }
    },
    [&](const std::array<int, 2>& e) { edges.push_back(e); },
    [&] { this->report(); });
  for (const auto& [t, k] : edges)
  {
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[k]), b = this->X(tri[(k + 1) % 3]);
    if (this->P.stopPoint && !(this->P.stopPoint(a) && this->P.stopPoint(b)))
    {
      continue;
    }
    const Vec2 middle = 0.5 * (a + b);
    this
      ->ShortCells[shortCell(static_cast<std::int64_t>(std::floor(middle.x / h)),
        static_cast<std::int64_t>(std::floor(middle.y / h)))]
      .push_back(static_cast<int>(this->Shorts.size()));
    this->Shorts.push_back({ middle, norm(b - a) });
  }
}

// Step 3's floor at x: the shortest edge a bad triangle there may have and still be refined,
// half the length a boundary edge there may have and still be split.
double Refiner::floorAt(Vec2 x) const
{
  const double h = this->P.minimumEdgeLength;
  double floor = kFloor * h;
  if (this->Shorts.empty())
  {
    return floor;
  }
  const std::int64_t ci = static_cast<std::int64_t>(std::floor(x.x / h));
  const std::int64_t cj = static_cast<std::int64_t>(std::floor(x.y / h));
  for (std::int64_t i = ci - 1; i <= ci + 1; ++i)
  {
    for (std::int64_t j = cj - 1; j <= cj + 1; ++j)
    {
      const auto found = this->ShortCells.find(shortCell(i, j));
      for (std::size_t e = 0; found != this->ShortCells.end() && e < found->second.size(); ++e)
      {
        const ShortEdge& s = this->Shorts[found->second[e]];
        if (norm2(s.middle - x) <= h * h)
        {
          floor = std::min(floor, std::max(kFloor * s.length, kLowestFloor * h));
        }
      }
    }
  }
  return floor;
}

RefinementResult Refiner::run(const std::vector<int>* bad)
{
  if (this->P.minimumAngle > 0.0)
  {
    const std::vector<int> found = bad ? std::vector<int>() : this->badTriangles();
    for (const int t : bad ? *bad : found)
    {
      this->Queue.push_back(t);
    }
  }
  std::vector<int> created;
  this->report(); // (what came before the run, a copy of the mesh and its neighbours, reported)
  while (!this->Queue.empty())
  {
    this->poll();
    const int t = this->Queue.front();
    this->Queue.pop_front();
    if (!this->bad(t))
    {
      continue;
    }
    if (this->Inserted >= this->Budget)
    {
      this->R.budgetReached = true;
      break;
    }
    const int corner = this->smallestCorner(t);
    const auto& tri = this->M.triangles[t];
    if (this->constrained(t, corner) && this->constrained(t, (corner + 2) % 3))
    {
      // A corner of the region: no interior point widens it. A spike of the mesh's own has
      // its longer side split on its curve (toward the model's wider corner).
      const int before = (corner + 2) % 3;
      const int side = norm2(this->X(tri[(corner + 1) % 3]) - this->X(tri[corner])) >=
          norm2(this->X(tri[before]) - this->X(tri[corner]))
        ? corner
        : before;
      if (this->meshSpike(t) && this->splitBoundary(t, side))
      {
        this->Queue.push_back(t);
      }
      continue;
    }
    const Vec2 p = this->X(tri[(corner + 1) % 3]), q = this->X(tri[(corner + 2) % 3]);
    const double l = norm(q - p);
    if (l < kFloor * this->P.minimumEdgeLength && l < this->floorAt(0.5 * (p + q)))
    {
      continue;
    }
    const Vec2 cc = circumcenter(this->X(tri[0]), this->X(tri[1]), this->X(tri[2]));
    const Vec2 m = 0.5 * (p + q);
    const double dc = norm(cc - m), doff = this->OffDistance * l;
    const Vec2 w = dc > doff ? m + (doff / dc) * (cc - m) : cc;
    if (!std::isfinite(w.x) || !std::isfinite(w.y))
    {
      continue; // no area by rounding (a curve point within rounding of an edge): left bad
    }
    int ct = -1, ck = -1;
    const int s = this->locate(t, w, ct, ck);
    if (s < 0)
    {
      if (ct >= 0 && this->splitBoundary(ct, ck))
      {
        this->Queue.push_back(t);
      }
      continue;
    }
    if (this->encroached(s, w, ct, ck))
    {
      if (this->splitBoundary(ct, ck))
      {
        this->Queue.push_back(t);
      }
      continue;
    }
    if (!this->Kept.empty() && this->inKept(s))
    {
      continue; // in a kept corner's wedge: left as step 7 made it
    }
    // On an edge of s (up to rounding): split that edge, else split s.
    const auto& ts = this->M.triangles[s];
    int onEdge = -1;
    for (int k = 0; k < 3; ++k)
    {
      const Vec2 a = this->X(ts[k]), b = this->X(ts[(k + 1) % 3]);
      if (std::fabs(orient2d(a, b, w)) <= 1e-9 * norm2(b - a))
      {
        onEdge = k;
      }
    }
    this->begin();
    if (onEdge >= 0)
    {
      if (this->constrained(s, onEdge) || !this->splitEdge(s, onEdge, w, created))
      {
        this->Recording = false;
        continue;
      }
    }
    else
    {
      this->insertIn(s, w, created);
    }
    if (!this->commit())
    {
      continue; // it would have lowered the smallest angle there: t is left as it is
    }
    ++this->R.interiorVertices;
    ++this->Inserted;
    this->queueBad(this->Changed); // t itself is gone: w lay inside its circumcircle
  }
  this->AngleAfterRun = this->countBad(this->R, &this->BadAfterRun);
  this->Ran = true;
  return this->R;
}

double Refiner::countBad(RefinementResult& result, std::vector<int>* found) const
{
  result.badTrianglesLeft = result.badTrianglesAtCorners = 0;
  result.badCentroids.clear();
  // The bad triangles (bad()) and the largest cosine, in one sweep. (Each part's on a cache
  // line of its own: written at every triangle, a line shared by the two threads took 3 to 4
  // times as long, 0.034-0.057 s a sweep at 1 M.)
  std::vector<int> list;
  std::vector<int>& bad = found ? *found : list;
  bad.clear();
  struct alignas(64) Part
  {
    std::vector<int> bad;
    double largest = -1.0;
  };
  Part parts[2];
  double worst = -1.0;
  this->sweepTriangles(
    [&](int t, int which)
    {
      if (this->M.region[t] >= 0 && this->Live[t] && (this->Kept.empty() || !this->inKept(t)))
      {
        Part& part = parts[which];
        const double c = this->smallestAngleCosine(this->M.triangles[t]);
        part.largest = std::max(part.largest, c);
        if (c > this->CosBad)
        {
          part.bad.push_back(t);
        }
      }
    },
    [&]
    {
      for (Part& part : parts)
      {
        bad.insert(bad.end(), part.bad.begin(), part.bad.end());
        part.bad.clear();
        worst = std::max(worst, part.largest);
      }
    });
  for (const int t : bad)
  {
    ++result.badTrianglesLeft;
    const int corner = this->smallestCorner(t);
    result.badTrianglesAtCorners +=
      this->constrained(t, corner) && this->constrained(t, (corner + 2) % 3);
    const auto& tri = this->M.triangles[t];
    result.badCentroids.push_back(
      (1.0 / 3.0) * (this->X(tri[0]) + this->X(tri[1]) + this->X(tri[2])));
  }
  return std::acos(std::clamp(worst, -1.0, 1.0)) * 180.0 / kPi;
}
// Makes the straight segment from vertex v (of triangle t) to the point e a chain of mesh edges
// (step 7): every edge it crosses is split where it crosses it, and e is inserted unless a
// vertex lies within tol of it. Returns the vertex at e (t then holds it), or -1 (a frozen
// triangle, a refused split, a walk too long). The vertices passed after v are appended to
// `path`.
int Refiner::conform(int v, int& t, Vec2 e, double tol, std::vector<int>& path)
{
  const double tol2 = tol * tol;
  for (int step = 0; step < kMaxWalk; ++step)
  {
    const Vec2 s = this->X(v);
    if (norm2(e - s) <= tol2)
    {
      return v;
    }
    int kv = -1;
    const int found = this->around(v, t, e, kv);
    if (found < 0 || !this->Live[found])
    {
      return -1;
    }
    const auto tri = this->M.triangles[found];
    const int ia = tri[(kv + 1) % 3], ib = tri[(kv + 2) % 3];
    const Vec2 a = this->X(ia), b = this->X(ib);
    const double lab = norm(b - a);
    const double beyond = -orient2d(a, b, e) / lab; // e's distance beyond the edge ab
    int edge = -1;                                  // the edge of `found` to split, or inside
    Vec2 w = e;
    if (beyond <= tol)
    {
      // e lies in the triangle: at a vertex, on an edge or inside.
      if (norm2(e - a) <= tol2 || norm2(e - b) <= tol2)
      {
        v = norm2(e - a) <= tol2 ? ia : ib;
        t = found;
        path.push_back(v);
        continue;
      }
      edge = this->nearEdge(tri, e, tol);
    }
    else
    {
      // The segment leaves through ab, at w.
      const double da = orient2d(s, e, a), db = orient2d(s, e, b);
      const double lambda = da - db != 0.0 ? da / (da - db) : 0.5;
      w = a + lambda * (b - a);
      // The side passes through a vertex on the curves this close to the crossing (up to the
      // curves' tolerance): a split there would leave a nearly flat triangle.
      const double snap2 = std::max(tol2, kSnap * kSnap * lab * lab);
      const bool nearA = norm2(w - a) <= tol2 || (norm2(w - a) <= snap2 && this->P.onCurve(a));
      const bool nearB = norm2(w - b) <= tol2 || (norm2(w - b) <= snap2 && this->P.onCurve(b));
      if (lambda <= 0.0 || lambda >= 1.0 || nearA || nearB)
      {
        v = lambda <= 0.0 || (nearA && !nearB) || (nearA && norm2(w - a) <= norm2(w - b)) ? ia : ib;
        t = found;
        path.push_back(v);
        continue;
      }
      edge = (kv + 1) % 3;
    }
    v = this->newVertex(found, edge, w, false, t);
    if (v < 0)
    {
      return -1;
    }
    path.push_back(v);
  }
  return -1;
}

// The edge of tri that the point e (inside it, on a kept corner's side) is so close to that
// a vertex at e would leave a nearly flat triangle on it (within tol, or kSnap of its length):
// that edge is split at e instead. -1 when none.
int Refiner::nearEdge(const std::array<int, 3>& tri, Vec2 e, double tol) const
{
  int edge = -1;
  double closest = HUGE_VAL;
  for (int k = 0; k < 3; ++k)
  {
    const Vec2 p = this->X(tri[k]), q = this->X(tri[(k + 1) % 3]);
    const double l = norm(q - p), d = std::fabs(orient2d(p, q, e)) / l,
                 u = dot(e - p, q - p) / (l * l);
    if (d <= std::max(tol, kSnap * l) && u > kSnap && u < 1.0 - kSnap && d < closest)
    {
      closest = d;
      edge = k;
    }
  }
  return edge;
}

// The triangle holding the point e, walked to in a straight line from vertex v (of triangle
// t) across any edge; -1 when the walk leaves the mesh or does not end.
int Refiner::walkTo(int v, int t, Vec2 e) const
{
  const Vec2 s = this->X(v);
  int kv = -1;
  int cur = this->around(v, t, e, kv);
  if (cur < 0)
  {
    return -1;
  }
  int k = (kv + 1) % 3; // the edge of cur the segment s -> e leaves through, if it leaves
  for (int step = 0; step < kMaxWalk && cur >= 0; ++step)
  {
    const auto& tri = this->M.triangles[cur];
    const Vec2 a = this->X(tri[k]), b = this->X(tri[(k + 1) % 3]);
    if (orient2d(a, b, e) >= 0.0)
    {
      return cur; // e on this side of the edge the segment leaves through: inside
    }
    const int next = this->Nbr[cur][k];
    if (next < 0)
    {
      return -1;
    }
    // In next = (b, a, c): the segment leaves through (a, c) or (c, b).
    const auto& nt = this->M.triangles[next];
    int j = 0;
    while (nt[j] != tri[(k + 1) % 3])
    {
      ++j;
    }
    const Vec2 c = this->X(nt[(j + 2) % 3]);
    k = orient2d(s, e, c) > 0.0 ? (j + 1) % 3 : (j + 2) % 3;
    cur = next;
  }
  return -1;
}

// The triangle around v (starting from t, which holds v, or any triangle when it does not)
// whose angle at v holds the direction to e, with v's corner in kv; -1 when none (v on the
// mesh's border, e outside).
int Refiner::around(int v, int t, Vec2 e, int& kv) const
{
  t = this->holding(v, t);
  if (t < 0)
  {
    return -1;
  }
  const Vec2 s = this->X(v);
  for (int way = 0; way < 2; ++way)
  {
    int cur = t;
    for (int turn = 0; turn < kMaxWalk && cur >= 0; ++turn)
    {
      const auto& tri = this->M.triangles[cur];
      const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      if (orient2d(s, this->X(tri[(k + 1) % 3]), e) >= 0.0 &&
        orient2d(s, this->X(tri[(k + 2) % 3]), e) <= 0.0)
      {
        kv = k;
        this->LastAround = cur;
        return cur;
      }
      cur = this->Nbr[cur][way == 0 ? k : (k + 2) % 3];
      if (cur == t)
      {
        break;
      }
    }
  }
  return -1;
}

// A triangle holding vertex v: t when it does, else one found from t (or, when t is -1, from
// around()'s last triangle) across at most kNearSearch edges, else the first in the mesh; -1
// when none. (Step 7's walks start from vertices just made or passed, near the last one.)
int Refiner::holding(int v, int t) const
{
  const auto holds = [&](int x)
  {
    const auto& tri = this->M.triangles[x];
    return hasVertex(tri, v);
  };
  if (t >= 0 && holds(t))
  {
    return t;
  }
  const int start = t >= 0 ? t : this->LastAround;
  if (start >= 0 && static_cast<std::size_t>(start) < this->M.triangles.size())
  {
    std::vector<int> seen{ start };
    for (std::size_t i = 0; i < seen.size() && seen.size() < kNearSearch; ++i)
    {
      if (holds(seen[i]) && this->Live[seen[i]])
      {
        return seen[i];
      }
      for (int n : this->Nbr[seen[i]])
      {
        if (n >= 0 && std::find(seen.begin(), seen.end(), n) == seen.end())
        {
          seen.push_back(n);
        }
      }
    }
  }
  for (std::size_t x = 0; x < this->M.triangles.size(); ++x)
  {
    if (holds(static_cast<int>(x)))
    {
      return static_cast<int>(x);
    }
  }
  return -1;
}

// The vertex at e (a point of a kept corner's side, reached from vertex v of triangle t): a
// vertex within tol of it, or one inserted there (on an edge within tol of it, at its
// projection, with the flips of 2). -1 when the walk fails.
int Refiner::vertexAt(int v, int& t, Vec2 e, double tol)
{
  const int s = this->walkTo(v, t, e);
  if (s < 0 || !this->Live[s])
  {
    return -1;
  }
  const auto tri = this->M.triangles[s];
  for (int k = 0; k < 3; ++k)
  {
    if (norm2(this->X(tri[k]) - e) <= tol * tol)
    {
      t = s;
      return tri[k];
    }
  }
  return this->newVertex(s, this->nearEdge(tri, e, tol), e, true, t);
}

// A new vertex at w in triangle s: its edge `edge` split at w, or, with no such edge (-1), or
// when the split is refused and `orInside` is set, s split at w, when w lies strictly inside
// it. Returns the vertex, with t a triangle around it, or -1.
int Refiner::newVertex(int s, int edge, Vec2 w, bool orInside, int& t)
{
  std::vector<int> created;
  if (edge < 0 || !this->splitEdge(s, edge, w, created))
  {
    const auto& tri = this->M.triangles[s];
    if ((edge >= 0 && !orInside) ||
      !(orient2d(this->X(tri[0]), this->X(tri[1]), w) > 0.0 &&
        orient2d(this->X(tri[1]), this->X(tri[2]), w) > 0.0 &&
        orient2d(this->X(tri[2]), this->X(tri[0]), w) > 0.0))
    {
      return -1;
    }
    this->insertIn(s, w, created);
  }
  const int wi = static_cast<int>(this->M.points.size()) - 1;
  t = -1;
  for (int c : created)
  {
    const auto& ct = this->M.triangles[c];
    t = hasVertex(ct, wi) ? c : t;
  }
  return wi;
}

// Makes the segment between vertices p and q (of a kept corner's side) a mesh edge: edges
// crossing it are flipped while that helps (Sloan), a vertex on it splits it in two, and what
// flips cannot clear is conformed (conform()). Appends the vertices after p to `path`.
bool Refiner::recoverEdge(int p, int q, double tol, std::vector<int>& path)
{
  std::vector<std::array<int, 2>> todo{ { p, q } };
  int t = -1;
  while (!todo.empty())
  {
    const auto [from, to] = todo.back();
    todo.pop_back();
    const Vec2 a0 = this->X(from), b0 = this->X(to);
    const double l = norm(b0 - a0);
    bool done = false;
    for (int attempt = 0; attempt < kRecoveryFlips && !done; ++attempt)
    {
      int kv = -1;
      int cur = this->around(from, t, b0, kv);
      if (cur < 0)
      {
        return false;
      }
      t = cur;
      auto tri = this->M.triangles[cur];
      if (tri[(kv + 1) % 3] == to || tri[(kv + 2) % 3] == to)
      {
        path.push_back(to);
        done = true;
        break;
      }
      // Along the crossing edges: flip the first that flips; stop at a vertex on the segment.
      int k = (kv + 1) % 3;
      bool flipped = false;
      int onSegment = -1;
      for (int step = 0; step < kMaxWalk && !flipped && onSegment < 0; ++step)
      {
        const int next = this->Nbr[cur][k];
        if (next < 0 || !this->Live[next])
        {
          return false;
        }
        const auto& nt = this->M.triangles[next];
        int j = 0;
        while (nt[j] != this->M.triangles[cur][(k + 1) % 3])
        {
          ++j;
        }
        const int c = nt[(j + 2) % 3];
        if (!this->constrained(cur, k) && this->flip(cur, k))
        {
          flipped = true;
          break;
        }
        if (c == to)
        {
          break;
        }
        if (std::fabs(orient2d(a0, b0, this->X(c))) <= tol * l)
        {
          onSegment = c;
          break;
        }
        k = orient2d(a0, b0, this->X(c)) > 0.0 ? (j + 1) % 3 : (j + 2) % 3;
        cur = next;
      }
      if (onSegment >= 0)
      {
        todo.push_back({ onSegment, to });
        todo.push_back({ from, onSegment });
        done = true;
      }
      else if (!flipped)
      {
        // Nothing flips: split what still crosses.
        const int v = this->conform(from, t, b0, tol, path);
        if (v != to)
        {
          return false;
        }
        done = true;
      }
    }
    if (!done)
    {
      const int v = this->conform(from, t, b0, tol, path);
      if (v != to)
      {
        return false;
      }
    }
  }
  return true;
}

std::size_t Refiner::keepCorners(std::vector<double>& radii,
  std::vector<std::vector<Vec2>>& outlines)
{
  const std::vector<SharpCorner>& corners = this->P.keptCorners;
  radii.assign(corners.size(), 0.0);
  outlines.assign(corners.size(), {});
  if (corners.empty() || !this->P.regionAt || !this->P.onCurve)
  {
    return 0;
  }
  std::size_t kept = 0;
  this->Keeping = true;
  this->KeepRan = true;
  for (std::size_t i = 0; i < corners.size(); ++i)
  {
    double radius2 = 0.0;
    std::vector<Vec2> outline;
    if (this->keepCorner(corners[i], radius2, outline))
    {
      radii[i] = std::sqrt(radius2);
      outlines[i] = outline;
      this->Kept.push_back(
        { corners[i].apex, corners[i].region, radius2, corners[i].angle, std::move(outline) });
      ++kept;
    }
  }
  this->Keeping = false;
  return kept;
}

// One corner of step 7 (see the top of this file): true when kept, with the squared radius its
// wedge reaches and its outline; false with everything undone.
bool Refiner::keepCorner(const SharpCorner& c,
  double& radius2,
  std::vector<Vec2>& outline,
  double cutWidth,
  const std::vector<int>* local)
{
  if (c.first.size() < 2 || c.second.size() < 2)
  {
    return false;
  }
  // The triangles looked at: all, or `local` and those the transaction changed or made (an
  // extension's: see extendWedges()).
  const bool cut = cutWidth > 0.0;
  const bool restore = !cut && local; // a corner's tip the mesh lost, rebuilt (not kept)
  std::vector<int> all = this->scope(local, false);
  const std::vector<Vec2>* sides[2] = { &c.first, &c.second };
  const double reach = std::max(polylineLength(c.first), polylineLength(c.second));
  // A vertex this close to a side is on it (the curves' vertices are within curveTolerance
  // of them; so are the chords between them, up to the chords' sag).
  const double tol = std::max(1e-7 * reach, 4.0 * this->P.curveTolerance);
  // The apex vertex (and a triangle around it), and the region's vertices on each side
  // nearest to the apex along it: where the region's wedge already is in the mesh.
  // (And the arcs of every vertex already on a side, which the new ones keep away from.)
  int apexV = -1, apexT = -1;
  int nearest[2] = { -1, -1 };
  bool reached = false; // a triangle of the region has the apex vertex
  double arc[2] = { HUGE_VAL, HUGE_VAL };
  std::vector<double> onSide[2];
  // An extension's region triangles count only in pieces of the region that reach beyond the
  // sides (the region's body): a piece left inside the wedge (triangles the compression gave
  // the region near the tip, cut off from the body by the neighbour's) is no part of it.
  const std::vector<int> body =
    cut ? this->regionBody(all, c.region, c.apex, reach) : std::vector<int>();
  // Each side's bounding box, widened: a vertex outside it lies on no segment of the side
  // (arcAlong() finds none), so its segments are not walked (with thousands of corners along
  // zigzag curves that walk made most of a run).
  Vec2 sideLo[2], sideHi[2];
  for (int s = 0; s < 2; ++s)
  {
    Box2 box;
    for (const Vec2& q : *sides[s])
    {
      box.add(q);
    }
    sideLo[s] = box.min - Vec2{ 2.0 * tol, 2.0 * tol };
    sideHi[s] = box.max + Vec2{ 2.0 * tol, 2.0 * tol };
  }
  ArcIndex arcs[2] = { ArcIndex(*sides[0]), ArcIndex(*sides[1]) };
  this->SideArcs.begin();
  for (std::size_t i = 0, n = local ? all.size() : this->M.triangles.size(); i < n; ++i)
  {
    this->poll();
    const std::size_t t = local ? static_cast<std::size_t>(all[i]) : i;
    if (!this->Live[t])
    {
      continue;
    }
    for (int v : this->M.triangles[t])
    {
      const double d2 = norm2(this->X(v) - c.apex);
      if (d2 <= tol * tol)
      {
        apexV = v;
        apexT = static_cast<int>(t);
        reached = reached || this->M.region[t] == c.region;
      }
      else if (d2 <= reach * reach)
      {
        // (Each vertex's arcs once: it is in about six of the triangles.)
        const std::array<double, 2>& arcsOfV = this->SideArcs.get(v,
          [&](std::array<double, 2>& values)
          {
            const Vec2 p = this->X(v);
            for (int s = 0; s < 2; ++s)
            {
              const bool inBox = p.x >= sideLo[s].x && p.x <= sideHi[s].x && p.y >= sideLo[s].y &&
                p.y <= sideHi[s].y;
              values[s] = inBox ? arcs[s].arc(p, tol) : -1.0;
            }
          });
        for (int s = 0; s < 2; ++s)
        {
          const double a = arcsOfV[s];
          if (a >= 0.0)
          {
            onSide[s].push_back(a);
          }
          if (a >= 0.0 && a < arc[s] && this->M.region[t] == c.region &&
            (!cut || std::binary_search(body.begin(), body.end(), static_cast<int>(t))))
          {
            arc[s] = a;
            nearest[s] = v;
          }
        }
      }
    }
  }
  if (nearest[0] < 0 || nearest[1] < 0 || (restore && reached))
  {
    return false;
  }
  // An extension starts where the wedge is cutWidth across (d0 from the apex),
  // and only where the region's triangles end farther from the apex than that on both sides;
  // a lost tip is rebuilt only where they end farther than where it is one finest edge wide,
  // plus a margin (nearer, what is lost is narrower than that).
  const double spacing = (restore ? kRestoredSpacing : kKeptSpacing) * this->P.minimumEdgeLength;
  // An extension's cut runs from d0 on one side to kWedgeSlant cutWidth nearer the apex (at
  // most d0 / 2) on the side where the region's triangles end nearer the apex (step 7').
  double from[2] = { 0.0, 0.0 }; // the distances from the apex where the new part begins
  if (cut || restore)
  {
    const double width = cut ? cutWidth : this->P.minimumEdgeLength;
    const double at = width / (2.0 * std::sin(0.5 * c.angle * kPi / 180.0));
    const double across = norm(pointAlong(c.first, at) - pointAlong(c.second, at));
    const double gap = (restore ? kRestoredMargin : 0.5) *
      std::max(kKeptSpacing * this->P.minimumEdgeLength, across);
    if (!(at + gap < std::min(arc[0], arc[1])) || !(across > 0.5 * width) ||
      !(across < 1.5 * width))
    {
      return false;
    }
    if (cut)
    {
      from[0] = from[1] = at;
      from[arc[0] <= arc[1] ? 0 : 1] -= std::min(kWedgeSlant * width, 0.5 * at);
    }
  }
  this->begin();
  if (!cut && apexV < 0)
  {
    // No vertex at the apex (a corner the mesh cut): one is inserted there, walked to
    // from the region's nearest vertex on the first side.
    apexT = -1;
    apexV = this->vertexAt(nearest[0], apexT, c.apex, tol);
    if (apexV < 0 || norm2(this->X(apexV) - c.apex) > tol * tol)
    {
      this->undo();
      return false;
    }
  }
  // Vertices on both sides at the same distances from the apex (kKeptSpacing
  // minimumEdgeLength apart, or the wedge's width where that is more, and the sides' own
  // points), inserted (with the flips of 2); then the sides between them made mesh edges
  // (recoverEdge()); the wedge's outline.
  outline.assign(cut ? 0 : 1, c.apex);
  std::vector<Vec2> second;
  bool ok = true;
  std::vector<int> chain[2];
  for (int s = 0; s < 2 && ok; ++s)
  {
    const std::vector<Vec2>& side = *sides[s];
    std::vector<std::pair<double, Vec2>> targets;
    double sum = 0.0;
    for (std::size_t j = 1; j < side.size(); ++j)
    {
      sum += norm(side[j] - side[j - 1]);
      if (sum < arc[s] - tol && sum > from[s] + tol)
      {
        targets.emplace_back(sum, side[j]);
      }
    }
    const std::size_t own = targets.size();                  // the side's points come first
    const double widening = std::sin(c.angle * kPi / 180.0); // the wedge's width per length
    if (cut)
    {
      // (At a vertex already on the side within half a minimumEdgeLength of the cut's end,
      // rather than beside it: at the slanted cut's nearer end, a vertex left between it and
      // the apex would make a sliver of the tip (the gulf at 1 M); at the other, the vertex
      // may end a region boundary of the old mesh that crosses the wedge, across which the cut
      // could not be recovered without a vertex off the curves, and the extension was undone
      // (f105 of the faulted sections never seen before: a 3.8-degree pinch-out ended where it
      // is two finest edges wide, 0.73 local edges from the mesh; a quarter before 2026-12-03).)
      double at = from[s], closest = 0.5 * this->P.minimumEdgeLength;
      for (double a : onSide[s])
      {
        if (std::fabs(a - from[s]) < closest)
        {
          closest = std::fabs(a - from[s]);
          at = a;
        }
      }
      targets.emplace_back(at, pointAlong(side, at));
    }
    for (double d = cut ? from[s] + std::max(spacing, widening * from[s]) : spacing;
         spacing > 0.0 && d < arc[s] - 0.5 * spacing;
         d += std::max(spacing, widening * d))
    {
      const double gap = 0.5 * std::max(spacing, widening * d);
      bool near = false;
      for (std::size_t k = 0; k < own; ++k)
      {
        near = near || std::fabs(targets[k].first - d) < gap;
      }
      for (double a : onSide[s])
      {
        near = near || std::fabs(a - d) < gap;
      }
      if (!near)
      {
        targets.emplace_back(d, pointAlong(side, d));
      }
    }
    std::sort(targets.begin(),
      targets.end(),
      [](const auto& x, const auto& y) { return x.first < y.first; });
    int t = apexT;
    if (cut)
    {
      // (A triangle around the region's nearest vertex, which side 0's insertions may have
      // changed.)
      t = -1;
      for (int u : this->scope(local, true))
      {
        const auto& tri = this->M.triangles[u];
        t = this->Live[u] && (tri[0] == nearest[s] || tri[1] == nearest[s] || tri[2] == nearest[s])
          ? u
          : t;
      }
      ok = t >= 0;
    }
    else
    {
      chain[s].push_back(apexV);
    }
    for (std::size_t k = 0; k < targets.size() && ok; ++k)
    {
      const int v =
        this->vertexAt(chain[s].empty() ? nearest[s] : chain[s].back(), t, targets[k].second, tol);
      ok = v >= 0;
      if (ok && (chain[s].empty() || v != chain[s].back()))
      {
        chain[s].push_back(v);
      }
    }
    if (ok && chain[s].back() != nearest[s])
    {
      chain[s].push_back(nearest[s]);
    }
  }
  this->Legalize = false;
  std::set<std::pair<int, int>> sideEdges;
  for (int s = 0; s < 2 && ok; ++s)
  {
    std::vector<int> path{ chain[s][0] };
    for (std::size_t k = 1; k < chain[s].size() && ok; ++k)
    {
      ok = this->recoverEdge(chain[s][k - 1], chain[s][k], tol, path);
    }
    for (std::size_t k = 1; k < path.size() && ok; ++k)
    {
      sideEdges.emplace(std::min(path[k - 1], path[k]), std::max(path[k - 1], path[k]));
    }
    std::vector<Vec2>& out = s == 0 ? outline : second;
    for (std::size_t k = 1; k < path.size() && ok; ++k)
    {
      out.push_back(this->X(path[k]));
    }
  }
  if (cut && ok)
  {
    // The wedge's new end: the chord between the sides' first vertices, a mesh edge.
    std::vector<int> path{ chain[0][0] };
    ok = this->recoverEdge(chain[0][0], chain[1][0], tol, path);
    outline.insert(outline.begin(), this->X(chain[0][0]));
  }
  this->Legalize = true;
  outline.insert(outline.end(), second.rbegin(), second.rend());
  if (cut && ok)
  {
    outline.push_back(this->X(chain[1][0]));
  }
  radius2 = 0.0;
  for (Vec2 p : outline)
  {
    radius2 = std::max(radius2, norm2(p - c.apex));
  }
  radius2 *= 1.0 + 1e-9;
  const auto inside = [&](Vec2 p, bool orOn)
  {
    for (std::size_t j = 0, n = outline.size(); j < n && orOn; ++j)
    {
      if (pointSegmentDistance2(p, outline[j], outline[(j + 1) % n]) <= tol * tol)
      {
        return true;
      }
    }
    return insidePolygon(outline, p);
  };
  // The triangles inside the outline take the corner's region.
  const auto count = [&]()
  {
    all = local ? this->scope(local, true) : all;
    return local ? all.size() : this->M.triangles.size();
  };
  const auto at = [&](std::size_t i) { return local ? static_cast<std::size_t>(all[i]) : i; };
  std::vector<std::pair<int, int>> retagged; // (triangle, its region before)
  for (std::size_t i = 0, n = count(); i < n && ok; ++i)
  {
    const std::size_t t = at(i);
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), d = this->X(tri[2]);
    if (this->M.region[t] == c.region || !this->Live[t] || norm2(a - c.apex) > radius2 ||
      norm2(b - c.apex) > radius2 || norm2(d - c.apex) > radius2 || !inside(a, true) ||
      !inside(b, true) || !inside(d, true) || !inside((1.0 / 3.0) * (a + b + d), false) ||
      (cut && this->P.regionAt((1.0 / 3.0) * (a + b + d)) != c.region))
    {
      continue; // (an extension's wedge may hold islands: they stay)
    }
    retagged.emplace_back(static_cast<int>(t), this->M.region[t]);
    this->M.region[t] = c.region;
  }
  // An extension's tip (apex, cut) stays with the region around it (the retag below would
  // give it to the wedge's: the model's region there).
  std::vector<Vec2> tip;
  if (cut && ok)
  {
    tip = { c.apex, this->X(chain[0][0]), this->X(chain[1][0]) };
  }
  const auto inTip = [&](const std::array<int, 3>& tri)
  {
    return !tip.empty() &&
      insidePolygon(tip, (1.0 / 3.0) * (this->X(tri[0]) + this->X(tri[1]) + this->X(tri[2])));
  };
  // Around it, triangles cut from their region by the sides (a side's bend beyond a chord
  // the mesh had) take the region at their centroid (retag()).
  for (int sweep = 0; sweep < 2 && ok; ++sweep)
  {
    for (std::size_t i = 0, n = count(); i < n; ++i)
    {
      const std::size_t t = at(i);
      const auto& tri = this->M.triangles[t];
      const int before = this->M.region[t];
      bool onSide = false; // (an extension: a triangle on a side, whatever its reach)
      for (int k = 0; k < 3 && cut; ++k)
      {
        onSide = onSide ||
          sideEdges.count(
            { std::min(tri[k], tri[(k + 1) % 3]), std::max(tri[k], tri[(k + 1) % 3]) }) > 0;
      }
      if ((before != c.region || onSide) && !inTip(tri) &&
        (onSide ||
          (norm2(this->X(tri[0]) - c.apex) <= radius2 &&
            norm2(this->X(tri[1]) - c.apex) <= radius2 &&
            norm2(this->X(tri[2]) - c.apex) <= radius2)) &&
        this->retag(static_cast<int>(t)))
      {
        retagged.emplace_back(static_cast<int>(t), before);
      }
    }
  }
  // Valid when every new region boundary edge joins two curve points, the wedge joins the
  // region's triangles beyond it, and reaches the apex.
  std::vector<int> mark;
  for (const auto& [t, before] : retagged)
  {
    mark.push_back(t);
  }
  std::sort(mark.begin(), mark.end());
  bool joins = retagged.empty(), apex = cut; // (an extension has no apex to reach)
  for (const auto& [t, before] : retagged)
  {
    const auto& tri = this->M.triangles[t];
    apex = apex || hasVertex(tri, apexV);
    for (int k = 0; k < 3 && ok; ++k)
    {
      const int n = this->Nbr[t][k];
      if (n >= 0 && this->M.region[n] == c.region)
      {
        joins = joins || !std::binary_search(mark.begin(), mark.end(), n);
      }
      else
      {
        ok = this->P.onCurve(this->X(tri[k])) && this->P.onCurve(this->X(tri[(k + 1) % 3]));
      }
    }
  }
  for (std::size_t i = 0, n = count(); i < n && ok && !apex; ++i)
  {
    const std::size_t t = at(i);
    const auto& tri = this->M.triangles[t];
    apex = this->M.region[t] == c.region && hasVertex(tri, apexV);
  }
  // ... and both sides are region boundaries (a corner the mesh does not have, e.g. beside a
  // spit of land thinner than the triangles, is not made).
  for (std::size_t i = 0, n = count(); i < n && ok; ++i)
  {
    const std::size_t t = at(i);
    const auto& tri = this->M.triangles[t];
    for (int k = 0; k < 3 && ok && this->M.region[t] == c.region; ++k)
    {
      const int n = this->Nbr[t][k];
      ok = n < 0 || this->M.region[n] != c.region ||
        sideEdges.count(
          { std::min(tri[k], tri[(k + 1) % 3]), std::max(tri[k], tri[(k + 1) % 3]) }) == 0;
    }
  }
  // ... and, after the flips of 2, no triangle around it nearly flat (a vertex too close to
  // an edge), and the wedge's triangles no worse than rungs across it: no angle below a
  // quarter of the corner's, none above kKeptLargest.
  if (ok)
  {
    all = this->scope(local, true);
    this->flipToDelaunay(local ? &all : nullptr);
  }
  const double cosLargest = std::cos(kKeptLargest * kPi / 180.0);
  const double cosSmallest = std::cos(0.25 * c.angle * kPi / 180.0);
  for (std::size_t i = 0, n = count(); i < n && ok; ++i)
  {
    const std::size_t t = at(i);
    const auto& tri = this->M.triangles[t];
    const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), d = this->X(tri[2]);
    if (norm2(a - c.apex) <= 4.0 * radius2 && this->Live[t])
    {
      ok = orient2d(a, b, d) > kFlat *
          std::sqrt(std::max({ norm2(b - a) * norm2(d - a),
            norm2(a - b) * norm2(d - b),
            norm2(a - d) * norm2(b - d) }));
      // (An extension's wedge is dropped, or refined after: no bound on its shape.)
      if (ok && !cut && this->M.region[t] == c.region && norm2(a - c.apex) <= radius2 &&
        norm2(b - c.apex) <= radius2 && norm2(d - c.apex) <= radius2 &&
        insidePolygon(outline, (1.0 / 3.0) * (a + b + d)))
      {
        double largest = 0.0;
        const double smallest = shapeCosine(a, b, d, largest);
        ok = smallest <= cosSmallest && largest >= cosLargest;
      }
    }
  }
  ok = ok && joins && apex;
  if (!ok)
  {
    for (const auto& [t, before] : retagged)
    {
      if (static_cast<std::size_t>(t) < this->Tri0)
      {
        this->M.region[t] = before;
      }
    }
    this->undo();
    return false;
  }
  this->Recording = false;
  (local ? this->TipVertices : this->KeptVertices) += this->M.points.size() - this->Points0;
  for (int s = 0; s < 2 && cut; ++s)
  {
    const double r = this->P.minimumEdgeLength;
    for (int v : chain[s])
    {
      this->ExtendedSides.push_back({ this->X(v), r * r });
    }
  }
  return true;
}

std::size_t Refiner::extendWedges()
{
  const std::vector<SharpCorner>& corners = this->P.wedgeCorners;
  if (corners.empty() || !this->P.regionAt || !this->P.onCurve ||
    !(this->P.minimumEdgeLength > 0.0))
  {
    return 0;
  }
  // Each corner looks at the triangles with a vertex within twice its sides' reach of its apex
  // (keepCorner()'s checks go no farther), found through a grid of those disks (a model with a
  // few thousand sharp corners along its curves made a sweep of the corners by abscissa take
  // most of a run): those that had one in the mesh as it was or after an extension that made
  // or changed them. The lists are made wedgeChunk corners at a time, from a copy of the mesh
  // as it was and the extensions' triangles since (thirty zigzag horizons of 10000 points, 166 k
  // corners, held 434 M items in their lists at once: 1.7 GB).
  const std::size_t nc = corners.size();
  std::vector<double> reach(nc);
  for (std::size_t i = 0; i < nc; ++i)
  {
    reach[i] = 2.0 * std::max(polylineLength(corners[i].first), polylineLength(corners[i].second));
  }
  const std::size_t chunk = this->P.wedgeChunk;
  const bool chunked = nc > chunk;
  const std::vector<std::array<int, 3>> initial = chunked
    ? std::vector<std::array<int, 3>>(this->M.triangles.begin(), this->M.triangles.end())
    : std::vector<std::array<int, 3>>();
  std::vector<std::pair<int, std::array<int, 3>>> since; // (chunked: each extension's triangles)
  std::size_t extended = 0;
  this->Keeping = true;
  for (std::size_t first = 0; first < nc && this->Inserted < this->Budget; first += chunk)
  {
    const std::size_t count = std::min(chunk, nc - first);
    // (The disks' boxes widened against rounding, for the grid and the chunk's box: a vertex
    // within a disk may lie a hair beyond its rounded box.)
    std::vector<Vec2> centre(count);
    std::vector<double> radius2(count), wide(count);
    Box2 chunkBox;
    for (std::size_t i = 0; i < count; ++i)
    {
      centre[i] = corners[first + i].apex;
      radius2[i] = reach[first + i] * reach[first + i];
      wide[i] =
        reach[first + i] * (1.0 + 1e-9) + 1e-12 * (std::fabs(centre[i].x) + std::fabs(centre[i].y));
      chunkBox.add(centre[i] - Vec2{ wide[i], wide[i] });
      chunkBox.add(centre[i] + Vec2{ wide[i], wide[i] });
    }
    const double margin = 1e-12 * chunkBox.scale();
    chunkBox.add(chunkBox.min - Vec2{ margin, margin });
    chunkBox.add(chunkBox.max + Vec2{ margin, margin });
    DiskGrid disks(centre, wide);
    std::vector<std::vector<int>> local(count);
    // The lists an extension added to, to be sorted again (the others stay sorted: a model with
    // a few thousand sharp corners sorted every list after every extension).
    std::vector<int> grown;
    std::vector<char> isGrown(count, 0);
    const auto add = [&](int t, const std::array<int, 3>& tri)
    {
      const Vec2 a = this->X(tri[0]), b = this->X(tri[1]), c = this->X(tri[2]);
      const Vec2 lo{ std::min({ a.x, b.x, c.x }), std::min({ a.y, b.y, c.y }) };
      const Vec2 hi{ std::max({ a.x, b.x, c.x }), std::max({ a.y, b.y, c.y }) };
      if (hi.x < chunkBox.min.x || lo.x > chunkBox.max.x || hi.y < chunkBox.min.y ||
        lo.y > chunkBox.max.y)
      {
        return;
      }
      disks.forEachNear(lo,
        hi,
        [&](int i)
        {
          for (int v : tri)
          {
            if (norm2(this->X(v) - centre[i]) <= radius2[i])
            {
              local[i].push_back(t);
              if (!isGrown[i])
              {
                isGrown[i] = 1;
                grown.push_back(i);
              }
              break;
            }
          }
        });
    };
    const auto sortGrown = [&]
    {
      for (const int c : grown)
      {
        sortUnique(local[c]);
        isGrown[c] = 0;
      }
      grown.clear();
    };
    // (Lists made in increasing order from the mesh as it was; then the extensions' since. A
    // triangle with no vertex in a cell of the grid that lists a disk is in no list: most
    // triangles of a 1 M mesh, whose boxes and cells took 0.05 s.)
    std::vector<char> mayHold(this->M.points.size());
    for (std::size_t v = 0; v < mayHold.size(); ++v)
    {
      mayHold[v] = disks.mayHold(this->M.points[v]);
    }
    const std::size_t nt = chunked ? initial.size() : this->M.triangles.size();
    for (std::size_t t = 0; t < nt; ++t)
    {
      this->poll();
      const std::array<int, 3>& tri = chunked ? initial[t] : this->M.triangles[t];
      if (mayHold[tri[0]] || mayHold[tri[1]] || mayHold[tri[2]])
      {
        add(static_cast<int>(t), tri);
      }
    }
    std::fill(isGrown.begin(), isGrown.end(), 0);
    grown.clear();
    for (const auto& [t, tri] : since)
    {
      this->poll();
      add(t, tri);
    }
    sortGrown();
    for (std::size_t k = 0; k < count && this->Inserted < this->Budget; ++k)
    {
      const std::size_t i = first + k;
      const std::size_t before = this->M.triangles.size();
      const std::size_t points = this->M.points.size();
      double radius2Kept = 0.0;
      std::vector<Vec2> outline;
      // Sharp wedges (the exterior's inlets, a region's spits) are cut, a region's wider
      // corners' lost tips rebuilt (as the mesher lists them; the exterior's wider ones left).
      const bool sharp = corners[i].angle < this->P.minimumAngle;
      if (!sharp && corners[i].region < 0)
      {
        continue;
      }
      const double cut = sharp ? kWedgeCut * this->P.minimumEdgeLength : 0.0;
      if (this->keepCorner(corners[i], radius2Kept, outline, cut, &local[k]))
      {
        ++extended;
        this->Inserted += this->M.points.size() - points;
        const auto changed = [&](int t)
        {
          add(t, this->M.triangles[t]); // (a changed slot may now reach another's disk)
          if (chunked)
          {
            since.emplace_back(t, this->M.triangles[t]);
          }
        };
        for (const Entry& e : this->Journal)
        {
          changed(e.t);
        }
        for (std::size_t t = before; t < this->M.triangles.size(); ++t)
        {
          changed(static_cast<int>(t));
        }
        sortGrown();
      }
    }
  }
  this->Keeping = false;
  return extended;
}

std::vector<int> Refiner::regionBody(const std::vector<int>& list,
  int region,
  Vec2 apex,
  double reach) const
{
  std::vector<int> own;
  for (const int t : list)
  {
    if (this->Live[t] && this->M.region[t] == region)
    {
      own.push_back(t);
    }
  }
  // Each of `own`'s place in it (PlaceTable).
  this->BodyPlaces.begin(own.size());
  for (std::size_t i = 0; i < own.size(); ++i)
  {
    this->BodyPlaces.insert(own[i], static_cast<int>(i));
  }
  // The pieces by a flood fill across edges between two of `own`, each with its farthest
  // vertex from the apex.
  std::vector<int> piece(own.size(), -1), stack;
  std::vector<double> farthest;
  for (std::size_t first = 0; first < own.size(); ++first)
  {
    if (piece[first] >= 0)
    {
      continue;
    }
    const int id = static_cast<int>(farthest.size());
    farthest.push_back(0.0);
    piece[first] = id;
    stack.assign(1, static_cast<int>(first));
    while (!stack.empty())
    {
      const std::array<int, 3>& tri = this->M.triangles[own[stack.back()]];
      const std::array<int, 3>& across = this->Nbr[own[stack.back()]];
      stack.pop_back();
      for (int k = 0; k < 3; ++k)
      {
        farthest[id] = std::max(farthest[id], norm2(this->X(tri[k]) - apex));
        const int at = across[k] >= 0 ? this->BodyPlaces.find(across[k]) : -1;
        if (at < 0)
        {
          continue;
        }
        const std::size_t j = static_cast<std::size_t>(at);
        if (piece[j] < 0)
        {
          piece[j] = id;
          stack.push_back(static_cast<int>(j));
        }
      }
    }
  }
  // The body: the pieces reaching beyond `reach`, or else the one reaching farthest.
  const double most = farthest.empty() ? 0.0 : *std::max_element(farthest.begin(), farthest.end());
  const double bound = std::min(reach * reach, most);
  std::vector<int> body;
  for (std::size_t i = 0; i < own.size(); ++i)
  {
    if (farthest[piece[i]] >= bound)
    {
      body.push_back(own[i]);
    }
  }
  return body;
}

// keepCorner()'s triangles: `local` (all when null: an empty list), with, when `changed`, the
// slots the transaction changed and the triangles it made.
std::vector<int> Refiner::scope(const std::vector<int>* local, bool changed) const
{
  if (!local)
  {
    return {};
  }
  std::vector<int> list = *local;
  if (changed && this->Recording)
  {
    for (const Entry& e : this->Journal)
    {
      list.push_back(e.t);
    }
    for (std::size_t t = this->Tri0; t < this->M.triangles.size(); ++t)
    {
      list.push_back(static_cast<int>(t));
    }
    sortUnique(list);
  }
  return list;
}

std::size_t Refiner::keptBad() const
{
  std::size_t count = 0;
  for (std::size_t t = 0; t < this->M.triangles.size() && !this->Kept.empty(); ++t)
  {
    const int ti = static_cast<int>(t);
    count += this->M.region[t] >= 0 && this->Live[t] &&
      this->smallestAngleCosine(this->M.triangles[t]) > this->CosBad && this->inKept(ti);
  }
  return count;
}

void Refiner::zonesBelow(double angle, std::vector<Zone>& zones) const
{
  const double cosine = std::cos(angle * kPi / 180.0);
  const auto below = [&](int t)
  {
    return this->M.region[t] >= 0 && this->Live[t] &&
      this->smallestAngleCosine(this->M.triangles[t]) > cosine;
  };
  // Below an angle up to minimumAngle, with no kept wedge, only bad triangles: after run(),
  // those it left are all there is to look at.
  std::vector<int> list;
  if (this->Ran && this->Kept.empty() && cosine >= this->CosBad)
  {
    std::copy_if(
      this->BadAfterRun.begin(), this->BadAfterRun.end(), std::back_inserter(list), below);
  }
  else
  {
    list = this->selectTriangles(below);
  }
  for (const int t : list)
  {
    zones.push_back(this->zoneAround(t));
  }
}
} // namespace

PointStars pointStars(std::size_t numberOfPoints,
  const LargeVector<std::array<int, 3>>& triangles,
  const std::vector<char>* only,
  const std::function<void()>& tick)
{
  PointStars stars;
  groupIntoRows(numberOfPoints,
    stars.start,
    stars.items,
    [&](auto&& emit)
    {
      for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        if (tick && t % kStarsTick == kStarsTick - 1)
        {
          tick();
        }
        for (int v : triangles[t])
        {
          if (!only || (*only)[v])
          {
            emit(v, static_cast<int>(t));
          }
        }
      }
    });
  return stars;
}

void validate(const RefinementParams& p)
{
  if (!(p.minimumAngle >= 0.0 && p.minimumAngle <= kLargestMinimumAngle))
  {
    std::ostringstream text;
    text << "MinimumAngle = " << std::to_string(p.minimumAngle) << " is out of range [0, "
         << kLargestMinimumAngle
         << "] (degrees; Delaunay refinement usually does not end above about 33)";
    throw ParameterError(text.str());
  }
  if (!(p.minimumEdgeLength >= 0.0) || !std::isfinite(p.minimumEdgeLength))
  {
    throw ParameterError("refinement minimum edge length " + std::to_string(p.minimumEdgeLength) +
      " is not a finite value >= 0");
  }
  if (!(p.maximumEdgeLength >= 0.0) || !std::isfinite(p.maximumEdgeLength))
  {
    throw ParameterError("refinement maximum edge length " + std::to_string(p.maximumEdgeLength) +
      " is not a finite value >= 0");
  }
  if (!(p.insertionBudget >= 0.0 && p.insertionBudget <= 100.0))
  {
    throw ParameterError("refinement insertion budget " + std::to_string(p.insertionBudget) +
      " is out of range [0, 100]");
  }
  if (!(p.curveAreaBudget >= 0.0 && p.curveAreaBudget <= 1.0))
  {
    throw ParameterError("refinement curve area budget " + std::to_string(p.curveAreaBudget) +
      " is out of range [0, 1]");
  }
  if (p.wedgeChunk < 1)
  {
    throw ParameterError("refinement wedge chunk " + std::to_string(p.wedgeChunk) +
      " is out of range [1, ...): the wedge corners listed at once");
  }
}

namespace
{
// The cosine of abc's smallest angle, opposite its shortest side s (squared lengths: s <= p,
// q), by the law of cosines. The shortest and the other two are picked with min and max, not
// branches: which side is shortest is a coin toss from one triangle to the next, and the
// sweeps of every triangle (the bad ones, the smallest angle) took about half as long again
// so. (The sum and product of p and q do not depend on their order: the same value either
// way.)
double smallestCosine(Vec2 a, Vec2 b, Vec2 c)
{
  const double e0 = norm2(c - b), e1 = norm2(a - c), e2 = norm2(b - a);
  const double lower = std::min(e0, e1);
  const double s = std::min(lower, e2), p = std::max(e0, e1), q = std::max(lower, e2);
  return (p + q - s) / (2.0 * std::sqrt(p * q));
}

// Whether abc is counter-clockwise beyond rounding: twice its area above 1e-12 of the squared
// length of its longer side at a.
bool turnsLeft(Vec2 a, Vec2 b, Vec2 c)
{
  return orient2d(a, b, c) > 1e-12 * std::max(norm2(b - a), norm2(c - a));
}

// Smallest-angle cosine of abc, or 2 when abc is not counter-clockwise (turnsLeft()).
double shapeCosine(Vec2 a, Vec2 b, Vec2 c)
{
  return turnsLeft(a, b, c) ? smallestCosine(a, b, c) : 2.0;
}

// The same and, in `largest`, the cosine of its largest angle (-1 when not counter-clockwise).
double shapeCosine(Vec2 a, Vec2 b, Vec2 c, double& largest)
{
  const bool turns = turnsLeft(a, b, c);
  largest = turns ? largestAngleCosine(a, b, c) : -1.0;
  return turns ? smallestCosine(a, b, c) : 2.0;
}

} // namespace

// Step 6: the short edge collapses (see the top of this file). Returns the collapses.
std::size_t collapseShortEdges(RegionMesh& m, const RefinementParams& P)
{
  return collapseShortEdgesAvoiding(m, P, {});
}

namespace
{
// collapseShortEdges() with no collapse at a triangle that has a vertex in one of `avoid` (the
// kept corners' disks).
std::size_t collapseShortEdgesAvoiding(RegionMesh& m,
  const RefinementParams& P,
  const std::vector<Zone>& avoid,
  const std::vector<Zone>& within)
{
  if (!P.onCurve || !P.curveSlide || !P.curveDistance || !(P.minimumAngle > 0.0) ||
    !(P.minimumEdgeLength > 0.0))
  {
    return 0;
  }
  const double cosBad = std::cos(P.minimumAngle * kPi / 180.0);
  const double shortLength = kFloor * P.minimumEdgeLength;
  const auto X = [&](int v) { return m.points[v]; };
  // A candidate: a region triangle below the angle, its shortest edge shorter than the floor,
  // outside `avoid` and inside `within`. Whether a triangle is one depends on its corners only,
  // and a collapse marks every corner of the triangles it changes as touched (skipped for the
  // rest of the sweep): the candidates of a sweep are found first, on two threads, and the
  // collapses then go through them in order, as one pass over every triangle would.
  const auto shortestEdge = [&](const std::array<int, 3>& tri)
  {
    int k = 0; // the edge (tri[k], tri[k + 1])
    for (int j = 1; j < 3; ++j)
    {
      k = norm2(X(tri[(j + 1) % 3]) - X(tri[j])) < norm2(X(tri[(k + 1) % 3]) - X(tri[k])) ? j : k;
    }
    return k;
  };
  const auto candidate = [&](std::size_t t)
  {
    const auto& tri = m.triangles[t];
    if (m.region[t] < 0)
    {
      return false;
    }
    const double cosine = shapeCosine(X(tri[0]), X(tri[1]), X(tri[2]));
    if (!(cosine > cosBad) || cosine > 1.0)
    {
      return false;
    }
    bool near = false, in = within.empty();
    for (int v : tri)
    {
      for (const Zone& z : avoid)
      {
        near = near || norm2(X(v) - z.center) <= z.radius2;
      }
      for (const Zone& z : within)
      {
        in = in || norm2(X(v) - z.center) <= z.radius2;
      }
    }
    if (near || !in)
    {
      return false;
    }
    const int k = shortestEdge(tri);
    return norm(X(tri[(k + 1) % 3]) - X(tri[k])) < shortLength;
  };
  std::map<int, std::size_t> count; // triangles per region (once the first sweep finds a
                                    // candidate: at 1 M triangles it finds none)
  std::size_t total = 0;
  for (int sweep = 0; sweep < kCollapseSweeps; ++sweep)
  {
    std::vector<int> candidates;
    gatherInOrder<int>(
      m.triangles.size(),
      kTwoThreadBlock,
      kTwoThreadItems,
      [&](std::size_t t, std::vector<int>& found)
      {
        if (candidate(t))
        {
          found.push_back(static_cast<int>(t));
        }
      },
      [&](int t) { candidates.push_back(t); },
      [] {});
    if (candidates.empty())
    {
      break;
    }
    if (sweep == 0)
    {
      for (int r : m.region)
      {
        ++count[r];
      }
    }
    const PointStars stars = pointStars(m.points.size(), m.triangles);
    const auto star = [&](int v)
    {
      return std::vector<int>(
        stars.items.begin() + stars.start[v], stars.items.begin() + stars.start[v + 1]);
    };
    std::vector<std::uint8_t> dead(m.triangles.size(), 0), touched(m.points.size(), 0);
    // The edges (v, x) of a triangle list around v: x, and whether the edge is a region
    // boundary (one triangle, or two of different regions); -1 in `regions` for the former.
    struct Edge
    {
      int x;
      bool boundary;
    };
    const auto edgesAround = [&](int v,
                               const std::vector<std::array<int, 3>>& tris,
                               const std::vector<int>& regs,
                               std::vector<Edge>& edges,
                               std::vector<int>& regions)
    {
      std::map<int, std::vector<int>> by; // other end -> regions of its triangles
      regions.clear();
      for (std::size_t i = 0; i < tris.size(); ++i)
      {
        const auto& tri = tris[i];
        const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
        by[tri[(k + 1) % 3]].push_back(regs[i]);
        by[tri[(k + 2) % 3]].push_back(regs[i]);
        regions.push_back(regs[i]);
      }
      edges.clear();
      bool manifold = true;
      for (const auto& [x, rs] : by)
      {
        manifold = manifold && rs.size() <= 2;
        const bool boundary = rs.size() == 1 || rs[0] != rs[1];
        edges.push_back({ x, boundary });
        if (rs.size() == 1)
        {
          regions.push_back(-1);
        }
      }
      sortUnique(regions);
      return manifold;
    };
    std::size_t collapsed = 0;
    for (const int t : candidates)
    {
      const auto tri = m.triangles[t];
      if (dead[t] || touched[tri[0]] || touched[tri[1]] || touched[tri[2]])
      {
        continue;
      }
      const int k = shortestEdge(tri); // (tri[k], tri[k + 1])
      // Try both ways (v merges into u), and for two free vertices a third: both merge at the
      // edge's middle (u moves there).
      double bestCosine = HUGE_VAL;
      int bestV = -1, bestU = -1;
      bool bestMid = false;
      for (int way = 0; way < 3; ++way)
      {
        const int u = tri[(k + (way & 1)) % 3], v = tri[(k + 1 - (way & 1)) % 3];
        const Vec2 mid = 0.5 * (X(u) + X(v));
        const auto Y = [&](int x) { return way == 2 && x == u ? mid : X(x); };
        if (P.modelCorner && P.modelCorner(X(v)))
        {
          continue; // (a model corner's vertex stays)
        }
        const std::vector<int> su = star(u), sv = star(v);
        std::vector<int> old = su;
        old.insert(old.end(), sv.begin(), sv.end());
        sortUnique(old);
        // The old neighbourhood: its worst shape, its regions and boundary edges at u and v.
        double oldCosine = -1.0, oldLargest = 1.0;
        bool ok = true;
        std::vector<int> shared;
        for (int s : old)
        {
          const auto& o = m.triangles[s];
          double l = 0.0;
          const double c = shapeCosine(X(o[0]), X(o[1]), X(o[2]), l);
          ok = ok && c <= 1.0; // no triangle without positive area nearby
          if (m.region[s] >= 0)
          {
            oldCosine = std::max(oldCosine, c);
            oldLargest = std::min(oldLargest, l);
          }
          if (hasVertex(o, u) && hasVertex(o, v))
          {
            shared.push_back(s);
          }
        }
        if (!ok || shared.empty() || shared.size() > 2)
        {
          continue;
        }
        std::vector<std::array<int, 3>> tris;
        std::vector<int> regs;
        std::vector<Edge> edgesU, edgesV, edgesAfter;
        std::vector<int> regionsU, regionsV, regionsAfter;
        for (int s : su)
        {
          tris.push_back(m.triangles[s]);
          regs.push_back(m.region[s]);
        }
        ok = edgesAround(u, tris, regs, edgesU, regionsU);
        tris.clear();
        regs.clear();
        for (int s : sv)
        {
          tris.push_back(m.triangles[s]);
          regs.push_back(m.region[s]);
        }
        ok = ok && edgesAround(v, tris, regs, edgesV, regionsV);
        std::vector<int> endsU, endsV;
        for (const Edge& e : edgesU)
        {
          if (e.boundary)
          {
            endsU.push_back(e.x);
          }
        }
        for (const Edge& e : edgesV)
        {
          if (e.boundary)
          {
            endsV.push_back(e.x);
          }
        }
        // v leaves: a free vertex, or one on a curve that may slide (no junction, no feature
        // point), merging into a vertex on the curves.
        const bool free = endsV.empty() && regionsV.size() == 1 && regionsV[0] >= 0;
        Vec2 at;
        const bool slides = endsV.size() == 2 && regionsV.size() == 2 && P.onCurve(X(u)) &&
          P.curveSlide(X(v), X(u), regionsV[0], regionsV[1], at);
        const bool freeU = endsU.empty() && regionsU.size() == 1 && regionsU[0] >= 0;
        if (way == 2 && !(free && freeU))
        {
          continue;
        }
        if (!ok || (!free && !slides))
        {
          continue;
        }
        bool lastOfRegion = false;
        for (int s : shared)
        {
          lastOfRegion = lastOfRegion || count[m.region[s]] <= 1;
        }
        if (lastOfRegion)
        {
          continue;
        }
        // The link condition: u and v have no common neighbour but the shared triangles'
        // third corners (else the collapse folds the mesh).
        std::vector<int> common;
        for (const Edge& a : edgesU)
        {
          for (const Edge& b : edgesV)
          {
            common.push_back(a.x == b.x ? a.x : -1);
          }
        }
        sortUnique(common);
        common.erase(std::remove(common.begin(), common.end(), -1), common.end());
        if (common.size() != shared.size())
        {
          continue;
        }
        // The new neighbourhood: v's triangles with v -> u, the shared ones gone.
        tris.clear();
        regs.clear();
        double newCosine = -1.0, newLargest = 1.0;
        for (int s : old)
        {
          if (std::find(shared.begin(), shared.end(), s) != shared.end())
          {
            continue;
          }
          auto o = m.triangles[s];
          for (int& x : o)
          {
            x = x == v ? u : x;
          }
          double l = 0.0;
          const double c = shapeCosine(Y(o[0]), Y(o[1]), Y(o[2]), l);
          ok = ok && c <= 1.0;
          if (m.region[s] >= 0)
          {
            newCosine = std::max(newCosine, c);
            newLargest = std::min(newLargest, l);
          }
          if (hasVertex(o, u))
          {
            tris.push_back(o);
            regs.push_back(m.region[s]);
          }
        }
        ok = ok && edgesAround(u, tris, regs, edgesAfter, regionsAfter) &&
          newCosine < std::min(oldCosine, bestCosine) - 1e-12 &&
          newLargest >= std::min(oldLargest, kSmoothingLargestCosine) - 1e-12;
        // Boundary edges: no more at u than at either end before, every new one between
        // vertices on curves and near them.
        std::size_t endsAfter = 0;
        for (const Edge& e : edgesAfter)
        {
          if (!ok || !e.boundary)
          {
            continue;
          }
          ++endsAfter;
          if (std::find(endsU.begin(), endsU.end(), e.x) == endsU.end())
          {
            const Vec2 a = X(u), b = X(e.x);
            ok = P.onCurve(a) && P.onCurve(b) &&
              P.curveDistance(0.5 * (a + b), HUGE_VAL) <=
                std::max(kSlideDeviation * norm(b - a), 0.5 * shortLength);
          }
        }
        if (ok && endsAfter <= std::max(endsU.size(), endsV.size()) &&
          regionsAfter.size() <= std::max(regionsU.size(), regionsV.size()))
        {
          bestCosine = newCosine;
          bestU = u;
          bestV = v;
          bestMid = way == 2;
        }
      }
      if (bestV < 0)
      {
        continue;
      }
      if (bestMid)
      {
        m.points[bestU] = 0.5 * (X(bestU) + X(bestV));
      }
      for (int s : star(bestV))
      {
        auto& o = m.triangles[s];
        if (hasVertex(o, bestU))
        {
          dead[s] = 1;
          --count[m.region[s]];
        }
        for (int& x : o)
        {
          x = x == bestV ? bestU : x;
        }
      }
      for (int w : { bestU, bestV })
      {
        for (int s : star(w))
        {
          for (int x : m.triangles[s])
          {
            touched[x] = 1;
          }
        }
      }
      ++collapsed;
    }
    if (collapsed == 0)
    {
      break;
    }
    total += collapsed;
    std::size_t kept = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
    {
      if (!dead[t])
      {
        m.triangles[kept] = m.triangles[t];
        m.region[kept] = m.region[t];
        m.level[kept] = m.level[t];
        ++kept;
      }
    }
    m.triangles.resize(kept);
    m.region.resize(kept);
    m.level.resize(kept);
  }
  return total;
}

// A copy of the mesh with room for what a run adds (withRoom()): its arrays do not copy
// themselves whole to new memory at the run's first insertion (at 1 M triangles, with the
// refiners' own arrays, 24 such copies in a run: 190 MB written). With `progress`, reports
// before, between and after the arrays (at 1 M their first writes took up to 0.15 s on a slow
// hour of this machine).
RegionMesh roomyCopy(const RegionMesh& mesh, const ProgressReporter* progress = nullptr)
{
  const auto report = [progress]
  {
    if (progress)
    {
      progress->report(0.0, kRefiningStage);
    }
  };
  RegionMesh copy;
  report();
  withRoom(copy.points, mesh.points.size()) = mesh.points;
  report();
  withRoom(copy.triangles, mesh.triangles.size()) = mesh.triangles;
  report();
  withRoom(copy.region, mesh.region.size()) = mesh.region;
  withRoom(copy.level, mesh.level.size()) = mesh.level;
  report();
  return copy;
}

// Step 4 of a pass (see the top of the file): a cautious run on a copy of the prepared mesh,
// then up to kBoldRuns bold ones, each on a copy, bold in the zones of the triangles the runs
// before left below the best angle; kept: the run with the larger smallest angle, or as large
// with fewer triangles below minimumAngle.
struct KeptRun
{
  RegionMesh mesh;                            // the mesh it made
  RefinementResult result;                    // its counts
  Handover handover;                          // its refiner's (prepare())
  std::size_t budget = 0;                     // the runs' budget of insertions
};

KeptRun keptRun(const RegionMesh& mesh,
  const Refiner& base,
  const BoundarySplitter& splitter,
  const RefinementParams& params,
  const ProgressReporter& progress)
{
  const std::vector<Zone> none;
  KeptRun kept{ roomyCopy(mesh), {}, {}, 0 };
  RegionMesh& best = kept.mesh;
  Refiner cautious(best, splitter, params, 1.0, none, progress.sub(0.1, 0.3));
  cautious.adopt(base);
  const std::vector<int> firstBad =
    params.minimumAngle > 0.0 ? cautious.badTriangles() : std::vector<int>();
  RefinementResult& bestResult = kept.result;
  bestResult = cautious.run(&firstBad);
  double bestAngle = cautious.angleAfterRun();
  std::vector<Zone> zones;
  for (int round = 0;
       round < kBoldRuns && params.minimumAngle > 0.0 && bestAngle < params.minimumAngle;
       ++round)
  {
    // (Reports between the copies too: at 1 M the last run's end, the copy of the mesh, its
    // neighbours and the run's first insertions took 0.14-0.17 s without one.)
    const ProgressReporter roundProgress =
      progress.sub(0.3 + 0.65 * round / kBoldRuns, 0.3 + 0.65 * (round + 1) / kBoldRuns);
    RegionMesh bold = roomyCopy(mesh, &roundProgress);
    Refiner run(bold, splitter, params, kBoldFloor, zones, roundProgress);
    run.adopt(base);
    const RefinementResult result = run.run(&firstBad); // (the same mesh as the cautious run's)
    const double angle = run.angleAfterRun();
    if (angle > bestAngle + 1e-9 ||
      (angle >= bestAngle - 1e-9 && result.badTrianglesLeft < bestResult.badTrianglesLeft))
    {
      bestAngle = std::max(angle, bestAngle);
      // The next round would repeat this one (the same mesh and zones) and not be kept: it is
      // skipped, its zones (this run's triangles below the best angle) added now. With none,
      // every later round would repeat it too (the 1 M gulf's first pass: 0.08 s a round).
      const bool more = round + 1 < kBoldRuns && bestAngle < params.minimumAngle;
      const std::size_t zonesBefore = zones.size();
      if (more)
      {
        run.zonesBelow(std::min(bestAngle, params.minimumAngle), zones);
      }
      best = std::move(bold);
      bestResult = result;
      kept.handover = run.takeHandover();
      if (more && zones.size() == zonesBefore)
      {
        break;
      }
      round += more ? 1 : 0;
      continue;
    }
    run.zonesBelow(std::min(bestAngle, params.minimumAngle), zones);
  }
  kept.budget = cautious.budget();
  if (kept.handover.neighbours.empty())
  {
    kept.handover = cautious.takeHandover(); // (the cautious run was kept)
  }
  return kept;
}

// One pass of refineDelaunay() (2 to 5 at the top of this file): the cautious run first (its
// smallest angle is the one to beat), then bold runs, each with cautious zones around the
// triangles where the previous bold run ended below the best so far; the run with the largest
// smallest angle (then the fewest bad triangles) is kept, then smoothed.
RefinementResult refinePass(RegionMesh& mesh,
  const BoundarySplitter& splitter,
  const RefinementParams& params,
  bool last,
  bool everyTip,
  RecoveryMemo* memo,
  RecoveryMemo* keep,
  Handover* handover,
  const ProgressReporter& progress)
{
  const std::vector<Zone> none;
  Refiner base(mesh, splitter, params, 1.0, none, progress.sub(0.0, 0.1));
  base.prepare(handover); // mesh is constrained Delaunay from here on
  const std::size_t recovered = base.recoverCurves(memo, keep);
  if (memo)
  {
    // Read by the recovery only: its memory (about 26 MB at 1 M) goes before the runs' copies
    // of the mesh, the refinement's peak.
    *memo = RecoveryMemo();
  }
  const std::size_t followed = base.followCurves();
  if (everyTip)
  {
    base.cutEveryTip();
  }
  const std::size_t dissolved = base.dissolveCorners();
  std::size_t sized = base.splitLongEdges();
  // 7: the kept corners, in the last pass before its runs (which mend the triangles beside).
  std::vector<double> keptRadius;
  std::vector<std::vector<Vec2>> keptOutline;
  const std::size_t extendedWedges = last ? base.extendWedges() : 0;
  const std::size_t keptCorners = last ? base.keepCorners(keptRadius, keptOutline) : 0;
  base.findShortEdges();
  const std::size_t flips = base.flips();
  KeptRun kept = keptRun(mesh, base, splitter, params, progress);
  RegionMesh& best = kept.mesh;
  RefinementResult& bestResult = kept.result;
  // 7': the short edges beside the extended wedges' sides, collapsed before the smoothing
  // moves them apart.
  const std::size_t cutCollapses = last && !base.extendedSides().empty()
    ? collapseShortEdgesAvoiding(best, params, base.keptDisks(), base.extendedSides())
    : 0;
  Refiner polish(best, splitter, params, 1.0, none, progress.sub(0.95, 1.0));
  // (The kept run's hand-over, unless the collapses changed the mesh since.)
  polish.prepare(cutCollapses == 0 ? &kept.handover : nullptr);
  polish.keepWedges(base);
  polish.takeShortEdges(base);
  bestResult.smoothingMoves = params.minimumAngle > 0.0 ? polish.smoothBad() : 0;
  bestResult.dissolvedCorners = dissolved + polish.dissolveCorners();
  bestResult.boundaryVertices += base.tipVertices() + polish.tipVertices() + base.keptVertices();
  bestResult.delaunayFlips += flips + polish.flips();
  std::optional<Refiner> collapsed; // the refiner of the mesh after the collapses of 6
  std::optional<double> counted;    // the smallest angle, when the last run's count holds
  // For the runs after the kept one: what they may still insert (the kept run's budget, less
  // what was used), what they add to the pass's result, and their count of what they left.
  const auto budgetLeft = [&]()
  {
    const std::size_t used = bestResult.interiorVertices + bestResult.boundaryVertices;
    return kept.budget - std::min(used, kept.budget);
  };
  const auto addInsertions = [&](const RefinementResult& r)
  {
    bestResult.interiorVertices += r.interiorVertices;
    bestResult.boundaryVertices += r.boundaryVertices;
    bestResult.budgetReached = bestResult.budgetReached || r.budgetReached;
  };
  const auto takeCount = [&](const RefinementResult& r)
  {
    bestResult.badTrianglesLeft = r.badTrianglesLeft;
    bestResult.badTrianglesAtCorners = r.badTrianglesAtCorners;
    bestResult.badCentroids = r.badCentroids;
  };
  if (last && params.minimumAngle > 0.0)
  {
    // The corners given away there leave triangles with unconstrained sharp corners behind
    // (a wedge's tip in its neighbour), and no refinement ran after the smoothing: a cautious
    // run mends what it can, with what is left of the kept run's budget, once the edges too
    // short for it are collapsed.
    const std::size_t collapses = collapseShortEdgesAvoiding(best, params, base.keptDisks());
    bestResult.collapsedEdges = cutCollapses + collapses;
    if (collapses > 0)
    {
      collapsed.emplace(best, splitter, params, 1.0, none, progress.sub(0.95, 1.0));
      collapsed->prepare();
      collapsed->keepWedges(base);
      collapsed->takeShortEdges(base);
      bestResult.delaunayFlips += collapsed->flips();
    }
    Refiner& mender = collapsed ? *collapsed : polish;
    const std::size_t flipsBefore = mender.flips();
    mender.limitBudget(budgetLeft());
    const RefinementResult mended = mender.run();
    addInsertions(mended);
    // Edges the smoothing, the collapses or a flip made longer than maximumEdgeLength.
    const std::size_t splits = mender.splitLongEdges();
    sized += splits;
    bestResult.delaunayFlips += mender.flips() - flipsBefore;
    if (splits == 0)
    {
      // (The run counted what it left, on the mesh as it is: no sweep again.)
      counted = mender.angleAfterRun();
      takeCount(mended);
    }
  }
  Refiner* final = collapsed ? &*collapsed : &polish; // the refiner of the mesh kept
  // (An earlier pass's count and smallest angle are never looked at: the last pass's are the
  // result's. At 1 M the count is a sweep of 0.03 s.)
  double angle = counted ? *counted : (last ? final->countBad(bestResult) : 0.0);
  std::vector<Zone> near;                             // (finisher's zones)
  std::optional<Refiner> finisher;
  std::optional<RegionMesh> finished;
  if (last && params.minimumAngle > 0.0 && angle < params.minimumAngle - 1e-9)
  {
    // (5, after the last pass) The cautious run left triangles below minimumAngle that an
    // insertion may mend (a boundary split it refused, a sliver at a lake's shore: lake126
    // of random_lakes_countries.py 118 130, 27.3 degrees): a bold run, bold only within
    // twice their longest edge of them, on a copy, kept as the runs of 4 are (a larger
    // smallest angle, or as large with fewer triangles below minimumAngle).
    for (const int t : final->mendableBad())
    {
      near.push_back(final->zoneAround(t));
    }
  }
  // A zone's bold insertions may leave a triangle below the angle to beat beside it (lake303
  // of random_lakes_countries.py 300 306: its worst spot mended, a 27.7-degree triangle made
  // next to it): the run is then made again, bold in those triangles' zones too, up to
  // kFinisherTries runs.
  for (int attempt = 0; attempt < kFinisherTries && !near.empty(); ++attempt)
  {
    finisher.reset(); // (a refiner of the copy before, not kept: it goes before its mesh)
    finished.emplace(roomyCopy(best));
    finisher.emplace(*finished, splitter, params, kBoldFloor, near, progress.sub(1.0, 1.0));
    finisher->boldInside();
    finisher->prepare();
    finisher->keepWedges(base);
    finisher->takeShortEdges(base);
    finisher->limitBudget(budgetLeft());
    const RefinementResult r = finisher->run();
    const double after = finisher->angleAfterRun();
    if (after > angle + 1e-9 ||
      (after >= angle - 1e-9 && r.badTrianglesLeft < bestResult.badTrianglesLeft))
    {
      angle = std::max(after, angle);
      addInsertions(r);
      bestResult.delaunayFlips += r.delaunayFlips;
      takeCount(r);
      final = &*finisher;
      break;
    }
    const std::size_t zones = near.size();
    finisher->zonesBelow(angle, near);
    if (near.size() == zones)
    {
      break; // (no triangle below the angle to beat: the same run again)
    }
  }
  if (last)
  {
    bestResult.minimumAngle = angle;
  }
  bestResult.keptCorners = keptCorners;
  bestResult.extendedWedges = extendedWedges;
  bestResult.keptCornerRadius = std::move(keptRadius);
  bestResult.keptCornerOutline = std::move(keptOutline);
  bestResult.keptCornerTriangles = final->keptBad();
  bestResult.sizeVertices = sized;
  bestResult.curveVertices = recovered + followed;
  bestResult.fidelitySplits = followed;
  if (handover)
  {
    // (For the next pass: the mesh's neighbours and more, from the refiner that changed it last.)
    *handover = final->takeHandover();
  }
  mesh = finisher && final == &*finisher ? std::move(*finished) : std::move(best);
  return bestResult;
}
} // namespace

RefinementResult refineDelaunay(RegionMesh& mesh,
  const BoundarySplitter& splitter,
  const RefinementParams& params,
  const ProgressReporter& progress,
  KnownCentroidRegions* known)
{
  validate(params);
  const std::size_t nt = mesh.triangles.size(), np = mesh.points.size();
  if (mesh.region.size() != nt || mesh.level.size() != nt)
  {
    throw ParameterError("refineDelaunay: " + std::to_string(nt) + " triangles but " +
      std::to_string(mesh.region.size()) + " regions and " + std::to_string(mesh.level.size()) +
      " levels");
  }
  for (std::size_t t = 0; t < nt; ++t)
  {
    for (int v : mesh.triangles[t])
    {
      if (v < 0 || static_cast<std::size_t>(v) >= np)
      {
        throw ParameterError("refineDelaunay: triangle " + std::to_string(t) + " refers to point " +
          std::to_string(v) + ", not in [0, " + std::to_string(np) + ")");
      }
    }
  }
  RefinementResult total;
  const int passes = params.curvePoint && params.regionAt ? kRecoveryPasses : 1;
  // The curve recovery's answers, from each pass for the next: most of the mesh is unchanged
  // between them. (Not for the last pass made again, which asks its own: its mesh's copy and
  // the last pass's answers, 26 MB at 1 M, would stay through the last pass, the refinement's
  // memory peak, for a pass that is seldom made again.)
  RecoveryMemo memos[2];
  // The caller's answers, for the first pass (as a memo without probes).
  RecoveryMemo given;
  if (known)
  {
    if (known->region.size() != known->triangles.size())
    {
      throw ParameterError("refineDelaunay: " + std::to_string(known->triangles.size()) +
        " known triangles but " + std::to_string(known->region.size()) + " known answers");
    }
    given.triangles = std::move(known->triangles);
    given.points = std::move(known->points);
    given.near = std::move(known->region);
    for (const auto& tri : given.triangles)
    {
      for (const int v : tri)
      {
        if (v < 0 || static_cast<std::size_t>(v) >= given.points.size())
        {
          throw ParameterError("refineDelaunay: a known triangle refers to point " +
            std::to_string(v) + ", not in [0, " + std::to_string(given.points.size()) + ")");
        }
      }
    }
  }
  Handover handover; // the mesh's neighbours and more, from each pass for the next (prepare())
  const bool amongRegions = std::any_of(params.wedgeCorners.begin(),
    params.wedgeCorners.end(),
    [](const SharpCorner& c) { return c.amongRegions; });
  for (int pass = 0; pass < passes; ++pass)
  {
    const bool last = pass + 1 == passes;
    const ProgressReporter part =
      progress.sub(static_cast<double>(pass) / passes, static_cast<double>(pass + 1) / passes);
    std::optional<RegionMesh> before;
    if (last && amongRegions && params.minimumAngle > 0.0)
    {
      before.emplace(roomyCopy(mesh, &part)); // (array by array, with progress between)
    }
    RecoveryMemo* memo =
      pass > 0 ? &memos[(pass - 1) % 2] : (given.triangles.empty() ? nullptr : &given);
    RecoveryMemo* keep = last ? nullptr : &memos[pass % 2];
    RefinementResult r =
      refinePass(mesh, splitter, params, last, passes > 1 && last, memo, keep, &handover, part);
    // (The pass let go of `memo` once its recovery had read it.)
    if (before && r.minimumAngle < params.minimumAngle - 1e-9)
    {
      // 7': the wedges among regions with a triangle below minimumAngle within twice their
      // reach are left out of the pass made again, which is kept when its smallest angle is
      // larger.
      RefinementParams without = params;
      const auto nearBad = [&](const SharpCorner& c)
      {
        const double reach = 2.0 * std::max(polylineLength(c.first), polylineLength(c.second));
        return c.amongRegions &&
          std::any_of(r.badCentroids.begin(),
            r.badCentroids.end(),
            [&](Vec2 g) { return norm2(g - c.apex) <= reach * reach; });
      };
      without.wedgeCorners.erase(
        std::remove_if(without.wedgeCorners.begin(), without.wedgeCorners.end(), nearBad),
        without.wedgeCorners.end());
      if (without.wedgeCorners.size() < params.wedgeCorners.size())
      {
        // (Its progress stays at the pass's end: the fractions never go back.)
        RefinementResult other = refinePass(*before,
          splitter,
          without,
          last,
          passes > 1,
          nullptr,
          nullptr,
          nullptr,
          part.sub(1.0, 1.0));
        if (other.minimumAngle > r.minimumAngle + 1e-9)
        {
          mesh = std::move(*before);
          r = std::move(other);
        }
      }
    }
    total.delaunayFlips += r.delaunayFlips;
    total.interiorVertices += r.interiorVertices;
    total.boundaryVertices += r.boundaryVertices;
    total.curveVertices += r.curveVertices;
    total.fidelitySplits += r.fidelitySplits;
    total.smoothingMoves += r.smoothingMoves;
    total.dissolvedCorners += r.dissolvedCorners;
    total.collapsedEdges += r.collapsedEdges;
    total.sizeVertices += r.sizeVertices;
    total.badTrianglesLeft = r.badTrianglesLeft;
    total.badTrianglesAtCorners = r.badTrianglesAtCorners;
    total.keptCorners = r.keptCorners;
    total.extendedWedges += r.extendedWedges;
    total.keptCornerTriangles = r.keptCornerTriangles;
    total.keptCornerRadius = r.keptCornerRadius;
    total.keptCornerOutline = r.keptCornerOutline;
    total.budgetReached = total.budgetReached || r.budgetReached;
    total.minimumAngle = r.minimumAngle;
  }
  return total;
}

} // namespace strata
