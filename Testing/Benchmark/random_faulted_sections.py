"""Random faulted sections in both input forms, for checks on models not seen before.

Run by hand, with Debian's Python (ParaView's VTK modules, shapely):
    /usr/bin/python3 Testing/Benchmark/random_faulted_sections.py FIRST_SEED LAST_SEED OUT_DIR
writes, for seeds FIRST_SEED..LAST_SEED-1, the same section twice: OUT_DIR/fNNN.vtp (Shared
curves form) and OUT_DIR/fNNN_loops.vtp (Loops form). A box 3 m, 1 km or 25 km wide and 0.2 to
0.6 times as high holds 4 to 8 layers between wavy horizons, cut by 1 to 4 normal faults
(straight or gently listric, dip 60-85 degrees, not crossing) from the bottom to the top; each
fault block's layers are moved down or up by throws of 2-50% of the mean layer thickness, and 1-2
thin layers (15-45% of it) end up in separate pieces where a throw is larger. 30-50% of the
horizons merge exactly into the horizon below over part of the width (true pinch-outs; the tip
is a sample point, the wedge angle there 1 to 15 degrees). Odd seeds have an angular
unconformity near the top (the faults stop at it, the 1-2 layers above are unfaulted, the tilted
layers below are cut by it); seeds 2, 5, 8, ... have a salt body (a smooth blob, centred on a
horizon away from the tips) cutting through the lower layers. Region id = layer index,
counted from the bottom (the same on both sides of a fault), the salt has the next id.
The line work (box, faults, each block's horizons up to just past its faults, unconformity,
salt outline) is noded with shapely, polygonized, each face labelled at a representative
point; faces below 1e-9 of the box's area go to their neighbour. The Loops form holds the rings
of each label's union, the Shared curves form the edges between different labels chained from
junction to junction (vertices where the number of such edges is not 2 or the label pair
changes); both use the same vertices. Mesh them with build/bin/triangulate_to_vtu and check them
with meshcheck.py (README, Measured).
"""
import math
import os
import sys
from collections import defaultdict

import numpy as np
import vtk
from shapely.geometry import LineString, MultiLineString, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import polygonize, unary_union

from random_sections import write_vtp  # same folder


def wave(x, width, amp, rng, terms=3):
    """A smooth random curve of about amp: a few sines over x."""
    y = np.zeros_like(x)
    for j in range(1, terms + 1):
        y += amp * rng.normal() / j * np.sin(2 * np.pi * rng.uniform(0.3, 1.5) * j * x / width
                                             + rng.uniform(0, 2 * np.pi))
    return y


def gentle(w, x, steepest):
    """w scaled down, if need be, so that its slope nowhere exceeds steepest."""
    s = np.abs(np.diff(w) / np.diff(x)).max()
    return w * (steepest / s) if s > steepest else w


def pinch_distance(x, kind, x0, x1):
    """Distance from x to the stretch where a pinched layer has no thickness (0 inside it)."""
    if kind == "left":  # no thickness left of x0
        return np.maximum(0.0, x - x0)
    if kind == "right":  # no thickness right of x0
        return np.maximum(0.0, x0 - x)
    return np.maximum(0.0, np.maximum(x0 - x, x - x1))  # none between x0 and x1


def thickness(full, d, slope):
    """full thickness, going to exactly 0 where d == 0 with the given slope (wedge angle)."""
    return full * (1.0 - np.exp(-slope * d / full))


def fault_trace(x_mid, y_mid, dip_top, listric, right, y_lo, y_hi, top):
    """x(y) samples of a normal fault through (x_mid, y_mid): dipping right (down toward +x) or
    left; its dip is dip_top at y = top and listric degrees less at y = 0."""
    ny = 2 if listric == 0 else 30
    ys = np.linspace(y_lo, y_hi, ny)
    fine = np.linspace(y_lo, y_hi, 2001)
    dip = np.radians(dip_top - listric * (1.0 - fine / top))
    dxdy = (-1.0 if right else 1.0) / np.tan(dip)
    xf = np.concatenate([[0.0], np.cumsum(0.5 * (dxdy[1:] + dxdy[:-1]) * np.diff(fine))])
    xf += x_mid - np.interp(y_mid, fine, xf)
    return ys, np.interp(ys, fine, xf)


