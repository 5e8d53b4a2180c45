"""Parts from the pieces of a mesh (the offline rule backend for artist-style meshes).

A *piece* is a connected component of the input (artists model a drawer front, its box and its
handle as separate objects). Pieces that touch or interpenetrate are rigidly joined; the group
holding the largest piece is the base. Small pieces on the base are controls: one reaching into
a hole below the surface around it is a button, pushed in along the surface's normal as far as
the hole leaves room; a round one standing proud of the surface it sits on (a front, a top or a
sloped panel) is a knob turning about that normal; a small group that touches nothing (a dial
modelled off its panel, its spindle left out) is judged the same way on the surface it stands
off. Thin fronts that touch the carcass but cover open space are split out with their handle and
body; loose handles join the panel they float on. A group far from the carcass and from every
other panel closes against nothing and stays fixed. Every other group is a movable part, whose
outward direction is the side where it shows the largest area visible from outside. A group
whose body reaches deep behind its front is a drawer, a part facing up is a lid, the rest are
doors.

All coordinates are canonical (+z up, -y front), metres.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import networkx as nx
import numpy as np
import trimesh

from rest2art.asset import numbered_names
from rest2art.config import PartsConfig
from rest2art.geometry.basics import (boxes_overlap, faces_at_extreme, first_hits, footprint_spread, inner_grid,
                                      outer_plane, panel_frame, perpendicular_basis, principal_axes, ray_distances,
                                      signed_volume)
from rest2art.geometry.fcl import bvh_object, distance
from rest2art.io.load import merged_vertex_ids
from rest2art.tolerances import RAY_NUDGE, TINY

OUTWARD = {"front": np.array([0.0, -1.0, 0.0]), "top": np.array([0.0, 0.0, 1.0]),
           "left": np.array([-1.0, 0.0, 0.0]), "right": np.array([1.0, 0.0, 0.0])}


PANELS = ("door", "drawer", "lid")
"""Movable parts that open like a panel and may carry fittings of their own."""

@dataclass
class Piece:
    """One connected component of the input."""

    index: int
    faces: np.ndarray
    """(k,) indices into the input faces."""
    mesh: trimesh.Trimesh
    lo: np.ndarray
    hi: np.ndarray

    @property
    def extents(self) -> np.ndarray:
        return self.hi - self.lo

    @property
    def centre(self) -> np.ndarray:
        return (self.lo + self.hi) / 2


@dataclass
class PartEstimate:
    """A rigid part found in the mesh."""

    semantic: str
    """base, drawer, door, lid, knob or button."""
    pieces: list[int]
    outward: np.ndarray | None = None
    """(3,) the direction the part opens towards (None for the base)."""
    panel: int | None = None
    """Index of the piece that forms the part's front panel."""
    name: str = ""
    extra: dict = field(default_factory=dict)
    parent: PartEstimate | None = None
    """The movable part it is mounted on (a dial or a lever on a door); None: the base."""


def split_pieces(vertices: np.ndarray, faces: np.ndarray, face_component: np.ndarray) -> list[Piece]:
    """(V, 3), (F, 3), (F,) -> one Piece per component id, in id order."""
    order = np.argsort(face_component, kind="stable")
    bounds = np.flatnonzero(np.diff(face_component[order])) + 1
    return [make_piece(k, idx, vertices, faces) for k, idx in enumerate(np.split(order, bounds))]


def contact_graph(pieces: list[Piece], tol: float) -> nx.Graph:
    """Graph over pieces with an edge where two pieces are closer than ``tol``."""
    graph = nx.Graph()
    graph.add_nodes_from(range(len(pieces)))
    lo = np.array([p.lo for p in pieces]) - tol
    hi = np.array([p.hi for p in pieces]) + tol
    overlap = boxes_overlap(lo, hi, lo, hi)
    objects: dict[int, object] = {}
    for i, j in zip(*np.nonzero(np.triu(overlap, 1))):
        for k in (i, j):
            if k not in objects:
                objects[k] = bvh_object(pieces[k].mesh.vertices, pieces[k].mesh.faces)
        if distance(objects[i], objects[j]) <= tol:
            graph.add_edge(int(i), int(j))
    return graph


def _volume(mesh: trimesh.Trimesh) -> float:
    if mesh.is_watertight and signed_volume(mesh) > 0:
        return signed_volume(mesh)
    return float(mesh.convex_hull.volume) if len(mesh.vertices) >= 4 else 0.0


SNAP_DEG = 10.0
"""A direction within this angle (deg) of a coordinate axis is taken to be that axis."""
DISC_DIAMETER_PER_STD = 4.0
"""A uniform disc's diameter is four times the standard deviation of its points along a line."""


def snap_axis(direction: np.ndarray) -> np.ndarray:
    """The (3,) unit ``direction`` snapped to the nearest signed coordinate axis when within
    ``SNAP_DEG`` of it (modelled parts are mostly aligned with the object's frame)."""
    k = int(np.argmax(np.abs(direction)))
    if abs(direction[k]) > np.cos(np.radians(SNAP_DEG)):
        return np.eye(3)[k] * np.sign(direction[k])
    return direction


def protrusion_axis(piece: Piece, mount: trimesh.Trimesh, reach: float) -> np.ndarray | None:
    """(3,) direction in which a small ``piece`` stands out of ``mount``: among the piece's
    principal axes (both signs; within 10 degrees of a coordinate axis they snap to it), the
    ones along which a ray from the piece's centre escapes the mount, and of those the one
    whose opposite ray meets the mount nearest (the plate a knob sits on, the floor of a
    button's hole). None when the piece's surface does not come within ``reach`` (m) of the
    mount's (surfaces, not vertices: a button's corners can stand clear of the bezel its sides
    slide in)."""
    if distance(bvh_object(piece.mesh.vertices, piece.mesh.faces), bvh_object(mount.vertices, mount.faces)) > reach:
        return None
    axes = principal_axes(piece.mesh.vertices)
    snapped = [snap_axis(a) for a in axes]
    candidates = np.concatenate([snapped, -np.array(snapped)])
    centre = piece.mesh.bounds.mean(axis=0)
    origins = np.tile(centre, (len(candidates), 1))
    forward = mount.ray.intersects_any(origins, candidates)
    locations, index_ray, _ = mount.ray.intersects_location(origins, -candidates, multiple_hits=False)
    back = np.full(len(candidates), np.inf)
    back[index_ray] = np.einsum("ij,ij->i", locations - origins[index_ray], -candidates[index_ray])
    back[forward] = np.inf
    if not np.isfinite(back).any():
        return None
    return candidates[int(np.argmin(back))].astype(float)


def small_control(piece: Piece, mount: trimesh.Trimesh | None, config: PartsConfig,
                  max_size: float | None = None, axis: np.ndarray | None = None,
                  normal: np.ndarray | None = None) -> tuple[str, np.ndarray, float] | None:
    """(kind, outward axis (3,), travel m) of a small piece, no larger than ``max_size`` (m;
    ``knob_max_size`` when None), mounted on ``mount``, standing out of it along ``axis`` (3,)
    (``protrusion_axis`` when None), on a surface whose outward normal is ``normal`` (3,;
    ``plate_normal``, None when unknown):

    * a ``button`` reaches ``button_min_sunk`` or more below the surface around it (it sits
      in a hole) and stands ``button_min_proud`` or more out of it; it is pushed in along
      the surface's normal as far as the hole leaves room (rays from its inner end), at most
      ``button_max_travel``;
    * a round cap (``knob_roundness``) held more than ``knob_max_gap`` off a side-facing
      surface on a stem is a ``button`` too (a mushroom push button), pushed in until it meets
      the surface; a rod lying along the surface (a hinge's knuckle) is not;
    * a ``knob`` sits on the surface (front, top or a sloped panel; a cap on a post standing
      up, like a tap's handle, too), round about its normal and standing proud by
      ``knob_min_height`` of its width or more; it turns about it;
    * a ``stick`` stands out of the surface along its long axis (``is_stick``: slender, within
      ``stick_max_lean_deg`` of ``normal``) and is not round about ``normal`` (it leans, or it
      is a flat bar): a toggle switch, a lever's bar, whatever hole its foot sits in; its axis
      is ``normal`` and the joints decide how it moves (``stick_lever``).

    None for anything else (a handle, a board, anything under the object)."""
    e = piece.extents
    if mount is None or e.max() > (config.knob_max_size if max_size is None else max_size) or e.min() <= 0:
        return None
    if axis is None:
        axis = protrusion_axis(piece, mount, config.mount_reach)
    if axis is None or axis[2] < -config.control_max_down:  # under the object: a foot, not a control
        return None
    if normal is not None and is_stick(piece.mesh.vertices, normal, config):
        spread = footprint_spread(piece.mesh.vertices, normal)
        if spread.max() > 0 and spread.min() / spread.max() < config.knob_roundness:
            return "stick", normal, 0.0
    along = piece.mesh.vertices @ axis
    surface = surface_height(piece, mount, axis, config)
    sunk = surface - float(along.min())
    if sunk >= config.button_min_sunk and float(along.max()) - surface >= config.button_min_proud:
        inner = piece.mesh.vertices[along <= along.min() + config.button_tip_band]
        room = hole_depth(inner, -axis, mount, config.button_max_travel)
        return "button", axis, room
    spread = footprint_spread(piece.mesh.vertices, axis)
    if spread.max() <= 0:
        return None
    round_ = spread.min() / spread.max() >= config.knob_roundness
    gap = -sunk  # how far its underside stands off the surface
    if gap > config.knob_max_gap and abs(axis[2]) < config.stem_button_max_up and round_:
        return "button", axis, gap  # a cap held off a front on a stem: pushed in until it meets it
    height = float(along.max()) - surface
    width = DISC_DIAMETER_PER_STD * float(spread.max())
    if round_ and height >= config.knob_min_height * width:
        return "knob", axis, 0.0
    return None


