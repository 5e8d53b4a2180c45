"""Small CPU rasteriser.

A z-buffered rasteriser writes a face-index map (which triangle is seen at each pixel) with
depth and normals; a picture is that map shaded with Lambert lighting.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rest2art.render.camera import Camera
from rest2art.tolerances import TINY

PALETTE = np.array([
    [200, 200, 200], [66, 133, 244], [219, 68, 55], [244, 180, 0], [15, 157, 88], [171, 71, 188],
    [0, 172, 193], [255, 112, 67], [158, 157, 36], [92, 107, 192], [240, 98, 146], [0, 137, 123],
], dtype=float)


@dataclass
class ViewMaps:
    """What one camera sees of a mesh: per pixel the face, depth, surface point and normal."""

    camera: Camera
    face: np.ndarray
    """(H, W) int64 face index, -1 on background."""
    depth: np.ndarray
    """(H, W) depth along the view axis, inf on background."""
    points: np.ndarray
    """(H, W, 3) surface point (world), 0 on background."""
    normals: np.ndarray
    """(H, W, 3) unit surface normal turned towards the camera (interpolated vertex normals)."""

    @property
    def mask(self) -> np.ndarray:
        return self.face >= 0

    def shaded(self) -> np.ndarray:
        """(H, W, 3) uint8 grey Lambert-shaded picture (light from the camera, up and left)."""
        light = -self.camera.rotation[2] - 0.5 * self.camera.rotation[1] - 0.3 * self.camera.rotation[0]
        light /= np.linalg.norm(light)
        shade = 0.3 + 0.7 * np.clip(self.normals @ light, 0, 1)
        image = np.full(self.face.shape + (3,), 255, np.uint8)
        image[self.mask] = (205 * shade[self.mask, None]).astype(np.uint8)
        return image


def blend_masks(picture: np.ndarray, masks: list[np.ndarray], alpha: float,
                colours: np.ndarray | None = None) -> np.ndarray:
    """(H, W, 3) uint8 ``picture`` with each (H, W) bool mask blended in with opacity ``alpha``,
    in ``colours[k]`` (RGB 0-255) or the palette's k-th vivid colour."""
    image = picture.astype(float)
    for k, mask in enumerate(masks):
        colour = PALETTE[1 + k % (len(PALETTE) - 1)] if colours is None else colours[k]
        image[mask] = (1 - alpha) * image[mask] + alpha * colour
    return image.astype(np.uint8)


def render_views(vertices: np.ndarray, faces: np.ndarray, cameras: list[Camera],
                 cull_backfaces: bool = True) -> list[ViewMaps]:
    """``render_maps`` for several cameras, sharing the per-mesh normals."""
    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces, np.int64)
    tri = vertices[faces]
    face_normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    vertex_normals = _vertex_normals(vertices, faces, face_normals)
    return [render_maps(vertices, faces, camera, cull_backfaces, vertex_normals, face_normals) for camera in cameras]


