"""Clearance between the collision hulls of parts that move against each other.

Hulls of neighbouring parts that overlap at rest are separated (shrunk, clipped on the plane
between them, or split around a hinge axis), and the hulls a part's swept volume hits are cut
so that every joint can travel its range. ``clear_asset_hulls`` runs this over a whole asset
and says what it changed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from rest2art.collision.hulls import closed_hull
from rest2art.config import CollisionConfig
from rest2art.geometry.basics import boxes_overlap, convex_overlap, perpendicular_basis, separating_overlaps
from rest2art.joints.sweep import farthest_along, range_values, swept_points
from rest2art.tolerances import EMPTY_VOLUME, FACING_COS, PARALLEL_COS, PERPENDICULAR_COS, SAME_POINT


def boxes_touch(hulls_a: list[trimesh.Trimesh], hulls_b: list[trimesh.Trimesh], pad: float = 0.0) -> np.ndarray:
    """(A, B) bool: whose axis-aligned bounding boxes (those of A grown by ``pad``, m) touch."""
    lo_a = np.array([h.bounds[0] for h in hulls_a]) - pad
    hi_a = np.array([h.bounds[1] for h in hulls_a]) + pad
    return boxes_overlap(lo_a, hi_a, np.array([h.bounds[0] for h in hulls_b]), np.array([h.bounds[1] for h in hulls_b]))


def shrink_hull(hull: trimesh.Trimesh, distance: float) -> trimesh.Trimesh | None:
    """The convex ``hull`` with every face plane moved inward by ``distance`` (m): a true
    inward offset, unlike scaling, which barely thins a flat panel. None when nothing is left."""
    from scipy.spatial import HalfspaceIntersection, QhullError

    hull = hull.convex_hull
    normals = hull.face_normals
    offsets = -np.einsum("ij,ij->i", normals, hull.triangles[:, 0]) + distance  # n.x + c <= 0 inside
    centre = hull.vertices.mean(axis=0)
    if np.any(normals @ centre + offsets >= 0):  # thinner than 2 x distance somewhere
        return None
    try:
        corners = HalfspaceIntersection(np.column_stack([normals, offsets]), centre).intersections
    except QhullError:
        return None
    small = closed_hull(corners)
    return small if small is not None and small.volume >= EMPTY_VOLUME else None


def clip_hull(hull: trimesh.Trimesh, normal: np.ndarray, offset: float, min_volume: float = EMPTY_VOLUME
              ) -> tuple[trimesh.Trimesh | None, np.ndarray]:
    """The part of the convex ``hull`` where normal . x <= ``offset`` (m), or None when too
    little is left, and the (K, 3) corners of the part cut away (empty when nothing was)."""
    v = np.asarray(hull.vertices, float)
    side = v @ normal - offset
    if np.all(side <= 0):
        return hull, np.zeros((0, 3))
    edges = np.asarray(hull.edges_unique)
    sa, sb = side[edges[:, 0]], side[edges[:, 1]]
    crossing = (sa > 0) != (sb > 0)
    t = sa[crossing] / (sa[crossing] - sb[crossing])
    cut = v[edges[crossing, 0]] + t[:, None] * (v[edges[crossing, 1]] - v[edges[crossing, 0]])
    removed = np.concatenate([v[side > 0], cut])
    small = closed_hull(np.concatenate([v[side <= 0], cut]))
    return (small if small is not None and small.volume >= min_volume else None), removed


def clip_to_solids(hulls: list[trimesh.Trimesh], solids: list[trimesh.Trimesh], axes: np.ndarray, margin: float,
                   min_volume: float = EMPTY_VOLUME) -> tuple[list[trimesh.Trimesh], int]:
    """``hulls`` cut back to the box, along the object's ``axes`` ((3, 3) rows, unit vectors),
    of the closed ``solids`` they stand for, grown by ``margin`` (m); hulls left with nothing are
    dropped. Returns the hulls and how many were cut. The solids decomposed for collision are
    decimated, and a decimated scan shell thickened again folds out by centimetres (furniture
    cabinet 60 scanned: a door's hulls 3 cm in front of its handle and 4 cm into the carcass;
    desk 99: a drawer's box 14 mm wider than its front, caught on the apron as it slides)."""
    if not solids or not hulls:
        return list(hulls), 0
    reach = np.concatenate([np.asarray(solid.vertices) for solid in solids]) @ axes.T
    lo, hi = reach.min(axis=0) - margin, reach.max(axis=0) + margin
    out, cut = [], 0
    for hull in hulls:
        clipped = hull
        for k, axis in enumerate(axes):
            for normal, offset in ((axis, hi[k]), (-axis, -lo[k])):
                if clipped is not None:
                    clipped = clip_hull(clipped, normal, offset, min_volume)[0]
        cut += clipped is not hull
        if clipped is not None:
            out.append(clipped)
    return out, cut


def split_around_axis(hull: trimesh.Trimesh, origin: np.ndarray, axis: np.ndarray, radius: float,
                      min_volume: float = EMPTY_VOLUME) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh]]:
    """Cut the convex ``hull`` by the square prism of half-width ``radius`` (m) around the line
    through ``origin`` along unit ``axis``: (pieces inside the prism, pieces outside), all convex
    (at most one inside and four outside)."""
    u, v = perpendicular_basis(axis)
    inside, outside = [hull], []
    for direction in (u, v):
        centre = float(origin @ direction)
        next_inside = []
        for piece in inside:
            high, _ = clip_hull(piece, -direction, -(centre + radius), min_volume)  # direction.x >= centre + r
            low, _ = clip_hull(piece, direction, centre - radius, min_volume)  # direction.x <= centre - r
            middle, _ = clip_hull(piece, direction, centre + radius, min_volume)
            middle = clip_hull(middle, -direction, -(centre - radius), min_volume)[0] if middle is not None else None
            outside += [p for p in (high, low) if p is not None]
            next_inside += [middle] if middle is not None else []
        inside = next_inside
    return inside, outside




