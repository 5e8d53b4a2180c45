"""The plausibility gate: is what the rules found the object, or an artefact of them?

Validation proves an asset is physically sound; it cannot tell that a cabinet whose drawers
became knobs is not the object. This stage reviews the structure before export:

* a joint whose range is (almost) empty is no joint: its part stays with the base; so is a
  drawer that draws out only a small share of its own box (something passes through its front,
  as a button's stem through a box's face, or stands in its way);
* a door, drawer or lid smaller than a hand can hold is no panel, and a part as large as the
  whole object in every direction is the carcass (unless it is built of pieces of its own that
  lie inside the carcass's box behind its front: a cabinet's one big drawer): both stay with
  the base;
* knobs stacked in several rows at the same sideways positions are the pulls of drawers the
  rules missed, not controls: they stay with the base (stove knobs sit in one row);
* a door or a drawer front with solid carcass right behind it opens onto nothing: it is a
  facade (a control panel, a keyboard, a trim plate), not a panel, and stays with the base
  (a drawer whose own box reaches deep behind its front is its own evidence);
* a panel that slides free of the object both ways along one direction is held by nothing
  (no track, no carcass side to stop it): it lies on the object, it is no sliding door or lid
  (a faucet's handle block on its body);
* a door or a lid is a panel: most of its surface faces the way it opens, front and back; a
  bar, a ball or a post (a lever's arm cut out of a scan) does not; and a panel's outline is
  closed: the legs and apron of a table, seen from the front, leave it open to the floor;
* a door swinging down or up about a horizontal hinge along its short edge, much narrower than
  it swings out (a strip of a control panel beside a microwave's door, a post's side face),
  is no flap: oven, dishwasher and wall-cabinet flaps hinge along an edge about as long as
  they are tall, or longer;
* a knob or button down at the floor the object stands on is a foot or a mounting bolt, not
  a control a hand reaches;
* a door, drawer or lid whose box holds another of them is the frame around it (the casing of
  a window around its sashes), not a panel: it stays with the base, before any joint is
  estimated, so that the others are judged against it; so is a door just behind another that
  meets it along an edge (the fixed pane of a sliding window, which the front sash slides over);
* a lone hinged part holding most of the floor the object stands on is its support (a
  laptop standing open whose keyboard was taken for a lid): it becomes the base, and the rest
  turns about the same hinge the other way;
* an object left with no movable part is *static*: it is not published as an articulated
  asset unless the user asks for it.

Every joint gets a confidence in [0, 1] from the evidence behind it (how its side was chosen,
how freely it opens), recorded with that evidence. All coordinates canonical (+z up, -y front).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from rest2art.config import GateConfig
from rest2art.geometry.basics import inner_grid, inside_box, perpendicular_basis
from rest2art.tolerances import TINY


@dataclass(frozen=True)
class GateFinding:
    """One structural finding: what was wrong, about which part, and what the gate did."""

    kind: str
    """zero_travel, stuck, no_front, loose_slide, tiny_panel, not_a_panel, narrow_flap, carcass_sized,
    pull_knobs, unbacked, standing_free, sliding_pair, no_opening, floor_control, frame, fixed_pane, support,
    lid_strip, plinth, worktop, open_below or static."""
    parts: tuple[str, ...]
    message: str
    action: str
    """demoted (the parts stay with the base), swapped (the part and the base trade places),
    door (the drawers named are doors), doubted (the part keeps its joint at confidence 0, so the
    asset is not published) or refused (the object is static)."""

    def to_dict(self) -> dict:
        return {"kind": self.kind, "parts": list(self.parts), "message": self.message, "action": self.action}


@dataclass
class GateResult:
    """The gate's verdict on one object."""

    decision: str
    """articulated or static."""
    demoted: list[str] = field(default_factory=list)
    """Parts the gate returned to the base."""
    findings: list[GateFinding] = field(default_factory=list)
    confidence: dict[str, float] = field(default_factory=dict)
    """Per movable part name, the confidence of its joint in [0, 1]."""

    def to_dict(self) -> dict:
        return {"decision": self.decision, "demoted": list(self.demoted),
                "findings": [f.to_dict() for f in self.findings],
                "confidence": {k: round(v, 3) for k, v in self.confidence.items()}}


def zero_travel(kind: str, upper: float, config: GateConfig) -> bool:
    """Whether a joint of ``kind`` with range (0, ``upper``) (m or rad) barely moves."""
    return upper < (config.min_travel if kind == "prismatic" else np.radians(config.min_angle_deg))


