"""Panels and protrusions found in one rendered view (the offline evidence behind both roles).

1. Edges: neighbouring pixels whose normals differ by more than ``normal_edge_deg`` (seams,
   grooves, corners), whose surface points are far apart for their pixel footprint (occlusion),
   that see different pieces of the mesh (component borders) or the background.
2. Regions: connected pixels between edges. Planar regions (coherent normals, big enough) are
   *facets*, each with a plane.
3. Facets meeting across an edge band are neighbours. Neighbours at a convex corner (each lies
   behind the other's plane) and without an occlusion gap belong to one rigid body (a door's
   front and its edge strips; the carcass's sides and top). Parallel neighbours (a groove
   between two coplanar fronts, or a step) are kept apart.
4. A body thicker than ``panel_max_thickness`` along its main facet's normal is carcass; a thin
   body whose main facet is big enough is a *panel* (door, drawer or lid front).
5. Inside each panel (and the carcass's front facets) the pixels standing proud of the facet's
   plane by ``protrusion_min`` are *protrusions*: handles on panels, knobs on the carcass.

All 3D quantities are canonical (+z up, -y front), metres.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from scipy import ndimage
from scipy.cluster.hierarchy import DisjointSet

from rest2art.config import SegmentConfig
from rest2art.parts.grips import alike, apart, meeting_pair
from rest2art.render.raster import ViewMaps
from rest2art.tolerances import TINY

FRONT = np.array([0.0, -1.0, 0.0])
UP = np.array([0.0, 0.0, 1.0])


@dataclass
class Protrusion:
    """A handle or knob standing proud of a surface, as seen in one view."""

    mask: np.ndarray
    """(H, W) bool."""
    centre: np.ndarray
    """(3,) centre of its 3D points."""
    extents: np.ndarray
    """(3,) axis-aligned extents of its 3D points, m."""
    height: float
    """How far it stands proud of its surface, m."""
    normal: np.ndarray | None = None
    """(3,) normal of the surface it stands on (unknown: None)."""
    foot: np.ndarray | None = None
    """(H, W) bool: ``mask`` and its foot, the pixels around it standing less than
    ``protrusion_min`` but at least ``protrusion_foot`` proud (None: not looked for). What a
    part of its own is seen with; ``mask`` is what its shape is measured on."""

    @property
    def footprint(self) -> np.ndarray:
        """(2,) extents in its surface's plane, m (how far it stands out is not its size); with
        the surface unknown, the two largest extents."""
        if self.normal is None:
            return np.sort(self.extents)[1:]
        return np.delete(self.extents, int(np.argmax(np.abs(self.normal))))

    def round(self, min_ratio: float) -> bool:
        """Footprint about as wide as high (a knob: the smaller side at least ``min_ratio`` of
        the larger) rather than a bar."""
        e = np.sort(self.footprint)
        return bool(e[0] >= min_ratio * e[1])


@dataclass
class Panel:
    """A thin rigid body of facets that is not the carcass: a door, drawer or lid front."""

    mask: np.ndarray
    """(H, W) bool, holes filled (its handles included)."""
    normal: np.ndarray
    """(3,) outward normal of its main facet, snapped to the nearest canonical axis."""
    lo: np.ndarray
    hi: np.ndarray
    """(3,) bounds of its 3D points (handles excluded)."""
    area: float
    """3D area of its facets, m^2."""
    handles: list[Protrusion] = field(default_factory=list)
    recesses: list[Protrusion] = field(default_factory=list)
    """Pockets sunk into its face (recessed handles); ``height`` is their depth, m."""

    @property
    def size(self) -> tuple[float, float]:
        """(width, height) in its plane: x and z for a front, x and y for a lid."""
        e = self.hi - self.lo
        return (float(e[0]), float(e[1] if abs(self.normal[2]) > 0.5 else e[2]))


@dataclass
class ViewAnalysis:
    """Everything the offline roles need from one view."""

    panels: list[Panel]
    knobs: list[Protrusion]
    """Round protrusions on the carcass's front or top."""
    regions: np.ndarray
    """(H, W) int32 region id per pixel (0 = edge or background), for debug pictures."""


def _neighbours(axis: int, step: int) -> tuple[tuple[slice, slice], tuple[slice, slice]]:
    """Index pair selecting every pixel and the one ``step`` pixels further along ``axis``."""
    a, b = [slice(None), slice(None)], [slice(None), slice(None)]
    a[axis], b[axis] = slice(None, -step), slice(step, None)
    return tuple(a), tuple(b)


def edge_map(view: ViewMaps, face_piece: np.ndarray | None, config: SegmentConfig,
             seams: np.ndarray | None = None) -> np.ndarray:
    """(H, W) bool: pixels on a normal, occlusion, piece or background discontinuity, or on a
    seam (``seams``, computed by ``seam_map`` when not given).

    Normals are compared ``edge_stride`` pixels apart on either side of a pixel (a seam on a
    scan is a smooth groove a few pixels wide, not a one-pixel jump)."""
    fg = view.mask
    n, p = view.normals, view.points
    footprint = np.where(fg, view.camera.pixel_size(np.where(fg, view.depth, 0.0)), 0.0)
    cos_edge = np.cos(np.radians(config.normal_edge_deg))
    s = config.edge_stride
    edge = ~fg.copy()
    for axis in (0, 1):
        for step in (1, s):
            a, b = _neighbours(axis, step)
            both = fg[a] & fg[b]
            cut = ~both if step == 1 else np.zeros_like(both)
            cut |= both & (np.einsum("ijk,ijk->ij", n[a], n[b]) < cos_edge)
            if step == 1:
                gap = np.linalg.norm(p[a] - p[b], axis=2)
                cut |= both & (gap > config.depth_edge_px * np.maximum(footprint[a], footprint[b]))
                edge[a] |= cut
                edge[b] |= cut
            else:  # mark the pixel in the middle of the stencil
                mid = [slice(None), slice(None)]
                mid[axis] = slice(step // 2, step // 2 + cut.shape[axis])
                edge[tuple(mid)] |= cut
    edge |= seam_map(view, config) if seams is None else seams
    if face_piece is not None:
        edge |= piece_borders(view, face_piece)
    if config.edge_close_px > 0:  # bridge the breaks of a dashed groove
        size = 2 * config.edge_close_px + 1
        kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size))
        edge = cv2.morphologyEx(edge.astype(np.uint8), cv2.MORPH_CLOSE, kernel).astype(bool)
    return edge | ~fg