PUSHED = ("button", "knob")
"""Parts whose slide may push them into their parent (buttons, plungers) and whose spindle may
turn in a hole of it (knobs, latches): a drawer or door that slid inwards would be a wrong
joint, for the validator to find, not a bore to carve."""


def carve_box(hull: trimesh.Trimesh, frame: np.ndarray, lo: np.ndarray, hi: np.ndarray,
              min_volume: float = EMPTY_VOLUME) -> list[trimesh.Trimesh]:
    """The convex ``hull`` less the box ``lo`` <= ``frame`` @ x <= ``hi`` (``frame`` (3, 3): unit
    axes as rows; ``lo``, ``hi`` (3,), m): at most six convex pieces, one beyond each face of the
    box (the exact convex split of a hull with a box-shaped hole or notch)."""
    pieces, rest = [], hull
    for k in range(3):
        for normal, offset in ((-frame[k], -hi[k]), (frame[k], lo[k])):  # beyond: e.x >= hi, e.x <= lo
            if rest is None:
                return pieces
            beyond, _ = clip_hull(rest, normal, offset, min_volume)
            pieces += [beyond] if beyond is not None else []
            rest, _ = clip_hull(rest, -normal, -offset, min_volume)
    return pieces


def pushes_into(axis: np.ndarray, child_points: np.ndarray, parent_lo: np.ndarray, parent_hi: np.ndarray) -> bool:
    """Whether a slide along unit ``axis`` drives a child ((N, 3) points at rest) into its parent
    (axis-aligned box ``parent_lo`` .. ``parent_hi``, m): the axis points against the outward
    normal of the box face the child sits on (the one its centre lies nearest to, or beyond), as
    a push button or plunger does and a drawer or sliding door does not."""
    centre = child_points.mean(axis=0)
    inside = np.r_[centre - parent_lo, parent_hi - centre]  # depth behind each face; < 0 beyond it
    k = int(np.argmin(inside))
    outward = np.eye(3)[k % 3] * (-1.0 if k < 3 else 1.0)
    return bool(axis @ outward < -FACING_COS)


def swept_box(moving: np.ndarray, joint, clearance: float, samples: int = 1) -> tuple[trimesh.Trimesh, np.ndarray,
                                                                                      np.ndarray, np.ndarray]:
    """The box the ``moving`` (N, 3) points pass through over ``joint``'s range, in the joint's
    frame (axis and two perpendiculars) at ``samples`` + 1 values from the lower limit to the
    upper (1 is exact for a slide), grown by ``clearance`` (m): (box mesh, (3, 3) frame rows,
    lo (3,), hi (3,) in that frame)."""
    axis = np.asarray(joint.axis, float)
    frame = np.vstack([*perpendicular_basis(axis), axis])
    points = swept_points(moving, joint.transform, range_values(joint.limit[0], joint.limit[1], samples,
                                                                with_lower=True))
    along = points @ frame.T
    lo, hi = along.min(axis=0) - clearance, along.max(axis=0) + clearance
    box = trimesh.creation.box(bounds=[lo, hi])
    box.apply_transform(np.vstack([np.column_stack([frame.T, np.zeros(3)]), [0, 0, 0, 1]]))
    return box, frame, lo, hi