def render_maps(vertices: np.ndarray, faces: np.ndarray, camera: Camera, cull_backfaces: bool = True,
                vertex_normals: np.ndarray | None = None, face_normals: np.ndarray | None = None) -> ViewMaps:
    """Face-index, depth, point and normal maps of a (V, 3) / (F, 3) mesh seen by ``camera``.

    With ``cull_backfaces`` faces whose winding turns them away from the camera are skipped (use
    it only for consistently wound meshes). ``vertex_normals`` (V, 3) and ``face_normals`` (F, 3,
    any length) may be passed in when the same mesh is rendered many times."""
    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces, np.int64)
    xy, depth = camera.project(vertices)
    tri_xy, tri_depth = xy[faces], depth[faces]
    if face_normals is None:
        tri = vertices[faces]
        face_normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    if cull_backfaces:
        towards = np.einsum("ij,ij->i", vertices[faces[:, 0]] - camera.eye, face_normals)
        faces_kept = np.flatnonzero(towards < 0)
    else:
        faces_kept = np.arange(len(faces))
    local, bary = rasterize(tri_xy[faces_kept], tri_depth[faces_kept], camera.width, camera.height, barycentric=True)
    face = np.where(local >= 0, faces_kept[np.maximum(local, 0)], -1) if len(faces_kept) else local
    seen = face >= 0
    corner = faces[face[seen]]
    points = np.zeros(face.shape + (3,))
    points[seen] = np.einsum("nk,nkd->nd", bary[seen], vertices[corner])
    if vertex_normals is None:
        vertex_normals = _vertex_normals(vertices, faces, face_normals)
    normals = np.zeros(face.shape + (3,))
    n = np.einsum("nk,nkd->nd", bary[seen], vertex_normals[corner])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), TINY)
    view = points[seen] - camera.eye
    n *= np.where(np.einsum("ij,ij->i", n, view) > 0, -1.0, 1.0)[:, None]
    normals[seen] = n
    depth_map = np.full(face.shape, np.inf)
    depth_map[seen] = (points[seen] - camera.eye) @ camera.rotation[2]
    return ViewMaps(camera, face, depth_map, points, normals)


def _vertex_normals(vertices: np.ndarray, faces: np.ndarray, face_normals: np.ndarray) -> np.ndarray:
    """(V, 3) area-weighted unit vertex normals from (F, 3) face normals whose length is twice
    the face area."""
    out = np.zeros_like(vertices)
    for k in range(3):
        for axis in range(3):
            out[:, axis] += np.bincount(faces[:, k], face_normals[:, axis], minlength=len(vertices))
    return out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), TINY)


def render_triangles(triangles: np.ndarray, colors: np.ndarray, up: np.ndarray, front: np.ndarray,
                     size: int = 480, azimuth_deg: float = -35.0, elevation_deg: float = 25.0,
                     segments: list[tuple[np.ndarray, np.ndarray, tuple]] = ()) -> np.ndarray:
    """(size, size, 3) uint8 RGB image of (T, 3, 3) triangles with (T, 3) RGB colours 0..255;
    ``segments`` (start, end, rgb) in 3D are drawn on top (joint axes)."""
    from rest2art.geometry.basics import rotation_about

    up = up / np.linalg.norm(up)
    front = front / np.linalg.norm(front)
    pts = triangles.reshape(-1, 3)
    centre = (pts.min(axis=0) + pts.max(axis=0)) / 2
    radius = np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)) / 2
    direction = rotation_about(up, np.radians(azimuth_deg)) @ front
    side = np.cross(up, direction)
    direction = rotation_about(side, -np.radians(elevation_deg)) @ direction
    distance = radius / np.tan(np.radians(18.0)) * 1.05
    camera = Camera.looking_at(centre + direction * distance, centre, up, 36.0, size)
    xy, depth = camera.project(pts)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), TINY)
    light = -camera.rotation[2] + 0.5 * up - 0.3 * camera.rotation[0]
    light /= np.linalg.norm(light)
    shade = 0.35 + 0.65 * np.abs(normals @ light)
    index = rasterize(xy.reshape(-1, 3, 2), depth.reshape(-1, 3), size, size)
    image = np.full((size, size, 3), 255, np.uint8)
    seen = index >= 0
    image[seen] = np.clip(colors[index[seen]] * shade[index[seen], None], 0, 255).astype(np.uint8)
    if len(segments):
        import cv2

        for start, end, rgb in segments:
            px, ends_depth = camera.project(np.array([start, end]))
            if (ends_depth <= 1e-6).any():
                continue
            a, b = (tuple(int(round(v * 16)) for v in q) for q in px)
            cv2.line(image, a, b, (0, 0, 0), 5, cv2.LINE_AA, shift=4)
            cv2.line(image, a, b, tuple(int(c) for c in rgb), 3, cv2.LINE_AA, shift=4)
            cv2.circle(image, b, 4 * 16, tuple(int(c) for c in rgb), -1, cv2.LINE_AA, shift=4)
    return image


