"""Fronts fused into one piece, told apart by their grips.

A scan fuses doors or drawers a few millimetres apart into one surface; held clear of the
carcass, that surface is a piece of its own, and the pieces see one front where there are two
doors or a column of drawers. Their grips still show: alike pulls side by side near the middle
of a front are a pair of doors meeting there; alike pulls one above the other are a column of
drawers. The front is cut halfway between them (the views do the same for a front cut out of
the carcass, ``parts.segment.panels``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import trimesh

from rest2art.config import PartsConfig
from rest2art.geometry.basics import panel_frame
from rest2art.parts.pieces import PartEstimate, Piece, make_piece, renumber
from rest2art.tolerances import FACING_COS, TINY


def face_plane(mesh: trimesh.Trimesh, outward: np.ndarray, config: PartsConfig) -> float:
    """Position (m) along ``outward`` (3,) of a front's face: the outermost level (in bins of
    ``grip_plane_bin`` m) holding ``grip_plane_min_share`` or more of the area of ``mesh``'s
    faces facing ``outward``. Not the densest: a glazed door's panes lie behind its frame."""
    facing = mesh.face_normals @ outward > FACING_COS
    along = mesh.triangles_center[facing] @ outward
    area = mesh.area_faces[facing]
    if not len(along):
        return float((mesh.vertices @ outward).max())
    level = np.floor((along - along.min()) / config.grip_plane_bin).astype(int)
    share = np.bincount(level, area) / area.sum()
    top = int(np.flatnonzero(share >= min(config.grip_plane_min_share, share.max()))[-1])
    return float(np.average(along[level == top], weights=area[level == top]))


def proud_patches(mesh: trimesh.Trimesh, outward: np.ndarray, config: PartsConfig) -> list[np.ndarray]:
    """Face ids of ``mesh`` (a front facing ``outward`` (3,)) in connected patches standing
    ``grip_min_proud`` (m) or more in front of its face (:func:`face_plane`), each covering
    ``grip_min_area`` (m^2) or more and reaching ``grip_min_height`` (m) out: its grips."""
    along = mesh.triangles_center @ outward
    plane = face_plane(mesh, outward, config)
    proud = np.flatnonzero(along > plane + config.grip_min_proud)
    if len(proud) == 0:
        return []
    adjacency = mesh.face_adjacency
    both = np.isin(adjacency, proud).all(axis=1)
    patches = trimesh.graph.connected_components(adjacency[both], nodes=proud)
    return [np.asarray(p) for p in patches
            if mesh.area_faces[p].sum() >= config.grip_min_area and along[p].max() >= plane + config.grip_min_height]


def alike(footprints: np.ndarray, ratio: float) -> bool:
    """Whether grips of (N, 2) in-plane ``footprints`` (m) are alike: each one's within ``ratio``
    of every other's both ways (sides sorted, so a bar across is a bar along)."""
    sides = np.sort(np.asarray(footprints, float), axis=1)
    return bool(np.all(sides.max(axis=0) <= ratio * np.maximum(sides.min(axis=0), TINY)))


def apart(centres: np.ndarray, sizes: np.ndarray, key: int) -> bool:
    """Whether grips at ``centres`` (N, 2) of ``sizes`` (N, 2) (across, up; m), N >= 2, do not
    overlap along axis ``key`` of the two: consecutive ones leave a gap."""
    order = np.argsort(centres[:, key])
    gaps = np.diff(centres[order, key]) - (sizes[order[:-1], key] + sizes[order[1:], key]) / 2
    return bool(len(centres) > 1 and gaps.min() > 0)


def meeting_pair(centres: np.ndarray, span: np.ndarray, middle: np.ndarray, max_offset: float, mirror_tol: float,
                 min_height_share: float) -> bool:
    """Whether two grips at ``centres`` (2, 2) (across, up; m) on a front ``span`` (2,) wide and
    tall, whose middle is at ``middle`` (2,), are the pulls of a pair of doors meeting there: one
    on each side of the middle, each within ``max_offset`` of the width of it, mirrored about it
    to ``mirror_tol`` of the width, on a front at least ``min_height_share`` as tall as it is wide.
    A wide drawer's two pulls stand out towards its ends; a safe's lever stands beside the dial
    in its middle."""
    if len(centres) != 2:
        return False
    offset = centres[:, 0] - middle[0]
    return bool(offset[0] * offset[1] < 0 and np.all(np.abs(offset) <= max_offset * span[0])
                and abs(offset.sum()) <= mirror_tol * span[0] and span[1] >= min_height_share * span[0])