def carve_bore(hulls: list[trimesh.Trimesh], moving: np.ndarray, joint, clearance: float,
               min_volume: float, log: ClearanceLog, samples: int = 1) -> list[trimesh.Trimesh]:
    """``hulls`` of a parent with the space the ``moving`` (N, 3) points (the vertices of the
    child's hulls at rest, one frame) pass through over ``joint``'s range removed (``swept_box``).
    A hull approximation fills the bore a button or plunger moves in, the hole a spindle turns
    in and the track a sliding door runs in; the mesh has them."""
    box, frame, lo, hi = swept_box(moving, joint, clearance, samples)
    out = []
    for hull in hulls:
        if convex_overlap(hull.vertices, hull.face_normals, box.vertices, box.face_normals)[0] <= 0:
            out.append(hull)
            continue
        pieces = carve_box(hull, frame, lo, hi, min_volume)
        log.carved += 1
        out += pieces
    return out


@dataclass
class ClearanceLog:
    """What clearing did to one part's hulls."""

    clipped: int = 0
    dropped: int = 0
    split: int = 0
    """Hulls cut around a hinge axis so that only the piece next to it gives way."""
    deepest_mm: float = 0.0
    """The deepest overlap removed."""
    left: int = 0
    """Overlaps not removed: deeper than allowed, or (sweeps) away from the hinge."""
    carved: int = 0
    """Hulls a pushed child's bore, or a turning child's spindle hole, was carved out of (``carve_bore``)."""

    def to_dict(self) -> dict:
        return {"clipped": int(self.clipped), "dropped": int(self.dropped), "split": int(self.split),
                "deepest_mm": round(float(self.deepest_mm), 2), "left": int(self.left), "carved": int(self.carved)}