def piece_borders(view: ViewMaps, face_piece: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels beside a neighbour showing another piece (``face_piece``: (F,) piece
    of every face): where a mesh made of pieces parts, however thin the part."""
    fg = view.mask
    piece = face_piece[np.maximum(view.face, 0)]
    out = np.zeros(fg.shape, bool)
    for axis in (0, 1):
        a, b = _neighbours(axis, 1)
        cut = fg[a] & fg[b] & (piece[a] != piece[b])
        out[a] |= cut
        out[b] |= cut
    return out


def seam_map(view: ViewMaps, config: SegmentConfig, grooves_only: bool = False) -> np.ndarray:
    """(H, W) bool: grooves and ridges, pixels lying deeper or nearer than the mean of their
    neighbours ``edge_stride`` pixels away on both sides by ``groove_depth`` (a seam between
    coplanar fronts bends the normals too little on a scan). ``grooves_only``: the deeper ones
    alone (a parting line, not a rounded convex corner)."""
    fg, s = view.mask, config.edge_stride
    depth = np.where(fg, view.depth, 0.0)
    out = np.zeros(fg.shape, bool)
    for axis in (0, 1):
        before = np.roll(depth, s, axis=axis)
        after = np.roll(depth, -s, axis=axis)
        ok = fg & np.roll(fg, s, axis=axis) & np.roll(fg, -s, axis=axis)
        bend = depth - (before + after) / 2
        out |= ok & ((bend if grooves_only else np.abs(bend)) > config.groove_depth)
    return out


def _parting_seams_down(body: np.ndarray, fg: np.ndarray, seams: np.ndarray, behind: np.ndarray,
                        reach: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, ...]:
    """Down each image column from the lower boundary of ``body`` (H, W): the first ``seams``
    pixel lying ``lo`` to ``hi`` ``behind`` the body's face (H, W, m) within ``reach`` (W,
    pixels) with more surface after it. Returns (columns, first row below the body, offset of
    that seam from it or -1, how far behind the surface seen unbroken from there reaches (m;
    -inf when none)), one entry per column the body covers."""
    rows = np.arange(body.shape[0])[:, None]
    columns = np.flatnonzero(body.any(axis=0))
    first = np.where(body, rows, -1).max(axis=0)[columns] + 1
    offsets = np.full(len(columns), -1)
    deepest = np.full(len(columns), -np.inf)
    for i, (x, y0) in enumerate(zip(columns, first)):
        r = int(reach[x])
        inside = fg[y0:y0 + r, x]
        run = int(np.argmin(inside)) if not inside.all() else len(inside)
        if run:
            deepest[i] = float(behind[y0:y0 + run, x].max())
        candidates = np.flatnonzero(seams[y0:y0 + r, x] & inside & (behind[y0:y0 + r, x] >= lo)
                                    & (behind[y0:y0 + r, x] <= hi))
        for k in candidates:
            after = np.flatnonzero(~seams[y0 + k:y0 + r, x] & inside[k:])
            if len(after) and inside[k:k + after[0] + 2].all() and after[0] + 2 <= len(inside) - k:
                offsets[i] = k
                break
    return columns, first, offsets, deepest


def lid_strip_below(view: ViewMaps, body: np.ndarray, seams: np.ndarray, config: SegmentConfig) -> np.ndarray | None:
    """The front edge strip of a lid under an up-facing ``body`` (H, W) seen alone, or None.

    A top seen alone is a lid when, down each image column from its lower boundary, a seam
    (``seams``: a groove or a ridge, the lid's parting line on a scan, or the border between two
    pieces) lies between ``lid_min_thickness`` and ``lid_max_thickness`` below the top and more
    surface follows it;
    a plain box top meets its side at a corner only, and a flat object's bottom edge is
    followed by background. It must hold in at least ``lid_seam_share`` of the columns.
    Returns the strip pixels (from the top down to the parting line)."""
    fg = view.mask
    if body.any(axis=0).sum() < 10:
        return None
    height = view.points @ UP
    top = float(np.median(height[body]))
    bottom = np.minimum(np.where(body, np.arange(body.shape[0])[:, None], -1).max(axis=0), body.shape[0] - 1)
    pixel = view.camera.pixel_size(view.depth[bottom, np.arange(body.shape[1])])
    reach = 2 * np.floor(config.lid_max_thickness / pixel) + 2
    columns, first, offsets, _ = _parting_seams_down(body, fg, seams, top - height, reach.astype(int),
                                                     config.lid_min_thickness, config.lid_max_thickness)
    strip = np.zeros_like(body)
    for x, y0, k in zip(columns, first, offsets):
        strip[y0:y0 + k, x] = k >= 0
    found = int((offsets >= 0).sum())
    return strip & fg if found >= config.lid_seam_share * len(columns) else None


def parting_line_share(view: ViewMaps, body: np.ndarray, normal: np.ndarray, plane: float,
                       grooves: np.ndarray, config: SegmentConfig) -> float:
    """Share of the lines leaving a front ``body`` (H, W) sideways across a side face seen unbroken
    to ``panel_max_thickness`` behind its face (at ``plane`` along ``normal``) that cross a
    groove (``grooves`` (H, W): ``seam_map``'s deeper pixels) ``lid_min_thickness`` or more
    behind it: the parting line a door or drawer covering a whole front leaves on the carcass's
    sides. A box's front meets its sides at a corner (a ridge, however rounded), not a groove.
    NaN when no side is seen that deep."""
    fg = view.mask
    behind = plane - view.points @ normal
    pixel = view.camera.pixel_size(np.where(fg, view.depth, np.inf))
    reach = 2 * config.panel_max_thickness / np.where(fg, pixel, np.inf) + 2
    seen = found = 0
    # turn each direction (left, right) into "down the columns"; not up, where a lid's own
    # parting line runs across the front
    for turn in (lambda a: a.T[::-1], lambda a: a.T):
        b, f = turn(body), turn(fg)
        r = np.nan_to_num(np.max(np.where(b, turn(reach), 0), axis=0), posinf=0).astype(int)
        _, _, offsets, deepest = _parting_seams_down(b, f, turn(grooves), turn(behind), r,
                                                     config.lid_min_thickness, config.panel_max_thickness)
        seen_deep = deepest >= config.panel_max_thickness  # a side seen as deep as a parting line can lie
        seen += int(seen_deep.sum())
        found += int((seen_deep & (offsets >= 0)).sum())
    return found / seen if seen else float("nan")


def snap_to_axis(normal: np.ndarray) -> np.ndarray:
    """The signed coordinate axis nearest to a (3,) direction."""
    k = int(np.argmax(np.abs(normal)))
    out = np.zeros(3)
    out[k] = np.sign(normal[k])
    return out


def _sloped(normal: np.ndarray, config: SegmentConfig) -> bool:
    """Whether a (3,) facet normal (any length) tilts ``sloped_min_deg`` or more off every axis."""
    return bool(normal @ snap_to_axis(normal) < np.cos(np.radians(config.sloped_min_deg)) * np.linalg.norm(normal))


def _front_or_up(axis: np.ndarray) -> bool:
    return bool(axis @ FRONT > 0.5 or axis @ UP > 0.5)


def fused_surface(face_piece: np.ndarray | None, config: SegmentConfig) -> bool:
    """Whether a mesh whose faces belong to the pieces ``face_piece`` (F,) is one fused surface
    (a scan): no pieces, or its largest holds ``fused_piece_share`` of its faces or more."""
    return face_piece is None or np.bincount(face_piece).max() >= config.fused_piece_share * len(face_piece)


def analyse_view(view: ViewMaps, face_piece: np.ndarray | None = None,
                 config: SegmentConfig = SegmentConfig()) -> ViewAnalysis:
    """Panels (with their handles) and carcass knobs in one view."""
    fg = view.mask
    seams = seam_map(view, config)
    edge = edge_map(view, face_piece, config, seams)
    several_pieces = face_piece is not None and len(np.unique(face_piece[view.face[fg]])) > 1
    # a scan's islands (a cap its unseen underside cut off) leave the rest one fused surface
    shell = int(np.argmax(np.bincount(face_piece))) if several_pieces and fused_surface(face_piece, config) else None
    # a lid's parting line: a seam on a fused surface, the border between two pieces on a mesh
    # made of pieces (a closed laptop's lid is too thin for its edge strip to be a facet of its own)
    parting = piece_borders(view, face_piece) if several_pieces else seams
    pixel_piece = face_piece[np.maximum(view.face, 0)] if several_pieces else None  # where feet may grow
    count, labels = cv2.connectedComponents((~edge).astype(np.uint8), connectivity=4)
    labels = labels.astype(np.int32)
    px = np.where(fg, view.camera.pixel_size(np.where(fg, view.depth, 0.0)), 0.0)
    ray = view.points - view.camera.eye
    ray /= np.maximum(np.linalg.norm(ray, axis=2, keepdims=True), TINY)
    cos_view = np.clip(np.abs(np.einsum("ijk,ijk->ij", ray, view.normals)), config.min_view_cos, 1.0)
    pixel_area = (px ** 2 / cos_view).ravel()
    stats = _region_stats(view, labels, count, pixel_area, config)
    if len(stats[0]) > 1:  # a knob as large as the strip it stands on cuts the strip's face in pieces
        piece = face_piece[np.maximum(view.face, 0)] if face_piece is not None else None
        joined = _join_across_fittings(view, labels, stats, piece, config)
        if (joined != labels).any():
            labels = joined
            stats = _region_stats(view, labels, count, pixel_area, config)
    facet_ids, area, normal, centroid = stats
    if not len(facet_ids):
        return ViewAnalysis([], [], labels)
    is_facet = np.zeros(count, bool)
    is_facet[facet_ids] = True

    # neighbours across edge bands: grow facets into the band, pairs meet where grown labels touch
    facet_map = np.where(is_facet[labels], labels, 0)
    distance, (iy, ix) = ndimage.distance_transform_edt(facet_map == 0, return_indices=True)
    grown = np.where(fg & (distance <= config.adjacency_band_px), facet_map[iy, ix], 0)
    joined = DisjointSet(int(f) for f in facet_ids)
    cos_parallel = np.cos(np.radians(config.parallel_deg))
    # a groove between two facets is a parting line (a door sunk in its carcass's frame), not
    # the fold of one body, however near and convex the two faces are
    grooves = seam_map(view, config, grooves_only=True)
    near_groove = grow_mask(grooves, 1)
    for axis in (0, 1):
        a, b = _neighbours(axis, 1)
        ga, gb = grown[a], grown[b]
        touch = (ga > 0) & (gb > 0) & (ga != gb)
        if not touch.any():
            continue
        la, lb = ga[touch], gb[touch]
        # the facet pixels nearest to each side of the meeting point: their 3D gap
        ya, xa = iy[a][touch], ix[a][touch]
        yb, xb = iy[b][touch], ix[b][touch]
        # a groove on the way from one to the other
        grooved = np.zeros(len(ya), bool)
        for t in np.linspace(0.0, 1.0, 2 * config.adjacency_band_px + 1)[1:-1]:
            grooved |= near_groove[np.round(ya + t * (yb - ya)).astype(int), np.round(xa + t * (xb - xa)).astype(int)]
        gap = np.linalg.norm(view.points[ya, xa] - view.points[yb, xb], axis=1)
        key = np.minimum(la, lb).astype(np.int64) * (count + 1) + np.maximum(la, lb)
        for k in np.unique(key):
            i, j = int(k // (count + 1)), int(k % (count + 1))
            if normal[i] @ normal[j] >= cos_parallel:
                continue  # a seam or a step: different parts
            if np.median(gap[key == k]) > config.occlusion_gap:
                continue  # one occludes the other
            if np.mean(grooved[key == k]) >= config.fold_groove_share:
                continue  # parted by a groove along their meeting edge
            convex = (centroid[j] - centroid[i]) @ normal[i] < 0 and (centroid[i] - centroid[j]) @ normal[j] < 0
            if convex:
                joined.merge(i, j)

    bodies: dict[int, list[int]] = {}
    for f in facet_ids:
        bodies.setdefault(joined[int(f)], []).append(int(f))
    panels, alone_tops, carcass_fronts = [], [], []
    outline = np.percentile(view.points[fg], [config.outline_percentile, 100 - config.outline_percentile], axis=0)
    mains = {key: max(members, key=lambda f: area[f]) for key, members in bodies.items()}
    sloped = [f for key, members in bodies.items() if _sloped(normal[mains[key]], config) for f in members]
    knobs, control_panels = [], set()
    for group, found in _sloped_knobs(view, labels, sloped, normal, fg, config, pixel_piece):
        knobs += found
        if found:
            control_panels.update(group)
    for key, members in bodies.items():
        main = mains[key]
        n = snap_to_axis(normal[main])
        if main in control_panels:
            continue  # a sloped face with knobs on it is a control panel (a stove's backsplash)
        body = np.isin(labels, members)
        along = view.points[body] @ n
        thickness = float(np.percentile(along, 98) - np.percentile(along, 2))
        if thickness > config.panel_max_thickness or not _front_or_up(n):
            carcass_fronts.extend(f for f in members if _front_or_up(snap_to_axis(normal[f])))
            continue
        alone = n @ UP > 0.5 and thickness < config.lid_min_thickness
        if alone:
            # a top seen alone is a lid only with its parting line under its front edge
            strip = lid_strip_below(view, body, parting, config)
            if strip is None:
                continue
            body = body | strip
        filled = _convex_fill(body) & fg  # a panel is a box: its picture is convex
        plane = float(np.median(view.points[labels == main] @ n))
        on_shell = not several_pieces or (shell is not None and np.mean(face_piece[view.face[body]] == shell) >= 0.5)
        if on_shell and n @ FRONT > 0.5 and _covers_the_front(view.points[body], outline, config) \
                and not parting_line_share(view, body, n, plane, grooves, config) >= config.lid_seam_share:
            # a front as large as the object's, on one fused surface with its sides, and no
            # parting line on them: the box's face
            carcass_fronts.extend(members)
            continue
        proud = _proud(view, filled, n, plane, config)
        pts = view.points[body & ~proud]
        # the panel reaches into the edge band around it (half of a groove is its own)
        around = grow_mask(filled, config.mask_grow_px)
        panel = Panel(filled | (around & edge & fg), n, pts.min(axis=0), pts.max(axis=0), float(area[members].sum()))
        if config.frame_rings:
            fittings = grow_mask(proud, config.mask_grow_px)
            ring = frame_ring(view, panel.mask, n, plane, panel.lo, panel.hi, fittings, config)
            if ring is not None:  # a framed front's sunk field: the front is the field and its frame
                panel.mask, panel.lo, panel.hi = ring
        if min(panel.size) < config.min_panel_size:
            # a drawer a few centimetres high loses half its height to the edge bands along its
            # seams: with a handle or a pocket on it, its size is checked with its share of the
            # bands (its outline stays its faces')
            reach = view.points[panel.mask & fg & ~proud]
            if min(Panel(panel.mask, n, reach.min(axis=0), reach.max(axis=0), 0.0).size) < config.min_panel_size:
                continue
            if not (_protrusions(view, proud, n, plane, config) or _recesses(view, filled, n, plane, panel.size, config)):
                continue
        beside = _handles_beside(view, panel.mask, n, plane, panel.size, config)
        panel.handles = _protrusions(view, proud | beside, n, plane, config)
        panel.recesses = _recesses(view, filled, n, plane, panel.size, config)
        if not alone and n @ FRONT > 0.5 and (
                _alike(panel.handles, config.fused_handle_alike_ratio, config.knob_min_roundness)
                or _meeting_knobs(view, filled, n, panel.handles, config)):
            # alike bar handles in a row or a column on one front, or a pair of doors' knobs by its
            # middle: that many doors or drawers, the seams between them closed (a scan fuses
            # fronts a few millimetres apart)
            fronts = _fused_fronts(view, filled, proud, n, panel.handles, pixel_area.reshape(fg.shape), config)
            if len(fronts) > 1:
                panels += fronts
                continue
        (alone_tops if alone else panels).append(panel)
    for f in carcass_fronts:
        n = snap_to_axis(normal[f])
        region = labels == f
        plane = float(np.median(view.points[region] @ n))
        filled = _convex_fill(region) & fg
        proud = _proud(view, filled, n, plane, config)
        bars, round_ = [], []
        for p in _protrusions(view, proud, n, plane, config, feet=True, piece=pixel_piece):
            if _is_knob(p, config):
                round_.append(p)
            elif n @ FRONT > 0.5 and _handle_on(p, labels, f, view, filled, n, config) \
                    and not _held_by(p, alone_tops, view.points, config.tab_contact):
                bars.append(p)  # a tab on a lid's front edge, over the front, is the lid's
        if not bars and n @ FRONT > 0.5 and _meeting_knobs(view, filled, n, round_, config):
            bars, round_ = round_, []  # a pair of doors' knobs by their meeting edge: pulls
        knobs += round_
        if bars:
            fronts = _fused_fronts(view, filled, proud, n, bars, pixel_area.reshape(fg.shape), config)
            covered = np.any([front.mask for front in fronts], axis=0) if fronts else np.zeros_like(fg)
            # a panel inside a fused front is part of it (a microwave door's window)
            panels = [p for p in panels if covered[p.mask].mean() < config.fused_inner_share] + fronts
    if config.frame_rings:
        panels = _without_framed_fields(panels, config)
    if not panels:
        # a top over a front with doors or drawers (cut out of the carcass's front by their
        # handles, too) is a worktop overhanging them, whose edge and shadow line look like a
        # lid's parting line; a lid seen with its strips is found
        panels += alone_tops
    return ViewAnalysis(panels, knobs, labels)


def _without_framed_fields(panels: list[Panel], config: SegmentConfig) -> list[Panel]:
    """``panels`` less the sunk fields of framed fronts whose frame is a panel of its own.

    A frame a few centimetres wide is a facet in its own right, bounded by its parting lines;
    its panel's mask is its outline filled, the field within it. The field is one more panel
    when ``frame_ring`` cannot follow its band to a parting line (a door standing proud of its
    carcass, whose band falls away past its edge). A panel is such a field when another
    panel's mask holds ``fused_inner_share`` of it, its face lies ``ring_step`` behind that
    panel's, and the band between their outlines (bounds) is as wide on every side within
    ``ring_width_ratio`` and under ``ring_max_share`` of the field's smaller side."""
    low, high = config.ring_step
    fields = set()
    for f, field_ in enumerate(panels):
        n = field_.normal
        a = int(np.argmax(np.abs(n)))
        inplane = [k for k in range(3) if k != a]
        smaller = min(float(field_.hi[k] - field_.lo[k]) for k in inplane)
        for j, frame in enumerate(panels):
            if j == f or j in fields or not np.allclose(frame.normal, n) \
                    or frame.mask[field_.mask].mean() < config.fused_inner_share:
                continue
            sunk = float((frame.lo + frame.hi) @ n - (field_.lo + field_.hi) @ n) / 2
            bands = np.array([[field_.lo[k] - frame.lo[k], frame.hi[k] - field_.hi[k]] for k in inplane]).ravel()
            if low <= sunk <= high and bands.min() > 0 and _even_bands(bands, smaller, config):
                fields.add(f)
                break
    return [p for k, p in enumerate(panels) if k not in fields]


def _region_stats(view: ViewMaps, labels: np.ndarray, count: int, pixel_area: np.ndarray,
                  config: SegmentConfig) -> tuple[np.ndarray, ...]:
    """Per region of ``labels`` (``count`` ids; ``pixel_area`` the (H*W,) 3D area of each
    pixel, m^2): (facet ids, 3D areas, mean unit normals (count, 3), centroids (count, 3)). A
    facet is a region of at least 30 pixels whose normals agree (``facet_coherence``) and whose
    area could hold half a panel either way."""
    flat = labels.ravel()
    pixels = np.bincount(flat, minlength=count).astype(float)
    area = np.bincount(flat, pixel_area, minlength=count)
    nsum = np.stack([np.bincount(flat, view.normals[..., k].ravel(), minlength=count) for k in range(3)], 1)
    psum = np.stack([np.bincount(flat, view.points[..., k].ravel(), minlength=count) for k in range(3)], 1)
    safe = np.maximum(pixels, 1)[:, None]
    coherence = np.linalg.norm(nsum, axis=1) / safe[:, 0]
    normal = nsum / np.maximum(np.linalg.norm(nsum, axis=1, keepdims=True), TINY)
    min_area = (0.5 * config.min_panel_size) ** 2
    facet_ids = np.flatnonzero((np.arange(count) > 0) & (pixels >= 30) & (coherence >= config.facet_coherence)
                               & (area >= min_area))
    return facet_ids, area, normal, psum / safe


def _join_across_fittings(view: ViewMaps, labels: np.ndarray, stats: tuple[np.ndarray, ...],
                          piece: np.ndarray | None, config: SegmentConfig) -> np.ndarray:
    """``labels`` with coplanar facets that only a fitting stands between made one region.

    Two parallel facets (``parallel_deg``) whose planes agree within ``coplanar_tol`` are one
    surface cut in two by something standing in front of it when what their joint picture
    adds to their own (the convex hulls') is foreground, at least ``bridge_front_share`` of it
    stands ``protrusion_min`` proud of their plane, all but ``bridge_stray_share`` of the rest
    lies within ``adjacency_band_px`` of that (its outline's edge band; the stray rest is the
    slivers the two hulls leave along the surface's own edges), and the proud part is a fitting
    (``_fitting_between``). A groove or a gap between two flush fronts is on or
    behind their plane and runs past the handles on them: they stay apart. With ``frame_rings``,
    two facets up to ``ring_split_max_gap`` apart are also one when they are a framed front's
    field that a pull as tall as it cuts in two (``_field_across_pull``). On a mesh made of
    pieces (``piece``, (H, W) piece id per pixel) facets of different pieces stay apart too."""
    facet_ids, _, normal, _ = stats
    ids = [int(f) for f in facet_ids]
    slices = ndimage.find_objects(labels)  # the box of region k at k - 1
    boxes, facet_points, owner = {}, {}, {}
    for f in ids:
        rows, cols = slices[f - 1]
        ys, xs = np.nonzero(labels[rows, cols] == f)
        ys, xs = ys + rows.start, xs + cols.start
        boxes[f] = (rows.start, rows.stop - 1, cols.start, cols.stop - 1)
        facet_points[f] = view.points[ys, xs]
        if piece is not None:
            owner[f] = int(np.bincount(piece[ys, xs]).argmax())
    cos_parallel = np.cos(np.radians(config.parallel_deg))
    px = float(np.median(view.camera.pixel_size(view.depth[view.mask])))
    reach = int(np.ceil(config.knob_max_size / max(px, TINY)))
    split_reach = int(np.ceil(config.ring_split_max_gap / max(px, TINY))) if config.frame_rings else 0
    joined = DisjointSet(ids)
    for a_i, i in enumerate(ids):
        for j in ids[a_i + 1:]:
            bi, bj = boxes[i], boxes[j]
            apart = max(bi[0] - bj[1], bj[0] - bi[1], bi[2] - bj[3], bj[2] - bi[3])  # px between their boxes
            if apart > max(reach, split_reach):
                continue
            n = normal[i]
            if n @ normal[j] < cos_parallel or (piece is not None and owner[i] != owner[j]):
                continue
            plane_i, plane_j = (float(np.median(facet_points[f] @ n)) for f in (i, j))
            if abs(plane_i - plane_j) > config.coplanar_tol:
                continue
            # both hulls lie in the box around the two facets: work on that crop
            crop = (slice(min(bi[0], bj[0]), max(bi[1], bj[1]) + 1), slice(min(bi[2], bj[2]), max(bi[3], bj[3]) + 1))
            mask_i, mask_j = labels[crop] == i, labels[crop] == j
            extra = _convex_fill(mask_i | mask_j) & ~_convex_fill(mask_i) & ~_convex_fill(mask_j)
            if not extra.any() or (extra & ~view.mask[crop]).any():
                continue
            points = view.points[crop]
            height = points[extra] @ n - (plane_i + plane_j) / 2
            front = np.zeros_like(extra)
            front[extra] = height >= config.protrusion_min
            fitting = apart <= reach and front.sum() >= config.bridge_front_share * extra.sum() \
                and (extra & ~grow_mask(front, config.adjacency_band_px)).sum() <= config.bridge_stray_share * extra.sum() \
                and _fitting_between(points[front], facet_points[i], facet_points[j], n, config)
            if fitting or (config.frame_rings and apart <= split_reach and _field_across_pull(
                    view, crop, mask_i | mask_j, extra, height, n, facet_points[i], facet_points[j], config)):
                joined.merge(i, j)
    root = np.arange(labels.max() + 1, dtype=labels.dtype)
    root[ids] = [joined[f] for f in ids]
    return root[labels]


def _field_across_pull(view: ViewMaps, crop: tuple[slice, slice], halves: np.ndarray, between: np.ndarray,
                       height: np.ndarray, normal: np.ndarray, a: np.ndarray, b: np.ndarray,
                       config: SegmentConfig) -> bool:
    """Whether two coplanar facets (``halves``: (h, w) bool in the view's ``crop``; their points
    ``a``, ``b`` (M, 3)) are one framed front's field that a pull as tall as the field (or a
    pocket) cuts in two. What lies between them (``between``, (h, w) bool; ``height``, m above
    their plane along ``normal``, per pixel of it) is the field and the pull, nowhere a frame's
    band (all but ``bridge_stray_share`` of it outside ``ring_step``: two framed fronts side by
    side have their frames between them), and the two together, the pull left out, are a field
    with a frame all round (``frame_ring``): two flush fronts with a pull on each by the groove
    between them have no frame round them."""
    if np.mean((height >= config.ring_step[0]) & (height <= config.ring_step[1])) > config.bridge_stray_share:
        return False
    mask, pull = np.zeros_like(view.mask), np.zeros_like(view.mask)
    mask[crop] = _convex_fill(halves)
    pull[crop][between] = height >= config.protrusion_min
    points = np.concatenate([a, b])
    n = snap_to_axis(normal)
    return frame_ring(view, mask, n, float(np.median(points @ n)), points.min(axis=0), points.max(axis=0),
                      grow_mask(pull, config.mask_grow_px), config) is not None


def _fitting_between(proud: np.ndarray, a: np.ndarray, b: np.ndarray, normal: np.ndarray,
                     config: SegmentConfig) -> bool:
    """Whether what stands ``proud`` (N, 3) between two coplanar facets' points ``a`` and ``b``
    (M, 3), facing ``normal``, is a fitting on the one surface they are: at most a knob across
    (``knob_max_size``: a knob as tall as the strip it stands on), or, larger (a cup pull), short
    of the facets' span across the line from one to the other (``bridge_max_cross_share``): the
    surface runs past it there. A drawer standing proud between two boards of an apron spans
    them across."""
    in_plane = [k for k in range(3) if k != int(np.argmax(np.abs(normal)))]
    extent = np.ptp(proud[:, in_plane], axis=0)
    if extent.max() <= config.knob_max_size:
        return True
    across = in_plane[int(np.argmin(np.abs(a.mean(axis=0) - b.mean(axis=0))[in_plane]))]
    span = min(float(np.ptp(a[:, across])), float(np.ptp(b[:, across])))
    return float(np.ptp(proud[:, across])) <= config.bridge_max_cross_share * span


def _covers_the_front(points: np.ndarray, outline: np.ndarray, config: SegmentConfig) -> bool:
    """Whether a front's (N, 3) points reach within ``full_face_margin`` of the object's (2, 3)
    bounds ``outline`` on every side in x and z (a rounded or bevelled rim is left out)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    near = np.r_[lo - outline[0], outline[1] - hi][[0, 2, 3, 5]]
    return bool((near <= config.full_face_margin).all())


def _held_by(bar: Protrusion, panels: list[Panel], points: np.ndarray, contact: float) -> bool:
    """Whether ``bar`` hangs on one of ``panels``: a panel larger than the bar's footprint both
    ways (not the bar's own upper face) some of whose 3D points (``points``, the view's (H, W,
    3)) lie within ``contact`` (m) of the bar's. A handle on that panel's edge, not on the
    surface below it."""
    from scipy.spatial import cKDTree

    own = points[bar.mask]
    holders = [p for p in panels if p.mask.any() and min(p.size) > bar.footprint.max()]
    return bool(len(own)) and any(
        np.isfinite(cKDTree(points[p.mask]).query(own, distance_upper_bound=contact)[0]).any() for p in holders)


def _handle_on(bar: Protrusion, labels: np.ndarray, facet: int, view: ViewMaps, filled: np.ndarray,
               normal: np.ndarray, config: SegmentConfig) -> bool:
    """Whether a protrusion of carcass facet ``facet`` (of the region ``labels``) is a handle on
    it: a bar at least ``fused_handle_min_length`` long and at most ``fused_handle_max_share`` of
    the facet along it, standing at most ``fused_handle_max_proud`` out, with the regions seen
    around it (past the edge band of its outline) mostly this facet, not a door it frames."""
    in_plane = np.delete(bar.extents, int(np.argmax(np.abs(normal))))
    pts = view.points[filled & view.mask]
    facet_extents = np.delete(pts.max(axis=0) - pts.min(axis=0), int(np.argmax(np.abs(normal))))
    k = int(np.argmax(in_plane))
    if in_plane[k] < config.fused_handle_min_length or in_plane[k] > config.fused_handle_max_share * facet_extents[k]:
        return False
    if bar.height > config.fused_handle_max_proud:
        return False
    ring = grow_mask(bar.mask, config.adjacency_band_px) & ~bar.mask & view.mask & (labels > 0)
    return bool(ring.any() and (labels[ring] == facet).mean() >= config.fused_handle_surround)


def _fused_fronts(view: ViewMaps, filled: np.ndarray, proud: np.ndarray, normal: np.ndarray,
                  bars: list[Protrusion], pixel_area: np.ndarray, config: SegmentConfig) -> list[Panel]:
    """Panels for a carcass facet that carries handles: on a fused scan a door or drawer whose
    edges are flush with the carcass merges with it, and the handle is what is left to tell it.
    Handles side by side at one height split the facet halfway between them into doors;
    handles one above the other split it into drawers; otherwise the facet is one panel."""
    (across, up), span, _, centres, sizes = _on_front(view, filled, normal, bars)
    spread = np.ptp(centres, axis=0) / np.maximum(span, 1e-9)

    tol = config.fused_handle_row_tol
    if spread[1] <= tol and apart(centres, sizes, 0):
        key, direction = 0, across  # side by side: doors
    elif spread[0] <= tol and apart(centres, sizes, 1):
        key, direction = 1, up  # one above the other: drawers
    else:
        key, direction = None, None
    if key is None:
        spans = [(filled, bars)]
    else:  # each handle's panel reaches halfway to its neighbours'
        order = np.argsort(centres[:, key])
        cuts = [-np.inf, *((centres[order[:-1], key] + centres[order[1:], key]) / 2), np.inf]
        coordinate = view.points @ direction
        spans = [(filled & (coordinate >= low) & (coordinate < high), [bars[i]])
                 for low, high, i in zip(cuts[:-1], cuts[1:], order)]
    out = []
    for mask, handles in spans:
        face = mask & ~proud & view.mask
        if face.sum() < 30:
            continue
        points = view.points[face]
        panel = Panel(mask, normal, points.min(axis=0), points.max(axis=0), float(pixel_area[face].sum()))
        if min(panel.size) < config.min_panel_size:
            continue
        panel.handles = handles
        out.append(panel)
    return out


def _on_front(view: ViewMaps, filled: np.ndarray, normal: np.ndarray, grips: list[Protrusion]) -> tuple:
    """A front (``filled``, facing ``normal`` (3,)) and its ``grips`` in the front's plane:
    ((across, up) unit axes (3,), (2,) its width and height, (2,) its middle, (N, 2) the grips'
    centres, (N, 2) their sizes), m."""
    up = UP if abs(normal @ UP) < 0.5 else -FRONT
    across = np.cross(up, normal)
    pts = view.points[filled & view.mask]
    along = np.column_stack([pts @ across, pts @ up])
    centres = np.array([[g.centre @ across, g.centre @ up] for g in grips])
    sizes = np.array([[abs(g.extents @ across), abs(g.extents @ up)] for g in grips])
    return (across, up), np.ptp(along, axis=0), (along.min(axis=0) + along.max(axis=0)) / 2, centres, sizes


def _alike(handles: list[Protrusion], ratio: float, round_ratio: float) -> bool:
    """Whether there are two ``handles`` or more, all bars (not ``round`` by ``round_ratio``), each
    one's footprint within ``ratio`` of every other's both ways: the pulls of a chest of drawers;
    not a handle and a lock, nor a safe's lever beside its dial."""
    return len(handles) >= 2 and not any(h.round(round_ratio) for h in handles) \
        and alike([h.footprint for h in handles], ratio)


def _meeting_knobs(view: ViewMaps, filled: np.ndarray, normal: np.ndarray, knobs: list[Protrusion],
                   config: SegmentConfig) -> bool:
    """Whether two alike round ``knobs`` (footprints within ``fused_handle_alike_ratio``) at one
    height (``fused_handle_row_tol``) on a front (``filled``, facing ``normal`` (3,)) are the
    pulls of a pair of doors meeting in its middle (``parts.grips.meeting_pair`` with
    ``fused_pair_*``): a scan closes the seam between the doors, and the knobs are what is left
    to tell them. Not a stove's row of knobs, nor a safe's lever beside its dial."""
    if len(knobs) != 2 or not all(k.round(config.knob_min_roundness) for k in knobs) \
            or not alike([k.footprint for k in knobs], config.fused_handle_alike_ratio):
        return False
    _, span, middle, centres, _ = _on_front(view, filled, normal, knobs)
    return abs(centres[0, 1] - centres[1, 1]) <= config.fused_handle_row_tol * span[1] and meeting_pair(
        centres, span, middle, config.fused_pair_max_offset, config.fused_pair_mirror_tol,
        config.fused_pair_min_height_share)


def _convex_fill(mask: np.ndarray) -> np.ndarray:
    """The convex hull of ``mask``'s pixels, filled."""
    ys, xs = np.nonzero(mask)
    hull = cv2.convexHull(np.stack([xs, ys], axis=1).astype(np.int32))
    out = np.zeros(mask.shape, np.uint8)
    cv2.fillConvexPoly(out, hull, 1)
    return out.astype(bool) | mask


def _sloped_knobs(view: ViewMaps, labels: np.ndarray, facets: list[int], normal: np.ndarray, fg: np.ndarray,
                  config: SegmentConfig, piece: np.ndarray | None = None) -> list[tuple[list[int], list[Protrusion]]]:
    """Knobs on a sloped control panel (a stove's backsplash), whose ``facets`` (ids into
    ``labels``, the knobs cut its face in pieces) tilt ``sloped_min_deg`` or more off every axis:
    facets parallel within ``parallel_deg`` form one plane, along their own ``normal`` (F, 3);
    what stands proud of it inside their joint outline, round and small, is a knob. Returns
    each plane's facets with its knobs."""
    out, left = [], list(facets)
    cos_parallel = np.cos(np.radians(config.parallel_deg))
    while left:
        n = normal[left[0]] / max(float(np.linalg.norm(normal[left[0]])), TINY)
        group = [f for f in left if normal[f] @ n >= cos_parallel * np.linalg.norm(normal[f])]
        left = [f for f in left if f not in group]
        region = np.isin(labels, group)
        plane = float(np.median(view.points[region] @ n))
        filled = _convex_fill(region) & fg
        out.append((group, [p for p in _protrusions(view, _proud(view, filled, n, plane, config), n, plane, config,
                                                    feet=True, piece=piece) if _is_knob(p, config)]))
    return out


def _is_knob(protrusion: Protrusion, config: SegmentConfig) -> bool:
    """Whether a protrusion on the carcass is a control knob: round and at most ``knob_max_size``
    across."""
    return protrusion.round(config.knob_min_roundness) and protrusion.footprint.max() <= config.knob_max_size


def frame_ring(view: ViewMaps, mask: np.ndarray, normal: np.ndarray, plane: float, lo: np.ndarray, hi: np.ndarray,
               fittings: np.ndarray, config: SegmentConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(mask, lo, hi) of the framed front around a panel's sunk field, or None when the panel
    is no field. ``mask``: (H, W) bool, the field's pixels; ``normal`` (3,), axis-snapped, and
    ``plane`` (m along it): the field's face; ``lo``/``hi`` (3,): its bounds, m; ``fittings``:
    (H, W) bool, its handles' pixels, left out of the profiles (a pull by the field's edge).

    Each side's height profile outward from the field's outline (the median height along
    ``normal`` of the view's points in bins one pixel wide, over the middle 60 % of that side)
    must rise by ``ring_step`` within ``ring_rise`` onto a band flat to ``ring_flat_tol``, and
    the band end at a parting line (``ring_outer_reach``): the frame a scan's blur and a
    view's seams leave too narrow to be a facet of its own (a drawer's, a few centimetres wide).
    The bands' widths must agree (``ring_width_ratio``) and stay under ``ring_max_share`` of the
    field's smaller side. The front's mask adds the view's pixels inside the widened bounds
    that lie no higher than the band and not behind the field."""
    fg = view.mask
    a = int(np.argmax(np.abs(normal)))
    inplane = [k for k in range(3) if k != a]
    extent = hi - lo
    smaller = float(min(extent[k] for k in inplane))
    if smaller <= 0:
        return None
    step = max(float(np.median(view.camera.pixel_size(view.depth[mask & fg]))), TINY)
    reach = config.ring_max_share * smaller + config.ring_outer_reach
    # the view's points within reach of the field, bare of its fittings (in a crop of the view
    # around the field, as far as the reach spans in pixels)
    rows, cols = np.nonzero(mask)
    if not len(rows):
        return None
    pad = int(np.ceil(2 * reach / step)) + 1
    crop = (slice(max(rows.min() - pad, 0), rows.max() + pad + 1),
            slice(max(cols.min() - pad, 0), cols.max() + pad + 1))
    near = np.zeros_like(fg)
    near[crop] = fg[crop]
    for k in inplane:
        near[crop] &= (view.points[crop][..., k] > lo[k] - reach) & (view.points[crop][..., k] < hi[k] + reach)
    points = view.points[near]
    height = points @ normal - plane
    bare = ~fittings[near]
    # the field's facet stops where the edge band along the step begins
    rise = config.ring_rise + (config.edge_stride + config.edge_close_px) * step
    edges = np.arange(-rise, reach + step, step)
    centres = (edges[:-1] + edges[1:]) / 2
    widths, heights = [], []
    for k in inplane:
        j = inplane[0] if k == inplane[1] else inplane[1]
        across = (points[:, j] > lo[j] + 0.2 * extent[j]) & (points[:, j] < hi[j] - 0.2 * extent[j])
        for sign, bound in ((-1.0, lo[k]), (1.0, hi[k])):
            out = sign * (points[:, k] - bound)  # distance outward from the field's outline
            sel = bare & across & (out > edges[0]) & (out < edges[-1])
            side = _ring_side(binned_median(out[sel], height[sel], edges), centres, rise, config)
            if side is None:
                return None
            widths.append(side[0])
            heights.append(side[1])
    widths = np.asarray(widths)
    if not _even_bands(widths, smaller, config) or np.ptp(heights) > 2 * config.ring_flat_tol:
        return None
    lo, hi = lo.copy(), hi.copy()
    for i, k in enumerate(inplane):
        lo[k] -= widths[2 * i]
        hi[k] += widths[2 * i + 1]
    inside = np.all([(points[:, k] >= lo[k]) & (points[:, k] <= hi[k]) for k in inplane], axis=0)
    inside &= (height >= -config.ring_flat_tol) & (height <= max(heights) + config.ring_flat_tol)
    front = mask.copy()
    front[near] |= inside
    return front, lo, hi


def _even_bands(widths: np.ndarray, smaller: float, config: SegmentConfig) -> bool:
    """Whether a frame's bands, ``widths`` (4,) m on the four sides of its field, agree within
    ``ring_width_ratio`` and stay under ``ring_max_share`` of the field's ``smaller`` side (m)."""
    return bool(widths.max() <= config.ring_width_ratio * widths.min() and widths.max() <= config.ring_max_share * smaller)


def binned_median(x: np.ndarray, y: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """(len(edges) - 1,) median of ``y`` (N,) over the ``x`` (N,) in each bin between ``edges``
    (ascending), NaN where a bin holds none."""
    bins = np.digitize(x, edges) - 1
    keep = (bins >= 0) & (bins < len(edges) - 1)
    bins, y = bins[keep], y[keep]
    order = np.lexsort((y, bins))
    bins, y = bins[order], y[order]
    counts = np.bincount(bins, minlength=len(edges) - 1)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    out = np.full(len(counts), np.nan)
    held = counts > 0
    out[held] = (y[starts[held] + (counts[held] - 1) // 2] + y[starts[held] + counts[held] // 2]) / 2
    return out


def _ring_side(profile: np.ndarray, out: np.ndarray, rise: float, config: SegmentConfig) -> tuple[float, float] | None:
    """(width, height) m of a frame's band in one side's height ``profile`` (per bin, NaN where
    nothing was seen) at ``out`` (m outward from the field's outline), the step up reached
    within ``rise`` (m), or None (``frame_ring``)."""
    seen = ~np.isnan(profile)
    field = seen & (out < 0)
    if not field.any() or abs(np.median(profile[field])) > config.ring_flat_tol:
        return None
    low, high = config.ring_step
    rising = np.flatnonzero(seen & (profile > low))
    if not len(rising) or out[rising[0]] > rise:
        return None
    # the band starts where the blurred step levels off
    start = next((i for i in range(rising[0], len(out) - 1)
                  if seen[i] and seen[i + 1] and abs(profile[i + 1] - profile[i]) <= config.ring_flat_tol / 2), None)
    if start is None or out[start] > rise + config.ring_rise:
        return None
    band = profile[start]
    if not low <= band <= high:
        return None
    end, missed = start, 0
    for i in range(start + 1, len(out)):
        if not seen[i]:
            missed += 1
            if missed > 1:
                return None  # the band runs into what the view does not see: not a parting line
            continue
        if abs(profile[i] - band) > config.ring_flat_tol:
            break
        end, missed = i, 0
    else:
        return None
    if end - start < 1:
        return None
    after = (np.arange(len(out)) > end) & seen & (out <= out[end] + config.ring_outer_reach)
    beyond = profile[after]
    if not len(beyond):
        return None
    if beyond[0] > band + config.ring_flat_tol:
        return float(out[end]), float(band)  # a step up onto the carcass
    if (beyond[1:] >= band - config.ring_flat_tol).any():
        return float(out[end]), float(band)  # a dent: the gap to the carcass or a neighbour
    return None


def _proud(view: ViewMaps, region: np.ndarray, normal: np.ndarray, plane: float, config: SegmentConfig) -> np.ndarray:
    """(H, W) bool: pixels of ``region`` standing at least ``protrusion_min`` above the plane."""
    height = np.where(region & view.mask, view.points @ normal - plane, 0.0)
    return region & (height >= config.protrusion_min)


def grow_mask(mask: np.ndarray, steps: int) -> np.ndarray:
    """(H, W) bool ``mask`` grown by ``steps`` pixels (8-connected)."""
    return cv2.dilate(mask.astype(np.uint8), np.ones((3, 3), np.uint8), iterations=steps).astype(bool)


def _handles_beside(view: ViewMaps, panel_mask: np.ndarray, normal: np.ndarray, plane: float,
                    size: tuple[float, float], config: SegmentConfig) -> np.ndarray:
    """(H, W) bool: blobs proud of a panel's face (``panel_mask``; ``plane`` along
    ``normal``; ``size`` its width and height, m) that start just past its outline
    (``handle_beside_px``) where the object steps back from the panel's face (what lies around
    them, past the panel, is mostly behind its plane or nothing), narrower or shorter than the
    panel: a handle mounted on its edge. A frame the panel is sunk into, a neighbour's face in
    the panel's plane and a fitting on it, or the edge of a neighbour running the panel's whole
    length are not."""
    near = grow_mask(panel_mask, config.handle_beside_px) & ~panel_mask
    proud = _proud(view, grow_mask(panel_mask, config.handle_beside_reach_px) & ~panel_mask, normal, plane, config)
    _, labels = cv2.connectedComponents(proud.astype(np.uint8), connectivity=8)
    height = view.points @ normal - plane
    out = np.zeros_like(panel_mask)
    for k in np.unique(labels[near & proud]):  # the blobs that start just past the outline
        blob = labels == k
        around = grow_mask(blob, 2) & ~blob & ~panel_mask
        if (around & (~view.mask | (height <= -config.protrusion_min))).sum() < 0.5 * around.sum():
            continue  # on a frame or a neighbour's face, not standing off the panel's edge
        e = np.ptp(view.points[blob], axis=0)  # along the axes of the panel's size
        if e[0] >= config.handle_beside_max_share * size[0] or \
                e[1 if abs(normal[2]) > 0.5 else 2] >= config.handle_beside_max_share * size[1]:
            continue  # the edge of a neighbour or of the carcass, running the panel's length
        out |= blob
    return out


def _recesses(view: ViewMaps, filled: np.ndarray, normal: np.ndarray, plane: float,
              size: tuple[float, float], config: SegmentConfig) -> list[Protrusion]:
    """Pockets sunk at least ``protrusion_min`` into a panel's face (``filled``, its (H, W)
    picture; ``plane`` its face along ``normal``; ``size`` its width and height, m), wholly
    inside its outline (past a rim ``edge_stride`` pixels wide: a panel's own rounded edge or
    edge strip reaches it) and at most ``recess_max_share`` of its footprint:
    recessed handles. A pocket's ``height`` is its depth."""
    band = np.ones((3, 3), np.uint8)
    inner = cv2.erode(filled.astype(np.uint8), band, iterations=config.edge_stride).astype(bool)
    rim = inner & ~cv2.erode(inner.astype(np.uint8), band).astype(bool)
    depth = np.where(inner & view.mask, plane - view.points @ normal, 0.0)
    sunk = inner & view.mask & (depth >= config.protrusion_min)
    out = []
    for pocket in _protrusions(view, sunk, normal, plane, config):
        if (pocket.mask & rim).any() or pocket.footprint.prod() > config.recess_max_share * size[0] * size[1]:
            continue
        pocket.height = float(depth[pocket.mask].max())
        out.append(pocket)
    return out


def _protrusions(view: ViewMaps, proud: np.ndarray, normal: np.ndarray, plane: float,
                 config: SegmentConfig, feet: bool = False, piece: np.ndarray | None = None) -> list[Protrusion]:
    """Connected blobs of proud pixels with a big enough footprint; with ``feet``, each with
    its foot (``_foot``; ``piece``: (H, W) piece id per pixel on a mesh made of pieces)."""
    count, labels = cv2.connectedComponents(proud.astype(np.uint8), connectivity=8)
    out = []
    for k in range(1, count):
        mask = labels == k
        pts = view.points[mask]
        if len(pts) < 8:
            continue
        extents = pts.max(axis=0) - pts.min(axis=0)
        footprint = np.delete(extents, int(np.argmax(np.abs(normal))))
        if footprint[0] * footprint[1] < config.protrusion_min_area:
            continue
        out.append(Protrusion(mask, (pts.min(axis=0) + pts.max(axis=0)) / 2, extents,
                              float((pts @ normal).max() - plane), np.asarray(normal, float),
                              _foot(view, mask, normal, plane, config, piece) if feet else None))
    return out


def _foot(view: ViewMaps, mask: np.ndarray, normal: np.ndarray, plane: float, config: SegmentConfig,
          piece: np.ndarray | None = None) -> np.ndarray:
    """(H, W) bool: a protrusion's ``mask`` grown over the pixels next to it that stand at
    least ``protrusion_foot`` above ``plane`` (along ``normal``) and face sideways (more than
    ``foot_side_deg`` off ``normal``), for as many pixels as ``protrusion_min`` spans in the
    view: the bottom of a knob's side, which a scan fuses into the surface it stands on,
    lower than a protrusion is found by (hysteresis: found by the high threshold, grown down
    to the low one). The surface around it faces along ``normal`` and stays out, however
    uneven; on a mesh made of pieces (``piece``, (H, W) piece id per pixel) so does every piece
    the protrusion is not made of (a button's bezel)."""
    px = float(view.camera.pixel_size(np.median(view.depth[mask])))
    steps = int(np.ceil(config.protrusion_min / max(px, TINY))) + 1
    rows, cols = np.nonzero(mask)
    crop = (slice(max(rows.min() - steps, 0), rows.max() + steps + 1),
            slice(max(cols.min() - steps, 0), cols.max() + steps + 1))
    side = np.abs(view.normals[crop] @ normal) < np.cos(np.radians(config.foot_side_deg))
    low = view.mask[crop] & side & (view.points[crop] @ normal - plane >= config.protrusion_foot)
    if piece is not None:
        low &= np.isin(piece[crop], np.unique(piece[mask]))
    grown = mask[crop]
    for _ in range(steps):
        grown = grown | (grow_mask(grown, 1) & low)
    out = np.zeros_like(mask)
    out[crop] = grown
    return out