def is_stick(vertices: np.ndarray, outward: np.ndarray, config: PartsConfig) -> bool:
    """Whether the (N, 3) ``vertices`` of a small piece make a stick standing out along
    ``outward`` (3,): their long principal axis within ``stick_max_lean_deg`` of it and
    ``stick_min_slenderness`` times as long as the piece is thick across it (a bar pull lies
    along its surface, a knob is as wide as tall)."""
    axes = principal_axes(vertices)
    if abs(float(axes[2] @ outward)) < np.cos(np.radians(config.stick_max_lean_deg)):
        return False
    length = float(np.ptp(vertices @ axes[2]))
    thickness = float(np.ptp(vertices @ axes[:2].T, axis=0).max())
    return length >= config.stick_min_slenderness * thickness


def surface_height(piece: Piece, mount: trimesh.Trimesh, axis: np.ndarray, config: PartsConfig) -> float:
    """Position along ``axis`` of the mount's surface around a small piece: rays cast against
    ``axis`` from above the piece, on rings 1, 2 and 3 ``surface_ring`` (m) outside its
    outline, hit the plate a knob stands on or the rim of a button's hole; the highest of the
    rings' median hits. The piece's lowest point where no ring hits."""
    along = piece.mesh.vertices @ axis
    helper = np.eye(3)[np.argmin(np.abs(axis))]
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    flat = piece.mesh.vertices - np.outer(along, axis)
    centre = flat.mean(axis=0)
    outline = float(np.linalg.norm(flat - centre, axis=1).max())
    angles = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
    ring = np.cos(angles)[:, None] * u + np.sin(angles)[:, None] * v
    heights = []
    for k in (1, 2, 3):  # a hole's clearance may swallow the first ring
        origins = centre + (outline + k * config.surface_ring) * ring + (along.max() + config.surface_ray_start) * axis
        locations, index_ray, _ = mount.ray.intersects_location(origins, np.tile(-axis, (len(origins), 1)),
                                                                multiple_hits=False)
        if len(index_ray) >= len(origins) // 2:
            heights.append(float(np.median(locations @ axis)))
    return max(heights) if heights else float(along.min())


def hole_depth(points: np.ndarray, direction: np.ndarray, mount: trimesh.Trimesh, limit: float) -> float:
    """Median free distance (m) from ``points`` (N, 3) along ``direction`` before the mount,
    at most ``limit``: how far a button can be pushed into its hole."""
    free = np.minimum(ray_distances(mount, points + RAY_NUDGE * direction, direction), limit)
    return float(np.median(free))


def facing_area(mesh: trimesh.Trimesh, direction: np.ndarray, band: float,
                occluder: trimesh.Trimesh | None = None, max_rays: int = 256) -> float:
    """Area of faces facing ``direction`` within ``band`` of the mesh's extreme along it; with
    an ``occluder``, only faces whose outward ray escapes it count (the exposed area)."""
    mask = faces_at_extreme(mesh, direction, band)
    if occluder is None or not mask.any():
        return float(mesh.area_faces[mask].sum())
    idx = np.flatnonzero(mask)
    area = mesh.area_faces[idx]
    if len(idx) > max_rays:  # sample faces by area: an unbiased estimate of the exposed share
        pick = np.random.default_rng(0).choice(len(idx), max_rays, replace=False, p=area / area.sum())
        weights = np.full(max_rays, area.sum() / max_rays)
        idx = idx[pick]
    else:
        weights = area
    origins = mesh.triangles_center[idx] + RAY_NUDGE * direction
    hit = occluder.ray.intersects_any(origins, np.tile(direction, (len(idx), 1)))
    return float(weights[~hit].sum())


def extract_parts(vertices: np.ndarray, faces: np.ndarray, face_component: np.ndarray,
                  config: PartsConfig = PartsConfig(), fused: bool = False) -> tuple[list[PartEstimate], list[Piece]]:
    """Group the pieces of a canonical-frame mesh into a base and movable parts. A ``fused``
    surface (a scan, a few islands aside) or a mesh of one piece is first searched for a small
    fixture's handle on a neck (``neck_parts``)."""
    pieces = split_pieces(vertices, faces, face_component)
    if len(pieces) == 1 or fused:
        found = neck_parts(pieces, vertices, faces, config)
        if found is not None:
            return found
    if len(pieces) == 1:
        return [PartEstimate("base", [0], name="base")], pieces
    graph = contact_graph(pieces, config.contact_tol)
    groups = [sorted(g) for g in nx.connected_components(graph)]
    box_volume = lambda idx: float(np.prod(  # noqa: E731
        np.max([pieces[i].hi for i in idx], axis=0) - np.min([pieces[i].lo for i in idx], axis=0)))
    groups, merged = merge_supports(groups, pieces, config)
    base_group = groups[0] if merged else max(groups, key=box_volume)
    # a lid with a grip on a box of boards first (it may be the box's largest board): the box's
    # front board under it, with open space behind, is no door (a cabinet of boards has its top
    # board where a box has its lid)
    boxed = split_touching_lids(base_group, -1, pieces, graph, config, boards=True)  # no anchor chosen yet
    in_lids = {k for lid in boxed for k in lid}
    walls_of = [{j for i in lid for j in graph.neighbors(i) if j in base_group and j not in in_lids} for lid in boxed]
    box_walls = set().union(*walls_of)
    largest, fronts_first = carcass_anchor([i for i in base_group if i not in in_lids], pieces, config)
    base_lo, base_hi = pieces_box([i for i in base_group if i not in fronts_first and i not in in_lids], pieces) \
        if fronts_first else (pieces[largest].lo, pieces[largest].hi)

    obj_lo = np.min([p.lo for p in pieces], axis=0)
    obj_hi = np.max([p.hi for p in pieces], axis=0)
    control_size = max(config.knob_max_size, config.knob_max_share * float((obj_hi - obj_lo).max()))
    fronts = split_touching_fronts([i for i in base_group if i not in in_lids],
                                   largest, pieces, graph, config, fronts_first, box_walls)
    split = {i for f in [*boxed, *fronts] for i in f}
    lids = split_touching_lids([i for i in base_group if i not in split], largest, pieces, graph, config)
    fronts += boxed + lids
    split |= {i for f in lids for i in f}
    others = [g for g in groups if g is not base_group]
    base_group = [i for i in base_group if i not in split]
    groups = attach_loose_handles([base_group, *others, *fronts], base_group, pieces, config)

    parts: list[PartEstimate] = []

    def control(i: int, group: list[int], anchor: int) -> PartEstimate | None:
        """Piece ``i`` of ``group`` (held by its piece ``anchor``) as a small control, or None."""
        if pieces[i].extents.max() > control_size:
            return None
        # what hangs on it (a knob's grip bar in front of its disc) is no surface it stands on:
        # it would block the way out along the knob's own axis; unless the two together are
        # too large for a control (a faucet's arm and its handle)
        rest = graph.subgraph([k for k in group if k != i])
        hanging = {k for component in nx.connected_components(rest) if anchor not in component
                   and any(graph.has_edge(i, j) for j in component) for k in component}
        lo, hi = pieces_box([i, *hanging], pieces)
        if float((hi - lo).max()) > control_size:
            hanging = set()
        others = [pieces[k].mesh for k in group if k != i and k not in hanging]
        if not others:
            return None
        mount = trimesh.util.concatenate(others)
        axis = protrusion_axis(pieces[i], mount, config.mount_reach)
        if axis is None:
            return None
        normal = plate_normal(pieces[i].mesh, mount, config)
        found = small_control(pieces[i], mount, config, control_size,
                              towards_normal(axis, normal, config, pieces[i].mesh), normal)
        if found is None:
            return None
        return control_estimate(found, [i], i)

    def controls_of(group: list[int], anchor: int) -> list[int]:
        """The pieces of ``group`` that are no control of it; its controls, with what hangs on
        them (``attach_hanging_pieces``), go to ``parts``."""
        found, kept = [], []
        for i in group:
            part = None if i == anchor else control(i, group, anchor)
            if part is not None:
                found.append(part)
            else:
                kept.append(i)
        parts.extend(attach_hanging_pieces(merge_riding_controls(found, graph), kept, anchor, graph))
        return kept

    base_pieces = controls_of(base_group, largest)
    parts += base_fittings(base_pieces, largest, pieces, graph, config)
    parts += slot_sliders(base_pieces, largest, pieces, graph, config)
    base = PartEstimate("base", base_pieces)
    # the part itself occludes too: its own inner faces (a drawer's back wall) are not its face
    scene = trimesh.util.concatenate([pieces[i].mesh for g in groups for i in g])
    panels = []
    for group in groups:
        if group is base_group:
            continue
        part = loose_control(group, groups, pieces, control_size, config) or hub_lever(group, groups, pieces, config)
        if part is not None:
            parts.append(part)
        else:
            panels.append(group)
    for group in panels:
        if floats_clear(group, [g for g in [base_group, *panels] if g is not group], pieces, config.part_max_gap):
            # a fixed piece of the scene the model was cut from (a control panel on the wall
            # above a stove), with the controls on it
            base.pieces.extend(controls_of(group, max(group, key=lambda i: box_volume([i]))))
            continue
        part = classify_group(group, pieces, base_lo, base_hi, obj_lo, obj_hi, config, scene)
        body = body_inside(set(group), set(base.pieces), pieces, graph, config) \
            if part is not None and part.semantic == "door" and part.outward @ OUTWARD["front"] > 0.5 else set()
        if body:  # a front held off its drawer's box, which runs in the carcass
            base.pieces = [i for i in base.pieces if i not in body]
            part = classify_group(sorted({*group, *body}), pieces, base_lo, base_hi, obj_lo, obj_hi, config,
                                  scene, part)
        if part is None:
            base.pieces.extend(group)
        else:
            parts.append(part)
    parts += [f for part in list(parts) if part.semantic in PANELS for f in turning_fittings(part, pieces, graph, config)]
    for part in parts:  # the views must not cut the boards under a lid out as fronts either
        for lid, walls in zip(boxed, walls_of):
            if set(lid) <= set(part.pieces):
                part.extra["box_walls"] = sorted(walls & set(base.pieces))
    for part in [p for p in parts if p.semantic == "button" and not compact_outline(p, pieces, config)]:
        parts.remove(part)  # a spout on its stub, sunk into the wall like a button: a fitting
        base.pieces.extend(part.pieces)
    for part in parts:
        if part.semantic == "button":
            take_stem(part, base, pieces, vertices, faces, config)
    base.name = "base"
    renumber(parts)
    return [base, *parts], pieces