def separate_hulls(hulls_a: list[trimesh.Trimesh], hulls_b: list[trimesh.Trimesh], share_a: float, clearance: float,
                   max_depth: float, log_a: ClearanceLog, log_b: ClearanceLog | None = None,
                   accept=None, min_volume: float = EMPTY_VOLUME, candidates: int = 8,
                   motions: tuple[tuple[str, np.ndarray], ...] = (), sweep_a=None, sweep_b=None,
                   farthest_a=None, farthest_b=None) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh]]:
    """Clip two sets of convex hulls (one frame) until no hull of A overlaps a hull of B.

    Each overlapping pair is cut by a plane normal to one of its separating-axis candidates
    (``geometry.separating_overlaps``, the ``candidates`` smallest overlaps) with a gap of
    ``clearance`` (m): the cut that keeps most volume among those ``accept(cut-away corners)``
    allows. A gives up ``share_a`` of the overlap, B the rest (1.0: only A is cut, e.g. a
    carcass around its door; 0.5: two siblings meet half-way). An overlap deeper than
    ``max_depth`` (m), or one no allowed cut removes, is left for the validator to find. Hulls
    cut down to nothing are dropped.

    ``motions``: (joint type, (3,) unit axis) of the joints that move A or B. A cut that stays
    a cut while they move (a plane normal to every hinge axis and parallel to every slide:
    the projection on its normal does not change) is taken before any other, and each hinge
    axis is a candidate of its own. ``sweep_a`` / ``sweep_b`` (hull -> convex hull of the
    space it sweeps) also find the pairs that only meet in motion; those are cut by a plane that
    holds or, with ``farthest_a`` / ``farthest_b`` ((N, 3) points, (3,) direction -> the
    farthest their motion carries them along it, m), by a plane at rest with each side cut back
    by how far its motion carries it across (two doors meeting in the middle: a door's back
    edge swings a little towards its neighbour as it opens). A pair that a plane at rest parts
    over the whole motion is left as it is. Returns the new lists."""
    a, b = list(hulls_a), list(hulls_b)
    if not a or not b:
        return a, b

    def holds(axis: np.ndarray) -> bool:
        return bool(motions) and all(abs(axis @ m) > PARALLEL_COS if kind == "revolute" else abs(axis @ m) < PERPENDICULAR_COS
                                     for kind, m in motions)

    across = motion_cross_axes(motions)
    sweeping = sweep_a is not None or sweep_b is not None
    reach_a = [sweep_a(h) if sweep_a else h for h in a]
    reach_b = [sweep_b(h) if sweep_b else h for h in b]
    exact = farthest_a is not None or farthest_b is not None
    if exact:  # the boxes the motions sweep, not those of a few sampled poses (a swing's start slips between them)
        lo_a, hi_a = swept_boxes(a, farthest_a)
        lo_b, hi_b = swept_boxes(b, farthest_b)
        touching = boxes_overlap(lo_a - clearance, hi_a + clearance, lo_b, hi_b)
    else:
        touching = boxes_touch(reach_a, reach_b, clearance)
    for i, j in zip(*np.nonzero(touching)):
        if a[i] is None or b[j] is None:
            continue
        at_rest, rest_axes = separating_overlaps(a[i].vertices, a[i].face_normals, b[j].vertices, b[j].face_normals)
        rest_axes = rest_axes[:candidates]
        if len(across):  # planes the motions span, oriented from A into B
            rest_axes = np.concatenate([rest_axes, separating_overlaps(a[i].vertices, across, b[j].vertices,
                                                                       np.zeros((0, 3)))[1]])
        directions = list(rest_axes)
        swing_depth: dict[tuple, float] = {}  # axis at rest -> how far the two cross it in motion
        if sweeping:
            in_motion, motion_axes = separating_overlaps(reach_a[i].vertices, reach_a[i].face_normals,
                                                         reach_b[j].vertices, reach_b[j].face_normals)
            if exact:
                swing_depth = {tuple(axis): swing_overlap(a[i].vertices, b[j].vertices, axis, farthest_a, farthest_b)
                               for axis in rest_axes}
                if min(swing_depth.values(), default=1.0) <= -clearance:
                    continue  # a plane at rest parts them by the clearance all the way
            elif in_motion[0] <= 0.0:
                continue
            directions += [axis for axis in motion_axes[:candidates] if holds(axis)]
        elif at_rest[0] <= 0.0:
            continue
        if at_rest[0] > max_depth:
            log_a.left += 1
            continue
        directions += [axis for kind, axis in motions if kind == "revolute"]
        best, best_kept, best_holds = None, -1.0, False
        for direction in directions:
            if swing_depth and not holds(direction):  # a plane the motions cross: cut back by how far they do
                axis, depth = direction, swing_depth.get(tuple(direction), -np.inf)
            elif sweeping and at_rest[0] <= 0.0 and not holds(direction):
                continue
            else:  # depth and side from the hulls at rest: along a plane that holds, motion does not change them
                overlap, axes = separating_overlaps(a[i].vertices, direction[None], b[j].vertices, np.zeros((0, 3)))
                depth, axis = float(overlap[0]), axes[0]
            # parted by less than the clearance is cut too when motion is known exactly
            if depth > max_depth or depth + clearance <= 0.0 or (depth <= 0.0 and not swing_depth):
                continue
            cut_a = float((a[i].vertices @ axis).max()) - share_a * (depth + clearance)  # A keeps axis.x <= cut_a
            cut_b = float((b[j].vertices @ axis).min()) + (1.0 - share_a) * (depth + clearance)  # B keeps axis.x >= cut_b
            new_a, removed_a = clip_hull(a[i], axis, cut_a, min_volume) if share_a > 0 else (a[i], np.zeros((0, 3)))
            new_b, removed_b = (clip_hull(b[j], -axis, -cut_b, min_volume) if share_a < 1
                                else (b[j], np.zeros((0, 3))))
            if accept is not None and not accept(np.concatenate([removed_a, removed_b])):
                continue
            kept = sum(h.volume for h in (new_a, new_b) if h is not None)
            if (holds(axis), kept) > (best_holds, best_kept):
                best, best_kept, best_holds = (new_a, new_b, float(depth)), kept, holds(axis)
        if best is None:
            log_a.left += int(at_rest[0] > 0.0)  # a pair that only meets in motion is the validator's to judge
            continue
        new_a, new_b, depth = best
        for new, old, hulls, reach, sweep, k, log in ((new_a, a[i], a, reach_a, sweep_a, i, log_a),
                                                      (new_b, b[j], b, reach_b, sweep_b, j, log_b)):
            if new is old or log is None:
                continue
            hulls[k] = new
            reach[k] = sweep(new) if sweep and new is not None else new
            log.clipped += new is not None
            log.dropped += new is None
            log.deepest_mm = max(log.deepest_mm, 1000 * depth)
    return [h for h in a if h is not None], [h for h in b if h is not None]


