"""Random geological cross-sections of four kinds, in the Shared curves form.

Run with Debian's Python (ParaView's VTK modules, numpy, scipy, shapely):
    /usr/bin/python3 random_geology.py FIRST_SEED LAST_SEED OUT_DIR
writes, for seeds FIRST_SEED..LAST_SEED-1, OUT_DIR/gNNN_KIND.vtp; the kind is seed % 4:
  0 diapir:       a box 1-30 km wide, 0.3-0.6 times as high, 3-8 wavy horizons dragged up
                  near a salt diapir: a closed salt body (its own region) rising from the
                  bottom layer (its root inside it or cut by the section's base), with a
                  mushroom cap whose lips overhang the stem; horizons end on the salt outline
                  (those below the overhang on the stem).
  1 graben:       3-8 wavy horizons offset by 2 or 3 planar normal faults (dip 55-80 degrees)
                  from the bottom to the top: the outer two dip toward each other (a graben,
                  the middle block dropped), a third one inside either way; throws 2-30% of
                  the mean layer thickness; 70% of the seeds give each fault block its own
                  region ids (the faults are curves from bottom to top), the others the
                  layer's index in all blocks (only the throws' stretches of faults remain).
  2 elongated:    height / width 0.005-0.03, 3-6 wavy horizons across, 1-3 layers thinned to
                  5% of their thickness over part of the width.
  3 unconformity: 2-6 horizons dipping 2-15 degrees (slightly wavy, left or right), at least
                  two of them truncated (at small angles) by a wavy erosional surface, 0-2
                  nearly flat horizons above it.
Horizons are sampled at 30-300 points. The line work (box, horizons past their ends, faults,
unconformity, salt outline) is noded with shapely, polygonized, and each face labelled at a
representative point by the model's own rule; faces below 1e-9 of the box's area go to their
neighbour. The curves are the edges between different labels chained from junction to
junction (vertices where the number of such edges is not 2 or the label pair changes);
vertices added by noding where a dissolved line crossed a curve are dropped. Region ids are
renumbered 0..n-1 (bottom up, salt last). Every model is checked: noding the curves again
adds no vertex and merges no segment (curves meet only at shared end points).
"""
import math
import os
import sys
from collections import defaultdict

import numpy as np
from scipy.interpolate import splev, splprep
from shapely.geometry import LineString, MultiLineString, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import polygonize, unary_union

# same folder
from random_faulted_sections import (gentle, labelled_faces, polydata, rings_of, runs,
                                     shared_curves, wave)
from random_sections import write_vtp

KINDS = ["diapir", "graben", "elongated", "unconformity"]


# ----------------------------------------------------------------------------- helpers
def bump(x, a, b, ramp):
    """1 on [a, b], 0 farther than ramp from it, smooth in between."""
    d = np.maximum(0.0, np.maximum(a - x, x - b)) / ramp
    return np.where(d < 1, 0.5 * (1 + np.cos(np.pi * np.minimum(d, 1))), 0.0)


def stack(X, width, n, rng, thin=(), amp=0.3, var=0.6):
    """n horizons over X, each above the one below (positive thicknesses), not yet scaled:
    the base wavy (amp), the thicknesses 1 +- var, layers in `thin` down to 5% over a stretch."""
    h = [wave(X, width, amp, rng)]
    for k in range(1, n):
        t = rng.uniform(1 - var, 1 + var) * (1 + var * np.sin(2 * np.pi * rng.uniform(0.2, 2) * X / width
                                                      + rng.uniform(0, 6)) * rng.uniform(0, 1))
        if k in thin:
            a = width * rng.uniform(0.05, 0.6)
            b = a + width * rng.uniform(0.05, 0.35)
            t = t * (1 - 0.95 * bump(X, a, b, width * rng.uniform(0.03, 0.2)))
        h.append(h[-1] + t)
    return h


def fit(h, lo, hi):
    """The horizons h mapped linearly (ordering kept) onto [lo, hi]."""
    a, b = min(x.min() for x in h), max(x.max() for x in h)
    return [lo + (x - a) * (hi - lo) / (b - a) for x in h]


