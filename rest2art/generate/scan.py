"""Fuse any set of part meshes into one scan-like surface with per-face part labels.

For meshes from other people (not watertight, overlapping, open), no exact signed distance is
available. Instead: the parts' surfaces are sampled densely and rasterised into a voxel grid;
the Euclidean distance transform gives the distance to the nearest surface; the level set at
``offset`` (half the widest gap to close) is meshed with marching cubes and only its outer
shells are kept (one per group of parts closer than the gap, none inside a part). Gaps narrower
than about 2 x ``offset`` close, grooves at part outlines stay as dents, and the surface lies
``offset`` outside the true one (a scan's usual blur). Each face is labelled with the part
whose surface is nearest.

A scanner or a multi-view reconstruction (2DGS) only has what its cameras saw. Parts made of
thin open shells (a hollow door slab, a carcass with no back, a drawer box) leave their insides
connected to the outer shell through gaps wider than the blur, so the level set holds cabinet
interiors and door backs that no camera outside can see: 30-70 % of the surface of the
development set's cabinets. Only faces seen from a sphere of cameras around the object are kept
(:func:`outside_visible_faces`).
"""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.ndimage import distance_transform_edt, minimum_filter
from scipy.spatial import cKDTree

from rest2art.render.camera import sphere_directions


def outside_visible_faces(mesh: trimesh.Trimesh, views: int = 64, pixel: float = 0.0025,
                          max_image: int = 1024) -> np.ndarray:
    """(F,) bool: faces of ``mesh`` that cameras spread over a sphere around it see (``views``
    cameras 4.5 bounding radii away with the rig's field of view, pixels of about ``pixel`` (m)
    at the object's centre, at most ``max_image`` wide). A face is seen when it is the nearest
    surface at some pixel, or when each of its corners lies within ``pixel`` of the nearest
    surface in some view: marching cubes leaves slivers narrower than a pixel that no pixel
    centre falls on."""
    from rest2art.config import SegmentConfig
    from rest2art.render.camera import cameras_around
    from rest2art.render.raster import render_views

    rig = SegmentConfig()
    lo, hi = mesh.bounds
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2) or 1.0
    distance = rig.camera_radius * radius
    width = int(np.clip(np.ceil(2 * distance * np.tan(np.radians(rig.fov_deg) / 2) / pixel), 64, max_image))
    cameras = cameras_around(centre, distance, views, rig.fov_deg, width)
    seen = np.zeros(len(mesh.faces), bool)
    corner_seen = np.zeros(len(mesh.vertices), bool)
    for view in render_views(mesh.vertices, mesh.faces, cameras, cull_backfaces=False):
        xy, depth = view.camera.project(mesh.vertices)
        tolerance = max(pixel, view.camera.pixel_size(depth.max()))
        # a pixel centre on the edge between two triangles may fall in neither (a crack): what
        # shows through is no nearer than its neighbours by more than the tolerance
        front = minimum_filter(view.depth, size=3)
        hit = (view.face >= 0) & (view.depth <= front + tolerance)
        seen[view.face[hit]] = True
        column, row = np.floor(xy).astype(int).T
        inside = (column >= 0) & (column < width) & (row >= 0) & (row < width)
        nearest = np.full(len(depth), -np.inf)
        nearest[inside] = front[row[inside], column[inside]]
        nearest[~np.isfinite(nearest)] = -np.inf  # a pixel of background sees no corner
        corner_seen |= depth <= nearest + tolerance
    return seen | corner_seen[mesh.faces].all(axis=1)


def outer_shells(shells: list[trimesh.Trimesh], probes: int = 8, rays: int = 26,
                 min_faces: int = 8) -> list[trimesh.Trimesh]:
    """The closed ``shells`` of a level set that no other shell encloses, each turned to face
    outwards. A part's level set has shells inside it (round a cavity, and round the solid
    inside its walls), which no camera outside sees; a part held apart from the rest (a drawer
    front on its runners, a door clear of its carcass) has a shell of its own beside the
    others, which a scan sees. A shell is enclosed when, from most of ``probes`` of its
    vertices, all of ``rays`` rays spread over the sphere hit a larger shell; slivers of fewer
    than ``min_faces`` faces are dropped."""
    shells = sorted([m for m in shells if len(m.faces) >= min_faces], key=lambda m: -np.prod(m.extents))
    if len(shells) < 2:
        return shells
    every = trimesh.util.concatenate(shells)
    owner = np.repeat(np.arange(len(shells)), [len(m.faces) for m in shells])
    directions = sphere_directions(rays)
    kept = []
    for k, shell in enumerate(shells):
        if k:
            probe = shell.vertices[np.linspace(0, len(shell.vertices) - 1, probes).astype(int)]
            origins = np.repeat(probe, len(directions), axis=0)
            vectors = np.tile(directions, (len(probe), 1))
            face, ray, _ = every.ray.intersects_id(origins, vectors, multiple_hits=True, return_locations=True)
            blocked = np.zeros(len(origins), bool)
            blocked[ray[owner[face] < k]] = True
            if np.mean(blocked.reshape(len(probe), -1).all(axis=1)) > 0.5:
                continue
        if shell.volume < 0:
            shell.invert()
        kept.append(shell)
    return kept


def fuse_meshes(meshes: list[trimesh.Trimesh], voxel: float = 0.005, offset: float = 0.004,
                max_faces: int = 200_000, seed: int = 0, outside_views: int = 64) -> tuple[trimesh.Trimesh, np.ndarray]:
    """One outer surface over ``meshes`` and (F,) int32 index of the nearest input mesh. With
    ``outside_views`` > 0 only the faces those cameras see are kept (the surface is open where
    it hid an inside); 0 keeps the outer shells whole."""
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
    mesh = trimesh.util.concatenate(outer_shells(mesh.split(only_watertight=False)))
    if len(mesh.faces) > max_faces:
        import fast_simplification

        v, f = fast_simplification.simplify(mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32),
                                            target_reduction=1 - max_faces / len(mesh.faces))
        mesh = trimesh.Trimesh(v.astype(np.float64), f, process=True)
    if outside_views:
        mesh.update_faces(outside_visible_faces(mesh, outside_views, pixel=voxel / 2))
        mesh.remove_unreferenced_vertices()
    _, nearest = cKDTree(points).query(mesh.triangles_center)
    return mesh, labels[nearest].astype(np.int32)