def drop_specks(hulls_a: list[trimesh.Trimesh], hulls_b: list[trimesh.Trimesh], share: float, clearance: float,
                log_a: ClearanceLog) -> list[trimesh.Trimesh]:
    """``hulls_a`` less its specks that touch B: hulls no longer than ``share`` of A's whole
    extent that no face plane of theirs or of a hull of B parts from B by ``clearance`` (m).
    A scan's segmentation leaves such specks of one door in the groove beside the next; cut
    or left, a speck a few millimetres across holds its neighbour in PyBullet (real-like
    wardrobe 414 and furniture wardrobes 67, 73 and 97, scanned)."""
    if not hulls_a or not hulls_b:
        return hulls_a
    lo, hi = _hulls_box(hulls_a)
    longest = share * float((hi - lo).max())
    kept = []
    for hull in hulls_a:
        speck = float(hull.extents.max()) <= longest and any(
            separating_overlaps(hull.vertices, hull.face_normals, other.vertices, other.face_normals)[0][0] > -clearance
            for other in hulls_b)
        if speck:
            log_a.dropped += 1
        else:
            kept.append(hull)
    return kept


def motion_cross_axes(motions: tuple[tuple[str, np.ndarray], ...]) -> np.ndarray:
    """(K, 3) unit normals of the planes that two different motion axes span (their cross
    products): a door hinged about z beside a drawer sliding along y is parted by a plane normal
    to x, which neither hull may have a face along (a scan's thin front slabs lean a little)."""
    axes = [np.asarray(axis, float) for _, axis in motions]
    out = []
    for k, first in enumerate(axes):
        for second in axes[k + 1:]:
            normal = np.cross(first, second)
            length = np.linalg.norm(normal)
            if length > np.sqrt(1.0 - PARALLEL_COS ** 2):  # not parallel
                out.append(normal / length)
    return np.array(out).reshape(-1, 3)


def swing_overlap(va: np.ndarray, vb: np.ndarray, axis: np.ndarray, farthest_a, farthest_b) -> float:
    """Overlap (m) along ``axis`` (3,, from A towards B) of the spaces two hulls' vertices
    ``va``, ``vb`` (N, 3) pass through: the farthest A's motion carries it along ``axis`` less
    the nearest B's carries it; <= 0 when a plane normal to ``axis`` parts them over both whole
    motions. ``farthest_a`` / ``farthest_b`` as in ``separate_hulls`` (None: the side does not
    move)."""
    reach_a = farthest_a(va, axis) if farthest_a else float((va @ axis).max())
    reach_b = farthest_b(vb, -axis) if farthest_b else float((vb @ -axis).max())
    return reach_a + reach_b  # A's farthest along the axis less B's nearest


def swept_boxes(hulls: list[trimesh.Trimesh], farthest) -> tuple[np.ndarray, np.ndarray]:
    """(lo (H, 3), hi (H, 3)): the axis-aligned boxes of the space each hull passes through,
    ``farthest`` as in ``separate_hulls`` (None: its own box)."""
    if farthest is None:
        return np.array([h.bounds[0] for h in hulls]), np.array([h.bounds[1] for h in hulls])
    axes = np.eye(3)
    hi = np.array([[farthest(h.vertices, e) for e in axes] for h in hulls])
    lo = -np.array([[farthest(h.vertices, -e) for e in axes] for h in hulls])
    return lo, hi


def _hulls_box(hulls: list[trimesh.Trimesh]) -> tuple[np.ndarray, np.ndarray]:
    """(lo (3,), hi (3,)): the axis-aligned box of ``hulls``, m."""
    corners = np.concatenate([h.bounds for h in hulls])
    return corners.min(axis=0), corners.max(axis=0)


def swept_hull(hull: trimesh.Trimesh, joint, samples: int) -> trimesh.Trimesh:
    """Convex hull of the space ``hull`` passes through over ``joint``'s range: the hull of
    its corners at ``samples`` + 1 poses (a slide's end poses are enough). For a hinge it
    holds a little more than the swept space, never less at the sampled poses."""
    steps = 1 if joint.type == "prismatic" else samples
    values = range_values(joint.limit[0], joint.limit[1], steps, with_lower=True)
    swept = closed_hull(swept_points(hull.vertices, joint.transform, values))
    return hull if swept is None else swept