def stuck_drawer(evidence: dict, config: GateConfig) -> bool:
    """Whether a drawer's joint ``evidence`` (its box's ``travel`` and the ``free`` length it
    draws out before it collides, m) says it leaves less than ``min_free_share`` of its box."""
    travel, free = evidence.get("travel"), evidence.get("free")
    return travel is not None and free is not None and float(travel) > 0 \
        and float(free) < config.min_free_share * float(travel)


def stuck_hinge(evidence: dict, config: GateConfig) -> bool:
    """Whether a hinged panel's joint ``evidence`` (its ``sweep``: each hinge tried and the
    ``free_deg`` it swings before it collides) says it collides before ``min_swing_deg`` on
    every one."""
    sweep = evidence.get("sweep")
    return bool(sweep) and all(float(s.get("free_deg", 0.0)) < config.min_swing_deg for s in sweep)


def tiny_panel(extents: np.ndarray, outward: np.ndarray, config: GateConfig) -> bool:
    """Whether a panel with box ``extents`` (3,) m, facing ``outward`` (3,), is smaller across
    than ``min_panel_size`` in either in-plane direction."""
    axis = int(np.argmax(np.abs(outward)))
    return bool(np.delete(extents, axis).min() < config.min_panel_size)


def slides_both_ways(evidence: dict, config: GateConfig) -> str | None:
    """The axis (``u`` or ``v``) along which a sliding panel's joint ``evidence`` (its
    ``slides``: direction, ``free_m`` and ``width_m`` tried) says it runs free at least
    ``loose_slide_share`` of its width both ways, or None. A panel held in a track (``held``
    edges: the middle pane of three runs free both ways) is never loose."""
    if evidence.get("held"):
        return None
    share = {s["direction"]: s["free_m"] / s["width_m"] for s in evidence.get("slides", [])
             if s.get("width_m", 0.0) > 0}
    for axis in ("u", "v"):
        if min(share.get(axis + "+", 0.0), share.get(axis + "-", 0.0)) >= config.loose_slide_share:
            return axis
    return None


def facing_share(mesh: trimesh.Trimesh, outward: np.ndarray, config: GateConfig) -> float:
    """Share of ``mesh``'s area whose faces face along ``outward`` (3,) or against it (the
    cosine's magnitude at least ``facing_cos``): near 1 for a slab, small for a bar or a ball."""
    area = mesh.area_faces
    aligned = np.abs(mesh.face_normals @ outward) >= config.facing_cos
    return float(area[aligned].sum() / max(area.sum(), 1e-12))


def open_outline_share(mesh: trimesh.Trimesh, outward: np.ndarray, config: GateConfig) -> float:
    """Share of the outline of ``mesh``'s faces that face along ``outward`` (3,) or against it
    (within ``facing_cos``; its box seen along ``outward``) that they leave empty and open to
    the outline's edge: near 0 for a panel, a framed door (its pane's hole is enclosed) or a
    front with a pull beside it, large for the legs and apron of a table seen from the front
    (an upside-down U). A drawer's box behind its front faces sideways and does not count."""
    import cv2
    from scipy import ndimage

    axis = int(np.argmax(np.abs(outward)))
    faces = mesh.faces[np.abs(mesh.face_normals @ outward) >= config.facing_cos]
    if not len(faces):
        return 0.0
    triangles = np.delete(mesh.vertices, axis, axis=1)[faces]  # (K, 3, 2) seen along the axis
    lo, size = triangles.min(axis=(0, 1)), np.ptp(triangles.reshape(-1, 2), axis=0)
    if size.min() <= 0:
        return 0.0
    cells = np.maximum(np.round(config.outline_cells * size / size.max()).astype(int), 1)
    grid = np.zeros((cells[1] + 1, cells[0] + 1), np.uint8)
    corners = np.round((triangles - lo) / size.max() * config.outline_cells).astype(np.int32)
    cv2.fillPoly(grid, list(corners), 1)
    labels, _ = ndimage.label(grid == 0)
    border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    return float(np.isin(labels, border[border > 0]).sum() / grid.size)


def narrow_flap(extents: np.ndarray, outward: np.ndarray, axis: np.ndarray, config: GateConfig) -> bool:
    """Whether a door with box ``extents`` (3,) m facing ``outward`` (3,) sideways and turning
    about ``axis`` (3,) is a flap (a horizontal hinge) whose hinge edge is shorter than
    ``min_flap_aspect`` times the length it swings out."""
    if abs(axis[2]) > 0.5 or abs(outward[2]) > 0.5:
        return False
    along, facing = int(np.argmax(np.abs(axis))), int(np.argmax(np.abs(outward)))
    if along == facing:
        return False
    swing = 3 - along - facing
    return bool(extents[along] < config.min_flap_aspect * extents[swing])


