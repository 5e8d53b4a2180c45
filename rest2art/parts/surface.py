"""Parts cut out of a fused surface by the rendered-view segmentation (a scan, or a mesh whose
pieces do not follow its parts).

The segmentation labels faces; :func:`add_segmented_parts` turns each label into a part of its
own: a door, drawer or lid keeps the faces of its front and the grip fused to it
(:func:`take_fused_grip`), a drawer over open space the box the scan shows under it
(:func:`hanging_box_faces`), and a knob or button the ring of surface it stands on
(:func:`ring_plate`). Stray facets a label reached across a gap are left to the base
(:func:`stray_facets`). Whole pieces the labels cover keep the piece rules of
:mod:`rest2art.parts.pieces`.

All coordinates are canonical (+z up, -y front), metres.
"""

from __future__ import annotations

import numpy as np
import trimesh

from rest2art.config import PartsConfig
from rest2art.geometry.basics import (boxes_overlap, footprint_spread, inside_box, perpendicular_basis, protrusion_size,
                                      ray_distances)
from rest2art.parts.pieces import (DISC_DIAMETER_PER_STD, PANELS, PartEstimate, Piece, controls_beside_the_grip,
                                   cut_fitting_pivot, cut_from_surface, cut_knob, dominant_normal, lean_deg,
                                   make_piece, pieces_box, renumber, snap_axis)
from rest2art.tolerances import RAY_NUDGE


def ring_plate(part_faces: np.ndarray, base_face: np.ndarray, vertices: np.ndarray, faces: np.ndarray,
               normal: np.ndarray, config: PartsConfig) -> tuple[np.ndarray, float | None]:
    """((3,) normal, level along it (m) or None) of the surface a control cut from a fused
    mesh stands on. Of the base faces (``base_face``, (F,) bool) within ``ring_width`` (m) of
    where its faces (``part_faces``, indices) meet them (wider than the fillet a scan rounds
    that corner with), those whose normals agree within ``plate_agree_deg`` with the most area
    (the plate, not the control's own foot left to the base): their area-weighted mean normal,
    snapped to an axis near it (``snap_axis``), and the area-weighted median of their centres
    along it. ``normal`` ((3,), the views' nearest axis) and None where that ring is empty; the
    same normal where the plate's lies more than ``ring_max_deg`` from it, unless the control
    stands wholly in front of the plate (``mount_reach``) and further out of it than along
    ``normal``: the views' normal is the side they saw most of, a stick's long side. A knob
    on a sloped panel tilts with the panel."""
    from scipy.spatial import cKDTree

    on_part = np.zeros(len(vertices), bool)
    on_part[faces[part_faces].ravel()] = True
    border = np.unique(faces[base_face & on_part[faces].any(axis=1)].ravel())
    border = border[on_part[border]]  # where the control meets the surface
    if not len(border):
        return normal, None
    candidates = np.flatnonzero(base_face)
    near = cKDTree(vertices[border]).query(vertices[faces[candidates]].mean(axis=1),
                                           distance_upper_bound=config.ring_width)[0]
    ring = candidates[np.isfinite(near)]
    if not len(ring):
        return normal, None
    triangles = vertices[faces[ring]]
    normals, valid = trimesh.triangles.normals(triangles)
    area = trimesh.triangles.area(triangles)[valid]
    plate = dominant_normal(normals, area, config.plate_agree_deg) if len(normals) else None
    if plate is None:
        return normal, None
    mean = snap_axis(plate)
    on_plate = normals @ plate >= np.cos(np.radians(config.plate_agree_deg))
    along = triangles[valid][on_plate].mean(axis=1) @ mean
    level = float(np.quantile(along, 0.5, weights=area[on_plate], method="inverted_cdf"))
    if float(mean @ normal) < np.cos(np.radians(config.ring_max_deg)):
        control = vertices[on_part]
        out = control @ mean
        if out.min() < level - config.mount_reach or np.ptp(out) <= np.ptp(control @ normal):
            return normal, None
    return mean, level


