"""A pinhole camera: pose, intrinsics, projection of points to pixels and back.

Pixels follow image convention (u right, v down, pixel centres at +0.5); depth is along the
camera's forward axis, in metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rest2art.tolerances import TINY


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose rows are the camera's right, down and forward axes."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward])


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: pixels (u right, v down), square pixels, principal point at the centre."""

    eye: np.ndarray
    """(3,) position."""
    rotation: np.ndarray
    """(3, 3) rows: the camera's right, down and forward axes in world coordinates."""
    focal: float
    """Focal length, pixels."""
    width: int
    height: int

    @classmethod
    def looking_at(cls, eye: np.ndarray, target: np.ndarray, up: np.ndarray, fov_deg: float,
                   width: int, height: int | None = None) -> "Camera":
        """A camera at ``eye`` looking at ``target``; ``fov_deg`` is the horizontal field of view."""
        eye = np.asarray(eye, float)
        focal = width / 2 / np.tan(np.radians(fov_deg) / 2)
        return cls(eye, look_at(eye, np.asarray(target, float), np.asarray(up, float)), float(focal),
                   int(width), int(height or width))

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 3) world points -> (N, 2) pixel coordinates and (N,) depths along the view axis."""
        cam = (np.asarray(points, float) - self.eye) @ self.rotation.T
        depth = cam[:, 2]
        xy = cam[:, :2] / np.where(np.abs(depth) > TINY, depth, TINY)[:, None] * self.focal
        return xy + [self.width / 2, self.height / 2], depth

    def pixel_size(self, depth: np.ndarray | float) -> np.ndarray | float:
        """World length covered by one pixel at ``depth``."""
        return np.asarray(depth) / self.focal


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


def sphere_directions(count: int) -> np.ndarray:
    """(count, 3) unit vectors spread evenly over the sphere (Fibonacci lattice)."""
    k = np.arange(count) + 0.5
    polar = np.arccos(1 - 2 * k / count)
    azimuth = np.pi * (1 + 5**0.5) * k
    return np.column_stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)])


def cameras_around(centre: np.ndarray, distance: float, count: int, fov_deg: float, width: int) -> list[Camera]:
    """``count`` cameras ``distance`` (m) from ``centre`` (3,) along ``sphere_directions``, each
    looking at it with +z up (+y for one looking nearly straight up or down)."""
    cameras = []
    for direction in sphere_directions(count):
        up = np.array([0.0, 0.0, 1.0]) if abs(direction[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
        cameras.append(Camera.looking_at(centre + distance * direction, centre, up, fov_deg, width))
    return cameras
