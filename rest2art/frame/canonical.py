"""Canonical frame: +z up, -y front, chosen from evidence in the geometry.

* Up: among the axes of the oriented bounding box perpendicular to the front, the file's
  convention unless the object cannot stand that way (its bottom contact patch is too small
  or its centroid falls outside it); then the side with the largest flat support (convex-hull
  facets facing down at the bottom). Top, bottom and sides of a box all carry it, so geometry
  alone cannot pick among them: feet or a plinth must not tip a cabinet over. The file's
  convention is the format's (+y for glTF, +z otherwise) unless the file stands the object on
  the origin plane of another axis with its base centred there (an asset's pivot at the middle
  of its base) and it can stand that way.
* Front: the side carrying the most visible relief: an orthographic depth map is cast from each
  side and the share of its silhouette covered by depth steps (seams, proud panels, handles,
  knobs) is its score. An object much wider than deep (a wardrobe, a door, a window) faces
  along its thin side, one of its two broad sides. The format's front (-y for z-up files)
  wins unless another side has clearly more, or differs clearly more from its opposite side
  than the format's front from its back (a front differs from its back, two sides alike); a
  side along the format's up axis needs overwhelming relief, and the format's bottom never
  wins (an overhanging lid shows its rim from below). Up is then chosen among the four
  directions perpendicular to the front. The other sides the front could be are kept, most
  relief first (``front_alternatives``): where nothing moves on the chosen side, the
  reconstruction tries them (``reconstruct_mesh``), as a flush door shows fewer seams than a
  side's overhang or a proud rim seen from behind.

Both can be overridden. The result is a rotation only, so mapping back is exact.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import trimesh

from rest2art.config import FrameConfig
from rest2art.errors import InputError
from rest2art.geometry.basics import perpendicular_basis
from rest2art.tolerances import TINY

AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1), "-z": (0, 0, -1)}


@dataclass
class CanonicalFrame:
    """Rotation from the input frame to the canonical one: p_canonical = R @ p_input."""

    rotation: np.ndarray
    """(3, 3) orthonormal, det +1."""
    up: np.ndarray
    """(3,) up direction in the input frame."""
    front: np.ndarray
    """(3,) front direction (outward normal of the front side) in the input frame."""
    evidence: dict = field(default_factory=dict)

    def to_canonical(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(points) @ self.rotation.T

    def to_input(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(points) @ self.rotation


def parse_direction(text: str) -> np.ndarray:
    """'+z', '-y', 'x' ... as a unit vector."""
    key = text if text[0] in "+-" else "+" + text
    if key not in AXES:
        raise InputError(f"direction '{text}': expected one of {', '.join(AXES)}")
    return np.array(AXES[key], dtype=float)


def candidate_axes(vertices: np.ndarray, config: FrameConfig, prior_ups: tuple[np.ndarray, ...] = ()) -> np.ndarray:
    """(3, 3) rows: the file's own axes unless an oriented box fits clearly tighter
    (``min_obb_gain``); then, if the object stands on the bottom of one of ``prior_ups`` (the
    format's up conventions, in order), that up and the axes of the tightest rectangle around
    it (a file turned about its up; an open laptop's leaned screen must not tip the box); else
    the OBB axes. Each is snapped to a coordinate axis when within tolerance."""
    hull_points, hull = vertices, None
    if len(vertices) > 4:
        try:
            hull = trimesh.convex.convex_hull(vertices)
            hull_points = hull.vertices
        except Exception:  # flat inputs have no 3D hull
            hull_points = vertices
    to_origin, obb_extents = trimesh.bounds.oriented_bounds(hull_points)
    aabb_volume = float(np.prod(np.ptp(hull_points, axis=0)))
    if np.prod(obb_extents) >= (1.0 - config.min_obb_gain) * aabb_volume:
        return np.eye(3)  # the author's axes fit as well as any: an L-shape's box may tilt 45 degrees
    axes = np.asarray(to_origin[:3, :3])  # rows are the box axes in the input frame
    standing = [u for u in prior_ups if hull is not None and stands_on(hull, u, config)]
    if standing:
        up = standing[0]
        basis = perpendicular_basis(up)
        to_rectangle, _ = trimesh.bounds.oriented_bounds_2D(hull_points @ basis.T)
        axes = np.array([*(np.asarray(to_rectangle[:2, :2]) @ basis), up])
    cos_tol = np.cos(np.radians(config.axis_aligned_tol_deg))
    snapped = []
    for a in axes:
        k = int(np.argmax(np.abs(a)))
        if abs(a[k]) >= cos_tol:
            a = np.zeros(3)
            a[k] = 1.0
        snapped.append(a / np.linalg.norm(a))
    snapped = np.array(snapped)
    if abs(np.linalg.det(snapped)) < config.snap_min_det:  # snapping broke orthogonality: keep the raw box
        snapped = axes
    return snapped


def stands_on(hull: trimesh.Trimesh, up: np.ndarray, config: FrameConfig) -> bool:
    """Whether the object can rest on its side facing -``up``: the bottom contact patch (hull
    facets within ``support_height`` of the lowest point) is a real area, at least
    ``min_support`` of the shadow, and the hull's centroid projects inside it."""
    height = hull.vertices @ up
    low = height.min()
    tol = config.support_height * (height.max() - low + 1e-9)
    near = hull.vertices[height <= low + tol]
    if len(near) < 3:
        return False
    helper = np.eye(3)[np.argmin(np.abs(up))]
    u = np.cross(up, helper)
    u /= np.linalg.norm(u)
    v = np.cross(up, u)
    flat = np.stack([near @ u, near @ v], axis=1)
    try:
        from scipy.spatial import ConvexHull

        patch = ConvexHull(flat)
    except Exception:  # collinear contact: an edge, not an area
        return False
    shadow = 0.5 * (np.abs(hull.face_normals @ up) * hull.area_faces).sum()
    if patch.volume < config.min_support * shadow:  # 2D hull: .volume is the area
        return False
    centroid = np.array([hull.center_mass @ u, hull.center_mass @ v])
    return bool(np.all(patch.equations[:, :2] @ centroid + patch.equations[:, 2] <= 1e-9))


def support_score(hull: trimesh.Trimesh, up: np.ndarray, config: FrameConfig) -> float:
    """Area of hull facets facing -up (``support_facing_cos``) within ``support_height`` of the
    bottom, over the projected hull area."""
    normals = hull.face_normals
    height = hull.vertices @ up
    low = height.min()
    centre_height = hull.triangles_center @ up
    tol = config.support_height * (height.max() - low + TINY)
    mask = (normals @ -up > config.support_facing_cos) & (centre_height < low + tol)
    facing = np.abs(normals @ up) * hull.area_faces
    projected = 0.5 * facing.sum()  # the hull's shadow area along up
    return float(hull.area_faces[mask].sum() / max(projected, TINY))


def relief_map(mesh: trimesh.Trimesh, side: np.ndarray, step: float, start_gap: float) -> np.ndarray:
    """(U, V) orthographic depth (m) of ``mesh`` seen from outside along -``side``, one ray
    every ``step`` metres, each starting ``start_gap`` (m) outside the mesh; NaN where a ray
    misses. The grid is centred on the mesh's box, so that the maps of two opposite sides
    sample the same lines of sight: a wardrobe's two sides show its doors' edges alike, not
    one side a pixel nearer its outline than the other."""
    side = side / np.linalg.norm(side)
    helper = np.eye(3)[np.argmin(np.abs(side))]
    u = np.cross(side, helper)
    u /= np.linalg.norm(u)
    v = np.cross(side, u)
    pu, pv, pd = mesh.vertices @ u, mesh.vertices @ v, mesh.vertices @ side
    gu, gv = (0.5 * (p.min() + p.max()) + step * (np.arange(n) - 0.5 * (n - 1))
              for p, n in ((pu, int(np.ptp(pu) / step) + 1), (pv, int(np.ptp(pv) / step) + 1)))
    GU, GV = np.meshgrid(gu, gv, indexing="ij")
    start = pd.max() + start_gap
    origins = GU.reshape(-1, 1) * u + GV.reshape(-1, 1) * v + start * side
    directions = np.tile(-side, (len(origins), 1))
    locations, index_ray, _ = mesh.ray.intersects_location(origins, directions, multiple_hits=False)
    depth = np.full(len(origins), np.nan)
    depth[index_ray] = start - locations @ side
    return depth.reshape(len(gu), len(gv))


def detail_score(depth: np.ndarray, step: float, config: FrameConfig) -> float:
    """Length (m) of relief edges (seams, panel steps, handles) in one side's ``relief_map``
    ``depth`` (U, V; m, NaN off the object; ``step`` m per pixel): pixels whose depth jumps by
    more than ``relief_jump`` to a neighbour, and by as much against the change before it (a
    step, not a steep slope), times the pixel size. Only connected runs of such pixels reaching
    ``relief_min_edge`` of the map or more count: seams and outlines are lines, a scan's pits
    and spikes are specks."""
    from scipy.ndimage import binary_erosion, find_objects, label

    hit = np.isfinite(depth)
    # the outline itself (and the chamfer a scan puts on it) is on every side: look inside it
    margin = max(2, int(np.ceil(config.outline_margin * max(depth.shape))))
    inner = binary_erosion(hit, iterations=margin)
    if inner.sum() < 10:
        return 0.0
    jump = np.zeros_like(hit)
    filled = np.where(hit, depth, 0.0)
    for axis in (0, 1):
        first = np.diff(filled, axis=axis)
        # a step, not a slope: the depth also jumps against the previous pixel's change (a
        # leaned screen or a sloped panel seen from above changes depth on every pixel)
        bend = np.diff(first, axis=axis, prepend=np.take(first, [0], axis=axis))
        d = (np.abs(first) > config.relief_jump) & (np.abs(bend) > config.relief_jump)
        # a step is marked on its nearer pixel (the edge of what stands in front), whichever
        # way the map runs: the maps of two opposite sides mark the same step alike
        before, after = [(0, 0), (0, 0)], [(0, 0), (0, 0)]
        before[axis], after[axis] = (0, 1), (1, 0)
        jump |= np.pad(d & (first > 0), before) | np.pad(d & (first < 0), after)
    jump &= inner
    runs, _ = label(jump, structure=np.ones((3, 3), dtype=bool))
    reach = [max(a.stop - a.start, b.stop - b.start) for a, b in find_objects(runs)]
    lines = np.array([False, *(r >= config.relief_min_edge * max(depth.shape) for r in reach)])
    return float(lines[runs].sum() * step)


def proud_fittings(depth: np.ndarray, step: float, config: FrameConfig) -> int:
    """How many handles or knobs one side's ``relief_map`` ``depth`` (U, V; m, NaN off the
    object; ``step`` m per pixel) shows: islands narrower than ``fitting_window`` that stand
    ``fitting_proud`` out of the surface around them (a grey opening's top-hat), of
    ``fitting_min_area`` to ``fitting_max_share`` of the side, inside ``fitting_border`` of its
    outline (a desk's legs frame its side panel and reach the outline)."""
    from scipy.ndimage import binary_erosion, grey_opening, label

    hit = np.isfinite(depth)
    if not hit.any():
        return 0
    near = np.where(hit, -depth, -np.nanmax(depth))
    width = max(3, int(round(config.fitting_window / step)))
    standing = near - grey_opening(near, size=(width, width))
    inner = binary_erosion(hit, iterations=max(2, int(np.ceil(config.fitting_border * max(depth.shape)))))
    islands, _ = label((standing > config.fitting_proud) & inner)
    areas = np.bincount(islands.ravel())[1:] * step * step
    side_area = hit.sum() * step * step
    return int(np.sum((areas >= config.fitting_min_area) & (areas <= config.fitting_max_share * side_area)))


def floor_axis(vertices: np.ndarray, config: FrameConfig) -> str | None:
    """The axis ("+x", "+y" or "+z") along which the file stands the object on the origin with
    its base centred there (its lowest point within ``floor_origin_tol`` of its size of 0 along
    that axis, the middle of what lies that near its lowest point, its footprint, within
    ``floor_centre_tol`` of its size of 0 along the other two): where an asset's pivot sits at
    the middle of its base, the file says which way is up, however far its top reaches forward
    (a sloped control panel). None when no axis or more than one fits."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    size = float((hi - lo).max())
    if size <= 0:
        return None
    fits = []
    for k in range(3):
        if abs(lo[k]) > config.floor_origin_tol * size:
            continue
        footprint = vertices[vertices[:, k] <= lo[k] + config.floor_origin_tol * size]
        middle = (footprint.min(axis=0) + footprint.max(axis=0)) / 2
        if (np.abs(np.delete(middle, k)) <= config.floor_centre_tol * size).all():
            fits.append(k)
    return "+" + "xyz"[fits[0]] if len(fits) == 1 else None


PRIOR_FRONT = {"+z": "-y", "+y": "+z", "-z": "+y", "-y": "-z", "+x": "-y", "-x": "-y"}


def estimate_frame(mesh: trimesh.Trimesh, config: FrameConfig = FrameConfig(), up: str | None = None,
                   front: str | None = None, prior_up: str = "+z") -> CanonicalFrame:
    """The canonical frame of ``mesh`` (input frame, metres); ``up``/``front`` override.

    ``prior_up`` is the file format's convention, used only where the geometry ties.
    """
    evidence: dict = {}
    hull = mesh.convex_hull
    if up is None and prior_up != "+y" and not stands_on(hull, parse_direction(prior_up), config) \
            and stands_on(hull, parse_direction("+y"), config):
        # the format's bottom cannot carry it and the other common convention's (y-up) can
        prior_up, evidence["convention"] = "+y", "y-up (it stands on -y, not on the format's bottom)"
    floor = floor_axis(mesh.vertices, config) if up is None else None
    if floor is not None and floor != prior_up and stands_on(hull, parse_direction(floor), config):
        # the file stands the object on its origin, base centred there, along another axis
        prior_up, evidence["convention"] = floor, f"{floor[1]}-up (its base sits centred on the origin plane)"
    axes = candidate_axes(mesh.vertices, config, (parse_direction(up or prior_up), parse_direction("+y")))
    directions = np.concatenate([axes, -axes])
    key = lambda d: str(np.round(d, 3).tolist())  # noqa: E731
    up_prior = parse_direction(up) if up is not None else parse_direction(prior_up)
    front_prior = parse_direction(PRIOR_FRONT.get(prior_up, "-y"))
    if front is not None:
        front_vec = parse_direction(front)
        evidence["front"] = "given"
    else:
        step = float(mesh.extents.max()) / config.relief_resolution
        maps = {i: relief_map(mesh, d, step, config.relief_ray_start) for i, d in enumerate(directions)
                if up is None or abs(d @ up_prior) < 0.5}
        scores = {i: detail_score(depth, step, config) for i, depth in maps.items()}
        evidence["front_relief"] = {key(directions[i]): round(s, 4) for i, s in scores.items()}
        level = [i for i in scores if abs(directions[i] @ up_prior) < 0.5]
        default = max(level, key=lambda i: directions[i] @ front_prior)
        span = {i: float(np.ptp(mesh.vertices @ directions[i])) for i in level}
        thin = min(span.values())
        facing = level
        judged = dict(scores)  # the relief the sides are compared by
        if max(span.values()) >= config.flat_ratio * thin:  # a door, a window, a panel: it faces along its thin side
            facing = [i for i in level if span[i] <= thin * (1 + 1e-6)]
            prior_dot = {i: round(float(directions[i] @ front_prior), 6) for i in facing}
            if len(set(prior_dot.values())) == 1:
                # the format's front says nothing between the two broad sides: what stands out
                # centimetres decides, not a scan's noise or a panel's millimetre seams
                coarse = replace(config, relief_jump=config.flat_relief_jump)
                judged.update({i: detail_score(maps[i], step, coarse) for i in facing})
                evidence["flat_relief"] = {key(directions[i]): round(judged[i], 4) for i in facing}
            default = max(facing, key=lambda i: (prior_dot[i], judged[i]))
            evidence["flat"] = round(max(span.values()) / thin, 2)
        # a flat object's narrow sides are not its front, whatever they show (a step along a
        # wardrobe's side, the edges of a door in its frame)
        best = max(facing, key=judged.get)
        opposite = lambda i: (i + len(axes)) % len(directions)  # noqa: E731
        choice, evidence["front"] = default, "prior"
        # a side shows what the other side shows (a wardrobe's two sides, its doors' edges);
        # a front differs from its back: the relief of a side less that of its opposite
        contrast = {i: judged[i] - judged[opposite(i)] for i in facing}
        floor = config.front_min_contrast * float(mesh.extents.max())
        if judged[best] > judged[default] * (1 + config.front_margin) + config.front_min_relief \
                and contrast[best] > max(contrast[default], 0.0) + floor:
            choice, evidence["front"] = best, "relief"
        elif "flat" not in evidence:
            rival = max(level, key=contrast.get)
            if contrast[rival] > max(contrast[default], 0.0) * (1 + config.front_contrast_margin) + floor:
                choice, evidence["front"] = rival, "relief against the opposite side"
        # a side along the format's up axis wins only with overwhelming relief (a file in
        # another up convention); lids and top handles alone must not tip the object over.
        # Never the format's bottom: files in the other common convention (y-up) put their
        # front on the z-up top, while the underside of a box or laptop shows the rim of its
        # overhanging lid all round, which is relief but not a front
        # and only where the object can stand in that other convention (on its -y side).
        # Only from z-up: once the file reads as y-up (by format or by evidence), no common
        # convention puts the front on its top (an open laptop's keyboard is relief seen from above)
        other_stands = prior_up == "+z" and stands_on(hull, parse_direction("+y"), config)
        for i in scores:
            if i not in level and (directions[i] @ up_prior < -0.5 or not other_stands):
                continue
            # what it shows beyond its opposite side: a box's lid shows its parting line from
            # above, and a scan's underside shows as much, where a front differs from its back
            shown = scores[i] - scores.get(opposite(i), 0.0)
            if i not in level and shown > config.off_axis_factor * scores[choice] + 2 * config.front_min_relief:
                choice, evidence["front"] = i, "relief (off the format's up)"
        # handles and knobs are on the front: a desk's side panel framed by its legs shows
        # more relief edges than the drawer fronts sunk into its front, not the drawers' knobs.
        # They overrule relief only: a file's own front stands against a single latch seen
        # from behind (metaworld's window shows its handle only from its back), and so does a
        # flat object's broad side, chosen by what stands out centimetres
        fittings = {} if "flat" in evidence else {i: proud_fittings(maps[i], step, config) for i in facing}
        evidence["front_fittings"] = {key(directions[i]): n for i, n in fittings.items()}
        fitted = [i for i in fittings if fittings[i]]
        if evidence["front"].startswith("relief") and choice in fittings and not fittings[choice] \
                and len(fitted) == 1:
            choice, evidence["front"] = fitted[0], "handles or knobs (on that side only)"
        front_vec = directions[choice]
        rivals = [scores[i] for i in scores if i != choice]
        # relief of the chosen side over its strongest rival: 1 is a tie, the prior decided
        evidence["front_margin"] = round(float(scores[choice] / max(max(rivals, default=0.0), 1e-9)), 3)
    if up is not None:
        up_vec = parse_direction(up)
        evidence["up"] = "given"
    else:
        candidates = [d for d in directions if abs(d @ front_vec) < 0.5]
        scores = np.array([support_score(hull, d, config) for d in candidates])
        stable = np.array([stands_on(hull, d, config) for d in candidates])
        evidence["up_support"] = {key(d): round(float(s), 3) for d, s in zip(candidates, scores)}
        # when the front lies along the format's up, the file follows the other common
        # convention (y-up); use it instead
        prior = up_prior if abs(front_vec @ up_prior) < 0.5 else parse_direction("+y")
        by_prior = max(range(len(candidates)), key=lambda i: candidates[i] @ prior)
        evidence["up_margin"] = round(float(scores[by_prior] - max(np.delete(scores, by_prior), default=0.0)), 3)
        if stable[by_prior]:
            up_vec, evidence["up"] = candidates[by_prior], "format convention (stands on that side)"
        else:
            best = max(range(len(candidates)), key=lambda i: (stable[i], scores[i]))
            upside_down = candidates[best] @ candidates[by_prior] < -0.5
            if upside_down and scores[by_prior] >= config.flip_support_ratio * scores[best]:
                # files are rarely stored upside down: flip only for a clearly better bottom
                up_vec, evidence["up"] = candidates[by_prior], "format convention (upside down is no better)"
            else:
                up_vec, evidence["up"] = candidates[best], "support (the convention's bottom cannot carry it)"
    if abs(front_vec @ up_vec) > 0.5:
        raise InputError("the front direction is parallel to the up direction; give --up and --front")
    if front is None:
        # the sides the front could be instead, most relief first (a flat object's broad side
        # only): the parts found decide between them when the chosen side shows none
        others = [i for i in facing if i != choice and abs(directions[i] @ up_vec) < 0.5]
        evidence["front_alternatives"] = [directions[i].round(6).tolist()
                                          for i in sorted(others, key=lambda i: -judged[i])]
    return CanonicalFrame(_rotation(up_vec, front_vec), up_vec, front_vec, evidence)


def front_shown(frame: CanonicalFrame) -> bool:
    """Whether the object showed its front: given by the user, turned to the side whose parts
    move, or a side with some relief chosen (not a file's front on an object with no relief on
    the side it names)."""
    evidence = frame.evidence
    return evidence.get("front") != "prior" or float(evidence.get("front_margin", 1.0)) > 0.0


def facing_instead(frame: CanonicalFrame, front: np.ndarray, reason: str) -> CanonicalFrame:
    """``frame`` with the same up and its front turned to ``front`` ((3,) unit, perpendicular
    to up); ``reason`` goes into its evidence."""
    front = np.asarray(front, float)
    evidence = {**frame.evidence, "front": reason, "front_before": frame.front.round(6).tolist()}
    return CanonicalFrame(_rotation(frame.up, front), frame.up.copy(), front, evidence)


def _rotation(up: np.ndarray, front: np.ndarray) -> np.ndarray:
    """Rotation sending ``up`` to +z and ``front`` to -y."""
    z = up / np.linalg.norm(up)
    y = -(front - (front @ z) * z)
    y /= np.linalg.norm(y)
    x = np.cross(y, z)
    return np.stack([x, y, z])