def neck_parts(pieces: list[Piece], vertices: np.ndarray, faces: np.ndarray,
               config: PartsConfig) -> tuple[list[PartEstimate], list[Piece]] | None:
    """The base and the handle of a small fixture cut out of its largest piece along a neck
    (``rest2art.parts.posts``), the other pieces (a scan's islands) left with the base: a head
    on a post that turns like a lever (``turn_asymmetry`` at least ``cut_fitting_min_asymmetry``:
    a tap's handle) is a knob turning about the post; else a handle standing out of
    the front on a neck that runs into a slot (a press's handle on its bar) slides along the
    slot (``slot_room``). None when the largest piece has neither (a handle on a door's face
    runs into no slot: it is the door's)."""
    from rest2art.parts.posts import front_handle, post_head, slot_room

    largest = max(pieces, key=lambda p: len(p.faces))
    moving = np.zeros(len(largest.faces), bool)
    post = post_head(largest.mesh, config)
    if post is not None:
        head = trimesh.Trimesh(largest.mesh.vertices, largest.mesh.faces[post.head], process=False)
        if turn_asymmetry(head, post.direction, post.pivot, config) < config.cut_fitting_min_asymmetry:
            post = None  # round about its column (a pedestal table's top, a stool's seat): no lever
    if post is not None:
        moving[post.head] = True
        part = PartEstimate("knob", [len(pieces)], post.direction, len(pieces), name="knob_0",
                            extra={"travel": 0.0, "pivot": post.pivot, "rule": "head on a post: turns about the post"})
    else:
        handle = front_handle(largest.mesh, config)
        slot = slot_room(largest.mesh, handle, config) if handle is not None else None
        if slot is None:
            return None
        moving[handle.head] = moving[handle.neck] = True
        part = PartEstimate("slider", [len(pieces)], handle.direction, len(pieces), name="slider_0",
                            extra={"travel": 0.0, "pivot": handle.pivot, "slot": slot})
    out = list(pieces)
    out[largest.index] = make_piece(largest.index, largest.faces[~moving], vertices, faces)
    out.append(make_piece(len(pieces), largest.faces[moving], vertices, faces))
    return [PartEstimate("base", [p.index for p in pieces], name="base"), part], out


def compact_outline(part: PartEstimate, pieces: list[Piece], config: PartsConfig) -> bool:
    """Whether ``part``'s outline seen along its ``outward`` axis is compact enough for a cap to
    push: its smaller footprint spread at least ``button_min_roundness`` of its larger."""
    points = np.concatenate([pieces[i].mesh.vertices for i in part.pieces])
    spread = footprint_spread(points, part.outward)
    return bool(spread[0] > 0 and spread[1] >= config.button_min_roundness * spread[0])


def stem_faces(cap_points: np.ndarray, triangles: np.ndarray, axis: np.ndarray, config: PartsConfig) -> np.ndarray:
    """(F,) bool: which faces, by their corners (F, 3, 3) ``triangles``, are the stem of a push
    button whose cap has the (N, 3) ``cap_points`` and is pushed in along -``axis`` (3,). Faces
    wholly behind the cap's back and within its inscribed radius (not a board's large face
    around a hole) are followed by their centres in ``stem_slice`` slices from the cap's back
    while no slice is empty and each slice's widest reach from the cap's axis stays within
    ``stem_widening`` over the narrowest before it (the collar or the wall the stem enters
    widens); a stem is thinner than its cap, at most ``stem_max_share`` of that radius. All
    False on a surface with no stem behind the cap."""
    in_plane = np.eye(3) - np.outer(axis, axis)
    back = float((cap_points @ axis).min())
    centre = (cap_points.min(axis=0) + cap_points.max(axis=0)) / 2
    spread = (cap_points - centre) @ in_plane
    radius = float(np.min(np.ptp(spread, axis=0)[np.abs(axis) < 0.5])) / 2
    centres = triangles.mean(axis=1)
    depth = back - centres @ axis
    reach = np.linalg.norm((triangles - centre) @ in_plane, axis=2).max(axis=1)
    candidate = (back - (triangles @ axis).max(axis=1) >= 0.0) & (reach < radius)
    slice_of = np.floor(depth / config.stem_slice).astype(np.int64)
    stem = np.zeros(len(triangles), bool)
    narrowest, last = np.inf, -1
    for k in np.unique(slice_of[candidate]):
        members = candidate & (slice_of == k)
        widest = float(reach[members].max())
        if k > last + 1 or widest > narrowest * (1.0 + config.stem_widening):
            break  # an empty slice before it (not joined to the cap), or the surface widens
        last = k
        narrowest = min(narrowest, widest)
        stem |= members
    if narrowest > config.stem_max_share * radius:
        return np.zeros(len(triangles), bool)
    return stem


def take_stem(part: PartEstimate, base: PartEstimate, pieces: list[Piece], vertices: np.ndarray, faces: np.ndarray,
              config: PartsConfig) -> None:
    """Give a push button the stem its cap stands on when the stem is fused into a base piece
    near it (``stem_faces``; a scan fuses a mushroom button's stem with its collar): that piece
    is split, its stem faces a new piece of the button's. ``pieces`` grows and the piece lists
    of ``part`` and ``base`` change, in place."""
    cap = np.concatenate([pieces[i].mesh.vertices for i in part.pieces])
    # touching it, or held off it as a loose control is (``loose_control``)
    reach = held_off_reach(float(np.ptp(cap, axis=0).max()), config)
    for j in pieces_near(part.pieces, [base.pieces], pieces, reach):
        mine = stem_faces(cap, pieces[j].mesh.triangles, part.outward, config)
        if not mine.any() or mine.all():
            continue
        stem = make_piece(len(pieces), pieces[j].faces[mine], vertices, faces)
        pieces.append(stem)
        rest = make_piece(len(pieces), pieces[j].faces[~mine], vertices, faces)
        pieces.append(rest)
        base.pieces = [rest.index if i == j else i for i in base.pieces]
        part.pieces = sorted([*part.pieces, stem.index])


def pieces_near(group: list[int], others: list[list[int]], pieces: list[Piece], reach: float) -> list[int]:
    """The pieces of the groups ``others`` whose boxes come within ``reach`` (m) of the box
    around the pieces ``group`` (a broad phase before an exact distance)."""
    lo, hi = pieces_box(group, pieces)
    return [i for g in others for i in g if np.all(pieces[i].lo <= hi + reach) and np.all(pieces[i].hi >= lo - reach)]


def floats_clear(group: list[int], others: list[list[int]], pieces: list[Piece], gap: float) -> bool:
    """Whether the pieces ``group`` lie further than ``gap`` (m) from every piece of the groups
    ``others`` (the carcass and the other panels; not the controls standing off it): nothing
    for a door, drawer or lid to close against."""
    near = pieces_near(group, others, pieces, gap)
    if not near:
        return True
    mine = trimesh.util.concatenate([pieces[i].mesh for i in group])
    theirs = trimesh.util.concatenate([pieces[i].mesh for i in near])
    return distance(bvh_object(mine.vertices, mine.faces), bvh_object(theirs.vertices, theirs.faces)) > gap


def held_off_reach(size: float, config: PartsConfig) -> float:
    """How far (m) a small thing ``size`` (m) across may stand off the surface it is held on by
    something the mesh leaves out: ``mount_reach``, or ``loose_reach_share`` of its size if more."""
    return max(config.mount_reach, config.loose_reach_share * size)


def round_across(sides: np.ndarray, config: PartsConfig) -> bool:
    """Whether the two (2,) extents (m) across an axis are within ``foot_roundness`` of each
    other (a round foot, spindle or rose; not a strip)."""
    small, large = np.sort(sides)
    return bool(large > 0 and small / large >= config.foot_roundness)


def loose_control(group: list[int], groups: list[list[int]], pieces: list[Piece], max_size: float,
                  config: PartsConfig) -> PartEstimate | None:
    """A group that touches nothing else and is no larger than ``max_size`` (m) as a control
    (``small_control``) on the groups within ``mount_reach`` of it, or ``loose_reach_share`` of
    its size if more: a knob held off its panel by a spindle the mesh leaves out, built of a
    disc and a grip bar; a button clear of its hole's walls. Its panel is its piece with the
    largest cross-section (the disc the joint turns about). None when it is no control."""
    lo, hi = pieces_box(group, pieces)
    if float((hi - lo).max()) > max_size:
        return None
    # held off by a gap small beside itself: a wide button floats further from its hole's walls
    reach = held_off_reach(float((hi - lo).max()), config)
    near = pieces_near(group, [g for g in groups if g is not group], pieces, reach)
    if not near:
        return None
    whole = merged_piece(group, pieces)
    mount = trimesh.util.concatenate([pieces[i].mesh for i in near])
    # the surface it stands off says its axis: a disc's and a bar's principal axes together
    # mislead, and one piece's lean a degree or two off its panel's normal
    normal = mount_normal(whole.mesh, mount, config)
    axis = protrusion_axis(whole, mount, reach) if len(group) == 1 else normal
    if axis is None:
        return None
    plate = plate_normal(whole.mesh, mount, config)
    found = small_control(whole, mount, config, max_size, towards_normal(axis, plate, config, whole.mesh), plate)
    if found is None:
        return None
    panel = max(group, key=lambda i: float(np.prod(np.sort(pieces[i].extents)[1:])))
    return control_estimate(found, sorted(group), panel)


