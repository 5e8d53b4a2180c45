"""Rigid joint motion models and the pinhole projection they are fitted through.

A revolute joint moves a rest-pose point p0 to R(w, theta_t)(p0 - q) + q, a prismatic joint to
p0 + d_t v. Everything is vectorised over frames (T) and points (N); coordinates are metres in
the frame the camera is expressed in, pixels follow ``rest2art.render.Camera`` (u right, v down,
pixel centres at +0.5).
"""

from __future__ import annotations

import numpy as np

from rest2art.render import Camera


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


def project(camera: Camera, points: np.ndarray) -> np.ndarray:
    """(..., 2) pixel coordinates of (..., 3) world points (depths must be positive)."""
    shape = points.shape[:-1]
    xy, _ = camera.project(points.reshape(-1, 3))
    return xy.reshape(*shape, 2)


def unproject(camera: Camera, pixels: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """(N, 3) world points seen at (N, 2) ``pixels`` with (N,) depths along the view axis."""
    pixels = np.asarray(pixels, float)
    depth = np.asarray(depth, float)
    centre = np.array([camera.width / 2, camera.height / 2])
    cam = np.concatenate([(pixels - centre) / camera.focal * depth[:, None], depth[:, None]], axis=1)
    return cam @ camera.rotation + camera.eye


