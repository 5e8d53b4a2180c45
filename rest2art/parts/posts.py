"""A head turning on the post it stands on (a tap's handle, a faucet's lever on its column),
found from the shape of one fused surface.

A fused scan of a tap is one surface: no piece tells its handle from its column. Its
horizontal sections do: a foot or a deck below, a column much narrower than what it carries,
and on top a head wider than the column. The head turns about the column's axis.

All coordinates are canonical (+z up), metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from rest2art.config import PartsConfig


@dataclass(frozen=True)
class PostHead:
    """A head standing on a post: the faces above the post's top (``cut``), turning about the
    vertical through ``pivot``."""

    faces: np.ndarray
    """(K,) indices of the head's faces."""
    pivot: np.ndarray
    """(3,) the post's axis at the cut, m."""
    cut: float
    """Height (m) of the post's last section below the head."""


def section_widths(mesh: trimesh.Trimesh, heights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((H,) largest horizontal extent (m; 0 where the plane meets nothing), (H, 2) centre (x, y)
    of the bounding box) of the mesh's sections by the horizontal planes at ``heights`` (H,) m."""
    lines, to_3d, _ = trimesh.intersections.mesh_multiplane(mesh, np.zeros(3), np.array([0.0, 0.0, 1.0]), heights)
    widths = np.zeros(len(heights))
    centres = np.zeros((len(heights), 2))
    for k, (segments, transform) in enumerate(zip(lines, to_3d)):
        if len(segments) == 0:
            continue
        flat = np.asarray(segments).reshape(-1, 2)
        points = trimesh.transform_points(np.column_stack([flat, np.zeros(len(flat))]), transform)[:, :2]
        lo, hi = points.min(axis=0), points.max(axis=0)
        widths[k] = float((hi - lo).max())
        centres[k] = (lo + hi) / 2
    return widths, centres


def post_head(mesh: trimesh.Trimesh, config: PartsConfig) -> PostHead | None:
    """The head on a post of one fused surface, or None. The surface is cut by ``post_levels``
    horizontal planes; the head is everything above the highest run of sections (the post)
    no wider than ``post_neck_share`` of the widest section above it (less its top sections
    wider than ``post_width_spread`` times its median: a hub under a long arm is the head's),
    the run at least ``post_min_height`` times as tall as it is wide, and the head no larger than
    ``lever_max_size`` (a hand turns it). A post reaching the top carries no head."""
    lo, hi = mesh.bounds
    height = float(hi[2] - lo[2])
    if height <= 0 or float((hi - lo).max()) > 2 * config.lever_max_size:
        return None
    step = height / config.post_levels
    heights = lo[2] + step * (np.arange(config.post_levels) + 0.5)
    widths, centres = section_widths(mesh, heights)
    head_width = np.maximum.accumulate(widths[::-1])[::-1]  # widest section at or above each level
    for top in range(len(heights) - 2, 0, -1):
        above = float(head_width[top + 1])
        if not 0 < widths[top] <= config.post_neck_share * above:
            continue
        bottom = top
        while bottom > 0 and 0 < widths[bottom - 1] <= config.post_neck_share * above:
            bottom -= 1
        post_width = float(np.median(widths[bottom:top + 1]))
        while top > bottom and widths[top] > config.post_width_spread * post_width:
            top -= 1  # the head's own narrower underside (a hub under a long arm)
        if (top - bottom + 1) * step < config.post_min_height * post_width:
            return None
        axis_xy = np.median(centres[bottom:top + 1], axis=0)
        centre = mesh.triangles_center
        # above the post's last section, what lies off the post's outline is the head (its
        # underside), within one level's spacing of where the sections tell them apart
        off_post = np.linalg.norm(centre[:, :2] - axis_xy, axis=1) > post_width / 2 + step
        is_head = (centre[:, 2] > heights[top] + step) | ((centre[:, 2] > heights[top]) & off_post)
        faces = np.flatnonzero(is_head)
        head = mesh.vertices[np.unique(mesh.faces[faces])]
        if not len(faces) or float(np.ptp(head, axis=0).max()) > config.lever_max_size:
            return None
        cut = float(heights[top])
        return PostHead(faces, np.array([*axis_xy, cut]), cut)
    return None