def control_estimate(found: tuple[str, np.ndarray, float], ids: list[int], panel: int) -> PartEstimate:
    """The part of a ``small_control`` reading ``found`` (kind, axis, travel) on the pieces
    ``ids``, turning about piece ``panel``: a stick is a knob whose joint its shape decides (a
    toggle, a lever; ``extra["stick"]``)."""
    kind, axis, travel = found
    if kind == "stick":
        return PartEstimate("knob", ids, axis, panel, extra={"travel": travel, "stick": True})
    return PartEstimate(kind, ids, axis, panel, extra={"travel": travel})


def hub_lever(group: list[int], groups: list[list[int]], pieces: list[Piece],
              config: PartsConfig) -> PartEstimate | None:
    """A group that touches nothing, too large for a control but no larger than
    ``lever_max_size`` (m), held off a surface by a small round hub: a lever or a crank
    whose shaft the mesh leaves out (a scan keeps no surface inside the gap). Its foot is its
    vertices within ``foot_band`` of where it comes nearest the other groups, at most
    ``knob_max_size`` across, round (``foot_roundness``) and at most ``fitting_max_share`` of the
    group's size, held off by a gap within ``held_off_reach`` of the foot's size. It turns, as a
    knob, about the normal of the foot's plane through its centre (the way it stands off the
    surface; snapped to a coordinate axis within 10 deg). None for anything else (a door held
    off by a gap comes nearest along its whole back or edge)."""
    lo, hi = pieces_box(group, pieces)
    size = float((hi - lo).max())
    if size > config.lever_max_size:
        return None
    near = pieces_near(group, [g for g in groups if g is not group], pieces, held_off_reach(config.knob_max_size, config))
    if not near:
        return None
    whole = merged_piece(group, pieces)
    mount = trimesh.util.concatenate([pieces[i].mesh for i in near])
    closest, gap, _ = trimesh.proximity.closest_point(mount, whole.mesh.vertices)
    foot = gap <= gap.min() + config.foot_band
    points = whole.mesh.vertices[foot]
    if len(points) < 3:
        return None
    normal = principal_axes(points)[0]  # the foot's plane: a hub's back face
    away = float(normal @ (points - closest[foot]).sum(axis=0))
    if abs(away) <= TINY:
        return None
    axis = snap_axis(normal * np.sign(away))
    sides = footprint_spread(points, axis)
    across = float(np.ptp(points - np.outer(points @ axis, axis), axis=0).max())
    if (across > min(config.knob_max_size, config.fitting_max_share * size) or not round_across(sides, config)
            or float(gap.min()) > held_off_reach(across, config) or axis[2] < -config.control_max_down):
        return None
    pivot = points.mean(axis=0)
    panel = max(group, key=lambda i: float(np.prod(np.sort(pieces[i].extents)[1:])))
    return PartEstimate("knob", sorted(group), axis, panel,
                        extra={"travel": 0.0, "pivot": pivot, "rule": "lever on a hub: turns about the hub's axis"})


def towards_normal(axis: np.ndarray, normal: np.ndarray | None, config: PartsConfig,
                   mesh: trimesh.Trimesh | None = None) -> np.ndarray:
    """A small control's (3,) axis: the ``normal`` of the surface it stands on where ``axis``
    (its own, from the way it stands out) lies within ``control_snap_deg`` of it (a disc and
    its grip bar together lean a little), or within ``control_isotropic_snap_deg`` where the
    control's ``mesh`` has no principal axis to speak of (``shape_spread`` under
    ``control_isotropy``: a knob about as wide, deep and tall as it is); else ``axis`` (the
    wall of a button's hole is no surface it stands on)."""
    if normal is None:
        return axis
    snap = config.control_snap_deg
    if mesh is not None and shape_spread(mesh.vertices) < config.control_isotropy:
        snap = config.control_isotropic_snap_deg
    return normal if float(axis @ normal) > np.cos(np.radians(snap)) else axis


def shape_spread(points: np.ndarray) -> float:
    """Ratio of the largest to the smallest standard deviation of (N, 3) ``points`` along
    their principal axes: 1 for a cube or a ball, large for a bar or a disc."""
    centred = points - points.mean(axis=0)
    variances = np.linalg.eigvalsh(centred.T @ centred / max(len(points), 1))
    return float(np.sqrt(variances[-1] / max(variances[0], TINY)))


def merge_riding_controls(controls: list[PartEstimate], graph: nx.Graph) -> list[PartEstimate]:
    """Controls with a control that touches nothing but another control folded into that one:
    a lever's arm, modelled as its own piece, stands on its hub and turns with it, and a bar
    on a knob is the knob's grip. Returns the controls that remain (piece lists edited in
    place)."""
    merged = True
    while merged:
        merged = False
        owner = {i: k for k, c in enumerate(controls) for i in c.pieces}
        for control in controls:
            touching = {owner.get(j) for i in control.pieces for j in graph.neighbors(i) if j not in control.pieces}
            if len(touching) == 1 and None not in touching:
                host = controls[touching.pop()]
                host.pieces = sorted([*host.pieces, *control.pieces])
                controls = [c for c in controls if c is not control]
                merged = True
                break
    return controls


def attach_hanging_pieces(controls: list[PartEstimate], host_pieces: list[int], anchor: int,
                          graph: nx.Graph) -> list[PartEstimate]:
    """Give a control the host's pieces that reach the host's ``anchor`` piece only through it:
    a faucet's or a lever's arm hangs on its hub and turns with it. Pieces held by two
    controls tie them into one rigid handle (a bar on two posts): those controls go back to
    the host. Returns the controls that remain; ``host_pieces`` and the controls' piece lists
    are edited in place."""
    if not controls:
        return controls
    owner = {i: k for k, part in enumerate(controls) for i in part.pieces}
    held: set[int] = set()
    for component in list(nx.connected_components(graph.subgraph(host_pieces))):
        touching = Counter(owner[j] for i in component for j in graph.neighbors(i) if j in owner)
        if anchor in component or not touching:
            continue
        if len(touching) > 1:
            held.update(touching)
            continue
        controls[next(iter(touching))].pieces.extend(sorted(component))
        host_pieces[:] = [i for i in host_pieces if i not in component]
    for k in sorted(held):
        host_pieces.extend(controls[k].pieces)
    return [c for k, c in enumerate(controls) if k not in held]


def turning_fittings(part: PartEstimate, pieces: list[Piece], graph: nx.Graph,
                     config: PartsConfig) -> list[PartEstimate]:
    """Fittings of a door, drawer or lid that turn on a joint of their own, as knobs whose
    ``parent`` is ``part`` (``is_turning_fitting`` on the groups of its pieces that stand on
    its panel, ``through_panel_pivot`` on those whose spindle passes through it, ``rose_pivot``
    on those that float in front of a rose): a lever, a wheel of spokes, a dial with its mark,
    a door's lever latch, a lock's thumb turn. ``part.pieces`` loses the
    fittings' pieces; its ``extra["fittings"]`` lists them (a hand still grips the panel
    there)."""
    if part.panel is None or part.outward is None:
        return []
    panel, d = pieces[part.panel], part.outward
    limit = fitting_limit(panel, d, config)
    others = [i for i in part.pieces if i != part.panel]
    found = []
    for component in nx.connected_components(graph.subgraph(others)):
        mesh = trimesh.util.concatenate([pieces[i].mesh for i in component])
        if not any(graph.has_edge(i, part.panel) for i in component):  # it floats off the part
            pivot = rose_pivot(mesh, [pieces[i] for i in others if graph.has_edge(i, part.panel)], d, limit, config)
        else:
            pivot = is_turning_fitting(mesh, d, limit, config)
            if pivot is None:
                pivot = through_panel_pivot([pieces[i] for i in component], panel, d, limit, config)
        if pivot is not None:
            found.append(PartEstimate("knob", sorted(component), d.copy(), min(component),
                                      extra={"travel": 0.0, "pivot": pivot}, parent=part))
    if found:
        taken = {i for f in found for i in f.pieces}
        part.pieces = [i for i in part.pieces if i not in taken]
        part.extra["fittings"] = sorted(taken)
    return found


def fitting_limit(panel: Piece, outward: np.ndarray, config: PartsConfig) -> float:
    """The most (m) a fitting of ``panel`` facing ``outward`` (3,) measures across:
    ``fitting_max_share`` of the panel's smaller extent in its plane."""
    in_plane = [k for k in range(3) if k != int(np.argmax(np.abs(outward)))]
    return config.fitting_max_share * float(panel.extents[in_plane].min())


def cut_fitting_pivot(fitting: Piece, owner: PartEstimate, pieces: list[Piece], config: PartsConfig) -> np.ndarray | None:
    """The (3,) pivot of a ``fitting`` the views cut from the surface of a door, drawer or lid
    ``owner`` that turns on it about its outward axis, or None (a bar pull, a round pull, a
    dial whose mark is as small as a scan's noise). It is a turning fitting (one round foot,
    standing out, not symmetric about it: ``is_turning_fitting``) at least
    ``cut_fitting_min_asymmetry`` asymmetric, held by its panel only at its foot: the surface
    it was cut from meets it no further than ``cut_fitting_held_reach`` of its reach from the
    pivot (a spoke wheel about its hub, a lever latch on its rose; a bar pull whose other post
    the scan fused into the panel is held at its far end too)."""
    if owner.outward is None or owner.panel is None:
        return None
    mesh, axis = fitting.mesh, owner.outward
    pivot = is_turning_fitting(mesh, axis, fitting_limit(pieces[owner.panel], axis, config), config)
    if pivot is None or turn_asymmetry(mesh, axis, pivot, config) < config.cut_fitting_min_asymmetry:
        return None
    flat = mesh.vertices - np.outer(mesh.vertices @ axis, axis)
    from_pivot = np.linalg.norm(flat - (pivot - (pivot @ axis) * axis), axis=1)
    held = cut_line(mesh, pieces[owner.panel].mesh)
    return pivot if not held.any() or from_pivot[held].max() <= config.cut_fitting_held_reach * from_pivot.max() else None


def cut_line(fitting: trimesh.Trimesh, panel: trimesh.Trimesh) -> np.ndarray:
    """(V,) bool over ``fitting``'s vertices: those it shares with ``panel`` (the line the
    views cut it from the panel's surface along; none for a piece of its own)."""
    ids = merged_vertex_ids(np.concatenate([fitting.vertices, panel.vertices]))
    return np.isin(ids[: len(fitting.vertices)], ids[len(fitting.vertices):])