def sizes(rng, lo, hi):
    width = float(math.exp(rng.uniform(math.log(1000.0), math.log(30000.0))))
    return round(width, 1), width * rng.uniform(lo, hi)


# ----------------------------------------------------------------------------- kinds
def diapir(rng):
    width, height = sizes(rng, 0.3, 0.6)
    nh = int(rng.integers(3, 9))
    n = int(rng.integers(30, 301))
    over = 0.02 * width
    X = np.linspace(-over, width + over, n)
    for _attempt in range(500):
        cx = width * rng.uniform(0.35, 0.65)
        s_b = width * rng.uniform(0.03, 0.07)      # stem half width at its root
        s_n = s_b * rng.uniform(0.5, 1.0)           # at its neck
        y_n = height * rng.uniform(0.45, 0.7)       # the neck
        y_t = y_n + height * rng.uniform(0.1, 0.22)  # the cap's top
        if y_t > 0.9 * height:
            continue
        side = []
        for sgn in (1, -1):
            R = s_n * rng.uniform(2.0, 4.0)
            d = height * rng.uniform(0.03, 0.12)     # the lip hangs this far below the neck
            cap = y_t - (y_n - d)
            side.append(sgn * np.array([
                [s_n, y_n], [s_n + 0.45 * (R - s_n), y_n - 0.55 * d],
                [0.93 * R, y_n - d], [R, y_n - d + 0.3 * cap], [0.65 * R, y_t - 0.12 * cap]]))
            side[-1][:, 1] *= sgn
        root = rng.random() < 0.35                  # the root cut by the section's base
        y_b = -0.1 * height if root else None
        # Horizons: a stack over the height, dragged up near the diapir.
        thin = set(rng.choice(np.arange(1, nh), int(rng.integers(0, 2)), replace=False).tolist()) \
            if nh > 2 else set()
        h = stack(X, width, nh, rng, thin)
        drag = rng.uniform(0.0, 0.25) * np.exp(-((X - cx) / (width * rng.uniform(0.08, 0.2))) ** 2)
        h = [x + drag for x in fit(h, 0, 1)]
        h = fit(h, height * 0.08, height * 0.93)
        h1 = float(np.interp(cx, X, h[0]))
        if h1 < 0.12 * height or h1 > y_n - 0.15 * height:
            continue
        if not root:
            y_b = h1 * rng.uniform(0.25, 0.7)
        s_m = 0.5 * (s_b + s_n) * rng.uniform(0.85, 1.15)
        right = [[s_b, y_b], [s_m, 0.5 * (y_b + y_n)]] + side[0].tolist()
        left = side[1].tolist()[::-1] + [[-s_m, 0.5 * (y_b + y_n)], [-s_b, y_b]]
        ctrl = np.array(right + [[0.0, y_t]] + left + [[0.0, y_b - 0.4 * s_b]])
        ctrl[:, 0] += cx
        ctrl += rng.normal(0, 0.004 * width, ctrl.shape)
        tck, _ = splprep([np.r_[ctrl[:, 0], ctrl[0, 0]], np.r_[ctrl[:, 1], ctrl[0, 1]]],
                         s=0, per=1, k=3)
        m = int(rng.integers(60, 301))
        u = np.linspace(0, 1, m, endpoint=False)
        px, py = splev(u, tck)
        salt = Polygon(np.c_[px, py])
        if not salt.is_valid or px.min() < 0.05 * width or px.max() > 0.95 * width or \
                py.max() > 0.92 * height:
            continue
        # The overhang: on both sides a vertical line through the lip meets salt only well
        # above the root.
        ok = True
        for sgn in (1, -1):
            xs = cx + sgn * 0.5 * (s_n + abs(side[0 if sgn > 0 else 1][2, 0]))
            cut = salt.intersection(LineString([(xs, -height), (xs, 2 * height)]))
            if cut.is_empty or cut.bounds[1] < max(y_b, 0) + 0.1 * height:
                ok = False
        if ok:
            break
    else:
        raise RuntimeError("no diapir found")
    box = Polygon([(0, 0), (width, 0), (width, height), (0, height)])
    lines = [LineString(box.exterior.coords), LineString(salt.exterior.coords)]
    lines += [LineString(np.c_[X, y]) for y in h]
    salt_id = nh + 1

    def label(q):
        if not box.contains(q):
            return -1
        if salt.contains(q):
            return salt_id
        return sum(int(q.y > np.interp(q.x, X, y)) for y in h)

    info = "%g m wide, %.0f m high: %d horizons, %d points each, salt %s (%d points)%s" % (
        width, height, nh, n, "rooted on the base" if root else "rooted in the bottom layer",
        m, ", thinned layers %s" % sorted(thin) if thin else "")
    return lines, label, box, info


