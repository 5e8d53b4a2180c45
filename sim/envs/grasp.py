"""Where a floating gripper takes hold of a movable part, from the part's geometry alone.

Pure functions on arrays, in the asset's own frame (metres). The outward direction of a part is
the way it starts to move when it opens (a slide's axis, a door's or lid's swing at its centre)
or, for a part that turns in place (a knob), its own axis pointing away from the parent. Along
that direction the part's outward face is the outermost level that spans most of the part;
vertices standing proud of it form the handle. With a handle (or a knob) the fingers close
across it ("pinch"); without one, the fingertips press on the face near the edge far from the
hinge, or at the face's centre for a slide ("press").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rest2art.config import EnvConfig
from rest2art.geometry.basics import unit

CANONICAL = np.concatenate([np.eye(3), -np.eye(3)])
"""(6, 3) the asset frame's axis directions, which outward directions snap to."""
SNAP_COS = np.cos(np.radians(20.0))
"""An outward direction within 20 degrees of a frame axis is snapped onto it."""
ELONGATED = 1.5
"""A handle whose in-plane spread is this many times longer one way than the other is a bar."""


@dataclass(frozen=True)
class Grasp:
    """How to hold a part, at the joint's closed state, in the asset frame."""

    point: np.ndarray
    """(3,) where the fingertips' centre goes (m)."""
    normal: np.ndarray
    """(3,) unit outward direction: the gripper points along -normal."""
    pinch: np.ndarray
    """(3,) unit direction, normal to ``normal``, along which the fingers close."""
    mode: str
    """'pinch' (a handle or knob to close the fingers on) or 'press' (a flat face)."""
    turns_in_place: bool = False
    """True for a part turning about an axis through itself (a knob)."""

    def frame(self) -> np.ndarray:
        """(3, 3) rotation whose columns are the gripper's x, y (pinch) and z (pointing) axes."""
        z = -self.normal
        y = self.pinch
        return np.column_stack([np.cross(y, z), y, z])


def snap(direction: np.ndarray) -> np.ndarray:
    """The frame axis nearest to unit ``direction`` (3,) when within 20 degrees, else itself."""
    cosines = CANONICAL @ direction
    k = int(np.argmax(cosines))
    return CANONICAL[k].copy() if cosines[k] >= SNAP_COS else unit(direction)


def perpendicular(n: np.ndarray, up: np.ndarray) -> np.ndarray:
    """A unit vector normal to ``n``, horizontal (normal to ``up``) where possible."""
    side = np.cross(up, n)
    if np.linalg.norm(side) < 1e-6:
        side = np.cross(np.array([1.0, 0.0, 0.0]), n)
    return unit(side)


