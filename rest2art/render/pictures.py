"""Pictures of an asset people look at (thumbnails, reports, README).

Parts in palette colours, posed at given joint values, with joint axes drawn on request;
perspective camera looking at the object from the front, to the left and above.
"""

from __future__ import annotations

import numpy as np

from rest2art.geometry.basics import transform_points
from rest2art.render.raster import PALETTE, render_triangles


def joint_segments(asset, extent: float) -> list[tuple[np.ndarray, np.ndarray, tuple]]:
    """A 3D segment per movable joint: revolute axes through their origin, prismatic arrows."""
    out = []
    for index, part in enumerate(asset.parts):
        joint = asset.joint_for(part.name)
        if joint is None or joint.type == "fixed":
            continue
        color = tuple(PALETTE[index % len(PALETTE)] * 0.6)
        if joint.type == "revolute":
            half = 0.35 * extent * joint.axis
            out.append((joint.origin - half, joint.origin + half, color))
        else:
            out.append((joint.origin, joint.origin + 0.3 * extent * joint.axis, color))
    return out


def render_asset(asset, values: dict[str, float] | None = None, size: int = 480, axes: bool = False) -> np.ndarray:
    """Picture of an ArticulatedAsset (parts coloured) with joints set to ``values``; ``axes``
    draws the joint axes."""
    up = asset.up
    front = asset.front
    tris, cols = [], []
    poses = asset.part_poses(values)
    for index, part in enumerate(asset.parts):
        v = transform_points(np.asarray(part.mesh.vertices), poses[part.name])
        tris.append(v[np.asarray(part.mesh.faces)])
        cols.append(np.tile(PALETTE[index % len(PALETTE)], (len(part.mesh.faces), 1)))
    triangles = np.concatenate(tris)
    segments = joint_segments(asset, float(np.ptp(triangles.reshape(-1, 3), axis=0).max())) if axes else []
    return render_triangles(triangles, np.concatenate(cols), up, front, size, segments=segments)


def closed_and_open(asset, size: int = 400, fraction: float = 0.8, axes: bool = False) -> np.ndarray:
    """Side-by-side picture: rest state and every joint at ``fraction`` of its range."""
    opened = {j.name: fraction * j.limit[1] for j in asset.movable_joints}
    return np.concatenate([render_asset(asset, None, size, axes), render_asset(asset, opened, size)], axis=1)


def label(image: np.ndarray, text: str) -> np.ndarray:
    """``image`` with a caption strip on top."""
    import cv2

    strip = np.full((28, image.shape[1], 3), 255, np.uint8)
    cv2.putText(strip, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (40, 40, 40), 1, cv2.LINE_AA)
    return np.concatenate([strip, image], axis=0)


def save_png(image: np.ndarray, path) -> None:
    import cv2

    cv2.imwrite(str(path), image[:, :, ::-1])
