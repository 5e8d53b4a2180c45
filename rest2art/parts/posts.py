"""A head on a neck, found from the shape of one fused surface: a tap's handle on its column,
a press's handle on the bar that runs into its slot.

A fused scan of a small fixture is one surface: no piece tells its handle from its body. Its
sections across one direction do: the body, then a neck much narrower than what it carries,
then at the end a head wider than the neck. Standing up, the neck is a column on a foot and
the head turns about it; standing out of the front, the neck is the handle's own bar.

All coordinates are canonical (+z up, -y front), metres.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import trimesh

from rest2art.config import PartsConfig
from rest2art.geometry.basics import perpendicular_basis, ray_distances


@dataclass(frozen=True)
class NeckHead:
    """A head at the end of a neck along ``direction``."""

    direction: np.ndarray
    """(3,) unit, from the body through the neck to the head."""
    head: np.ndarray
    """(K,) indices of the head's faces (beyond the neck's last section)."""
    neck: np.ndarray
    """(L,) indices of the neck's faces: between the body and the head, within its outline."""
    pivot: np.ndarray
    """(3,) the neck's axis at its end under the head, m."""
    width: float
    """The neck's width (m): the median of its sections' largest extents."""
    root: float
    """Position (m) along ``direction`` where the neck leaves the body."""
    outline: np.ndarray
    """(2, 2) the box (low, high corner) of the neck's sections in ``perpendicular_basis``
    coordinates of ``direction``, m."""