def base_fittings(base_pieces: list[int], anchor: int, pieces: list[Piece], graph: nx.Graph,
                  config: PartsConfig) -> list[PartEstimate]:
    """Turning fittings standing on the carcass's main piece ``anchor``: groups of the other
    base pieces that touch it and nothing else of the base and pass ``is_turning_fitting``
    about the normal of the mount where they meet it (a lever on a post, a lock's lever on a
    fixed door). ``base_pieces`` loses their pieces (edited in place)."""
    mount = pieces[anchor].mesh
    limit = float(pieces[anchor].extents.max())  # no larger than what it stands on
    found = []
    rest = [i for i in base_pieces if i != anchor]
    for component in nx.connected_components(graph.subgraph(rest)):
        if not any(graph.has_edge(i, anchor) for i in component):
            continue
        mesh = trimesh.util.concatenate([pieces[i].mesh for i in component])
        axis = mount_normal(mesh, mount, config)
        if axis is None or axis[2] < -config.control_max_down:
            continue
        pivot = is_turning_fitting(mesh, axis, limit, config)
        if pivot is not None:
            found.append(PartEstimate("knob", sorted(component), axis, min(component),
                                      extra={"travel": 0.0, "pivot": pivot}))
    taken = {i for f in found for i in f.pieces}
    base_pieces[:] = [i for i in base_pieces if i not in taken]
    return found


def slot_sliders(base_pieces: list[int], anchor: int, pieces: list[Piece], graph: nx.Graph,
                 config: PartsConfig) -> list[PartEstimate]:
    """Handles that run in a slot of the carcass's main piece ``anchor`` (a press's handle, a
    slide lever): a base piece that stands out of the anchor's box through one face, within the
    face's outline, and reaches behind it ``slider_min_reach`` times its own thickness or more
    (it passes through an opening), with the pieces it holds that lie wholly in front of that
    face (its grip). Semantic ``slider``, ``outward`` the face's normal; the joint stage finds
    the direction the slot leaves room along. ``base_pieces`` loses their pieces (in place)."""
    box_lo, box_hi = pieces[anchor].lo, pieces[anchor].hi
    found, taken = [], set()
    for seed in [i for i in base_pieces if i != anchor]:
        if seed in taken:
            continue
        piece = pieces[seed]
        for k, sign in ((k, sign) for k in range(3) for sign in (-1.0, 1.0)):
            face = box_lo[k] if sign < 0 else box_hi[k]
            out = sign * ((piece.hi[k] if sign > 0 else piece.lo[k]) - face)
            into = sign * (face - (piece.lo[k] if sign > 0 else piece.hi[k]))
            plane = [m for m in range(3) if m != k]
            thickness = float(piece.extents[plane].min())
            within = all(box_lo[m] <= piece.lo[m] and piece.hi[m] <= box_hi[m] for m in plane)
            if not (within and out > thickness and into >= config.slider_min_reach * thickness):
                continue
            in_front = {j for j in base_pieces if j != anchor
                        and sign * ((pieces[j].lo[k] if sign > 0 else pieces[j].hi[k]) - face) >= 0}
            members = nx.node_connected_component(graph.subgraph(in_front | {seed}), seed)  # with its grip
            taken |= members
            found.append(PartEstimate("slider", sorted(members), sign * np.eye(3)[k], seed, extra={"travel": 0.0}))
            break
    base_pieces[:] = [i for i in base_pieces if i not in taken]
    return found


def touching_faces(mesh: trimesh.Trimesh, mount: trimesh.Trimesh, config: PartsConfig) -> np.ndarray:
    """(K,) the ``mount``'s faces nearest ``mesh``'s vertices that lie within ``mount_reach``
    (m) of its nearest one (which may be sunk into the mount): where the two meet."""
    _, distance, triangle = trimesh.proximity.closest_point(mount, mesh.vertices)
    return np.unique(triangle[distance <= distance.min() + config.mount_reach])


def mount_normal(mesh: trimesh.Trimesh, mount: trimesh.Trimesh, config: PartsConfig) -> np.ndarray | None:
    """(3,) outward normal of ``mount``'s surface where ``mesh`` meets it (the faces nearest its
    vertices that lie within ``mount_reach`` of its nearest one, which may be sunk into the
    mount; by area; snapped to a coordinate axis within 10 deg), or None when the faces there
    disagree (a corner). The caller knows that the two touch."""
    touching = touching_faces(mesh, mount, config)
    normals = mount.face_normals[touching] * mount.area_faces[touching, None]
    mean = normals.sum(axis=0)
    if np.linalg.norm(mean) < config.foot_roundness * np.linalg.norm(normals, axis=1).sum():
        return None
    return snap_axis(mean / np.linalg.norm(mean))


def plate_normal(mesh: trimesh.Trimesh, mount: trimesh.Trimesh, config: PartsConfig) -> np.ndarray | None:
    """(3,) outward normal of the plate a small control stands on: of the mount's faces where
    ``mesh`` meets it (as ``mount_normal`` finds them), those whose normals agree within
    ``plate_agree_deg`` with the most area (the plate around a hole, not its walls), averaged
    by area; None when no face is near."""
    touching = touching_faces(mesh, mount, config)
    if not len(touching):
        return None
    return dominant_normal(mount.face_normals[touching], mount.area_faces[touching], config.plate_agree_deg)


def dominant_normal(normals: np.ndarray, area: np.ndarray, agree_deg: float) -> np.ndarray | None:
    """(3,) area-weighted mean of the unit ``normals`` (N, 3) that agree within ``agree_deg``
    with the most ``area`` (N,): the plane most of the faces lie in; None when it is empty."""
    agree = normals @ normals.T >= np.cos(np.radians(agree_deg))
    best = agree[int(np.argmax(agree @ area))]
    mean = (normals[best] * area[best, None]).sum(axis=0)
    return mean / np.linalg.norm(mean) if np.linalg.norm(mean) > 0 else None


def is_turning_fitting(mesh: trimesh.Trimesh, axis: np.ndarray, limit: float,
                       config: PartsConfig) -> np.ndarray | None:
    """The (3,) pivot of a fitting that turns about ``axis`` on its mount, or None: it stands
    on one round foot (``standing_pivot``) and is not symmetric about the axis through it
    (``turn_asymmetry``: a lever's arm, spokes, a dial's mark). A plain round pull is
    symmetric; a bar or a cup pull is held at two posts or along a strip."""
    pivot = standing_pivot(mesh, axis, limit, config)
    if pivot is None or turn_asymmetry(mesh, axis, pivot, config) < config.fitting_min_asymmetry:
        return None
    return pivot


def standing_pivot(mesh: trimesh.Trimesh, axis: np.ndarray, limit: float, config: PartsConfig,
                   surface: float | None = None) -> np.ndarray | None:
    """(3,) centre of the one round foot (``single_mount``) a fitting stands on, at most
    ``limit`` (m) across and standing out along ``axis`` by ``fitting_min_height`` of its width
    (a hinge leaf lies flat), or None. How far it stands out is measured from its lowest
    point, or from ``surface`` (m along ``axis``, the mount's face around it) where that lies
    lower: a fitting cut from a fused surface leaves its foot in the panel."""
    along = mesh.vertices @ axis
    width = float(np.ptp(mesh.vertices - np.outer(along, axis), axis=0).max())
    foot = float(along.min()) if surface is None else min(float(along.min()), surface)
    if width > limit or float(along.max()) - foot < config.fitting_min_height * width:
        return None
    return single_mount(mesh, axis, config)


def grip_groups(centres: np.ndarray, panel: Piece, outward: np.ndarray, mirror: float) -> list[int]:
    """Which of the fittings at ``centres`` (G, 3) on a ``panel`` facing ``outward`` (3,) a hand
    grips it by: the one furthest off the panel's middle, as a share of its width or height (a
    safe's spoke handle towards its free edge, not the dial nearer its hinge), with another
    that mirrors it about the middle within ``mirror`` of that size both ways (pulls at both
    ends of a lid's front)."""
    frame = np.stack(panel_frame(outward))
    lo, hi = frame @ panel.lo, frame @ panel.hi
    offsets = (centres @ frame.T - (lo + hi) / 2) / np.maximum(np.abs(hi - lo), TINY)  # (G, 2)
    k = int(np.argmax(np.abs(offsets).max(axis=1)))
    along = int(np.argmax(np.abs(offsets[k])))
    mirrored = [j for j in range(len(centres)) if j != k
                and abs(offsets[k, along] + offsets[j, along]) <= mirror
                and abs(offsets[k, 1 - along] - offsets[j, 1 - along]) <= mirror]
    return [k, *mirrored[:1]]


def controls_beside_the_grip(owner: PartEstimate, rigid: list[int], pieces: list[Piece],
                             config: PartsConfig) -> list[tuple[int, np.ndarray]]:
    """(piece, pivot) of the fittings among ``rigid`` (pieces the views cut from door
    ``owner``'s surface that no other rule turns) that are controls beside its grip: a door is
    gripped at one fitting (``grip_groups`` over all its fittings, within
    ``grip_mirror_share``); a round one beside that, standing on one round foot out of the
    door's face (``standing_pivot``, its footprint round within ``foot_roundness``, no wider
    than the door's smaller side), turns about the middle of the line the views cut it along
    (``cut_line``: the rose it stands on; its foot where it has none): a safe's dial, whose
    mark a scan cannot show; a lock's thumb turn cut with its round rose, whose bar rests on
    the rose a hair above the door, so the foot alone leans towards the bar."""
    fittings = owner.extra.get("fittings", [])
    if owner.semantic != "door" or len(fittings) < 2 or owner.outward is None:
        return []
    panel, axis = pieces[owner.panel], owner.outward
    centres = np.array([pieces[i].mesh.vertices.mean(axis=0) for i in fittings])
    grips = {fittings[g] for g in grip_groups(centres, panel, axis, config.grip_mirror_share)}
    in_plane = np.abs(axis) < 0.5
    limit = float(panel.extents[in_plane].min())
    out = []
    for i in rigid:
        mesh = pieces[i].mesh
        if i in grips or not round_across(pieces[i].extents[in_plane], config):
            continue
        pivot = standing_pivot(mesh, axis, limit, config, surface_height(pieces[i], panel.mesh, axis, config))
        if pivot is None:
            continue
        rose = mesh.vertices[cut_line(mesh, panel.mesh)]
        if len(rose):  # to the rose's middle in the door's plane, at the foot's height
            shift = (rose.min(axis=0) + rose.max(axis=0)) / 2 - pivot
            pivot = pivot + shift - (shift @ axis) * axis
        out.append((i, pivot))
    return out