def graben(rng):
    nh = int(rng.integers(3, 9))
    n = int(rng.integers(30, 301))
    nf = 2 if rng.random() < 0.6 else 3
    for _attempt in range(1000):
        width, height = sizes(rng, 0.2, 0.5)
        xt = sorted(rng.uniform(0.1, 0.9, nf) * width)
        dips = rng.uniform(55, 80, nf)
        dirs = [1] + [int(rng.choice([-1, 1])) for _ in range(nf - 2)] + [-1]  # +1: dips right
        ys = np.linspace(-0.02 * height, 1.02 * height, int(rng.integers(30, 301)))
        faults = [xt[i] + dirs[i] * (height - ys) / math.tan(math.radians(dips[i]))
                  for i in range(nf)]
        if min(f.min() for f in faults) < 0.04 * width or \
                max(f.max() for f in faults) > 0.96 * width:
            continue
        if all((faults[i + 1] - faults[i]).min() > 0.05 * width for i in range(nf - 1)):
            break
    else:
        raise RuntimeError("no graben found")
    over = 0.02 * width
    X = np.linspace(-over, width + over, n)
    T = height / (nh + 1)
    throws = rng.uniform(0.02, 0.3, nf) * T
    offsets = [0.0]  # upward shift of each block
    for d, t in zip(dirs, throws):
        offsets.append(offsets[-1] - t if d > 0 else offsets[-1] + t)
    lo = 0.07 * height - min(0.0, min(offsets))
    hi = 0.93 * height - max(0.0, max(offsets))
    thin = set(rng.choice(np.arange(1, nh), int(rng.integers(0, 2)), replace=False).tolist())
    h = fit(stack(X, width, nh, rng, thin), lo, hi)
    blocks = [[y + o for y in h] for o in offsets]

    def fx(i, y):
        return np.interp(y, ys, faults[i])

    box = Polygon([(0, 0), (width, 0), (width, height), (0, height)])
    lines = [LineString(box.exterior.coords)] + [LineString(np.c_[f, ys]) for f in faults]
    # Each block's horizons, cut a little past its faults.
    margin = 0.01 * width
    for j, block in enumerate(blocks):
        left = np.full_like(ys, -2 * over) if j == 0 else faults[j - 1] - margin
        right = np.full_like(ys, width + 2 * over) if j == nf else faults[j] + margin
        region = Polygon(np.r_[np.c_[left, ys], np.c_[right, ys][::-1]])
        for y in block:
            piece = LineString(np.c_[X, y]).intersection(region)
            for g in getattr(piece, "geoms", [piece]):
                if isinstance(g, LineString) and not g.is_empty:
                    lines.append(g)

    own = rng.random() < 0.7  # each block its own region ids (else the layer's index)

    def label(q):
        if not box.contains(q):
            return -1
        j = sum(int(q.x > fx(i, q.y)) for i in range(nf))
        return (j * (nh + 1) if own else 0) + \
            sum(int(q.y > np.interp(q.x, X, y)) for y in blocks[j])

    info = "%g m wide, %.0f m high: %d horizons, %d points each, %d faults (%s), throws %s of T%s" % (
        width, height, nh, n, nf,
        ", ".join("%s %.0f" % ("R" if d > 0 else "L", a) for d, a in zip(dirs, dips)),
        "/".join("%.0f%%" % (100 * t / T) for t in throws),
        ", thinned layers %s" % sorted(thin) if thin else "")
    info += ", ids per block" if own else ", ids per layer"
    return lines, label, box, info


