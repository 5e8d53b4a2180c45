"""The vectorised rasteriser against trimesh ray casting, and the per-view maps."""

from __future__ import annotations

import numpy as np
import trimesh

from rest2art.render.camera import Camera
from rest2art.render.raster import rasterize, render_maps


def _scene() -> trimesh.Trimesh:
    box = trimesh.creation.box((0.6, 0.4, 0.5))
    ball = trimesh.creation.icosphere(3, 0.15)
    ball.apply_translation((0.1, -0.3, 0.1))  # pokes out of the box's front
    return trimesh.util.concatenate([box, ball])


def test_face_index_matches_ray_casting():
    mesh = _scene()
    camera = Camera.looking_at(np.array([0.9, -1.8, 1.0]), np.zeros(3), np.array([0, 0, 1.0]), 35.49, 96)
    view = render_maps(mesh.vertices, mesh.faces, camera, cull_backfaces=True)
    ys, xs = np.mgrid[0:96, 0:96]
    pixel = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
    local = np.concatenate([(pixel - 48) / camera.focal, np.ones((len(pixel), 1))], axis=1)
    directions = local @ camera.rotation
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    hit = mesh.ray.intersects_first(np.tile(camera.eye, (len(directions), 1)), directions)
    ours = view.face.ravel()
    assert (ours >= 0).sum() > 800
    # pixels whose centre lies on a shared edge may pick either neighbour: allow a thin margin
    assert np.mean(ours == hit) > 0.98
    seen = ours >= 0
    depth = np.linalg.norm(view.points.reshape(-1, 3)[seen] - camera.eye, axis=1)
    locations, index_ray, _ = mesh.ray.intersects_location(np.tile(camera.eye, (seen.sum(), 1)),
                                                           directions[seen], multiple_hits=False)
    true = np.full(seen.sum(), np.nan)
    true[index_ray] = np.linalg.norm(locations - camera.eye, axis=1)
    assert np.nanmedian(np.abs(depth - true)) < 1e-6


def test_nearest_triangle_wins_and_backfaces_are_culled():
    tri_xy = np.array([[[0, 0], [10, 0], [0, 10]]] * 2, float)
    tri_depth = np.array([[2.0, 2.0, 2.0], [1.0, 1.0, 1.0]])
    index = rasterize(tri_xy, tri_depth, 10, 10)
    assert index[1, 1] == 1 and index[9, 9] == -1
    # a triangle wound away from the camera disappears with culling
    camera = Camera.looking_at(np.array([0, 0, -5.0]), np.zeros(3), np.array([0, 1.0, 0]), 40, 32)
    verts = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], float)
    towards = render_maps(verts, np.array([[0, 2, 1]]), camera)
    away = render_maps(verts, np.array([[0, 1, 2]]), camera)
    assert towards.mask.sum() > 20
    assert (away.mask.sum() == 0) != (towards.mask.sum() == 0)