def cut_knob(owner: PartEstimate, index: int, pivot: np.ndarray) -> PartEstimate:
    """A knob of piece ``index``, which the views cut from part ``owner``'s surface, turning
    on ``owner`` about its outward axis through ``pivot`` (3,)."""
    return PartEstimate("knob", [index], owner.outward.copy(), index, parent=owner,
                        extra={"travel": 0.0, "pivot": pivot, "source": "segmentation", "cut_from_surface": True})


def through_panel_pivot(fitting: list[Piece], panel: Piece, axis: np.ndarray, limit: float,
                        config: PartsConfig) -> np.ndarray | None:
    """The (3,) pivot of a fitting whose spindle passes through its ``panel`` (a door's lever
    latch, a lever on each side), or None. One round piece of ``fitting`` spans the panel's
    thickness along ``axis`` (3,); what stands in front of the panel with it is at most
    ``limit`` (m) across and not symmetric about the spindle (``turn_asymmetry``). The pivot is
    the spindle's centre on the panel's front."""
    along = panel.mesh.vertices @ axis
    back, front = float(along.min()), float(along.max())
    span = [np.sort([p.lo @ axis, p.hi @ axis]) for p in fitting]
    spindles = [p for p, (a, b) in zip(fitting, span) if a <= back and b >= front]
    if len(spindles) != 1:
        return None
    spindle = spindles[0]
    plane = np.abs(axis) < 0.5
    if not round_across(spindle.extents[plane], config):
        return None
    standing = trimesh.util.concatenate([p.mesh for p, (_, b) in zip(fitting, span) if b > front])
    flat = standing.vertices - np.outer(standing.vertices @ axis, axis)
    if float(np.ptp(flat, axis=0).max()) > limit:
        return None
    centre = (spindle.lo + spindle.hi) / 2
    pivot = centre + (front - float(centre @ axis)) * axis
    if turn_asymmetry(standing, axis, pivot, config) < config.fitting_min_asymmetry:
        return None
    return pivot


def rose_pivot(mesh: trimesh.Trimesh, roses: list[Piece], axis: np.ndarray, limit: float,
               config: PartsConfig) -> np.ndarray | None:
    """The (3,) pivot of a fitting ``mesh`` that floats in front of a round rose on its panel,
    held by a spindle the mesh leaves out (a lock's thumb turn over its escutcheon), or None.
    Of the ``roses`` (pieces standing on the panel), the round ones (in-plane sides within
    ``foot_roundness``) whose front lies within ``mount_reach`` behind the fitting's back
    along ``axis`` (3,), or ``loose_reach_share`` of its size if more, and whose centre the
    fitting's outline covers: exactly one (a bar over two posts is held by both). The fitting
    is at most ``limit`` (m) across and not symmetric about the rose's centre
    (``turn_asymmetry``); the pivot is that centre on the rose's front."""
    along = mesh.vertices @ axis
    flat = mesh.vertices - np.outer(along, axis)
    size = float(np.ptp(flat, axis=0).max())
    if size > limit:
        return None
    reach = held_off_reach(float(mesh.extents.max()), config)
    plane = np.abs(axis) < 0.5
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    under = []
    for rose in roses:
        front = float((rose.mesh.vertices @ axis).max())
        centre = (rose.lo + rose.hi) / 2
        centre = centre - (centre @ axis) * axis
        covered = np.all(centre[plane] >= lo[plane]) and np.all(centre[plane] <= hi[plane])
        if round_across(rose.extents[plane], config) and 0.0 <= float(along.min()) - front <= reach and covered:
            under.append(centre + front * axis)
    if len(under) != 1 or turn_asymmetry(mesh, axis, under[0], config) < config.fitting_min_asymmetry:
        return None
    return under[0]


FOOT_MAX_POINTS = 5000
"""Most foot vertices :func:`single_mount` links pairwise: the pairs within ``foot_link`` grow
with the square of the density (a subdivided 1M-face knob's foot: gigabytes of pairs), so a
denser foot keeps one vertex per cell a quarter of ``foot_link`` wide, close enough to each
other that the clusters stay the same."""