def rasterize(tri_xy: np.ndarray, tri_depth: np.ndarray, width: int, height: int,
              barycentric: bool = False, max_candidates: int = 4_000_000):
    """Z-buffer (T, 3, 2) pixel-space triangles with (T, 3) camera depths (> 0 in front).

    Returns the (H, W) int64 face-index map (-1 = background; nearest surface wins, pixel
    centres at +0.5); with ``barycentric`` also (H, W, 3) perspective-correct barycentric
    weights of the pixel centre in its triangle (0 on background).

    Vectorised: every triangle's bounding box is expanded into candidate pixels, a chunk of
    triangles at a time (at most ``max_candidates`` pixels per chunk bounds the memory), the
    inside test uses edge functions and the z-test ``np.minimum.at`` over pixel ids.
    """
    tri_xy = np.asarray(tri_xy, np.float64)
    tri_depth = np.asarray(tri_depth, np.float64)
    depth_buffer = np.full(height * width, np.inf)
    index = np.full(height * width, -1, np.int64)
    bary = np.zeros((height * width, 3)) if barycentric else None
    lo = np.floor(tri_xy.min(axis=1) - 0.5).astype(np.int64) + 1  # first pixel whose centre may be inside
    hi = np.floor(tri_xy.max(axis=1) - 0.5).astype(np.int64)
    lo = np.maximum(lo, 0)
    hi = np.minimum(hi, [width - 1, height - 1])
    a, b, c = tri_xy[:, 0], tri_xy[:, 1], tri_xy[:, 2]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    keep = np.flatnonzero((hi[:, 0] >= lo[:, 0]) & (hi[:, 1] >= lo[:, 1]) & (np.abs(area) > TINY)
                          & (tri_depth.min(axis=1) > 1e-9))
    if not len(keep):
        return (index.reshape(height, width), bary.reshape(height, width, 3)) if barycentric else index.reshape(height, width)
    box_w = hi[keep, 0] - lo[keep, 0] + 1
    counts = box_w * (hi[keep, 1] - lo[keep, 1] + 1)
    chunk_end = np.cumsum(counts)
    start = 0
    while start < len(keep):
        stop = int(np.searchsorted(chunk_end, chunk_end[start] - counts[start] + max_candidates, side="right"))
        stop = max(stop, start + 1)
        tris = keep[start:stop]
        n = counts[start:stop]
        t_local = np.repeat(np.arange(len(tris)), n)
        offset = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        t = tris[t_local]
        w = box_w[start:stop][t_local]
        px = lo[t, 0] + offset % w
        py = lo[t, 1] + offset // w
        xs, ys = px + 0.5, py + 0.5
        inv = 1.0 / area[t]
        w0 = ((b[t, 0] - xs) * (c[t, 1] - ys) - (c[t, 0] - xs) * (b[t, 1] - ys)) * inv
        w1 = ((c[t, 0] - xs) * (a[t, 1] - ys) - (a[t, 0] - xs) * (c[t, 1] - ys)) * inv
        w2 = 1.0 - w0 - w1
        inside = (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9)
        t, px, py, w0, w1, w2 = t[inside], px[inside], py[inside], w0[inside], w1[inside], w2[inside]
        inv_z = w0 / tri_depth[t, 0] + w1 / tri_depth[t, 1] + w2 / tri_depth[t, 2]
        z = 1.0 / inv_z
        pixel = py * width + px
        np.minimum.at(depth_buffer, pixel, z)
        win = z <= depth_buffer[pixel]
        index[pixel[win]] = t[win]
        if barycentric:
            weights = np.stack([w0[win] / tri_depth[t[win], 0], w1[win] / tri_depth[t[win], 1],
                                w2[win] / tri_depth[t[win], 2]], axis=1) * z[win, None]
            bary[pixel[win]] = weights
        start = stop
    index = index.reshape(height, width)
    return (index, bary.reshape(height, width, 3)) if barycentric else index