def plinth_strip(lo: np.ndarray, hi: np.ndarray, base_vertices: np.ndarray, config: GateConfig) -> bool:
    """Whether a front with box (``lo``, ``hi``) (3,) m reaches across ``plinth_width_share`` of
    the carcass beside it (``base_vertices`` (N, 3) at its height; canonical: x across the
    front) and nothing of the base lies more than ``plinth_floor_tol`` m below it but legs (in
    at most ``plinth_below_share`` of ``plinth_columns`` columns across it): a drawer there with
    no grip is the carcass's plinth, a kick board cut out of a scan by the shadow line above it,
    or the bottom rail of a carcass on legs (a top board overhanging the sides widens the
    object, not the carcass)."""
    z, x = base_vertices[:, 2], base_vertices[:, 0]
    level = x[(z >= lo[2]) & (z <= hi[2])]
    if not len(level) or hi[0] - lo[0] < config.plinth_width_share * float(np.ptp(level)):
        return False
    below = x[(z < lo[2] - config.plinth_floor_tol) & (x >= lo[0]) & (x <= hi[0])]
    columns = np.unique(np.minimum(((below - lo[0]) / max(hi[0] - lo[0], TINY) * config.plinth_columns).astype(int),
                                   config.plinth_columns - 1))
    return len(columns) <= config.plinth_below_share * config.plinth_columns


def worktop(lid_lo: np.ndarray, lid_hi: np.ndarray, fronts: list[tuple[np.ndarray, np.ndarray]],
            config: GateConfig) -> bool:
    """Whether a lid with box (``lid_lo``, ``lid_hi``) (3,) m lies over a door or drawer facing
    the front with a grip (``fronts``: their boxes; canonical: x across, z up) across
    ``worktop_min_share`` of its width or more: the top board over a cabinet's fronts, whose
    overhang leaves a groove under its edge as a lid's parting line does. A box's lid closes the
    box; a bare board of its front under it is no door to trust over the lid."""
    for lo, hi in fronts:
        overlap = min(hi[0], lid_hi[0]) - max(lo[0], lid_lo[0])
        if hi[2] <= lid_hi[2] and overlap >= config.worktop_min_share * (hi[0] - lo[0]):
            return True
    return False


def lid_strip(extents: np.ndarray, config: GateConfig) -> bool:
    """Whether a lid with box ``extents`` (3,) m (canonical: x across the front, y front to
    back) is less than ``min_lid_depth_share`` as deep as it is wide: a window frame's top bar
    seen alone from above, not a box's cover (a box or a laptop is at least a third as deep as
    wide)."""
    return bool(extents[1] < config.min_lid_depth_share * extents[0])


def pull_knob_groups(centres: np.ndarray, outwards: np.ndarray, config: GateConfig,
                     sizes: np.ndarray | None = None) -> list[np.ndarray]:
    """Indices of front knobs laid out like drawer pulls: columns of knobs at one sideways
    position spanning ``min_pull_rows`` or more distinct heights, each at least
    ``min_pull_spacing`` apart and ``min_pull_spacing_share`` times the column's largest knob
    (a drawer is much taller than its pull; a stove's grid of dials sits a dial apart).

    ``centres`` (K, 3) knob centres, ``outwards`` (K, 3) their axes, ``sizes`` (K,) their
    largest extent (m; none known when None). Knobs facing up (a cooktop) never count; a
    single row (a stove's control panel) never counts."""
    front = np.flatnonzero(np.abs(outwards[:, 2]) < 0.5)
    if len(front) < config.min_pull_rows:
        return []
    sizes = np.zeros(len(centres)) if sizes is None else np.asarray(sizes, float)
    x, z = centres[front, 0], centres[front, 2]
    rows = _clusters(z, config.pull_align_tol)
    if rows.max() + 1 < config.min_pull_rows:
        return []
    columns = _clusters(x, config.pull_align_tol)
    groups = []
    for c in np.unique(columns):
        members = front[columns == c]
        heights = np.sort([z[rows == r].mean() for r in np.unique(rows[columns == c])])
        # drawers are stacked a hand's height apart; a keypad's buttons are not
        spacing = max(config.min_pull_spacing, config.min_pull_spacing_share * float(sizes[members].max()))
        if len(heights) >= config.min_pull_rows and np.diff(heights).min() >= spacing:
            groups.append(members)
    return groups