def low_cap(vertices: np.ndarray, outward: np.ndarray, level: float, config: PartsConfig) -> float | None:
    """How far (m) a control cut from a fused mesh, its (N, 3) ``vertices``, stands above the
    plate at ``level`` (m along ``outward`` (3,)) when it stands less than ``knob_min_height``
    of its width or less than ``knob_min_grip`` (too low to grip and turn: a push button in
    its hole, the hole's clearance closed by the scan); None for a knob."""
    _, width = protrusion_size(vertices, outward)
    height = float((vertices @ outward).max()) - level
    return height if 0.0 < height < max(config.knob_min_height * width, config.knob_min_grip) else None


def carries_base_controls(piece: Piece, parts: list[PartEstimate], pieces: list[Piece], config: PartsConfig) -> bool:
    """Whether a knob or button of the base that faces sideways (its outward axis within 60
    degrees of level) touches ``piece``'s box grown by ``attach_tolerance`` (m): the block an
    oven's knobs stand on; a knob on top of a lid is its grip."""
    controls = [p for p in parts[1:] if p.semantic in ("knob", "button") and p.parent is None
                and p.outward is not None and abs(float(p.outward[2])) < 0.5]
    if not controls:
        return False
    boxes = [pieces_box(p.pieces, pieces) for p in controls]
    lo, hi = np.array([b[0] for b in boxes]), np.array([b[1] for b in boxes])
    tol = config.attach_tolerance
    return bool(boxes_overlap(lo, hi, piece.lo[None] - tol, piece.hi[None] + tol).any())


def hot_plate(points: np.ndarray, up: np.ndarray, config: PartsConfig) -> bool:
    """Whether the (N, 3) ``points`` of a fitting on a top facing ``up`` (3,) make a burner or a
    hot plate: round seen from above (``knob_roundness``), at least ``plate_min_width`` (m) across
    and standing at most ``plate_max_height`` of that width out of the top: wider than a hand
    grips, too low to grip by its side."""
    spread = footprint_spread(points, up)
    if spread.max() <= 0 or spread.min() / spread.max() < config.knob_roundness:
        return False
    width = DISC_DIAMETER_PER_STD * float(spread.max())
    return width >= config.plate_min_width and float(np.ptp(points @ up)) <= config.plate_max_height * width


def cooktop(label: int, segmented: list, face_label: np.ndarray, triangles: np.ndarray, up: np.ndarray,
            config: PartsConfig) -> bool:
    """Whether the top ``label`` of ``face_label`` (F,; ``segmented`` indexed from 1) carries
    ``cooktop_min_plates`` handle labels or more that are ``hot_plate`` s (``triangles`` (F, 3, 3),
    ``up`` (3,) its normal)."""
    plates = 0
    for j, other in enumerate(segmented, start=1):
        if other.category == "handle" and other.parent == label:
            faces = face_label == j
            plates += bool(faces.any()) and hot_plate(triangles[faces].reshape(-1, 3), up, config)
    return plates >= config.cooktop_min_plates