def elongated(rng):
    width = float(math.exp(rng.uniform(math.log(1000.0), math.log(30000.0))))
    width = round(width, 1)
    ratio = rng.uniform(0.005, 0.03)
    height = width * ratio
    nh = int(rng.integers(3, 7))
    n = int(rng.integers(30, 301))
    over = 0.02 * width
    X = np.linspace(-over, width + over, n)
    thin = set(rng.choice(np.arange(1, nh), min(nh - 1, int(rng.integers(1, 4))),
                          replace=False).tolist())
    h = fit(stack(X, width, nh, rng, thin), height * rng.uniform(0.03, 0.15),
            height * rng.uniform(0.85, 0.97))
    box = Polygon([(0, 0), (width, 0), (width, height), (0, height)])
    lines = [LineString(box.exterior.coords)] + [LineString(np.c_[X, y]) for y in h]

    def label(q):
        if not box.contains(q):
            return -1
        return sum(int(q.y > np.interp(q.x, X, y)) for y in h)

    info = "%g m wide, %.1f m high (ratio %.4f): %d horizons, %d points each, thinned layers %s" % (
        width, height, ratio, nh, n, sorted(thin))
    return lines, label, box, info


def unconformity(rng):
    nh = int(rng.integers(3, 9))
    nup = min(int(rng.integers(0, 3)), nh - 3)
    nlow = nh - 1 - nup
    n = int(rng.integers(30, 301))
    for _attempt in range(500):
        width, height = sizes(rng, 0.2, 0.5)
        over = 0.02 * width
        X = np.linspace(-over, width + over, n)
        u0 = height * rng.uniform(0.5, 0.8)
        U = u0 + wave(X, width, height * rng.uniform(0.01, 0.04), rng, terms=4)
        ceiling = height * 0.95
        if U.max() > ceiling - 0.08 * height * (nup + 1) or U.min() < 0.3 * height:
            continue
        dip = rng.uniform(2, 15)
        sgn = 1 if rng.random() < 0.5 else -1
        tilt = sgn * math.tan(math.radians(dip)) * (X - 0.5 * width)
        rise = math.tan(math.radians(dip)) * width
        low, high = -0.4 * rise + rng.uniform(0.05, 0.4) * u0, u0 + 0.5 * rise
        if high - low < 0.3 * u0:
            continue
        d = (high - low) / nlow  # vertical spacing
        steep = 0.3 * math.tan(math.radians(dip))  # the waves' steepest slope
        low_h = [low + d * (k + 0.5 + rng.uniform(-0.2, 0.2)) + tilt +
                 gentle(wave(X, width, 0.06 * d, rng), X, steep) for k in range(nlow)]
        if any((low_h[k + 1] - low_h[k]).min() < 0.2 * d for k in range(nlow - 1)):
            continue
        # enough of them seen below the unconformity, inside the box
        inside = (X > 0) & (X < width)
        seen = sum(int(((y > 0) & (y < U) & inside).any()) for y in low_h)
        cut = sum(int(((y > U) & inside).any() and ((y < U) & (y > 0) & inside).any())
                  for y in low_h)
        if seen >= 2 and cut >= min(2, nlow):
            break
    else:
        raise RuntimeError("no unconformity found")
    up = []
    if nup:
        a = U.max() + 0.04 * height
        levels = np.sort(rng.uniform(a, ceiling, nup))
        up = [lv + wave(X, width, 0.003 * height, rng) for lv in levels]
        if nup == 2 and (up[1] - up[0]).min() < 0.01 * height:
            up = up[:1]
    box = Polygon([(0, 0), (width, 0), (width, height), (0, height)])
    lines = [LineString(box.exterior.coords), LineString(np.c_[X, U])]
    lines += [LineString(np.c_[X, y]) for y in up]
    # The dipping horizons up to a little past the unconformity.
    for y in low_h:
        below = y <= U
        below = below | np.r_[below[1:], False] | np.r_[False, below[:-1]]
        for a, b in runs(below):
            if b > a:
                lines.append(LineString(np.c_[X[a:b + 1], y[a:b + 1]]))

    def label(q):
        if not box.contains(q):
            return -1
        if q.y > np.interp(q.x, X, U):
            return nlow + 1 + sum(int(q.y > np.interp(q.x, X, y)) for y in up)
        return sum(int(q.y > np.interp(q.x, X, y)) for y in low_h)

    info = "%g m wide, %.0f m high: %d dipping horizons (dip %.1f %s), %d seen, %d cut, %d flat above, %d points each" % (
        width, height, nlow, dip, "R" if sgn < 0 else "L", seen, cut, len(up), n)
    return lines, label, box, info


