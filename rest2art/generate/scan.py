"""Fuse any set of part meshes into one scan-like surface with per-face part labels.

For meshes from other people (not watertight, overlapping, open), no exact signed distance is
available. Instead: the parts' surfaces are sampled densely and rasterised into a voxel grid;
the Euclidean distance transform gives the distance to the nearest surface; the level set at
``offset`` (half the widest gap to close) is meshed with marching cubes and only the outer
shell is kept. Gaps narrower than about 2 x ``offset`` close, grooves at part outlines stay as
dents, and the surface lies ``offset`` outside the true one (a scan's usual blur). Each face is
labelled with the part whose surface is nearest.
"""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.ndimage import distance_transform_edt
from scipy.spatial import cKDTree


def fuse_meshes(meshes: list[trimesh.Trimesh], voxel: float = 0.005, offset: float = 0.004,
                max_faces: int = 200_000, seed: int = 0) -> tuple[trimesh.Trimesh, np.ndarray]:
    """One outer surface over ``meshes`` and (F,) int32 index of the nearest input mesh."""
    from skimage.measure import marching_cubes

    rng = np.random.default_rng(seed)
    points, labels = [], []
    for k, mesh in enumerate(meshes):
        count = int(np.clip(mesh.area / (0.35 * voxel) ** 2, 100, 3_000_000))
        pts, _ = trimesh.sample.sample_surface(mesh, count, seed=rng)
        points.append(np.asarray(pts))
        labels.append(np.full(len(pts), k, np.int32))
    points, labels = np.concatenate(points), np.concatenate(labels)
    pad = offset + 3 * voxel
    lo = points.min(axis=0) - pad
    shape = np.ceil((points.max(axis=0) + pad - lo) / voxel).astype(int) + 1
    occupied = np.zeros(shape, bool)
    idx = np.round((points - lo) / voxel).astype(int)
    occupied[idx[:, 0], idx[:, 1], idx[:, 2]] = True
    distance = distance_transform_edt(~occupied) * voxel
    verts, faces, _, _ = marching_cubes(distance.astype(np.float32), level=offset, spacing=(voxel,) * 3)
    mesh = trimesh.Trimesh(verts + lo, faces, process=True)
    shells = mesh.split(only_watertight=False)
    mesh = max(shells, key=lambda m: np.prod(m.extents))
    if mesh.volume < 0:
        mesh.invert()
    if len(mesh.faces) > max_faces:
        import fast_simplification

        v, f = fast_simplification.simplify(mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32),
                                            target_reduction=1 - max_faces / len(mesh.faces))
        mesh = trimesh.Trimesh(v.astype(np.float64), f, process=True)
    _, nearest = cKDTree(points).query(mesh.triangles_center)
    return mesh, labels[nearest].astype(np.int32)
