"""The camera rig for mesh inputs and the rendered views (paper: View Selection Strategy).

The canonical mesh (+z up, -y front) is seen from N' = azimuth_steps x elevation_steps cameras
spread over +-azimuth around the front and the elevation range, at ``camera_radius`` times the
radius of the object's bounding sphere (the paper's radius on the normalised object).
"""

from __future__ import annotations

import numpy as np

from rest2art.config import SegmentConfig
from rest2art.render.camera import Camera
from rest2art.render.raster import ViewMaps, render_views


def camera_rig(vertices: np.ndarray, config: SegmentConfig = SegmentConfig()) -> list[Camera]:
    """Cameras looking at the centre of the (V, 3) canonical vertices, azimuth-major order."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre = (lo + hi) / 2
    radius = float(np.linalg.norm(hi - lo) / 2) or 1.0
    cameras = []
    for az in np.radians(np.linspace(-config.azimuth_deg, config.azimuth_deg, config.azimuth_steps)):
        for el in np.radians(np.linspace(*config.elevation_deg, config.elevation_steps)):
            direction = np.array([np.sin(az) * np.cos(el), -np.cos(az) * np.cos(el), np.sin(el)])
            cameras.append(Camera.looking_at(centre + config.camera_radius * radius * direction, centre,
                                             np.array([0.0, 0.0, 1.0]), config.fov_deg, config.image_size))
    return cameras


def render_rig(vertices: np.ndarray, faces: np.ndarray, config: SegmentConfig = SegmentConfig(),
               consistent_winding: bool = True) -> list[ViewMaps]:
    """Face-index, depth, point and normal maps of the canonical mesh from every rig camera."""
    cameras = camera_rig(vertices, config)
    return render_views(vertices, faces, cameras, config.cull_backfaces and consistent_winding)