# ----------------------------------------------------------------------------- line work
def curves_of(lines, label, area):
    """The shared curves (chains with (left, right) labels) of the noded line work, as
    random_faulted_sections.py finds them (but an edge joined over a dropped vertex gets an id
    above both it replaces): (chains, faces, tiny faces merged)."""
    original = set()
    for line in lines:
        original.update(line.coords)
    faces, labels, left_of, merged = labelled_faces(lines, label, 1e-9 * area)
    chains, _, _ = shared_curves(left_of, labels, original, fresh_ids=True)
    return chains, len(faces), merged


def check(chains):
    """Curves meet only at shared end points (noding them again adds no vertex and merges no
    segment; no curve end dangles); every face of the curves' arrangement sees one region id
    on all its sides (left of a curve walked forward: its LeftRegion), and -1 outside."""
    segs = sum(len(c) - 1 for c, _ in chains)
    noded = unary_union(MultiLineString([LineString(c) for c, _ in chains]))
    nsegs = sum(len(g.coords) - 1 for g in getattr(noded, "geoms", [noded]))
    assert nsegs == segs, "noding the curves again: %d segments, not %d" % (nsegs, segs)
    ends = defaultdict(int)
    for c, _ in chains:
        if c[0] != c[-1]:
            ends[c[0]] += 1
            ends[c[-1]] += 1
    assert all(k >= 2 for k in ends.values()), "a dangling curve end"
    side = {}  # directed segment -> region on its left
    for c, (left, right) in chains:
        for a, b in zip(c[:-1], c[1:]):
            assert (a, b) not in side and (b, a) not in side, "a segment twice"
            side[(a, b)], side[(b, a)] = left, right
    covered = set()
    for f in polygonize([LineString(c) for c, _ in chains]):
        f = orient(f, 1.0)
        seen = set()
        for r in rings_of(f):
            c = list(r.coords)
            for a, b in zip(c[:-1], c[1:]):
                seen.add(side[(a, b)])
                covered.add((a, b))
        assert len(seen) == 1 and -1 not in seen, "a face with sides %s" % sorted(seen)
    for ab, lab in side.items():
        if ab not in covered:
            assert lab == -1, "outside the curves, region %d" % lab


def relabel(chains):
    """Region ids renumbered 0..n-1 in the order of the raw labels."""
    ids = sorted(set(l for _, lr in chains for l in lr) - {-1})
    new = {r: i for i, r in enumerate(ids)}
    new[-1] = -1
    return [(c, (new[l], new[r])) for c, (l, r) in chains], len(ids)


def model(seed, out):
    kind = KINDS[seed % 4]
    rng = np.random.default_rng([seed, 68])
    lines, label, box, info = globals()[kind](rng)
    chains, nfaces, merged = curves_of(lines, label, box.area)
    check(chains)
    chains, nregions = relabel(chains)
    name = "g%03d_%s" % (seed, kind)
    source = "random_geology.py seed %d (%s): %s; %d faces, %d tiny merged, %d regions, %d curves" % (
        seed, kind, info, nfaces, merged, nregions, len(chains))
    write_vtp(os.path.join(out, name + ".vtp"), polydata(
        [c for c, _ in chains], [("LeftRegion", [lr[0] for _, lr in chains]),
                                 ("RightRegion", [lr[1] for _, lr in chains])], name, source))
    print("%s: %s" % (name, source))


if __name__ == "__main__":
    first, last, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    os.makedirs(out, exist_ok=True)
    for s in range(first, last):
        model(s, out)