def section_boxes(mesh: trimesh.Trimesh, direction: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """(H, 2, 2) the box (low, high corner) of the mesh's section by each plane across the unit
    ``direction`` (3,) at the positions ``levels`` (H,) m along it, in ``perpendicular_basis``
    coordinates of ``direction``; NaN where a plane meets nothing."""
    plane = perpendicular_basis(direction)
    lines, to_3d, _ = trimesh.intersections.mesh_multiplane(mesh, np.zeros(3), direction, levels)
    boxes = np.full((len(levels), 2, 2), np.nan)
    for k, (segments, transform) in enumerate(zip(lines, to_3d)):
        if len(segments):
            flat = np.asarray(segments).reshape(-1, 2)
            points = trimesh.transform_points(np.column_stack([flat, np.zeros(len(flat))]), transform) @ plane.T
            boxes[k] = points.min(axis=0), points.max(axis=0)
    return boxes


def in_box(points: np.ndarray, box: np.ndarray, margin: float) -> np.ndarray:
    """(N,) whether the (N, 2) ``points`` lie in the (2, 2) ``box`` grown by ``margin``."""
    return np.all((points >= box[0] - margin) & (points <= box[1] + margin), axis=1)


def neck_head(mesh: trimesh.Trimesh, direction: np.ndarray, min_length: float,
              config: PartsConfig) -> NeckHead | None:
    """The head at the far end of ``mesh`` along ``direction`` (3,) on a neck, or None. The
    surface is cut by ``post_levels`` planes across it; the neck is the last run of sections
    no wider than ``post_neck_share`` of the widest one beyond it, less its sections at either
    end wider than ``post_width_spread`` times its median (a hub under a long arm is the head's,
    a low foot the body's), at least ``min_length`` times as long as it is wide, with a body
    before it; the head is what lies beyond it (and, past its last section, outside its outline
    by more than the sections' spacing: the head's underside), no larger than ``lever_max_size``
    (a hand turns it). Only a mesh no larger than twice that is cut."""
    along = mesh.vertices @ direction
    lo, hi = float(along.min()), float(along.max())
    if hi <= lo or float(np.ptp(mesh.vertices, axis=0).max()) > 2 * config.lever_max_size:
        return None
    step = (hi - lo) / config.post_levels
    levels = lo + step * (np.arange(config.post_levels) + 0.5)
    boxes = section_boxes(mesh, direction, levels)
    widths = np.nan_to_num(np.max(boxes[:, 1] - boxes[:, 0], axis=1))
    beyond = np.maximum.accumulate(widths[::-1])[::-1]  # widest section at or beyond each level
    top = next((k for k in range(len(levels) - 2, 0, -1)
                if 0 < widths[k] <= config.post_neck_share * beyond[k + 1]), None)
    if top is None:
        return None
    narrow = config.post_neck_share * beyond[top + 1]
    bottom = top
    while bottom > 0 and 0 < widths[bottom - 1] <= narrow:
        bottom -= 1
    width = float(np.median(widths[bottom:top + 1]))
    while top > bottom and widths[top] > config.post_width_spread * width:
        top -= 1  # the head's own narrower underside
    while bottom < top and widths[bottom] > config.post_width_spread * width:
        bottom += 1  # a low foot or the body's edge
    if bottom == 0 or (top - bottom + 1) * step < min_length * width:
        return None  # no body before the neck, or too short a neck
    outline = np.array([boxes[bottom:top + 1, 0].min(axis=0), boxes[bottom:top + 1, 1].max(axis=0)])
    plane = perpendicular_basis(direction)
    flat = mesh.triangles_center @ plane.T
    t = mesh.triangles_center @ direction
    off_neck = ~in_box(flat, outline, step)
    is_head = (t > levels[top] + step) | ((t > levels[top]) & off_neck)
    head = np.flatnonzero(is_head)
    points = mesh.vertices[np.unique(mesh.faces[head])] if len(head) else np.zeros((0, 3))
    if not len(head) or float(np.ptp(points, axis=0).max()) > config.lever_max_size:
        return None
    root = float(levels[bottom] - step / 2)
    neck = np.flatnonzero(~is_head & (t > root) & ~off_neck)
    pivot = outline.mean(axis=0) @ plane + levels[top] * direction
    return NeckHead(direction.astype(float), head, neck, pivot, width, root, outline)


def post_head(mesh: trimesh.Trimesh, config: PartsConfig) -> NeckHead | None:
    """The head on a post standing up (a tap's handle on its column): ``neck_head`` along +z
    with a column at least ``post_min_height`` times as tall as it is wide."""
    return neck_head(mesh, np.array([0.0, 0.0, 1.0]), config.post_min_height, config)


def front_handle(mesh: trimesh.Trimesh, config: PartsConfig) -> NeckHead | None:
    """The handle standing out of the front of a small fixture (a press's handle on its bar):
    ``neck_head`` along -y with a neck at least ``handle_neck_min_length`` times as long as it
    is wide, its neck extended by what continues it into the body (``into_body``: the bar in
    its slot)."""
    found = neck_head(mesh, np.array([0.0, -1.0, 0.0]), config.handle_neck_min_length, config)
    if found is None:
        return None
    return dataclasses.replace(found, neck=np.union1d(found.neck, into_body(mesh, found, config.neck_outline_margin)))


def into_body(mesh: trimesh.Trimesh, found: NeckHead, margin: float) -> np.ndarray:
    """(K,) faces that continue the neck of ``found`` into the body: behind its root, within its
    outline grown by ``margin`` (m), reached from its faces over such faces."""
    from rest2art.io.load import merged_vertex_ids
    from rest2art.parts.segment.lifting import face_adjacency_graph, grow_region

    flat = mesh.triangles_center @ perpendicular_basis(found.direction).T
    allowed = in_box(flat, found.outline, margin) & (mesh.triangles_center @ found.direction <= found.root)
    graph = face_adjacency_graph(merged_vertex_ids(mesh.vertices)[mesh.faces], len(mesh.vertices))
    seed = np.zeros(len(mesh.faces), bool)
    seed[found.neck] = True
    return np.flatnonzero(grow_region(graph + graph.T, seed, allowed) & ~seed)


def slot_room(mesh: trimesh.Trimesh, found: NeckHead, config: PartsConfig) -> tuple[np.ndarray, float] | None:
    """((3,) unit direction, travel m) a handle whose neck runs into the body (``front_handle``)
    can slide along, or None. Beside the neck, along each of the four directions across it, rays
    from just outside the body, ``slot_probe_step`` apart and three across the neck, look for
    room at least ``slot_room_share`` as deep as the neck goes in: a slot. The travel is how far
    that room runs from the neck's outline; the longest wins if it is at least the neck's
    thickness (a bar in a round hole has none) and the room across it is less than that (a slot
    has walls beside the neck; a handle's rose on a plain face finds room all round)."""
    plane = perpendicular_basis(found.direction)
    inside = mesh.triangles_center[found.neck] @ found.direction
    depth = found.root - float(inside.min()) if len(inside) else 0.0
    if depth <= config.neck_outline_margin:
        return None
    lo, hi = found.outline
    start = found.root + config.neck_outline_margin
    runs = {}
    for k, sign in ((k, sign) for k in range(2) for sign in (1.0, -1.0)):
        other = 1 - k
        across = np.linspace(lo[other], hi[other], 5)[1:-1]
        edge = hi[k] if sign > 0 else lo[k]
        reach = float(np.ptp(mesh.vertices @ plane[k]))
        run = 0.0
        for offset in np.arange(config.slot_probe_step, reach, config.slot_probe_step):
            flat = np.zeros((len(across), 2))
            flat[:, k] = edge + sign * offset
            flat[:, other] = across
            free = ray_distances(mesh, flat @ plane + start * found.direction, -found.direction)
            if not np.all(np.isfinite(free) & (free - config.neck_outline_margin >= config.slot_room_share * depth)):
                break  # off the body (inf) or the slot's end
            run = float(offset)
        runs[k, sign] = run
    (k, sign), travel = max(runs.items(), key=lambda item: item[1])
    thickness = float(np.min(hi - lo))
    walled = max(runs[1 - k, 1.0], runs[1 - k, -1.0]) < thickness  # a slot has walls beside the neck
    return (sign * plane[k], travel) if travel >= thickness and walled else None