def outward_direction(vertices: np.ndarray, joint_type: str, axis: np.ndarray, origin: np.ndarray,
                      parent_centre: np.ndarray, twist_ratio: float) -> tuple[np.ndarray, bool]:
    """Outward unit direction (3,) of a part with ``vertices`` (V, 3) and whether it turns in
    place (its centre nearer to the revolute ``axis`` than ``twist_ratio`` times its farthest
    vertex)."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre = (lo + hi) / 2
    if joint_type == "prismatic":
        return snap(unit(axis)), False
    r = centre - origin
    r = r - (r @ axis) * axis
    offsets = vertices - origin
    reach = float(np.linalg.norm(offsets - np.outer(offsets @ axis, axis), axis=1).max())
    if np.linalg.norm(r) < twist_ratio * reach:
        sign = 1.0 if axis @ (centre - parent_centre) >= 0 else -1.0
        return snap(sign * unit(axis)), True
    return snap(unit(np.cross(axis, r))), False


def face_level(heights: np.ndarray, spans: np.ndarray, band: float) -> float:
    """The outermost height at which the vertices within ``band`` span at least half of the
    part's largest in-plane extent.

    ``heights`` (V,) along the outward direction, ``spans`` (V, 2) in-plane coordinates."""
    full = float(np.max(np.ptp(spans, axis=0)))
    for level in np.unique(np.round(heights / band) * band)[::-1]:
        near = np.abs(heights - level) <= band
        if near.sum() >= 2 and float(np.max(np.ptp(spans[near], axis=0))) >= 0.5 * full:
            return float(heights[near].max())
    return float(heights.max())


def find_grasp(vertices: np.ndarray, joint_type: str, axis: np.ndarray, origin: np.ndarray,
               parent_centre: np.ndarray, up: np.ndarray, config: EnvConfig = EnvConfig()) -> Grasp:
    """The grasp of a part with ``vertices`` (V, 3) moved by a joint (``joint_type``, unit
    ``axis`` (3,), ``origin`` (3,)), its parent's centre (3,) and the up direction (3,)."""
    vertices = np.asarray(vertices, float)
    axis = unit(np.asarray(axis, float))
    normal, turns = outward_direction(vertices, joint_type, axis, np.asarray(origin, float),
                                      np.asarray(parent_centre, float), config.twist_ratio)
    heights = vertices @ normal
    top = float(heights.max())
    if turns:  # a knob: fingers across it, halfway along the part (at most 1 cm in)
        length = float(np.ptp(heights))
        depth = min(0.01, 0.5 * length)
        on_axis = origin + ((vertices.mean(axis=0) - origin) @ axis) * axis
        point = on_axis + (top - depth - on_axis @ normal) * normal
        return Grasp(point, normal, perpendicular(normal, up), "pinch", True)
    u = perpendicular(normal, up)
    v = np.cross(normal, u)
    spans = vertices @ np.column_stack([u, v])
    level = face_level(heights, spans, config.face_band)
    proud = heights > level + config.handle_min_proud
    if proud.sum() >= config.handle_min_points:
        handle = vertices[proud]
        plane = handle - np.outer(handle @ normal, normal)
        centre = (plane.min(axis=0) + plane.max(axis=0)) / 2
        centred = plane - plane.mean(axis=0)
        _, spread, rows = np.linalg.svd(centred, full_matrices=False)
        if spread[0] > ELONGATED * spread[1]:  # a bar: close across it
            long_axis = unit(rows[0] - (rows[0] @ normal) * normal)
            pinch = unit(np.cross(normal, long_axis))
        else:  # round: close horizontally
            pinch = u
        handle_top = float((handle @ normal).max())
        depth = min(0.01, 0.5 * (handle_top - level))
        return Grasp(centre + (handle_top - depth) * normal, normal, snap(pinch), "pinch")
    return press_grasp(vertices, normal, level, joint_type, axis, origin, u, config)


def press_grasp(vertices: np.ndarray, normal: np.ndarray, level: float, joint_type: str, axis: np.ndarray,
                origin: np.ndarray, across: np.ndarray, config: EnvConfig) -> Grasp:
    """Fingertips on the face at height ``level`` along ``normal`` (3,): near the edge far from
    a hinge, fingers along it; at the face's centre for a slide, fingers along ``across`` (3,)."""
    face = vertices[np.abs(vertices @ normal - level) <= config.face_band]
    lo, hi = face.min(axis=0), face.max(axis=0)
    point = (lo + hi) / 2
    pinch = across
    if joint_type == "revolute":
        away = unit(np.cross(normal, axis))
        if away @ (point - origin) < 0:
            away = -away
        far = float((face @ away).max())
        point = point + (far - config.edge_inset - point @ away) * away
        pinch = axis
    point = point + (level - point @ normal) * normal
    return Grasp(point, normal, unit(pinch - (pinch @ normal) * normal), "press")


def find_back_grasp(vertices: np.ndarray, axis: np.ndarray, origin: np.ndarray, parent_centre: np.ndarray,
                    up: np.ndarray, config: EnvConfig = EnvConfig()) -> Grasp | None:
    """For a swinging panel (revolute, not turning in place): fingertips pressed on its inner
    face near the edge far from the hinge, the side to lift an opened flap by when its handle
    faces the floor; None for other parts."""
    vertices = np.asarray(vertices, float)
    axis = unit(np.asarray(axis, float))
    normal, turns = outward_direction(vertices, "revolute", axis, np.asarray(origin, float),
                                      np.asarray(parent_centre, float), config.twist_ratio)
    if turns:
        return None
    inner = -normal
    u = perpendicular(inner, up)
    spans = vertices @ np.column_stack([u, np.cross(inner, u)])
    level = face_level(vertices @ inner, spans, config.face_band)
    return press_grasp(vertices, inner, level, "revolute", axis, np.asarray(origin, float), u, config)