def single_mount(mesh: trimesh.Trimesh, axis: np.ndarray, config: PartsConfig) -> np.ndarray | None:
    """(3,) centre of the one round foot a fitting stands on, or None when it stands on several
    (a bar's two posts) or on a long strip (a cup pull). The foot is the fitting's vertices
    within ``foot_band`` of its back along ``axis`` (what meets or enters the mount), one
    cluster when neighbours lie within ``foot_link`` of each other."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    along = mesh.vertices @ axis
    foot = np.unique(mesh.vertices[along <= along.min() + config.foot_band], axis=0)
    if len(foot) > FOOT_MAX_POINTS:  # a dense mesh: one vertex per quarter-link cell links the same
        _, first = np.unique(np.floor(foot / (config.foot_link / 4)).astype(np.int64), axis=0, return_index=True)
        foot = foot[np.sort(first)]
    pairs = cKDTree(foot).query_pairs(config.foot_link, output_type="ndarray")
    links = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(foot), len(foot)))
    if connected_components(links, directed=False)[0] != 1:
        return None
    if not round_across(np.sort(np.ptp(foot - np.outer(foot @ axis, axis), axis=0))[1:], config):
        return None
    return (foot.min(axis=0) + foot.max(axis=0)) / 2


def turn_asymmetry(mesh: trimesh.Trimesh, axis: np.ndarray, pivot: np.ndarray, config: PartsConfig) -> float:
    """How far a shape is from symmetric about the line through ``pivot`` along ``axis``, in
    [0, 1]: over ``fitting_sectors`` angular sectors, the spread of the farthest reach and of
    the highest point, each as a share of its largest (0 for a turned knob, 1 for a lever)."""
    points = np.concatenate([mesh.vertices, mesh.triangles_center])
    rel = points - pivot
    height = rel @ axis
    flat = rel - np.outer(height, axis)
    u, v = perpendicular_basis(axis)
    sector = ((np.arctan2(flat @ v, flat @ u) + np.pi) / (2 * np.pi) * config.fitting_sectors).astype(int)
    sector = np.minimum(sector, config.fitting_sectors - 1)
    reach = np.zeros(config.fitting_sectors)
    top = np.zeros(config.fitting_sectors)
    np.maximum.at(reach, sector, np.linalg.norm(flat, axis=1))
    np.maximum.at(top, sector, height - height.min())
    spread = lambda x: float((x.max() - x.min()) / x.max()) if x.max() > 0 else 0.0  # noqa: E731
    return max(spread(reach), spread(top))


def merge_supports(groups: list[list[int]], pieces: list[Piece], config: PartsConfig) -> tuple[list[list[int]], bool]:
    """``groups`` with every group that stands on the floor (reaches within ``floor_tol`` of
    the object's bottom) and is not a flat upright panel merged into one: the posts of a door
    frame, the legs and the carcass of a table stand there together and are the base (a
    laptop's keyboard lying on the table, not its raised screen); a door or a front that
    reaches the floor stays apart (judged by its largest piece, so a handle or a dial
    standing on it does not make it thick). Returns the groups, the supports first, and
    whether any group stands on the floor."""
    bottom = min(pieces[i].lo[2] for g in groups for i in g)
    supports = []
    for g in groups:
        lo = np.min([pieces[i].lo for i in g], axis=0)
        board = max(g, key=lambda i: np.prod(np.sort(pieces[i].extents)[1:]))
        e = pieces[board].extents
        thin, wide = min(e[0], e[1]), max(e[0], e[1])
        panel = thin <= config.panel_max_thickness and wide >= config.panel_aspect * thin \
            and min(wide, e[2]) >= config.min_panel_size
        if lo[2] <= bottom + config.floor_tol and not panel:
            supports.append(g)
    if not supports:
        return groups, False
    merged = sorted(i for g in supports for i in g)
    return [merged, *[g for g in groups if g not in supports]], True


def is_panel(piece: Piece, outward: np.ndarray, config: PartsConfig) -> bool:
    """Thin along ``outward`` and at least ``min_panel_size`` across."""
    axis = int(np.argmax(np.abs(outward)))
    plane = np.delete(piece.extents, axis)
    thickness = piece.extents[axis]
    return bool(thickness <= config.panel_max_thickness and thickness <= plane.min() / config.panel_min_aspect
                and plane.min() >= config.min_panel_size)


def _in_footprint(piece: Piece, panel: Piece, axis: int, tol: float) -> bool:
    plane = [k for k in range(3) if k != axis]
    return bool(np.all(piece.lo[plane] >= panel.lo[plane] - tol) and np.all(piece.hi[plane] <= panel.hi[plane] + tol))


def share_over(piece: Piece, panel: Piece, axis: int, tol: float) -> float:
    """Share of ``piece``'s box, seen along ``axis``, that lies over ``panel``'s box grown by
    ``tol`` (m): 1 for a handle on a door's face (a flat grip plate too), 0 for a piece beside
    its edge."""
    plane = [k for k in range(3) if k != axis]
    lo, hi = np.maximum(piece.lo[plane], panel.lo[plane] - tol), np.minimum(piece.hi[plane], panel.hi[plane] + tol)
    extent = piece.extents[plane]
    share = np.where(extent > tol, np.clip(hi - lo, 0.0, None) / np.maximum(extent, tol), (hi >= lo).astype(float))
    return float(np.prod(share))


def carcass_anchor(base_group: list[int], pieces: list[Piece], config: PartsConfig) -> tuple[int, list[int]]:
    """The carcass's main piece among ``base_group`` and the pieces passed over for it: the
    largest piece by box volume, unless it is a front panel (``is_panel`` facing -y, at the
    front of the pieces not wholly in front of it within ``front_tolerance``, with a cavity
    behind it): on a carcass built of boards a full overlay door is the largest board. Then the
    next largest that is not."""
    order = sorted(base_group, key=lambda i: -float(np.prod(pieces[i].extents)))
    front, skipped = OUTWARD["front"], []
    for i in order[:-1]:
        rest = [pieces[k] for k in base_group if k != i]
        behind = [p.lo[1] for p in rest if p.hi[1] > pieces[i].lo[1] + config.front_member_tolerance]  # not its fittings
        at_front = bool(behind) and pieces[i].lo[1] <= min(behind) + config.front_tolerance
        if not (is_panel(pieces[i], front, config) and at_front and _cavity_behind(pieces[i], rest, config)):
            return i, skipped
        skipped.append(i)
    return order[0], []


def split_touching_fronts(base_group: list[int], largest: int, pieces: list[Piece], graph: nx.Graph,
                          config: PartsConfig, covering: list[int] = (),
                          box_walls: set[int] = frozenset()) -> list[list[int]]:
    """Movable fronts that touch the carcass (real assets often have no gap).

    A front is a thin panel facing -y near the carcass's front with open space behind it (rays
    from its back travel at least ``cavity_depth``: a carcass board has a wall right behind it);
    it takes with it the pieces inside its footprint that touch it, directly or through each
    other: a handle on its face, a drawer body behind; and those wholly in front of its face
    that touch them, wherever they reach (a lever's grip on its spindle, past the door's edge).
    It takes none of the pieces that hang together with the carcass's main piece ``largest``
    without it, though they lie inside its footprint: the boards of a carcass built of boards
    behind a full overlay door or a drawer front. ``covering``: fronts ``carcass_anchor``
    passed over (the largest piece of such a carcass). ``box_walls``: pieces that are no front
    (a box's boards under its lid).
    """
    front = OUTWARD["front"]

    def carcass_without(f: int) -> set[int]:
        """The pieces that hang together with ``largest`` without front ``f`` and what stands on it."""
        keep = [i for i in base_group if i != f and i not in covering and pieces[i].hi[1] > pieces[f].lo[1]
                + config.front_member_tolerance]
        return nx.node_connected_component(graph.subgraph(keep), largest) if largest in keep else set()

    carcass = [largest]
    if covering or is_panel(pieces[largest], front, config):
        # a carcass of boards, whose main piece may be its back: its front is where its walls begin
        walls = nx.node_connected_component(graph.subgraph(
            [i for i in base_group if i == largest or not is_panel(pieces[i], front, config)]), largest) - {largest}
        carcass = sorted(walls) or carcass
    # its face: a top board's edge reaching past it is no front a door or drawer lies on
    carcass_front = -outer_plane(trimesh.util.concatenate([pieces[i].mesh for i in carcass]), front,
                                 config.carcass_front_band)
    candidates = [i for i in base_group if i != largest and i not in box_walls and is_panel(pieces[i], front, config)
                  and pieces[i].lo[1] <= carcass_front + config.front_tolerance]
    taken: set[int] = set()
    fronts = []
    for f in sorted(candidates, key=lambda i: -np.prod(np.delete(pieces[i].extents, 1))):
        if f in taken:
            continue
        panel = pieces[f]
        boards = carcass_without(f)
        members = {f}
        frontier = [f]
        while frontier:
            k = frontier.pop()
            for j in graph.neighbors(k):
                if j in members or j == largest or j in taken or j not in base_group or j in boards:
                    continue
                in_front = pieces[j].hi[1] <= panel.lo[1] + config.front_member_tolerance
                if k == f and in_front and share_over(pieces[j], panel, 1, config.front_member_tolerance) < config.front_fitting_share:
                    continue  # a board or lip of the carcass in front of the panel's edge, not its fitting
                if _in_footprint(pieces[j], panel, 1, config.front_member_tolerance) or in_front:
                    members.add(j)
                    frontier.append(j)
        members |= body_inside(members, boards - taken, pieces, graph, config)
        rest = [i for i in base_group if i not in members]
        if not rest or not _cavity_behind(panel, [pieces[i] for i in rest], config):
            continue
        taken |= members
        fronts.append(sorted(members))
    return fronts


def body_inside(front: set[int], boards: set[int], pieces: list[Piece], graph: nx.Graph,
                config: PartsConfig) -> set[int]:
    """A drawer's body behind the pieces ``front`` of a front facing -y, among ``boards``, the
    carcass's pieces (a drawer's box runs on the carcass's walls or bottom, or stops against its
    back, so it hangs together with them): the pieces starting within ``body_gap`` (m) behind the
    front's back, and what touches them, that lie behind the front's face (a button's stem runs
    through it), inside its outline (``front_member_tolerance``) and inside the box of all
    ``boards`` by ``body_inset`` or more on every side but the front (a carcass's own boards make
    that box), together spanning ``body_min_cover`` of the front's width and of its height (a box,
    not a shelf). Empty when there is none."""
    if not boards:
        return set()
    lo, hi = pieces_box(sorted(boards), pieces)
    outline = merged_piece(sorted(front), pieces)
    inset = config.body_inset
    inside = {i for i in boards if _in_footprint(pieces[i], outline, 1, config.front_member_tolerance)
              and pieces[i].lo[1] >= outline.lo[1]  # behind the front's face: not a stem through it
              and np.all(pieces[i].lo[[0, 2]] >= lo[[0, 2]] + inset) and np.all(pieces[i].hi <= hi - inset)}
    back = max(float(pieces[i].hi[1]) for i in front)
    near = [i for i in inside if pieces[i].lo[1] <= back + config.body_gap]
    sub = graph.subgraph(inside)
    body = set().union(*(nx.node_connected_component(sub, i) for i in near))
    if not body:
        return set()
    body_lo, body_hi = pieces_box(sorted(body), pieces)
    cover = (body_hi - body_lo)[[0, 2]] / np.maximum(outline.extents[[0, 2]], 1e-9)
    return body if bool(np.all(cover >= config.body_min_cover)) else set()


def _cavity_behind(panel: Piece, rest: list[Piece], config: PartsConfig,
                   outward: np.ndarray = OUTWARD["front"], enclosed: bool = False) -> bool:
    """Whether ``cavity_min_share`` or more of the rays from the panel's back (against its
    ``outward``, a coordinate axis; a ``cavity_grid`` square grid over the inner
    ``cavity_grid_share`` of it) travel at least ``cavity_depth`` before they hit the rest of
    the base; ``enclosed``: and then hit it (a floor under a lid, not the open room under a
    table top). A ray whose first hit is a closed piece's face turned away from it started
    inside that solid (a bezel sunk into a block): no room there."""
    occluder = trimesh.util.concatenate([p.mesh for p in rest])
    k = int(np.argmax(np.abs(outward)))
    a, b = [m for m in range(3) if m != k]
    u = inner_grid(config.cavity_grid_share, config.cavity_grid)
    A, B = np.meshgrid(panel.lo[a] + u * panel.extents[a], panel.lo[b] + u * panel.extents[b])
    direction = -np.sign(outward[k]) * np.eye(3)[k]
    origins = np.zeros((A.size, 3))
    origins[:, a], origins[:, b] = A.ravel(), B.ravel()
    origins[:, k] = (panel.hi[k] if direction[k] > 0 else panel.lo[k]) + RAY_NUDGE * direction[k]
    closed = np.concatenate([np.full(len(p.mesh.faces), p.mesh.is_watertight) for p in rest])
    depth, inside = first_hits(occluder, origins, direction, closed)
    depth[inside] = 0.0
    room = depth >= config.cavity_depth
    if enclosed:
        room &= np.isfinite(depth)
    return bool(np.mean(room) >= config.cavity_min_share)


def split_touching_lids(base_group: list[int], largest: int, pieces: list[Piece], graph: nx.Graph,
                        config: PartsConfig, boards: bool = False) -> list[list[int]]:
    """Lids that rest on or sink into an open-top body built as one piece (a chest, a bin, a
    box): a thin panel facing up (``is_panel``) that touches one piece besides what stands on
    it, the body, which rises no higher than the lid's top, covers ``lid_min_cover`` or more of
    the body's outline seen from above, and closes a cavity: rays from its underside travel
    ``cavity_depth`` or more and meet the body's floor (``_cavity_behind``, enclosed), and the
    body's walls stand round the cavity (level rays from under the lid's middle meet it in all
    four directions within the lid's outline; a table's legs do not). The lid takes the pieces
    that touch it and lie wholly above its underside (a handle on its edge). A top board of a
    carcass of boards rests on several boards and stays with it: a box of boards with a lid
    and a cabinet of boards with an inset door look alike. ``boards``: instead, lids resting on
    a body of several boards that carry a grip of their own (pieces standing on the lid no
    wider than ``lid_grip_max_share`` of it: a tab, a handle; a crown moulding runs the whole
    width): the grip says which panel opens."""
    up = OUTWARD["top"]
    found, taken = [], set()
    for i in base_group:
        lid = pieces[i]
        if i == largest or i in taken or not is_panel(lid, up, config):
            continue
        above = [j for j in base_group if pieces[j].lo[2] >= lid.lo[2] - config.front_member_tolerance]
        members = nx.node_connected_component(graph.subgraph(above), i)
        below = sorted({j for m in members for j in graph.neighbors(m) if j in base_group and j not in members})
        if (len(below) < 2) if boards else (len(below) != 1):
            continue
        if boards:
            # a grip stands out of the lid (over its top, past its edge); a board under it does not
            tol = config.front_member_tolerance
            grip = [m for m in members if m != i
                    and (np.any(pieces[m].hi > lid.hi + tol) or np.any(pieces[m].lo[:2] < lid.lo[:2] - tol))]
            if not grip:
                continue
            grip_lo, grip_hi = pieces_box(grip, pieces)
            if float((grip_hi - grip_lo)[:2].max()) > config.lid_grip_max_share * float(lid.extents[:2].max()):
                continue
        body = merged_piece(below, pieces)
        if body.hi[2] > lid.hi[2] + config.front_member_tolerance:
            continue
        if share_over(body, lid, 2, 0.0) < config.lid_min_cover:
            continue
        rest = [pieces[j] for j in base_group if j not in members]
        if not _cavity_behind(lid, rest, config, up, enclosed=True) or not _walled_below(lid, body, config):
            continue
        taken |= members
        found.append(sorted(members))
    return found


def merged_piece(ids: list[int], pieces: list[Piece]) -> Piece:
    """The pieces ``ids`` as one Piece (index of the first): a body of boards, a loose control
    of a disc and a grip bar."""
    if len(ids) == 1:
        return pieces[ids[0]]
    lo, hi = pieces_box(ids, pieces)
    return Piece(ids[0], np.concatenate([pieces[i].faces for i in ids]),
                 trimesh.util.concatenate([pieces[i].mesh for i in ids]), lo, hi)


def leaf_piece(part: PartEstimate, pieces: list[Piece], tolerance: float, frame_share: float) -> Piece:
    """The leaf of panel part ``part`` as one Piece: its panel with the pieces framing it in its
    plane (the stiles and rails of a frame-and-panel door, whose panel is only its largest piece),
    those lying within ``tolerance`` (m) of the panel's depth along the part's outward, reaching
    past the panel's outline and running ``frame_share`` or more of the panel's width or height
    along it, together reaching past both of its opposite edges (a frame round it); a handle
    stands further out, a tab on a lid's edge is short, a grip along a screen's top edge reaches
    past one edge only, a glazing bar inside the frame adds nothing. The panel itself when
    nothing frames it."""
    d, panel = part.outward, pieces[part.panel]
    depth = panel.mesh.vertices @ d
    plane = np.abs(d) < 0.5
    framing = []
    for i in part.pieces:
        if i == part.panel:
            continue
        along = pieces[i].mesh.vertices @ d
        if along.min() < depth.min() - tolerance or along.max() > depth.max() + tolerance:
            continue
        if _in_footprint(pieces[i], panel, int(np.argmax(np.abs(d))), 0.0):
            continue
        if not np.any(pieces[i].extents[plane] >= frame_share * panel.extents[plane]):
            continue
        framing.append(i)
    if not framing:
        return panel
    lo, hi = pieces_box([part.panel, *framing], pieces)
    if not np.any((lo < panel.lo - TINY) & (hi > panel.hi + TINY) & plane):
        return panel  # past one edge only: a grip along it, not a frame round the panel
    return merged_piece([part.panel, *framing], pieces)


def _walled_below(lid: Piece, body: Piece, config: PartsConfig) -> bool:
    """Whether level rays from ``cavity_depth`` / 2 under the middle of the ``lid``'s underside
    meet the ``body`` in all four directions within the lid's outline: walls round a cavity."""
    centre = np.array([(lid.lo[0] + lid.hi[0]) / 2, (lid.lo[1] + lid.hi[1]) / 2, lid.lo[2] - config.cavity_depth / 2])
    for k in (0, 1):
        for sign in (-1.0, 1.0):
            direction = sign * np.eye(3)[k]
            reach = float(ray_distances(body.mesh, centre[None], direction)[0])
            if reach > lid.extents[k] / 2 + config.front_member_tolerance:
                return False
    return True


