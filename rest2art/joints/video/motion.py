"""Rigid joint motion models.

A revolute joint moves a rest-pose point p0 to R(w, theta_t)(p0 - q) + q, a prismatic joint to
p0 + d_t v. Everything is vectorised over frames (T) and points (N); coordinates are metres.
"""

from __future__ import annotations

import numpy as np


def rotation_matrices(axis: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(T, 3, 3) Rodrigues rotations by (T,) ``angles`` rad about the (3,) unit ``axis``."""
    k = np.asarray(axis, float)
    k = k / np.linalg.norm(k)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    angles = np.asarray(angles, float)[:, None, None]
    return np.eye(3) + np.sin(angles) * kx + (1 - np.cos(angles)) * (kx @ kx)


def revolute_points(anchors: np.ndarray, axis: np.ndarray, pivot: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(T, N, 3) positions of (N, 3) rest-pose ``anchors`` rotated by each of (T,) ``angles``
    about the line through ``pivot`` along ``axis``."""
    R = rotation_matrices(axis, angles)
    return np.einsum("tij,nj->tni", R, anchors - pivot) + pivot


def prismatic_points(anchors: np.ndarray, direction: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(T, N, 3) positions of (N, 3) ``anchors`` slid by each of (T,) ``offsets`` m along
    the unit ``direction``."""
    v = np.asarray(direction, float) / np.linalg.norm(direction)
    return anchors[None] + np.asarray(offsets, float)[:, None, None] * v