def _split_hit_hulls(hulls: list[trimesh.Trimesh], swept: list[list[trimesh.Trimesh]], joint,
                     config: CollisionConfig, log: ClearanceLog) -> list[trimesh.Trimesh]:
    """``hulls`` with every one that a swept pose overlaps and that reaches beyond the hinge
    prism cut around the joint axis (``split_around_axis``), so that a clip next to the hinge
    does not shave a whole panel."""
    posed = [h for hs in swept for h in hs]
    if not posed or not hulls:
        return hulls
    near = boxes_touch(hulls, posed)
    out = []
    for hull, row in zip(hulls, near):
        hit = any(convex_overlap(hull.vertices, hull.face_normals, posed[k].vertices, posed[k].face_normals)[0] > 0
                  for k in np.flatnonzero(row))
        if not hit:
            out.append(hull)
            continue
        inside, outside = split_around_axis(hull, joint.origin, joint.axis, config.hinge_clearance_radius,
                                            config.min_hull_volume)
        if not outside:
            out.append(hull)
            continue
        log.split += 1
        out += inside + outside
    return out


def clear_asset_hulls(asset, config: CollisionConfig = CollisionConfig()) -> dict[str, dict]:
    """Clip the collision hulls of an ``ArticulatedAsset`` (in place) so that no two parts
    overlap at rest and no revolute part hits its ancestors near its hinge while it swings.

    Hull approximations bulge by millimetres to centimetres (CoACD's concavity threshold is a
    share of the piece's size) and a fused scan gives a door and its frame only a groove between
    them: without this, a correct asset starts interpenetrating. At rest, a part's ancestor gives
    way to it and siblings meet half-way. Over each revolute range (``clearance_sweep_samples``
    poses, denser than the validator's) only ancestor hulls within ``hinge_clearance_radius`` of
    the axis are cut, the space the door's back edge sweeps next to its hinge; an overlap
    further out or deeper than ``clearance_max_depth`` means a wrong part or joint and is left
    for the validator. A slide that pushes a part into its ancestor (a button, a plunger:
    ``pushes_into``) has its bore carved out of the ancestor's hulls (``carve_bore``): a hull
    approximation fills the hole a button sits in (the joint rules gave it no more travel than
    that hole leaves). So has a knob or latch whose hulls still pass through an ancestor's at
    rest (the hole its spindle turns in), and a handle running in a slot (``slider``); and a
    sliding door or sash has its track (the box its hulls sweep) carved out of the ancestor
    hulls: a scan fuses the sash to the groove it runs in and the groove's hulls fill it, and
    the frame's hulls reach into its track by centimetres (4.5 and 5.4 cm in real-like windows 7
    and 46 scanned); the joint rules' sweep of the mesh gave it its travel. Returns the per-part
    log."""
    parents = {p.name: p.parent for p in asset.parts}

    def ancestors(name: str) -> list[str]:
        chain, parent = [], parents.get(name)
        while parent is not None:
            chain.append(parent)
            parent = parents.get(parent)
        return chain

    def carried(joint) -> list[str]:
        """The parts ``joint`` moves: its child and the child's descendants."""
        return [n for n in names if n == joint.child or joint.child in ancestors(n)]

    names = [p.name for p in asset.parts]
    hulls = {p.name: list(p.collision) for p in asset.parts}
    logs = {name: ClearanceLog() for name in names}
    args = dict(clearance=config.clearance, max_depth=config.clearance_max_depth, min_volume=config.min_hull_volume)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if a in ancestors(b):
                hulls[a], hulls[b] = separate_hulls(hulls[a], hulls[b], 1.0, log_a=logs[a], **args)
            elif b in ancestors(a):
                hulls[b], hulls[a] = separate_hulls(hulls[b], hulls[a], 1.0, log_a=logs[b], **args)
            else:  # siblings: cut apart where they meet at rest or in motion, by a plane that holds
                hulls[a], hulls[b] = (drop_specks(hulls[a], hulls[b], config.speck_share, config.sibling_clearance, logs[a]),
                                      drop_specks(hulls[b], hulls[a], config.speck_share, config.sibling_clearance, logs[b]))
                joints = [j if j is not None and j.type in ("revolute", "prismatic") and j.limit[1] > j.limit[0]
                          else None for j in map(asset.joint_for, (a, b))]
                motions = tuple((j.type, np.asarray(j.axis, float)) for j in joints if j is not None)
                sweeps = [None if j is None else (lambda h, j=j: swept_hull(h, j, config.sibling_sweep_samples))
                          for j in joints]
                reaches = [None if j is None else (lambda points, direction, j=j: farthest_along(points, j, direction))
                           for j in joints]
                hulls[a], hulls[b] = separate_hulls(hulls[a], hulls[b], 0.5, log_a=logs[a], log_b=logs[b],
                                                    motions=motions, sweep_a=sweeps[0], sweep_b=sweeps[1],
                                                    farthest_a=reaches[0], farthest_b=reaches[1],
                                                    **{**args, "clearance": config.sibling_clearance})
    for joint in asset.movable_joints:
        if joint.type != "revolute" or joint.limit[1] <= joint.limit[0]:
            continue
        moving = carried(joint)
        poses = [joint.transform(value) for value in range_values(*joint.limit, config.clearance_sweep_samples)]
        swept = [[h.copy().apply_transform(T) for n in moving for h in hulls[n]] for T in poses]
        reach = config.hinge_clearance_radius * np.sqrt(2.0) + SAME_POINT  # the prism's corner

        def near_hinge(points: np.ndarray, joint=joint) -> bool:
            offset = points - joint.origin
            radial = offset - np.outer(offset @ joint.axis, joint.axis)
            return bool(len(points) == 0 or np.linalg.norm(radial, axis=1).max() <= reach)

        for ancestor in ancestors(joint.child):
            hulls[ancestor] = _split_hit_hulls(hulls[ancestor], swept, joint, config, logs[ancestor])
            for posed in swept:
                hulls[ancestor], _ = separate_hulls(hulls[ancestor], posed, 1.0, log_a=logs[ancestor],
                                                    accept=near_hinge, **args)
    for joint in asset.movable_joints:
        if joint.type != "prismatic" or joint.limit[1] <= joint.limit[0] or asset.part(joint.child).semantic != "drawer":
            continue
        moving = [h for n in carried(joint) for h in hulls[n]]
        motion = (("prismatic", np.asarray(joint.axis, float)),)
        for ancestor in ancestors(joint.child):  # along a drawer's run, by planes parallel to it
            hulls[ancestor], _ = separate_hulls(hulls[ancestor], moving, 1.0, log_a=logs[ancestor], motions=motion,
                                                sweep_b=lambda h, joint=joint: swept_hull(h, joint, 1),
                                                **{**args, "max_depth": config.slide_clearance_max_depth})
    for joint in asset.movable_joints:
        semantic = asset.part(joint.child).semantic
        sliding = joint.type == "prismatic" and semantic == "door"  # a sliding door or sash, in its track
        if joint.limit[1] <= joint.limit[0] or (semantic not in (*PUSHED, "slider") and not sliding):
            continue
        moving = [h for n in carried(joint) for h in hulls[n]]
        if not moving:
            continue
        pushed = joint.type == "prismatic" and semantic in PUSHED  # a button or plunger: its bore, when pushed inwards
        samples = 1 if joint.type == "prismatic" else config.clearance_sweep_samples
        moving_points = np.concatenate([h.vertices for h in moving])
        for ancestor in ancestors(joint.child):
            if not hulls[ancestor]:
                continue
            if sliding:  # the track the mesh's sweep found free, which the hulls fill
                hulls[ancestor] = carve_bore(hulls[ancestor], moving_points, joint, config.clearance,
                                             config.min_hull_volume, logs[ancestor])
                continue
            if pushed:
                if not pushes_into(np.asarray(joint.axis, float), moving_points, *_hulls_box(hulls[ancestor])):
                    continue
                points = moving_points
            else:  # a knob's or latch's spindle hole, a handle's slot: where it still passes through at rest
                through = [h.vertices for h in moving if any(
                    convex_overlap(h.vertices, h.face_normals, a.vertices, a.face_normals)[0] > config.clearance
                    for a in hulls[ancestor])]
                if not through:
                    continue
                points = np.concatenate(through)
            hulls[ancestor] = carve_bore(hulls[ancestor], points, joint, config.clearance, config.min_hull_volume,
                                         logs[ancestor], samples)
    for part in asset.parts:
        part.collision = hulls[part.name]
    return {name: log.to_dict() for name, log in logs.items()}