def attach_loose_handles(groups: list[list[int]], base_group: list[int], pieces: list[Piece],
                         config: PartsConfig) -> list[list[int]]:
    """A small group with no panel of its own that floats just in front of a movable panel
    (a handle modelled a few millimetres off its door) joins that panel's group."""
    front = OUTWARD["front"]

    def has_panel(group: list[int]) -> bool:
        return any(is_panel(pieces[i], front, config) for i in group)

    movable = [g for g in groups if g is not base_group and has_panel(g)]
    out = list(groups)
    for group in groups:
        if group is base_group or has_panel(group):
            continue
        lo, hi = pieces_box(group, pieces)
        centre = (lo + hi) / 2
        for target in movable:
            panel = max((pieces[i] for i in target if is_panel(pieces[i], front, config)),
                        key=lambda p: np.prod(np.delete(p.extents, 1)))
            inside = np.all(centre[[0, 2]] >= panel.lo[[0, 2]]) and np.all(centre[[0, 2]] <= panel.hi[[0, 2]])
            if inside and 0.0 <= panel.lo[1] - hi[1] + config.attach_tolerance <= config.handle_standoff:
                target.extend(group)
                out.remove(group)
                break
    return out


def classify_group(group: list[int], pieces: list[Piece], base_lo: np.ndarray, base_hi: np.ndarray,
                   obj_lo: np.ndarray, obj_hi: np.ndarray, config: PartsConfig,
                   occluder: trimesh.Trimesh | None = None, known: PartEstimate | None = None) -> PartEstimate | None:
    """A movable part from a group of touching pieces, or None (it stays with the base).

    Its outward direction is the side where it shows the largest area that can be seen from
    outside (rays escape ``occluder``, the whole object). ``known``: the group's front classified
    before, without the box found behind it; its direction and panel are kept (the box's own
    walls face out too, from inside the carcass)."""
    mesh = trimesh.util.concatenate([pieces[i].mesh for i in group])
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    best, best_area = None, 0.0
    if known is not None:
        best = next(name for name, d in OUTWARD.items() if np.allclose(d, known.outward))
    for name, d in OUTWARD.items() if known is None else ():
        extreme = mesh.vertices @ d
        # exposed: nothing of the carcass lies beyond the part on that side
        base_extreme = max(base_lo @ d, base_hi @ d)
        if extreme.max() < base_extreme - config.panel_max_thickness:
            continue
        area = facing_area(mesh, d, np.inf, occluder)
        if area > best_area:
            best, best_area = name, area
    if best is None:
        return None
    d = OUTWARD[best]
    plane = [k for k in range(3) if abs(d[k]) < 0.5]
    size = (hi - lo)[plane]
    if size.min() < config.min_panel_size:
        return None
    panel = known.panel if known is not None else max(group, key=lambda i: facing_area(
        pieces[i].mesh, d, max(config.front_band_share * np.ptp(pieces[i].mesh.vertices @ d), config.front_band_min)))
    front = float((pieces[panel].mesh.vertices @ d).max())
    # a drawer's body spans its front (sides, back, a box); a handle on the back face does not
    body = sorted({panel, *body_pieces(group, pieces, d, config.body_min_span)})
    depth_behind = front - min(float((pieces[i].mesh.vertices @ d).min()) for i in body)
    obj_depth = float(np.ptp(np.array([obj_lo, obj_hi]) @ d))
    if best == "top":
        semantic = "lid"
    elif depth_behind >= config.drawer_min_depth_share * obj_depth and \
            lean_deg(pieces[panel].mesh, d) <= config.drawer_max_lean_deg:
        semantic = "drawer"
    else:
        semantic = "door"
    return PartEstimate(semantic, group, d, panel, extra={"depth_behind": depth_behind})


LEAN_BIN_DEG = 2.0
"""Width (deg) of the tilt classes ``lean_deg`` weighs a front's faces in."""


def lean_deg(mesh: trimesh.Trimesh, outward: np.ndarray) -> float:
    """Tilt (deg) of a front's face off the (3,) unit ``outward``: the tilt class (of
    ``LEAN_BIN_DEG``) holding the most area among ``mesh``'s faces within 60 degrees of it, either
    way round (an open surface's normals may point in). 0 for an upright front, whatever the
    chamfer, J-pull or handle on it; the tilt of a leaned one (a laptop's open screen)."""
    cos = np.abs(mesh.face_normals @ outward)
    facing = cos > 0.5
    if not facing.any():
        return 0.0
    tilt = np.degrees(np.arccos(np.clip(cos[facing], -1.0, 1.0)))
    area = np.bincount((tilt // LEAN_BIN_DEG).astype(int), mesh.area_faces[facing])
    return float((np.argmax(area) + 0.5) * LEAN_BIN_DEG) if np.argmax(area) else 0.0


def pieces_box(ids: list[int], pieces: list[Piece]) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (3,) m: the box around the pieces ``ids``."""
    return np.min([pieces[i].lo for i in ids], axis=0), np.max([pieces[i].hi for i in ids], axis=0)


def body_pieces(ids: list[int], pieces: list[Piece], outward: np.ndarray, share: float) -> list[int]:
    """The pieces among ``ids`` that, seen along ``outward`` (3,), span at least ``share`` of the
    smaller side of all of them together: a part's boards, boxes and panes, not the handles
    and knobs standing off it."""
    plane = np.abs(outward) < 0.5
    lo, hi = pieces_box(ids, pieces)
    smaller = float((hi - lo)[plane].min())
    return [i for i in ids if float(pieces[i].extents[plane].max()) >= share * smaller]


def make_piece(index: int, faces_idx: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> Piece:
    """A Piece over the given input faces."""
    mesh = trimesh.Trimesh(vertices, faces[faces_idx], process=False)
    mesh.remove_unreferenced_vertices()
    return Piece(index, faces_idx, mesh, mesh.vertices.min(axis=0), mesh.vertices.max(axis=0))


def renumber(parts: list[PartEstimate]) -> None:
    """Name ``parts`` in place ``kind_k`` by their semantics, k counting up per kind in order."""
    for part, name in zip(parts, numbered_names([p.semantic for p in parts])):
        part.name = name


def cut_from_surface(part: PartEstimate) -> bool:
    """Whether the views cut ``part`` out of a piece of the mesh (a fused surface) rather than
    finding whole pieces: it shows only its front and edges, no back, track or pieces under it
    to judge by."""
    return bool(part.extra.get("cut_from_surface"))