def face_rays(part_vertices: np.ndarray, outward: np.ndarray, config: GateConfig) -> tuple[np.ndarray, np.ndarray]:
    """(origins (K, 3), directions (K, 3)) of rays cast inward through a part's face: an
    ``open_grid`` x ``open_grid`` grid over the inner ``open_grid_share`` of the face of
    ``part_vertices`` (N, 3) seen along ``outward`` (3,), starting ``open_ray_start`` (m) in
    front of it."""
    front = float((part_vertices @ outward).max())
    u, v = perpendicular_basis(outward)
    pu, pv = part_vertices @ u, part_vertices @ v
    t = inner_grid(config.open_grid_share, config.open_grid)
    a, b = (g.ravel() for g in np.meshgrid(pu.min() + t * np.ptp(pu), pv.min() + t * np.ptp(pv)))
    origins = a[:, None] * u + b[:, None] * v + (front + config.open_ray_start) * outward
    return origins, np.tile(-outward, (len(origins), 1))


def backed_share(part_vertices: np.ndarray, outward: np.ndarray, carcass: trimesh.Trimesh,
                 config: GateConfig) -> float:
    """Share of the rays cast inward through a part's face (``face_rays``; ``part_vertices``
    (N, 3) m, ``outward`` (3,)) that meet the ``carcass`` behind it at all: near 1 for a drawer
    front over its cabinet, near 0 for a panel standing free (a laptop's screen)."""
    origins, directions = face_rays(part_vertices, outward, config)
    return float(np.mean(carcass.ray.intersects_any(origins, directions)))


def open_below_share(part_vertices: np.ndarray, outward: np.ndarray, carcass: trimesh.Trimesh,
                     config: GateConfig) -> float:
    """Share of the points ``below_probe_depth`` (m) behind a door's back face, over the grid of
    ``face_rays`` (``part_vertices`` (N, 3) m, ``outward`` (3,)), from which a ray straight down
    (-z) meets nothing of the ``carcass``: near 0 for a door over a compartment (its floor), near
    1 for a board of a desk's frame over the knee room."""
    origins, _ = face_rays(part_vertices, outward, config)
    along = part_vertices @ outward
    behind = float(along.max() - along.min()) + config.open_ray_start + config.below_probe_depth
    points = origins - behind * outward
    down = np.tile([0.0, 0.0, -1.0], (len(points), 1))
    return float(np.mean(~carcass.ray.intersects_any(points, down)))


def open_front_below(part_vertices: np.ndarray, outward: np.ndarray, whole: trimesh.Trimesh,
                     config: GateConfig) -> float:
    """Share of the rays cast inward from a row of points ``below_probe_drop`` (m) under a
    front's bottom edge, across the inner ``open_grid_share`` of its width (``part_vertices``
    (N, 3) m, facing ``outward`` (3,), horizontal), that meet none of ``whole`` (the object; the
    part lies above the rays) within ``below_probe_reach`` (m) of its face: near 1 for an apron
    board over a desk's knee room, near 0 for a drawer over the next drawer, a rail or a plinth.
    0 when the rays would pass under the object (a front down to its bottom: no knee room)."""
    up = np.array([0.0, 0.0, 1.0])
    across = np.cross(up, outward)
    along = part_vertices @ across
    t = inner_grid(config.open_grid_share, config.open_grid)
    front = float((part_vertices @ outward).max())
    height = float(part_vertices[:, 2].min()) - config.below_probe_drop
    if height <= float(whole.bounds[0, 2]):
        return 0.0
    origins = (along.min() + t * np.ptp(along))[:, None] * across + (front + config.open_ray_start) * outward \
        + height * up
    directions = np.tile(-outward, (len(origins), 1))
    locations, index_ray, _ = whole.ray.intersects_location(origins, directions, multiple_hits=False)
    reach = np.full(len(origins), np.inf)
    reach[index_ray] = (front - locations @ outward)
    return float(np.mean(reach > config.below_probe_reach))


def open_share_behind(part_vertices: np.ndarray, outward: np.ndarray, carcass: trimesh.Trimesh,
                      object_depth: float, config: GateConfig, fused: bool = False) -> float:
    """Share of a grid of rays through a panel's face that find room behind it.

    ``part_vertices`` (N, 3) of the part (m), ``outward`` (3,) the unit direction it faces,
    ``carcass`` the rest of the object, ``object_depth`` its extent along ``outward`` (m). Rays
    start just in front of the part and run inward over ``open_grid`` x ``open_grid`` points
    spanning the inner 80 % of its face; one counts when the carcass lies more than
    ``max(min_opening_depth, opening_depth_share * object_depth)`` behind the part's back (or
    not at all: a door in a wall frame). A door over a cavity scores near 1, a plate glued on
    solid carcass near 0. On a ``fused`` surface (a part cut out of a scan) only the front of
    a door's slab is the part, its back and the cavity's walls are carcass: there the room is
    also the free length along the ray, from each face it leaves material through to the next
    it enters."""
    along = part_vertices @ outward
    back = float(along.min())
    origins, directions = face_rays(part_vertices, outward, config)
    needed = max(config.min_opening_depth, config.opening_depth_share * object_depth)
    if not fused:
        locations, index_ray, _ = carcass.ray.intersects_location(origins, directions, multiple_hits=False)
        room = np.full(len(origins), np.inf)
        room[index_ray] = back - locations @ outward
        return float(np.mean(room > needed))
    locations, index_ray, index_tri = carcass.ray.intersects_location(origins, directions, multiple_hits=True)
    depth = locations @ outward
    leaving = carcass.face_normals[index_tri] @ -outward > 0
    free = np.full(len(origins), np.inf)
    for ray in np.unique(index_ray):
        mine = np.flatnonzero(index_ray == ray)
        mine = mine[np.argsort(-depth[mine])]  # nearest first
        # a scan that saw no inside at all (one shell) is judged as before, by its first face
        free[ray] = max(free_length(depth[mine], leaving[mine], back), back - depth[mine[0]])
    return float(np.mean(free > needed))


