"""Small CPU renderer for pictures people look at (thumbnails, reports, README).

A z-buffered rasterizer writes a face-index map (which triangle is seen at each pixel); the
picture is that map shaded with Lambert lighting. Perspective camera looking at the object from
the front, to the left and above.
"""

from __future__ import annotations

import numpy as np

from rest2art.geometry import transform_points

PALETTE = np.array([
    [200, 200, 200], [66, 133, 244], [219, 68, 55], [244, 180, 0], [15, 157, 88], [171, 71, 188],
    [0, 172, 193], [255, 112, 67], [158, 157, 36], [92, 107, 192], [240, 98, 146], [0, 137, 123],
], dtype=float)


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose rows are the camera's right, down and forward axes."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward])


def render_triangles(triangles: np.ndarray, colors: np.ndarray, up: np.ndarray, front: np.ndarray,
                     size: int = 480, azimuth_deg: float = -35.0, elevation_deg: float = 25.0,
                     segments: list[tuple[np.ndarray, np.ndarray, tuple]] = ()) -> np.ndarray:
    """(size, size, 3) uint8 RGB image of (T, 3, 3) triangles with (T, 3) RGB colours 0..255;
    ``segments`` (start, end, rgb) in 3D are drawn on top (joint axes)."""
    from rest2art.geometry import rotation_about

    up = up / np.linalg.norm(up)
    front = front / np.linalg.norm(front)
    pts = triangles.reshape(-1, 3)
    centre = (pts.min(axis=0) + pts.max(axis=0)) / 2
    radius = np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)) / 2
    direction = rotation_about(up, np.radians(azimuth_deg)) @ front
    side = np.cross(up, direction)
    direction = rotation_about(side, -np.radians(elevation_deg)) @ direction
    distance = radius / np.tan(np.radians(18.0)) * 1.05
    eye = centre + direction * distance
    R = look_at(eye, centre, up)
    cam = (pts - eye) @ R.T
    focal = size / 2 / np.tan(np.radians(18.0))
    xy = cam[:, :2] / np.maximum(cam[:, 2:3], 1e-6) * focal + size / 2
    tri_xy = xy.reshape(-1, 3, 2)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    light = -R[2] + 0.5 * up - 0.3 * R[0]
    light /= np.linalg.norm(light)
    shade = 0.35 + 0.65 * np.abs(normals @ light)
    index = rasterize(tri_xy, cam[:, 2].reshape(-1, 3), size, size)
    image = np.full((size, size, 3), 255, np.uint8)
    seen = index >= 0
    image[seen] = np.clip(colors[index[seen]] * shade[index[seen], None], 0, 255).astype(np.uint8)
    if len(segments):
        import cv2

        for start, end, rgb in segments:
            ends = (np.array([start, end]) - eye) @ R.T
            if (ends[:, 2] <= 1e-6).any():
                continue
            px = ends[:, :2] / ends[:, 2:3] * focal + size / 2
            a, b = (tuple(int(round(v * 16)) for v in q) for q in px)
            cv2.line(image, a, b, (0, 0, 0), 5, cv2.LINE_AA, shift=4)
            cv2.line(image, a, b, tuple(int(c) for c in rgb), 3, cv2.LINE_AA, shift=4)
            cv2.circle(image, b, 4 * 16, tuple(int(c) for c in rgb), -1, cv2.LINE_AA, shift=4)
    return image


def rasterize(tri_xy: np.ndarray, tri_depth: np.ndarray, width: int, height: int) -> np.ndarray:
    """(H, W) int64 face-index map (-1 = background) of (T, 3, 2) pixel-space triangles with
    (T, 3) camera depths; nearest surface wins, pixel centres at +0.5."""
    depth_buffer = np.full((height, width), np.inf)
    index = np.full((height, width), -1, np.int64)
    lo = np.floor(tri_xy.min(axis=1)).astype(int)
    hi = np.ceil(tri_xy.max(axis=1)).astype(int)
    visible = (hi[:, 0] >= 0) & (hi[:, 1] >= 0) & (lo[:, 0] < width) & (lo[:, 1] < height) & (tri_depth.min(axis=1) > 0)
    for k in np.flatnonzero(visible):
        x0, y0 = max(lo[k, 0], 0), max(lo[k, 1], 0)
        x1, y1 = min(hi[k, 0], width - 1), min(hi[k, 1], height - 1)
        if x1 < x0 or y1 < y0:
            continue
        xs, ys = np.meshgrid(np.arange(x0, x1 + 1) + 0.5, np.arange(y0, y1 + 1) + 0.5)
        (ax, ay), (bx, by), (cx, cy) = tri_xy[k]
        area = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        if abs(area) < 1e-12:
            continue
        w0 = ((bx - xs) * (cy - ys) - (cx - xs) * (by - ys)) / area
        w1 = ((cx - xs) * (ay - ys) - (ax - xs) * (cy - ys)) / area
        w2 = 1.0 - w0 - w1
        inside = (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9)
        if not inside.any():
            continue
        z = w0 * tri_depth[k, 0] + w1 * tri_depth[k, 1] + w2 * tri_depth[k, 2]
        window = depth_buffer[y0:y1 + 1, x0:x1 + 1]
        closer = inside & (z < window)
        window[closer] = z[closer]
        index[y0:y1 + 1, x0:x1 + 1][closer] = k
    return index


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
    up = np.asarray(asset.metadata.get("frame", {}).get("up", [0, 0, 1]), float)
    front = np.asarray(asset.metadata.get("frame", {}).get("front", [0, -1, 0]), float)
    tris, cols = [], []
    for index, part in enumerate(asset.parts):
        T = np.eye(4)
        joint = asset.joint_for(part.name)
        if joint is not None and values and joint.name in values:
            T = joint.transform(values[joint.name])
        v = transform_points(np.asarray(part.mesh.vertices), T)
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