def runs(mask):
    """Index ranges [a, b] of the runs of True in mask."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if not m and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(mask) - 1))
    return out


def rings_of(f):
    """The exterior and interior rings of polygon f."""
    return [f.exterior] + list(f.interiors)


def labelled_faces(lines, label, tiny):
    """The faces of the noded line work (counter-clockwise), each labelled label(its
    representative point), a face below tiny in area given the label it shares the most
    boundary with: (faces, labels, directed edge -> face on its left, tiny faces merged)."""
    faces = [orient(f, 1.0) for f in polygonize(unary_union(MultiLineString(lines)))]
    labels = [label(f.representative_point()) for f in faces]
    left_of = {}  # directed edge -> face on its left
    for i, f in enumerate(faces):
        for r in rings_of(f):
            c = list(r.coords)
            for a, b in zip(c[:-1], c[1:]):
                left_of[(a, b)] = i
    merged = 0
    for i in sorted(range(len(faces)), key=lambda i: faces[i].area):
        if faces[i].area >= tiny:
            break
        if labels[i] < 0:
            continue
        contact = defaultdict(float)
        for r in rings_of(faces[i]):
            c = list(r.coords)
            for a, b in zip(c[:-1], c[1:]):
                other = labels[left_of[(b, a)]] if (b, a) in left_of else -1
                if other != labels[i]:
                    contact[other] += math.dist(a, b)
        if contact:
            best = max((v, k) for k, v in contact.items() if k >= 0 or len(contact) == 1)[1]
            labels[i] = best
            merged += 1
    return faces, labels, left_of, merged


def shared_curves(left_of, labels, original, fresh_ids=False):
    """The edges between different labels (labels[left_of[edge]] on their left, -1 where no
    face is) chained from junction to junction (vertices where the number of such edges is not
    2 or the label pair changes), closed curves without junctions as they are. Vertices not in
    original where a dissolved line crossed a boundary go first. Returns (chains, each
    (vertices, (left, right)); the edges, id -> [a, b, left, right]; the vertices gone).
    fresh_ids: an edge joined over a vertex that goes takes an id above both it replaces (else
    the next above the edges left, as this script numbers them)."""
    # Boundary edges (different labels on both sides), with left and right labels.
    edges = {}  # id -> [a, b, left, right]
    seen = set()
    for (a, b), i in left_of.items():
        if (b, a) in seen:
            continue
        seen.add((a, b))
        left = labels[i]
        right = labels[left_of[(b, a)]] if (b, a) in left_of else -1
        if left != right:
            edges[len(edges)] = [a, b, left, right]
    at = defaultdict(set)
    for e, (a, b, _, _) in edges.items():
        at[a].add(e)
        at[b].add(e)

    def through(v, e_in, e_out):
        """e_in oriented to end at v, e_out to start at v: (a, L, R), (c, L, R)."""
        a, b, left, right = edges[e_in]
        first = (a, left, right) if b == v else (b, right, left)
        a, b, left, right = edges[e_out]
        second = (b, left, right) if a == v else (a, right, left)
        return first, second

    # Vertices where a dissolved line crossed a boundary: off the input vertices, on a
    # straight run between two boundary vertices with the same labels; they go.
    removed = set()
    for v in list(at):
        if v in original or len(at[v]) != 2:
            continue
        e1, e2 = sorted(at[v])
        (a, l1, r1), (c, l2, r2) = through(v, e1, e2)
        if (l1, r1) != (l2, r2) or a == c:
            continue
        ax, ay, cx_, cy_ = a[0], a[1], c[0], c[1]
        length = math.hypot(cx_ - ax, cy_ - ay)
        off = abs((cx_ - ax) * (v[1] - ay) - (cy_ - ay) * (v[0] - ax)) / length
        along = ((v[0] - ax) * (cx_ - ax) + (v[1] - ay) * (cy_ - ay)) / length ** 2
        if off > 1e-10 * length or not 0 < along < 1:
            continue
        del edges[e1], edges[e2]
        e = max(edges, default=max(e1, e2)) + 1
        if fresh_ids:
            e = max(e, e1 + 1, e2 + 1)
        edges[e] = [a, c, l1, r1]
        at[a] = (at[a] - {e1, e2}) | {e}
        at[c] = (at[c] - {e1, e2}) | {e}
        del at[v]
        removed.add(v)

    # Chains between junctions (degree != 2 or the label pair changes).
    junction = set()
    for v, es in at.items():
        if len(es) != 2:
            junction.add(v)
            continue
        e1, e2 = sorted(es)
        (_, l1, r1), (_, l2, r2) = through(v, e1, e2)
        if (l1, r1) != (l2, r2):
            junction.add(v)
    used = set()
    chains = []

    def walk(v, e):
        chain, pair = [v], None
        while True:
            used.add(e)
            a, b, left, right = edges[e]
            v, lr = (b, (left, right)) if a == v else (a, (right, left))
            assert pair is None or pair == lr
            pair = lr
            chain.append(v)
            if v in junction or v == chain[0]:
                return chain, pair
            e = next(iter(at[v] - {e}))

    for v in sorted(junction):
        for e in sorted(at[v]):
            if e not in used:
                chains.append(walk(v, e))
    for e in sorted(edges):
        if e not in used:  # a closed curve without junctions
            chains.append(walk(edges[e][0], e))
    return chains, edges, removed


def section(seed):
    """The section of one seed: (chains with left/right labels, loops with ids, description)."""
    rng = np.random.default_rng(seed)
    width = float(rng.choice([1000.0, 25000.0, 3.0]))
    height = width * rng.uniform(0.2, 0.6)
    nlayers = int(rng.integers(4, 9))
    has_unc = seed % 2 == 1
    has_salt = seed % 3 == 2
    nup = (1 if nlayers < 6 else int(rng.integers(1, 3))) if has_unc else 0
    nlow = nlayers - nup
    over = 0.02 * width  # horizons run this far past the box's sides

    # Abscissae shared by all horizons (the pinch-outs' tips among them).
    n = int(rng.integers(100, 250))
    base_x = np.linspace(0.0, width, n)

    # Pinch-outs: which horizons merge into the one below, where, at what angle.
    # Horizons: lower 1..nlow-1 (1 cannot pinch), the unconformity, upper 1..nup-1.
    candidates = [("low", k) for k in range(2, nlow)] + [("up", k) for k in range(1, nup)]
    total = (nlow - 1) + nup
    npinch = min(len(candidates), max(1, int(round(rng.uniform(0.3, 0.5) * total))))
    pinches = {}
    for i in rng.choice(len(candidates), npinch, replace=False):
        kind = ["left", "right", "middle"][int(rng.integers(0, 3))]
        x0 = width * (rng.uniform(0.15, 0.6) if kind == "left" else rng.uniform(0.4, 0.85)
                      if kind == "right" else rng.uniform(0.1, 0.6))
        x1 = min(x0 + width * rng.uniform(0.1, 0.4), 0.9 * width)
        pinches[candidates[int(i)]] = (kind, x0, x1, math.tan(math.radians(rng.uniform(1, 15))))
    tips = []
    for kind, x0, x1, _ in pinches.values():
        tips += [x0] if kind != "middle" else [x0, x1]
    dx = width / (n - 1)
    keep = [xi for xi in base_x if xi in (0.0, width) or min(abs(xi - t) for t in tips) > 0.3 * dx]
    X = np.array(sorted(set(keep + tips + [-over, width + over])))

    # Unconformity (base of the upper layers) and the upper horizons.
    unc_level = height * rng.uniform(0.68, 0.8) if has_unc else height
    U = unc_level + wave(X, width, 0.02 * height, rng) if has_unc else None
    upper = []  # upper horizons 1..nup-1 (absolute y), each above the one below
    if has_unc:
        tu = (height - unc_level) / (nup + 0.6)
        below = U
        for k in range(1, nup):
            f = tu * rng.uniform(0.6, 1.0)
            full = f + gentle(0.3 * f * np.sin(2 * np.pi * rng.uniform(0.3, 2) * X / width
                                               + rng.uniform(0, 6)), X, 0.05)
            p = pinches.get(("up", k))
            t = thickness(full, pinch_distance(X, p[0], p[1], p[2]), p[3]) if p else full
            below = below + t
            upper.append(below)

    # Faults: sorted by position, non-crossing, inside the box, stopping just past the
    # unconformity.
    nfaults = int(rng.integers(1, 5))
    y_lo = -0.02 * height
    for _attempt in range(200):
        mids = np.sort(rng.uniform(0.12, 0.88, nfaults)) * width
        if nfaults > 1 and np.diff(mids).min() < 0.12 * width:
            continue
        faults = []
        for xm in mids:
            dip_top = rng.uniform(60, 85)
            listric = 0.0 if rng.random() < 0.5 or dip_top < 63 else \
                rng.uniform(3, min(15, dip_top - 60))
            right = bool(rng.random() < 0.5)
            y_hi = 1.02 * height
            ys, xs = fault_trace(xm, 0.5 * unc_level, dip_top, listric, right, y_lo, y_hi,
                                 unc_level)
            if has_unc:  # cut just past where it meets the unconformity
                lo_y, hi_y = 0.0, height
                for _ in range(100):
                    mid = 0.5 * (lo_y + hi_y)
                    if mid < np.interp(np.interp(mid, ys, xs), X, U):
                        lo_y = mid
                    else:
                        hi_y = mid
                ys, xs = fault_trace(xm, 0.5 * unc_level, dip_top, listric, right, y_lo,
                                     lo_y + 0.02 * height, unc_level)
            faults.append((ys, xs, right, dip_top, listric))
        grid = np.linspace(0, height, 200)
        fx = [np.interp(grid, f[0], f[1]) for f in faults]
        if min(f.min() for f in fx) < 0.03 * width or max(f.max() for f in fx) > 0.97 * width:
            continue
        if all((fx[i + 1] - fx[i]).min() > 0.04 * width for i in range(nfaults - 1)):
            break
    else:
        raise RuntimeError("seed %d: no fault layout found" % seed)

    # Lower layers in units of the mean layer thickness T: base horizon, thicknesses, tilt,
    # block offsets (normal faults: the hanging wall goes down). The random draws come first,
    # then T is found so that the stack fits (the wedge slopes are in model units, hence the
    # few rounds).
    tilt = rng.uniform(0.4, 1.2) if has_unc else rng.uniform(0.0, 0.3)
    tilt *= 1 if rng.random() < 0.5 else -1
    base_wave = wave(X, width, 0.25, rng)
    factors, waves = [], []
    thin = set(rng.choice(np.arange(1, nlow - 1), min(nlow - 2, int(rng.integers(1, 3))),
                          replace=False).tolist())
    for k in range(1, nlow - 1):  # layer k lies between horizons k and k + 1
        factors.append(rng.uniform(0.15, 0.45) if k in thin else rng.uniform(0.7, 1.3))
        waves.append(0.35 * np.sin(2 * np.pi * rng.uniform(0.3, 2) * X / width
                                   + rng.uniform(0, 6)))
    throws = rng.uniform(0.02, 0.5, nfaults)
    offsets = [0.0]  # downward shift of each block, units of T
    for f, th in zip(faults, throws):
        offsets.append(offsets[-1] + (th if f[2] else -th))
    offsets = np.array(offsets) - np.mean(offsets)
    bottom = rng.uniform(0.3, 0.7)  # thinnest bottom layer, units of T
    own = []  # the samples of each block (between its faults at mid-height)
    mid_x = [np.interp(0.5 * unc_level, f[0], f[1]) for f in faults]
    for j in range(nfaults + 1):
        left = mid_x[j - 1] if j > 0 else 0.0
        right = mid_x[j] if j < nfaults else width
        own.append((X >= left) & (X <= right))

    def stack(T):
        h = [gentle(T * base_wave, X, 0.12) + T * tilt * (X - 0.5 * width) / width]
        for k in range(2, nlow):
            f = T * factors[k - 2]
            full = f + gentle(f * waves[k - 2], X, 0.05)
            p = pinches.get(("low", k))
            t = thickness(full, pinch_distance(X, p[0], p[1], p[2]), p[3]) if p else full
            h.append(h[-1] + t)
        low = min((h[0] - T * o)[m].min() for o, m in zip(offsets, own))
        shift = bottom * T - low
        return [[(hk + shift) - T * o for hk in h] for o in offsets]

    T = unc_level / (nlow + 1)
    for _ in range(8):
        blocks = stack(T)
        top = np.concatenate([b[-1][m] for b, m in zip(blocks, own)]) / T
        if has_unc:  # a quarter of the top lower horizon 0.3 T or more below the unconformity
            T = U.min() / (np.percentile(top, 25) + 0.3)
        else:  # the top layer at least 0.5 T thick
            T = height / (top.max() + 0.5)
    blocks = stack(T)

    # Salt: a smooth blob among the lower layers.
    salt = None
    if has_salt:
        ceiling = (U.min() if has_unc else height) - 0.05 * height
        rx = width * rng.uniform(0.05, 0.14)
        for _attempt in range(50):  # away from the pinch-outs' tips
            cx = width * rng.uniform(0.25, 0.75)
            if all(abs(cx - t) > 1.3 * rx for t in tips):
                break
        j = sum(int(cx > xm) for xm in mid_x)
        levels = [np.interp(cx, X, hk) for hk in blocks[j]]
        levels = [y for y in levels if 0.15 * height < y < ceiling - 0.1 * height]
        # centred on a horizon, so that it cuts a few layers
        cy = levels[int(rng.integers(0, len(levels)))] if levels else 0.5 * ceiling
        ry = T * rng.uniform(0.8, 2.0)
        th = np.linspace(0, 2 * np.pi, int(rng.integers(80, 160)), endpoint=False)
        rr = np.ones_like(th)
        for k in range(2, 6):
            rr += 0.15 * rng.normal() / k * np.cos(k * th + rng.uniform(0, 2 * np.pi))
        rr = np.clip(rr, 0.5, 1.5)
        px, py = rx * rr * np.cos(th), ry * rr * np.sin(th)
        sy = min(1.0, (ceiling - cy) / py.max(), (cy - 0.04 * height) / -py.min())
        sx = min(1.0, (0.95 * width - cx) / px.max(), (cx - 0.05 * width) / -px.min())
        ring = np.c_[cx + sx * px, cy + sy * py]
        salt = Polygon(ring)
        assert salt.is_valid

    # The line work.
    box = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height), (0.0, 0.0)]
    lines = [LineString(box)]
    fault_lines = [LineString(np.c_[f[1], f[0]]) for f in faults]
    lines += fault_lines
    for j, block in enumerate(blocks):
        for hk in block:
            lo, hi = 0, len(X) - 1
            line = LineString(np.c_[X, hk])
            if j > 0:  # from the last sample before the left fault
                cut = line.intersection(fault_lines[j - 1])
                xs = [p.x for p in getattr(cut, "geoms", [cut])] if not cut.is_empty else \
                    [faults[j - 1][1].min()]
                lo = max(0, int(np.searchsorted(X, min(xs), "left")) - 1)
            if j < len(faults):  # to the first sample after the right fault
                cut = line.intersection(fault_lines[j])
                xs = [p.x for p in getattr(cut, "geoms", [cut])] if not cut.is_empty else \
                    [faults[j][1].max()]
                hi = min(len(X) - 1, int(np.searchsorted(X, max(xs), "right")))
            mask = np.zeros(len(X), bool)
            mask[lo:hi + 1] = True
            if has_unc:  # up to the first sample above the unconformity
                below_unc = hk <= U
                below_unc = below_unc | np.r_[below_unc[1:], False] | np.r_[False, below_unc[:-1]]
                mask &= below_unc
            for a, b in runs(mask):
                if b > a:
                    lines.append(LineString(np.c_[X[a:b + 1], hk[a:b + 1]]))
    if has_unc:
        lines += [LineString(np.c_[X, U])] + [LineString(np.c_[X, g]) for g in upper]
    if salt is not None:
        lines.append(LineString(list(salt.exterior.coords)))
    original = set()
    for line in lines:
        original.update(line.coords)

    salt_id = nlayers

    def label(q):
        x, y = q.x, q.y
        if not (0 < x < width and 0 < y < height):
            return -1
        if salt is not None and salt.contains(q):
            return salt_id
        if has_unc and y > np.interp(x, X, U):
            return nlow + sum(int(y > np.interp(x, X, g)) for g in upper)
        j = sum(int(x > np.interp(y, f[0], f[1])) for f in faults)
        return sum(int(y > np.interp(x, X, hk)) for hk in blocks[j])

    # Faces, their labels, tiny faces to their neighbour.
    tiny = 1e-9 * width * height
    faces, labels, left_of, merged = labelled_faces(lines, label, tiny)
    # Shared curves: the boundary edges chained between junctions.
    chains, edges, removed = shared_curves(left_of, labels, original)

    # Loops: the rings of each label's union, on the same vertices.
    edge_labels = {frozenset((a, b)): (left, right) for a, b, left, right in edges.values()}
    loops = []
    for lab in sorted(set(labels) - {-1}):
        union = unary_union([faces[i] for i in range(len(faces)) if labels[i] == lab])
        count = 0
        for part in getattr(union, "geoms", [union]):
            for r in rings_of(part):
                if Polygon(r).area < tiny:
                    continue
                c = [p for p in r.coords if p not in removed]
                if c[0] != c[-1]:
                    c.append(c[0])
                for a, b in zip(c[:-1], c[1:]):
                    assert lab in edge_labels[frozenset((a, b))], (seed, lab, a, b)
                count += len(c) - 1
                loops.append((c, lab))
        assert count == sum(1 for lr in edge_labels.values() if lab in lr), (seed, lab)
    info = ("%s m wide, %.0f m high: %d layers, %d faults (%s), %d pinch-outs%s%s; "
            "%d faces, %d tiny merged" % (
                ("%g" % width), height, nlayers, nfaults,
                ", ".join("%s %.0f%s" % ("R" if f[2] else "L", f[3], " listric %.0f" % f[4]
                                         if f[4] else "") for f in faults),
                npinch, ", unconformity" if has_unc else "", ", salt" if has_salt else "",
                len(faces), merged))
    return chains, loops, info


def polydata(curves, arrays, name, source):
    """PolyData of polylines on shared points (one id per distinct vertex)."""
    pd = vtk.vtkPolyData()
    points = vtk.vtkPoints()
    points.SetDataTypeToDouble()
    ids = {}
    lines = vtk.vtkCellArray()
    for c in curves:
        lines.InsertNextCell(len(c))
        for p in c:
            if p not in ids:
                ids[p] = points.InsertNextPoint(p[0], p[1], 0.0)
            lines.InsertCellPoint(ids[p])
    pd.SetPoints(points)
    pd.SetLines(lines)
    for array_name, values in arrays:
        a = vtk.vtkIntArray()
        a.SetName(array_name)
        for v in values:
            a.InsertNextValue(int(v))
        pd.GetCellData().AddArray(a)
    for key, text in (("Name", name), ("Source", source)):
        s = vtk.vtkStringArray()
        s.SetName(key)
        s.InsertNextValue(text)
        pd.GetFieldData().AddArray(s)
    return pd


def model(seed, out):
    """Writes OUT/fNNN.vtp (Shared curves) and OUT/fNNN_loops.vtp (Loops) of one seed."""
    chains, loops, info = section(seed)
    name = "f%03d" % seed
    source = "random_faulted_sections.py seed %d: %s" % (seed, info)
    write_vtp(os.path.join(out, name + ".vtp"), polydata(
        [c for c, _ in chains], [("LeftRegion", [p[0] for _, p in chains]),
                                 ("RightRegion", [p[1] for _, p in chains])], name, source))
    write_vtp(os.path.join(out, name + "_loops.vtp"), polydata(
        [c for c, _ in loops], [("RegionId", [r for _, r in loops])], name + "_loops", source))
    print("%s: %s; %d curves, %d loops" % (name, info, len(chains), len(loops)))


if __name__ == "__main__":
    first, last, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    os.makedirs(out, exist_ok=True)
    for s in range(first, last):
        model(s, out)