def floor_area(mesh: trimesh.Trimesh, floor: float, config: GateConfig) -> float:
    """Area (m^2) of ``mesh``'s faces facing down (-z) within ``floor_band`` of ``floor`` (z, m):
    what the mesh stands on."""
    down = (mesh.face_normals[:, 2] < -config.facing_cos) & (mesh.triangles_center[:, 2] < floor + config.floor_band)
    return float(mesh.area_faces[down].sum())


def enclosing_frames(lo: np.ndarray, hi: np.ndarray, mounted_on: list[int | None], tolerance: float) -> list[int]:
    """Indices of the panels (boxes ``lo``, ``hi`` (N, 3), m) whose box holds the box of another
    panel not mounted on it (``mounted_on[k]``: index of the panel k is mounted on, or None),
    grown by ``tolerance``: a door or a drawer front never holds another in its own outline
    and depth, a window's or a door's frame holds its sashes."""
    out = []
    for k in range(len(lo)):
        inside = inside_box(lo, hi, lo[k], hi[k], tolerance)
        inside[k] = False
        inside &= np.array([m != k for m in mounted_on])
        if inside.any():
            out.append(k)
    return out


def nearest_box_edge(vertices: np.ndarray, axis: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(3,) the point of the line through ``point`` along ``axis`` moved onto the nearest of the
    four edges parallel to ``axis`` of the box around ``vertices`` (V, 3) seen along ``axis``
    (a hinge line put on the edge of the part that turns about it)."""
    basis = perpendicular_basis(axis)
    flat = vertices @ basis.T
    corners = np.array([[x, y] for x in (flat[:, 0].min(), flat[:, 0].max())
                        for y in (flat[:, 1].min(), flat[:, 1].max())])
    here = basis @ point
    nearest = corners[np.argmin(np.linalg.norm(corners - here, axis=1))]
    return point + (nearest - here) @ basis


def free_length(depths: np.ndarray, leaving: np.ndarray, start: float) -> float:
    """Length (m) of empty space along one ray from ``start``, through its (K,) hits at
    ``depths`` (positions along the direction the ray came from, nearest first), each
    ``leaving`` material or entering it: from the start and from each face it leaves, to the
    next face it enters. Past the last face it leaves the ray is outside the object, which does
    not count."""
    total, since = 0.0, start
    for depth, leaves in zip(depths, leaving):
        if leaves:
            since = depth if since is None else since
        elif since is not None:
            total += max(since - depth, 0.0)
            since = None
    return float(total)


def front_plane(mesh: trimesh.Trimesh, outward: np.ndarray, config: GateConfig) -> float:
    """Position (m) along ``outward`` of the plane holding the most area of ``mesh`` that faces
    ``outward`` and is seen from in front (no face of the mesh before it): a drawer's front,
    not the button standing on it nor the inside of its back panel."""
    facing = np.flatnonzero(mesh.face_normals @ outward > config.facing_cos)
    if len(facing) == 0:
        return float((mesh.vertices @ outward).max())
    centres = mesh.triangles_center[facing] + config.open_ray_start * outward
    seen = ~mesh.ray.intersects_any(centres, np.tile(outward, (len(facing), 1)))
    if not seen.any():
        return float((mesh.vertices @ outward).max())
    along = np.round(centres[seen] @ outward / config.plane_resolution).astype(np.int64)
    bins, inverse = np.unique(along, return_inverse=True)
    area = np.bincount(inverse.ravel(), weights=mesh.area_faces[facing[seen]])
    return float(bins[np.argmax(area)] * config.plane_resolution)


def panel_beside_door(bare: tuple[np.ndarray, float], handled: tuple[np.ndarray, float], config: GateConfig) -> bool:
    """Whether a door without a handle is the carcass's panel beside a door with one: each
    given as its (2, 2) outline box (min and max along the in-plane axes u, v of
    ``panel_frame``, m) and the position of its face along its outward axis (m). The bare one
    lies beside the other (``side_panel_reach``) over half its own height and is at most
    ``side_panel_narrow_share`` as wide, or ``side_panel_max_share`` with its face
    ``side_panel_min_step`` or more behind the other's."""
    (box_a, face_a), (box_b, face_b) = bare, handled
    width_a, width_b = box_a[1, 0] - box_a[0, 0], box_b[1, 0] - box_b[0, 0]
    gap = max(box_a[0, 0] - box_b[1, 0], box_b[0, 0] - box_a[1, 0])
    overlap = min(box_a[1, 1], box_b[1, 1]) - max(box_a[0, 1], box_b[0, 1])
    if abs(gap) > config.side_panel_reach or overlap < 0.5 * (box_a[1, 1] - box_a[0, 1]):
        return False
    stepped = face_b - face_a >= config.side_panel_min_step
    return bool(width_a <= config.side_panel_narrow_share * width_b
                or (stepped and width_a <= config.side_panel_max_share * width_b))


def _clusters(values: np.ndarray, tol: float) -> np.ndarray:
    """(N,) cluster ids of 1-D ``values``: sorted neighbours closer than ``tol`` share one."""
    order = np.argsort(values)
    ids = np.zeros(len(values), int)
    ids[order] = np.concatenate([[0], np.cumsum(np.diff(values[order]) > tol)])
    return ids


def hinge_guessed(evidence: dict) -> bool:
    """Whether a joint's ``evidence`` says its hinge side was chosen for want of a handle (its
    rule ``... (no handle)``): a guess, not evidence of which side the panel opens from."""
    return "no handle" in str(evidence.get("rule", ""))


def slides_for_want_of_a_hinge(evidence: dict) -> bool:
    """Whether a joint's ``evidence`` says its panel slides only because every hinge it was tried
    on collided early: a fallback, no more evidence of the side it faces than a guessed hinge (a
    desk's side board, read from the side, slides along the legs framing it)."""
    return "every hinge collides early" in str(evidence.get("rule", ""))


def bare_drawer(evidence: dict) -> bool:
    """Whether a joint's ``evidence`` is a drawer's with no grip found on its front (no handle,
    no pocket): a flush rectangle on a face, which a wall of a box built of boards or the panel
    under a lid is as well; it says little of which side is the front."""
    return str(evidence.get("rule", "")).startswith("drawer") and evidence.get("grip") is False


def joint_confidence(evidence: dict, kind: str, upper: float, cap: float, config: GateConfig) -> float:
    """Confidence in [0, 1] of one joint from its rule's ``evidence`` and how far it opens
    (``upper`` of ``cap``, rad or m).

    A side chosen by a handle or a lid's back edge is evidence; a side chosen for want of one
    (``outer side (no handle)``) is a guess; a joint that stops early in its sweep is doubtful."""
    rule = str(evidence.get("rule", ""))
    base = config.rule_confidence.get(rule.split(":")[0].split(",")[0].strip(), config.default_confidence)
    if hinge_guessed(evidence):
        base = min(base, config.rule_confidence.get("guess", base))
    share = float(np.clip(upper / cap, 0.0, 1.0)) if cap > 0 else 1.0
    return float(np.clip(base * (config.open_weight * share + 1.0 - config.open_weight), 0.0, 1.0))


def review(parts: list, joints: dict, extents: dict[str, np.ndarray], caps: dict[str, float],
           config: GateConfig, open_behind: dict[str, float] | None = None,
           floor_heights: dict[str, float] | None = None, facing: dict[str, float] | None = None,
           open_outline: dict[str, float] | None = None, enclosed: set[str] | None = None,
           backed: dict[str, float] | None = None,
           door_fronts: dict[str, tuple[np.ndarray, float]] | None = None,
           plinths: set[str] | None = None, worktops: set[str] | None = None,
           open_below: dict[str, float] | None = None) -> GateResult:
    """Review the structure of ``parts`` (PartEstimate, the base first) and their ``joints``
    (part name -> JointEstimate); ``extents`` maps part names to their (3,) box size (m), the
    whole object's under ``base``,
    ``caps`` to the largest range their joint could have (rad or m), ``open_behind`` panels to
    their ``open_share_behind``, ``floor_heights`` controls to the height of their top above
    the object's bottom (m), ``facing`` doors and lids to their ``facing_share``,
    ``open_outline`` doors, drawers and lids to their ``open_outline_share``; ``enclosed`` names
    the parts of their own pieces that lie inside the carcass's box behind their front (never
    the carcass, however large: a cabinet's one big drawer); ``backed`` drawers without a body
    of their own to their ``backed_share``; ``door_fronts`` hinged doors facing the front to
    their outline box and face position (``panel_beside_door``); ``plinths`` names the drawers
    with no grip that reach across the whole carcass at its bottom (``plinth_strip``),
    ``worktops`` the lids over doors or drawers with a grip on the front (``worktop``),
    ``open_below`` doors without a handle (a handle says door, whatever its maker modelled behind
    it), hinged or sliding, facing sideways, whose room the object closes at the back, to their
    ``open_below_share`` (and drawers cut out of a scan's surface that showed no box behind
    them; with a grip, only those over open space in front too, ``open_front_below``: a grip
    does not put a box behind an apron board). Returns the verdict; the caller demotes the
    parts it names."""
    result = GateResult("articulated")
    demoted: set[str] = set()
    stuck: set[str] = set()
    for name in sorted(plinths or ()):
        result.findings.append(GateFinding("plinth", (name,), f"{name}: a strip with no grip across the whole "
                                                              "carcass at its bottom: its plinth or bottom rail, not a "
                                                              "drawer",
                                           "demoted"))
        demoted.add(name)
    for name in sorted(worktops or ()):
        result.findings.append(GateFinding("worktop", (name,), f"{name}: a top over the doors or drawers of the "
                                                               "front: the worktop, not a lid", "demoted"))
        demoted.add(name)
    movable = [p for p in parts if p.semantic != "base"]
    for part in movable:
        joint = joints.get(part.name)
        if joint is None:
            continue
        if part.semantic != "knob" and zero_travel(joint.type, joint.upper, config):
            result.findings.append(GateFinding("zero_travel", (part.name,),
                                               f"{part.name}: its {joint.type} joint opens by only {joint.upper:.4g}",
                                               "demoted"))
            demoted.add(part.name)
        elif joint.type == "prismatic" and (axis := slides_both_ways(joint.evidence, config)) is not None:
            result.findings.append(GateFinding(
                "loose_slide", (part.name,), f"{part.name}: slides free both ways along {axis}: nothing holds it in "
                                             "a track, it lies on the object", "demoted"))
            demoted.add(part.name)
        elif part.semantic == "drawer" and stuck_drawer(joint.evidence, config):
            result.findings.append(GateFinding(
                "stuck", (part.name,), f"{part.name}: draws out {float(joint.evidence['free']) * 100:.1f} cm of its "
                                       f"{float(joint.evidence['travel']) * 100:.1f} cm box before it collides: stuck, "
                                       "not a drawer", "demoted"))
            demoted.add(part.name)
        elif str(joint.evidence.get("rule", "")).startswith("no front shown"):
            result.findings.append(GateFinding(
                "no_front", (part.name,), f"{part.name}: no side of the object shows any relief, so which side is "
                                          "its front, and where this bare panel hinges, is the file's guess; pass "
                                          "--front (e.g. --front=-y) to say which side it is", "doubted"))
        elif part.semantic in ("door", "lid") and joint.type == "revolute" and stuck_hinge(joint.evidence, config):
            # a panel the views or pieces show, that swings on no edge: what holds it is not
            # understood, and the object without it would be published as if it were
            result.findings.append(GateFinding(
                "stuck", (part.name,), f"{part.name}: collides before {config.min_swing_deg:g} degrees on every "
                                       f"hinge tried ({len(joint.evidence['sweep'])}): stuck, not a panel that "
                                       "swings", "doubted"))
            stuck.add(part.name)
    # knobs that turn about their own normal, as a pull would if it were one (not a lever)
    knobs = [p for p in movable if p.semantic == "knob" and p.name in joints and p.outward is not None
             and abs(float(np.asarray(joints[p.name].axis) @ p.outward)) > config.facing_cos]
    if knobs:
        centres = np.array([joints[p.name].origin for p in knobs])
        outwards = np.array([joints[p.name].axis for p in knobs])
        sizes = np.array([float(np.max(extents.get(p.name, 0.0))) for p in knobs])
        for group in pull_knob_groups(centres, outwards, config, sizes):
            names = tuple(knobs[k].name for k in group)
            result.findings.append(GateFinding(
                "pull_knobs", names, f"{len(names)} knobs stacked in one column at {len(group)} heights look like "
                                     "the pulls of drawers that were not found, not controls", "demoted"))
            demoted.update(names)
    for name, share in (backed or {}).items():
        if name not in demoted and share < config.min_backed_share:
            result.findings.append(GateFinding(
                "unbacked", (name,), f"{name}: only {share:.0%} of its face has the object behind it: a panel "
                                     "standing free, with nothing to draw out of", "demoted"))
            demoted.add(name)
    for name, share in (open_behind or {}).items():
        if name not in demoted and share < config.min_open_share:
            result.findings.append(GateFinding(
                "no_opening", (name,), f"{name}: solid carcass right behind it ({share:.0%} of its face opens onto "
                                       "room): a facade, not a door or drawer", "demoted"))
            demoted.add(name)
    for name, share in sorted((open_below or {}).items()):
        if name not in demoted and share >= config.open_below_min_share:
            result.findings.append(GateFinding(
                "open_below", (name,), f"{name}: the room behind it is open below from {share:.0%} of its face, "
                                       "down to the floor: a board over knee room, not a door closing a "
                                       "compartment nor a drawer's front (its box would be in sight)", "demoted"))
            demoted.add(name)
    fronts = door_fronts or {}
    bare = [n for n in fronts if hinge_guessed(joints[n].evidence)]
    for name in bare:
        beside = next((other for other in fronts if other not in bare
                       and panel_beside_door(fronts[name], fronts[other], config)), None)
        if name not in demoted and beside is not None:
            cm = lambda n: round(float(np.ptp(fronts[n][0][:, 0])) * 100, 1)  # noqa: E731
            step = fronts[beside][1] - fronts[name][1]
            where = f"{step * 100:.1f} cm behind its face" if step >= config.side_panel_min_step else "level with it"
            result.findings.append(GateFinding(
                "side_panel", (name,), f"{name}: no handle, {cm(name)} cm wide beside {beside}'s {cm(beside)} cm, "
                                       f"{where}: the carcass's panel beside a door, not a door", "demoted"))
            demoted.add(name)
    whole = extents.get("base")
    for name, height in (floor_heights or {}).items():
        if name not in demoted and whole is not None and height < config.floor_control_share * whole[2]:
            result.findings.append(GateFinding(
                "floor_control", (name,), f"{name}: a control whose top is {height * 100:.1f} cm above the floor "
                                          "the object stands on is a foot or a bolt", "demoted"))
            demoted.add(name)
    for part in movable:
        size = extents.get(part.name)
        if whole is not None and size is not None and part.name not in demoted \
                and part.name not in (enclosed or set()) and np.all(size >= config.max_part_share * whole):
            result.findings.append(GateFinding("carcass_sized", (part.name,),
                                               f"{part.name}: a {part.semantic} as large as the whole object "
                                               "is the carcass, not a part of it", "demoted"))
            demoted.add(part.name)
    for part in movable:  # is each door, drawer and lid a panel?
        if part.semantic not in ("door", "drawer", "lid") or part.name in demoted:
            continue
        joint, size, share = joints.get(part.name), extents.get(part.name), (facing or {}).get(part.name)
        cm = None if size is None else np.round(np.asarray(size) * 100, 1).tolist()
        if size is not None and tiny_panel(np.asarray(size), part.outward, config):
            finding = GateFinding("tiny_panel", (part.name,), f"{part.name}: a {part.semantic} only {cm} cm across",
                                  "demoted")
        elif (opened := (open_outline or {}).get(part.name)) is not None and opened >= config.max_open_outline:
            finding = GateFinding("open_frame", (part.name,), f"{part.name}: {opened:.0%} of its outline is open to its "
                                                              "edge: an open frame (legs and rails), not a panel",
                                  "demoted")
        elif share is not None and share < config.min_facing_share:
            finding = GateFinding("not_a_panel", (part.name,), f"{part.name}: only {share:.0%} of its surface faces "
                                                               "the way it opens: a bar or a post, not a panel", "demoted")
        elif part.semantic == "door" and joint is not None and joint.type == "revolute" and size is not None \
                and narrow_flap(np.asarray(size), part.outward, joint.axis, config):
            finding = GateFinding("narrow_flap", (part.name,), f"{part.name}: a flap {cm} cm hinged along its short "
                                                               "edge", "demoted")
        elif part.semantic == "lid" and size is not None and lid_strip(np.asarray(size), config):
            finding = GateFinding("lid_strip", (part.name,), f"{part.name}: a lid {cm} cm, a strip: the top bar of a "
                                                             "frame, not the cover of a box", "demoted")
        else:
            continue
        result.findings.append(finding)
        demoted.add(part.name)
    result.demoted = sorted(demoted)
    for part in movable:
        if part.name in demoted or part.name not in joints:
            continue
        j = joints[part.name]
        result.confidence[part.name] = 0.0 if part.name in stuck else \
            joint_confidence(j.evidence, j.type, j.upper, caps.get(part.name, 0.0), config)
    if not result.confidence:
        result.decision = "static"
        result.findings.append(GateFinding("static", (), "no movable part was found",
                                           "allowed (--allow-static)" if config.allow_static else "refused"))
    return result