def grip_cuts(mesh: trimesh.Trimesh, outward: np.ndarray, config: PartsConfig,
              lying: tuple[trimesh.Trimesh, ...] = ()) -> tuple[str, np.ndarray, list[float]] | None:
    """How a one-piece front (``mesh``, facing ``outward`` (3,)) divides by its grips:
    (semantic of each share, (3,) axis across the cuts, cut positions along it, m), or None.
    The grips of the fronts ``lying`` on it (:func:`lies_on`: a raised panel a scan left a
    shell of its own) count as its own. Two alike grips (footprints within
    ``grip_alike_ratio``) at one height (within ``grip_row_tol`` of the front's height) that are
    a :func:`meeting_pair` (``grip_pair_*``): a pair of doors. Alike grips in one column, apart:
    drawers."""
    points = [m.vertices[np.unique(m.faces[p])] for m in (mesh, *lying) for p in proud_patches(m, outward, config)]
    if len(points) < 2:
        return None
    u, v = panel_frame(outward)
    span = np.array([np.ptp(mesh.vertices @ u), np.ptp(mesh.vertices @ v)])
    middle = np.array([(mesh.vertices @ u).min(), (mesh.vertices @ v).min()]) + span / 2
    centres = np.array([[p.mean(axis=0) @ u, p.mean(axis=0) @ v] for p in points])
    sizes = np.array([[np.ptp(p @ u), np.ptp(p @ v)] for p in points])
    if not alike(sizes, config.grip_alike_ratio) or np.any(sizes >= config.grip_max_span * span):
        return None  # a grip beside a lock; a strip along the front: a rim, no grip
    spread = np.ptp(centres, axis=0) / np.maximum(span, TINY)
    if spread[1] <= config.grip_row_tol and apart(centres, sizes, 0) and meeting_pair(
            centres, span, middle, config.grip_pair_max_offset, config.grip_pair_mirror_tol,
            config.grip_pair_min_height_share):
        key, axis, semantic = 0, u, "door"
    elif spread[0] <= config.grip_row_tol and apart(centres, sizes, 1):
        key, axis, semantic = 1, v, "drawer"
    else:
        return None
    ordered = np.sort(centres[:, key])
    return semantic, axis, list((ordered[:-1] + ordered[1:]) / 2)


def lies_on(inner: trimesh.Trimesh, front: trimesh.Trimesh, outward: np.ndarray, config: PartsConfig) -> bool:
    """Whether the front ``inner`` lies on the front ``front`` (both facing ``outward`` (3,)):
    inside its outline (grown by ``grip_lying_margin``, m), smaller than it, and standing out
    from its face (:func:`face_plane`) rather than behind it."""
    u, v = panel_frame(outward)
    axes = np.stack([u, v])
    lo, hi = (front.vertices @ axes.T).min(axis=0), (front.vertices @ axes.T).max(axis=0)
    in_lo, in_hi = (inner.vertices @ axes.T).min(axis=0), (inner.vertices @ axes.T).max(axis=0)
    inside = np.all(in_lo >= lo - config.grip_lying_margin) and np.all(in_hi <= hi + config.grip_lying_margin)
    return bool(inside and np.prod(in_hi - in_lo) < np.prod(hi - lo)
                and (inner.vertices @ outward).max() > face_plane(front, outward, config))


def split_fused_fronts(parts: list[PartEstimate], pieces: list[Piece], vertices: np.ndarray, faces: np.ndarray,
                       config: PartsConfig) -> tuple[list[PartEstimate], list[Piece]]:
    """``parts`` with each door or drawer of one piece that :func:`grip_cuts` divides replaced
    by its shares (new pieces appended to ``pieces``; ``vertices`` (V, 3), ``faces`` (F, 3) the
    canonical mesh); faces reaching ``grip_seam_reach`` (m) or more across a cut on both sides
    join the base. A drawer cut from a front with nothing behind it takes the object's depth
    along its normal as its own (the surface hides its box)."""
    out, pieces = [parts[0]], list(pieces)
    depth = np.ptp(vertices, axis=0)
    fronts = [p for p in parts[1:] if p.semantic in ("door", "drawer") and len(p.pieces) == 1]
    joined: set[int] = set()  # fronts lying on a divided front: now its shares'
    divided: set[int] = set()
    for part in parts[1:]:
        if id(part) in joined:
            continue
        if part.semantic not in ("door", "drawer") or len(part.pieces) != 1:
            out.append(part)
            continue
        panel = pieces[part.panel]
        lying = [q for q in fronts if q is not part and id(q) not in joined | divided and q.outward @ part.outward > FACING_COS
                 and lies_on(pieces[q.panel].mesh, panel.mesh, part.outward, config)]
        cut = grip_cuts(panel.mesh, part.outward, config, tuple(pieces[q.panel].mesh for q in lying))
        if cut is None:
            out.append(part)
            continue
        semantic, axis, positions = cut
        corners = panel.mesh.vertices[panel.mesh.faces] @ axis  # (F, 3)
        share = np.searchsorted(positions, corners.mean(axis=1))
        # a scan's seam between the fronts holds slivers reaching far across the cut: neither
        # front's (their hulls would overlap by that much), they stay with the base
        seam = np.searchsorted(positions, corners.min(axis=1) + config.grip_seam_reach) \
            != np.searchsorted(positions, corners.max(axis=1) - config.grip_seam_reach)
        share[seam] = -1
        if np.bincount(share[~seam], minlength=len(positions) + 1).min() < config.grip_share_min_faces:
            out.append(part)
            continue
        if seam.any():
            piece = make_piece(len(pieces), panel.faces[seam], vertices, faces)
            pieces.append(piece)
            out[0] = replace(out[0], pieces=[*out[0].pieces, piece.index])
        # a front lying on a share is that share's (its raised panel)
        on_share = [int(np.searchsorted(positions, pieces[q.panel].mesh.vertices.mean(axis=0) @ axis)) for q in lying]
        for k in range(len(positions) + 1):
            piece = make_piece(len(pieces), panel.faces[share == k], vertices, faces)
            pieces.append(piece)
            extra = dict(part.extra, split_by_grips=True)
            if semantic == "drawer":
                extra["depth_behind"] = max(float(depth @ np.abs(part.outward)), float(part.extra.get("depth_behind", 0.0)))
            held = [i for q, at in zip(lying, on_share) if at == k for i in q.pieces]
            out.append(PartEstimate(semantic, [piece.index, *held], part.outward, piece.index, extra=extra))
        joined |= {id(q) for q in lying}
        divided.add(id(part))
    out = [p for p in out if id(p) not in joined]
    if len(out) != len(parts):
        renumber(out[1:])
    return out, pieces