def face_patches(idx: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> tuple[trimesh.Trimesh, list[np.ndarray]]:
    """The faces ``idx`` (of ``faces`` (F, 3) on ``vertices`` (V, 3)) as one mesh, coincident
    vertices merged, and its patches of connected faces (arrays of positions in ``idx``)."""
    patch = trimesh.Trimesh(vertices, faces[idx], process=False)
    patch.merge_vertices()
    return patch, trimesh.graph.connected_components(patch.face_adjacency, nodes=np.arange(len(idx)))


def stray_facets(idx: np.ndarray, vertices: np.ndarray, faces: np.ndarray, share: float, reach: float) -> np.ndarray:
    """(len(idx),) bool: the faces ``idx`` (of ``faces`` (F, 3) on ``vertices`` (V, 3)) in
    patches of connected faces with less than ``share`` of the largest patch's area that lie
    further than ``reach`` (m) from it."""
    patch, groups = face_patches(idx, vertices, faces)
    area = np.array([patch.area_faces[g].sum() for g in groups])
    main = patch.submesh([groups[int(np.argmax(area))]], append=True)
    stray = np.zeros(len(idx), bool)
    for group, a in zip(groups, area):
        if a < share * area.max():
            corners = patch.vertices[np.unique(patch.faces[group])]
            stray[group] = trimesh.proximity.closest_point(main, corners)[1].min() > reach
    return stray


def segmented_part(semantic: str, piece: Piece, idx: np.ndarray, labels: np.ndarray, normal: np.ndarray,
                   vertices: np.ndarray, faces: np.ndarray, cut: bool, depth_behind: float,
                   config: PartsConfig) -> PartEstimate:
    """The part of a segmented ``piece`` (its input faces ``idx``) of ``semantic`` facing
    ``normal`` (3,; snapped to an axis: the views' or its plate's); ``labels`` (F,) 0 on the
    base's faces. A knob turns about its plate's normal (``ring_plate``) and is a button where it
    stands too low to grip (``low_cap``). ``cut``: cut out of a fused surface; ``depth_behind`` (m): the object's
    depth along its normal, a drawer's depth where the surface shows no interior."""
    extra = {"depth_behind": depth_behind, "source": "segmentation", "cut_from_surface": cut}
    outward = normal.astype(float)
    if semantic == "knob":  # the views snap their normals to the axes; a knob turns about its plate's
        outward, level = ring_plate(idx, labels == 0, vertices, faces, outward, config)
        height = None if level is None else low_cap(piece.mesh.vertices, outward, level, config)
        if height is not None:
            semantic = "button"
            extra["travel"] = min(height, config.button_max_travel)
    return PartEstimate(semantic, [piece.index], outward, piece.index, extra=extra)


def cap_among_controls(cap: Piece, normal: np.ndarray, controls: list[Piece], config: PartsConfig) -> bool:
    """Whether ``cap``, a grip the views found on the base facing ``normal`` (3,), is a control:
    at least ``control_min_neighbours`` ``controls`` (knobs and buttons facing the same way)
    share its face, it is about as wide as it is long across that face
    (``control_max_elongation``: a pull is a bar), and no control holds its centre (it is no
    control's rim or skirt)."""
    if len(controls) < config.control_min_neighbours:
        return False
    u, v = perpendicular_basis(normal)
    spans = sorted([float(np.ptp(cap.mesh.vertices @ u)), float(np.ptp(cap.mesh.vertices @ v))])
    if spans[0] <= 0 or spans[1] > config.control_max_elongation * spans[0]:
        return False
    centre = ((cap.lo + cap.hi) / 2)[None]
    return not any(inside_box(centre, centre, c.lo, c.hi, 0.0)[0] for c in controls)


def nested_fitting(piece: Piece, fittings: list[int], pieces: list[Piece], config: PartsConfig) -> int | None:
    """The index of the first of a panel's ``fittings`` (piece indices) whose box holds
    ``piece``'s box, or lies in it, grown by ``control_fragment_margin`` of the larger's larger
    side: one grip that views saw whole and in part; None when there is none."""
    for index in fittings:
        other = pieces[index]
        for inner, outer in ((piece, other), (other, piece)):
            margin = config.control_fragment_margin * float(np.max(outer.hi - outer.lo))
            if inside_box(inner.lo[None], inner.hi[None], outer.lo, outer.hi, margin)[0]:
                return index
    return None


def panels_seen_again(parts: list[PartEstimate], pieces: list[Piece], face_label: np.ndarray, area: np.ndarray,
                      labels: np.ndarray) -> dict[int, PartEstimate]:
    """Per segmentation label among ``labels`` (panels the views found again on movable parts'
    faces; ``face_label`` (F,), ``area`` (F,) m^2), the door, drawer or lid holding most of it."""
    panels = [part for part in parts if part.semantic in PANELS]
    if not panels:
        return {}
    holder = np.full(len(face_label), -1)
    for n, part in enumerate(panels):
        holder[np.concatenate([pieces[i].faces for i in part.pieces])] = n
    out = {}
    for k in labels:
        on = (face_label == k) & (holder >= 0)
        if on.any():
            out[int(k)] = panels[int(np.argmax(np.bincount(holder[on], area[on], minlength=len(panels))))]
    return out


def take_fused_grip(part: PartEstimate, idx: np.ndarray, pieces: list[Piece], vertices: np.ndarray,
                    faces: np.ndarray, seen_as: str, depth: float, config: PartsConfig) -> Piece | None:
    """A grip the views found on ``part`` (its faces ``idx``), cut out of the part's panel piece
    when it is fused into it: the panel piece is replaced by the rest, and the grip becomes a
    new piece of ``part`` (both appended to ``pieces``) and is returned; None where the grip
    is no fused share of the panel (``fused_grip_max_share`` of its faces at most, after its
    stray facets). A door the views saw as a drawer (a grip in its middle) whose front shows
    nothing behind it is a drawer whose box the surface hides, ``depth`` (m) deep."""
    panel = pieces[part.panel]
    idx = idx[np.isin(idx, panel.faces)]
    if len(idx) < 8:
        return None
    idx = idx[~stray_facets(idx, vertices, faces, config.handle_stray_share, config.handle_stray_reach)]
    if not 0 < len(idx) <= config.fused_grip_max_share * len(panel.faces):
        return None
    rest = make_piece(len(pieces), np.setdiff1d(panel.faces, idx), vertices, faces)
    grip = make_piece(len(pieces) + 1, idx, vertices, faces)
    pieces += [rest, grip]
    part.pieces = [rest.index if i == part.panel else i for i in part.pieces] + [grip.index]
    part.panel = rest.index
    if seen_as == "drawer" and part.semantic == "door" and len(part.pieces) == 2:
        part.semantic = "drawer"
        part.extra["depth_behind"] = max(depth, float(part.extra.get("depth_behind", 0.0)))
    return grip


def hanging_box_faces(front: Piece, outward: np.ndarray, candidates: np.ndarray, everything: trimesh.Trimesh,
                      depth: float, config: PartsConfig) -> np.ndarray:
    """The faces among ``candidates`` (indices into ``everything``, the whole input surface in
    the canonical frame, +z up) of the box behind a drawer ``front`` facing ``outward`` (3,),
    cut out of that surface, where the surface shows the box from below, hanging over open
    space (a desk's drawer over its knee room).

    Its floor: faces facing down (``box_floor_facing_cos``) with nothing under them, at least
    ``box_floor_min_clearance`` over the object's lowest point (an object's own bottom stands
    on the ground), in the lower part of the front's height (``box_floor_max_height_share``: a
    top over the front is no floor) and within ``depth`` (m) behind it, in a connected patch of
    ``box_floor_min_share`` of the front's area or more that stays within the front's outline
    across and clear of the object's sides at its height (``box_floor_tolerance``): a carcass
    bottom runs on past a front beside it, or to the carcass's sides under a front as wide as
    the carcass (under a top that overhangs them). Its walls: the faces standing on that floor
    up to the front's top, inside and out. A closed carcass hides its drawers' boxes; only open
    space below shows one."""
    up = np.array([0.0, 0.0, 1.0])
    tolerance = config.box_floor_tolerance
    across = np.cross(up, outward)
    centres = everything.triangles_center[candidates]
    front_depth = float((front.mesh.vertices @ outward).min())
    behind = front_depth - centres @ outward
    low_half = front.lo[2] + config.box_floor_max_height_share * (front.hi[2] - front.lo[2])
    keep = (everything.face_normals[candidates] @ up < -config.box_floor_facing_cos) \
        & (centres[:, 2] > max(front.lo[2] - tolerance, everything.bounds[0, 2] + config.box_floor_min_clearance)) \
        & (centres[:, 2] < low_half) & (behind > 0) & (behind < depth)
    idx = candidates[keep]
    if not len(idx):
        return idx
    idx = idx[~np.isfinite(ray_distances(everything, everything.triangles_center[idx] - RAY_NUDGE * up, -up))]
    if not len(idx):
        return idx
    _, groups = face_patches(idx, everything.vertices, everything.faces)
    span = np.sort(np.array([front.lo, front.hi]) @ across)
    triangles = everything.triangles
    heights = triangles[:, :, 2]
    floors = []
    for group in groups:
        points = triangles[idx[group]].reshape(-1, 3)
        reach = points @ across
        # the object's sides at the floor's height (a top overhanging the carcass is higher up)
        level = (heights.min(axis=1) <= points[:, 2].max() + tolerance) & (heights.max(axis=1) >= points[:, 2].min() - tolerance)
        sides = triangles[level].reshape(-1, 3) @ across
        if everything.area_faces[idx[group]].sum() >= config.box_floor_min_share * front.mesh.area \
                and reach.min() >= max(span[0] - tolerance, sides.min() + tolerance) \
                and reach.max() <= min(span[1] + tolerance, sides.max() - tolerance):
            floors.append(idx[group])
    if not floors:
        return idx[:0]
    floor = np.concatenate(floors)
    # the box stands on that floor, from the back of its front up to the front's top
    points = triangles[floor].reshape(-1, 3)
    lo = np.array([(points @ across).min(), 0.0, points[:, 2].min()]) - tolerance
    hi = np.array([(points @ across).max() + tolerance, (front_depth - points @ outward).max() + tolerance,
                   front.hi[2] - tolerance])
    where = np.stack([centres @ across, behind, centres[:, 2]], axis=1)
    return np.union1d(floor, candidates[np.all((where >= lo) & (where <= hi), axis=1)])


def whole_pieces(idx: np.ndarray, face_piece: np.ndarray, pieces: list[Piece]) -> bool:
    """Whether the faces ``idx`` are whole pieces of the base (``face_piece`` (F,): the base piece
    of each face, -1 elsewhere), not cut out of a fused surface."""
    touched, count = np.unique(face_piece[idx], return_counts=True)
    return all(i >= 0 and n == len(pieces[i].faces) for i, n in zip(touched, count))


def add_segmented_parts(parts: list[PartEstimate], pieces: list[Piece], face_label: np.ndarray,
                        segmented: list, vertices: np.ndarray, faces: np.ndarray,
                        config: PartsConfig = PartsConfig(), min_faces: int = 8) -> tuple[list[PartEstimate], list[Piece]]:
    """Movable parts found by segmentation among the base's faces.

    ``face_label`` (F,) indexes ``segmented`` from 1 (0 = base); handle labels become extra
    pieces of their panel's part, so the hinge rules can see them. Faces that pieces already
    gave to a movable part keep it, and a segmented part with ``seen_again_share`` of its area
    or more on the faces of a door, drawer or lid the pieces found is that panel seen again: the
    rest of its faces (the walls of a box under its lid) stay with the base, and its handles,
    fused into that panel's piece, are cut out as its grip (:func:`take_fused_grip`); so does a
    segmented panel with as much on the boards under a lid resting on boards (``box_walls``). A
    drawer's depth behind its front is unknown on a surface without interior: it is taken as the
    object's depth along its normal."""
    base = parts[0]
    base_faces = np.concatenate([pieces[i].faces for i in base.pieces])
    labels = np.zeros(len(face_label), np.int64)
    labels[base_faces] = face_label[base_faces]
    triangles = vertices[faces]
    area = trimesh.triangles.area(triangles)
    in_panels, in_walls = np.zeros(len(face_label), bool), np.zeros(len(face_label), bool)
    for part in parts[1:]:
        if part.semantic in PANELS:
            in_panels[np.concatenate([pieces[i].faces for i in part.pieces])] = True
        for i in part.extra.get("box_walls", []):
            in_walls[pieces[i].faces] = True
    labelled_area = config.seen_again_share * np.bincount(face_label, area, minlength=len(segmented) + 1)
    seen_again = np.bincount(face_label, area * in_panels, minlength=len(segmented) + 1) >= labelled_area
    is_panel_label = np.array([False, *(seg.category in PANELS for seg in segmented)])
    on_walls = np.bincount(face_label, area * in_walls, minlength=len(segmented) + 1)
    seen_again |= is_panel_label & (on_walls >= labelled_area)
    seen_again[0] = False
    labels[seen_again[face_label]] = 0
    seen_on = panels_seen_again(parts, pieces, face_label, area, np.flatnonzero(seen_again))
    face_piece = np.full(len(face_label), -1)  # the base piece of each face
    for i in base.pieces:
        face_piece[pieces[i].faces] = i
    pieces = list(pieces)
    new_parts: list[PartEstimate] = []
    obj_extent = vertices.max(axis=0) - vertices.min(axis=0)
    by_label: dict[int, PartEstimate] = {}
    for k, seg in enumerate(segmented, start=1):
        if seg.category == "handle":
            continue
        idx = np.flatnonzero(labels == k)
        if len(idx) < min_faces:
            labels[idx] = 0
            continue
        whole = whole_pieces(idx, face_piece, pieces)
        piece = make_piece(len(pieces), idx, vertices, faces)
        if seg.category == "lid" and carries_base_controls(piece, parts, pieces, config):
            labels[idx] = 0  # a top whose front carries the base's knobs is a control block, no lid
            continue
        if seg.category == "lid" and cooktop(k, segmented, labels, triangles, seg.normal, config):
            labels[idx] = 0  # a top carrying burners is a cooktop: what stands on it is no grip
            continue
        pieces.append(piece)
        semantic = seg.category
        if semantic == "drawer" and lean_deg(piece.mesh, seg.normal) > config.drawer_max_lean_deg:
            semantic = "door"  # a drawer's front stands upright; a leaned panel swings (an open screen)
        part = segmented_part(semantic, piece, idx, labels, seg.normal, vertices, faces, not whole,
                              float(obj_extent @ np.abs(seg.normal)), config)
        by_label[k] = part
        new_parts.append(part)
    controls = [p for p in new_parts if p.semantic in ("knob", "button")]  # the views' own, on the base
    rigid_cut: dict[int, list[int]] = {}  # per panel label, the fittings cut from its surface kept rigid
    for k, seg in enumerate(segmented, start=1):
        if seg.category != "handle":
            continue
        idx = np.flatnonzero(labels == k)
        owner = by_label.get(seg.parent)
        if owner is None and seg.parent in seen_on:
            # on a panel the pieces found, fused into its one piece (a scan's front held clear of
            # the carcass is a shell of its own): cut out, it is that panel's grip
            panel_seen = segmented[seg.parent - 1]
            held = take_fused_grip(seen_on[seg.parent], np.flatnonzero(face_label == k), pieces, vertices, faces,
                                   panel_seen.category, float(obj_extent @ np.abs(panel_seen.normal)), config)
            if held is not None:
                seen_on[seg.parent].extra.setdefault("fittings", []).append(held.index)
            continue
        if owner is not None:  # a handle lies on its panel: faces far past its outline are not the handle's
            centres = vertices[faces[idx]].mean(axis=1)
            panel = pieces[owner.panel]
            in_plane = np.abs(owner.outward) < 0.5  # how far it stands out is the handle's own
            within = np.all(((centres >= panel.lo - config.handle_max_overhang)
                             & (centres <= panel.hi + config.handle_max_overhang))[:, in_plane], axis=1)
            labels[idx[~within]] = 0
            idx = idx[within]
        # cut with its panel from one piece (a scan's fused surface): a spoke wheel turns on its
        # door as it would if it were pieces of its own (``turning_fittings``)
        fused = owner is not None and owner.semantic in PANELS and len(np.unique(face_piece[idx])) == 1 \
            and set(np.unique(face_piece[pieces[owner.panel].faces])) == set(np.unique(face_piece[idx]))
        if fused:
            stray = stray_facets(idx, vertices, faces, config.handle_stray_share, config.handle_stray_reach)
            labels[idx[stray]] = 0
            idx = idx[~stray]
        if owner is None and seg.parent == 0 and len(idx) >= min_faces \
                and len(controls) >= config.control_min_neighbours:  # else no face has enough controls
            cap = make_piece(len(pieces), idx, vertices, faces)
            # it faces the way the plate it stands on does: seen from above, a stick standing
            # out of a front shows its long side (``ring_plate``)
            facing, _ = ring_plate(idx, labels == 0, vertices, faces, seg.normal, config)
            beside = [c for c in controls if float(c.outward @ facing) > config.control_facing_cos]
            if cap_among_controls(cap, facing, [pieces[c.panel] for c in beside], config):
                # a cap on the base among the controls of its face is one more control; the
                # fragments the views cut out of it as knobs are its own
                margin = config.control_fragment_margin * float(np.max(cap.hi - cap.lo))
                inside = [c for c in controls  # a fragment may face any way: a sliver of its top
                          if inside_box(pieces[c.panel].lo[None], pieces[c.panel].hi[None], cap.lo, cap.hi, margin)[0]]
                if inside:
                    idx = np.unique(np.concatenate([idx, *(pieces[c.panel].faces for c in inside)]))
                    gone = {id(c) for c in inside}
                    new_parts = [p for p in new_parts if id(p) not in gone]
                    controls = [c for c in controls if id(c) not in gone]
                    cap = make_piece(len(pieces), idx, vertices, faces)
                pieces.append(cap)
                new_parts.append(segmented_part("knob", cap, idx, labels, facing, vertices, faces,
                                                not whole_pieces(idx, face_piece, pieces),
                                                float(obj_extent @ np.abs(facing)), config))
                continue
        if owner is None or len(idx) < min_faces:
            labels[idx] = 0
            continue
        piece = make_piece(len(pieces), idx, vertices, faces)
        whole = nested_fitting(piece, owner.extra.get("fittings", []), pieces, config)
        if whole is not None:
            # a stretch of a grip that some views cut short (a bar pull seen in part) is that grip
            pieces[whole] = make_piece(whole, np.union1d(pieces[whole].faces, idx), vertices, faces)
            continue
        pieces.append(piece)
        owner.extra.setdefault("fittings", []).append(piece.index)
        pivot = cut_fitting_pivot(piece, owner, pieces, config) if fused else None
        if pivot is None:
            owner.pieces.append(piece.index)
            if fused:
                rigid_cut.setdefault(seg.parent, []).append(piece.index)
            continue
        new_parts.append(cut_knob(owner, piece.index, pivot))
    for label, rigid in rigid_cut.items():
        owner = by_label[label]
        for index, pivot in controls_beside_the_grip(owner, rigid, pieces, config):
            owner.pieces.remove(index)
            new_parts.append(cut_knob(owner, index, pivot))
    everything = None
    for label, part in by_label.items():
        if part.semantic not in ("drawer", "door") or not cut_from_surface(part) or abs(part.outward[2]) > 0.5:
            continue
        if everything is None:
            everything = trimesh.Trimesh(vertices, faces, process=False)
        free = base_faces[labels[base_faces] == 0]
        floor = hanging_box_faces(pieces[part.panel], part.outward, free, everything, part.extra["depth_behind"], config)
        if len(floor) >= min_faces:  # the box the surface shows below the front moves with it
            labels[floor] = label
            piece = make_piece(len(pieces), floor, vertices, faces)
            pieces.append(piece)
            part.pieces.append(piece.index)
            part.extra["box_floor"] = piece.index
            part.semantic = "drawer"  # an upright front with a box hanging behind it is drawn out
    if not new_parts or not (labels[base_faces] == 0).any():  # a segmentation that takes all the base is wrong
        renumber(parts[1:])  # a door the views saw as a drawer is named as one
        return parts, pieces
    # the base keeps its unlabelled faces, piece by piece
    kept_base = []
    for i in base.pieces:
        rest = pieces[i].faces[labels[pieces[i].faces] == 0]
        if len(rest) == len(pieces[i].faces):
            kept_base.append(i)
        elif len(rest):
            piece = make_piece(len(pieces), rest, vertices, faces)
            pieces.append(piece)
            kept_base.append(piece.index)
    base = PartEstimate("base", kept_base, name="base")
    out = [base, *parts[1:], *new_parts]
    renumber(out[1:])
    return out, pieces
