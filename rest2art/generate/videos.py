"""Simulated motion videos of a known articulated object, for proving the fitting (validation
only: the pipeline never sees them).

Every movable part of a ground-truth asset opens together over ``n_frames`` from the chosen view;
each frame is rendered with the project's rasterizer (a solid 3D texture that moves with the
part, so that an image tracker has something to follow) and the ground-truth tracks are the
projections of the frame-0 surface points carried by their part's motion, visible where the
rendered frame shows that part at that depth. Degradations model what goes wrong in generated
videos and trackers: pixel noise, dropout, a hallucinated extra moving region, non-rigid wobble,
a slowly drifting camera and a motion that stops early.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rest2art.geometry.basics import rotation_about, transform_points
from rest2art.joints.video.tracks import Tracks, grid_queries
from rest2art.render.camera import Camera, project
from rest2art.render.raster import ViewMaps, render_maps


@dataclass(frozen=True)
class Degradation:
    """What a simulated video gets wrong. Lengths in metres, angles in degrees."""

    noise_px: float = 0.0
    """Gaussian noise added to every tracked position (frame 0 stays exact)."""
    dropout: float = 0.0
    """Fraction of (frame > 0, point) observations randomly marked invisible."""
    hallucinated: float = 0.0
    """Fraction of each part's tracks (a contiguous patch) that follow an imagined motion."""
    wobble_m: float = 0.0
    """Amplitude of a smooth non-rigid deformation growing with the opening."""
    drift_deg: float = 0.0
    """The camera turns by this much (and shifts by as many cm) over the video."""
    stop_fraction: float = 1.0
    """The motion stalls at this fraction of the full opening."""

    def label(self) -> str:
        changed = [f"{k}={v:g}" for k, v in self.__dict__.items() if v != Degradation.__dataclass_fields__[k].default]
        return ", ".join(changed) or "clean"


@dataclass
class SimulatedVideo:
    camera: Camera
    values: dict[str, np.ndarray]
    """Per moving part (child name), (T,) true joint value per frame."""
    tracks: dict[str, Tracks]
    """Per moving part, its tracks (degraded)."""
    anchors: dict[str, np.ndarray]
    """Per moving part, (N, 3) frame-0 surface points of its tracks (exact)."""
    depth0: np.ndarray
    """(H, W) rendered depth of frame 0."""
    masks0: dict[str, np.ndarray]
    """Per part (all parts), its (H, W) bool mask in frame 0."""
    frames: np.ndarray | None = None
    """(T, H, W, 3) uint8 textured frames, when rendered."""
    outlier: dict[str, np.ndarray] = field(default_factory=dict)
    """Per moving part, (N,) bool: the track belongs to the hallucinated region."""


def opening_profile(n_frames: int, upper: float, fraction: float = 0.8, stop_fraction: float = 1.0) -> np.ndarray:
    """(T,) joint values easing from 0 to ``fraction * upper`` (smoothstep), stalled at
    ``stop_fraction`` of that."""
    s = np.linspace(0.0, 1.0, n_frames)
    ease = s * s * (3 - 2 * s)
    return fraction * upper * np.minimum(ease, stop_fraction)


def _posed(asset, values: dict[str, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[np.ndarray]]:
    vertices, faces, part_of_face, transforms = [], [], [], []
    offset = 0
    by_joint = {j.name: values[j.child] for j in asset.joints if j.child in values}
    poses = asset.part_poses(by_joint)
    for index, part in enumerate(asset.parts):
        T = poses[part.name]
        transforms.append(T)
        vertices.append(transform_points(np.asarray(part.mesh.vertices), T))
        faces.append(np.asarray(part.mesh.faces) + offset)
        part_of_face.append(np.full(len(part.mesh.faces), index))
        offset += len(part.mesh.vertices)
    return np.concatenate(vertices), np.concatenate(faces), np.concatenate(part_of_face), transforms


def _texture(points: np.ndarray, seed: int = 7) -> np.ndarray:
    """(N,) albedo in [0.25, 1] of a solid texture at (N, 3) rest-frame points (sum of random
    3D sinusoids with 1.5-6 cm wavelengths)."""
    rng = np.random.default_rng(seed)
    directions = rng.normal(size=(8, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    wavelengths = rng.uniform(0.015, 0.06, 8)
    phases = rng.uniform(0, 2 * np.pi, 8)
    k = directions * (2 * np.pi / wavelengths)[:, None]
    value = np.sin(points @ k.T + phases).mean(axis=1)
    return np.clip(0.62 + 0.9 * value, 0.25, 1.0)


def render_frame(asset, camera: Camera, values: dict[str, float], textured: bool = True) -> tuple[ViewMaps, np.ndarray, np.ndarray | None]:
    """The posed asset seen by ``camera``: its maps, the (H, W) part index per pixel (-1 on
    background) and, with ``textured``, the (H, W, 3) uint8 picture."""
    vertices, faces, part_of_face, transforms = _posed(asset, values)
    view = render_maps(vertices, faces, camera)
    part_map = np.where(view.face >= 0, part_of_face[np.maximum(view.face, 0)], -1)
    if not textured:
        return view, part_map, None
    image = view.shaded().astype(float)
    seen = part_map >= 0
    rest = np.zeros((int(seen.sum()), 3))
    pts, owners = view.points[seen], part_map[seen]
    for index, T in enumerate(transforms):
        mine = owners == index
        if mine.any():
            inv = np.linalg.inv(T)
            rest[mine] = transform_points(pts[mine], inv)
    image[seen] *= _texture(rest)[:, None]
    return view, part_map, np.clip(image, 0, 255).astype(np.uint8)


def choose_view(asset, cameras: list[Camera]) -> Camera:
    """The camera that sees the most pixels of the movable parts at rest (the paper conditions
    the video on the view with the best masks; seen area stands in for their quality)."""
    moving = {asset.part_index(j.child) for j in asset.movable_joints}
    best, best_area = cameras[0], -1
    for camera in cameras:
        _, part_map, _ = render_frame(asset, camera, {}, textured=False)
        area = int(np.isin(part_map, list(moving)).sum())
        if area > best_area:
            best, best_area = camera, area
    return best


def _drifted(camera: Camera, fraction: float, drift_deg: float, direction: np.ndarray) -> Camera:
    if drift_deg == 0 or fraction == 0:
        return camera
    R = rotation_about(direction, np.radians(drift_deg) * fraction)
    return Camera(camera.eye + 0.01 * drift_deg * fraction * direction, R @ camera.rotation,
                  camera.focal, camera.width, camera.height)


@dataclass
class RenderedMotion:
    """Every frame of an opening rendered once; degradations are applied on top of it."""

    values: dict[str, np.ndarray]
    maps: list[tuple[ViewMaps, np.ndarray]]
    """Per frame, the maps and the (H, W) part index per pixel."""
    images: np.ndarray | None


def render_motion(asset, camera: Camera, n_frames: int = 24, open_fraction: float = 0.8,
                  stop_fraction: float = 1.0, render_images: bool = False) -> RenderedMotion:
    """Render every movable joint of ``asset`` opening together (``opening_profile``)."""
    values = {j.child: opening_profile(n_frames, j.limit[1], open_fraction, stop_fraction) for j in asset.movable_joints}
    maps, images = [], []
    for t in range(n_frames):
        view, part_map, image = render_frame(asset, camera, {n: float(v[t]) for n, v in values.items()},
                                             textured=render_images)
        maps.append((view, part_map))
        images.append(image)
    return RenderedMotion(values, maps, np.stack(images) if render_images else None)


def simulate_video(asset, camera: Camera, n_frames: int = 24, degradation: Degradation = Degradation(),
                   seed: int = 0, render_images: bool = False, open_fraction: float = 0.8,
                   erosion_fraction: float = 0.02, max_points: int = 300,
                   rendered: RenderedMotion | None = None) -> SimulatedVideo:
    """Open every movable joint of ``asset`` together in front of ``camera`` and return the
    tracks (ground truth plus ``degradation``), with the frames when ``render_images``.
    ``rendered`` reuses a ``render_motion`` of the same camera and stop fraction."""
    rng = np.random.default_rng(seed)
    joints = {j.child: j for j in asset.movable_joints}
    if rendered is None:
        rendered = render_motion(asset, camera, n_frames, open_fraction, degradation.stop_fraction, render_images)
    values, frames_maps = rendered.values, rendered.maps
    n_frames = len(frames_maps)
    view0, part_map0 = frames_maps[0]
    masks0 = {p.name: part_map0 == i for i, p in enumerate(asset.parts)}
    drift_axis = rng.normal(size=3)
    drift_axis /= np.linalg.norm(drift_axis)
    tracks, anchors, outliers = {}, {}, {}
    for name, joint in joints.items():
        index = asset.part_index(name)
        queries = grid_queries(masks0[name], erosion_fraction, max_points=max_points)
        if not len(queries):
            continue
        rows, cols = np.floor(queries[:, 1]).astype(int), np.floor(queries[:, 0]).astype(int)
        p0 = view0.points[rows, cols]
        N = len(p0)
        scale = float(np.ptp(p0, axis=0).max()) or 1.0
        wobble_k = rng.normal(size=(3, 3)) * (2 * np.pi / max(scale, 1e-3))
        wobble_phase = rng.uniform(0, 2 * np.pi, 3)
        outlier = np.zeros(N, bool)
        imagined = np.zeros(3)
        if degradation.hallucinated > 0:
            centre = p0[rng.integers(N)]
            nearest = np.argsort(np.linalg.norm(p0 - centre, axis=1))
            outlier[nearest[:int(round(degradation.hallucinated * N))]] = True
            imagined = rng.normal(size=3)
            imagined *= 0.5 * scale / np.linalg.norm(imagined)
        xy = np.zeros((n_frames, N, 2))
        visible = np.zeros((n_frames, N), bool)
        top = max(float(np.abs(values[name]).max()), 1e-12)
        for t in range(n_frames):
            T = joint.transform(float(values[name][t]))
            pts = transform_points(p0, T)
            progress = abs(float(values[name][t])) / top
            if degradation.wobble_m:
                pts = pts + degradation.wobble_m * progress * np.sin(p0 @ wobble_k.T + wobble_phase)
            if outlier.any():
                pts[outlier] = p0[outlier] + progress * imagined
            cam_t = _drifted(camera, t / max(n_frames - 1, 1), degradation.drift_deg, drift_axis)
            xy[t] = project(cam_t, pts)
            # visible where the rendered frame shows this part at this depth
            true_xy, true_depth = camera.project(transform_points(p0, T))
            view_t, part_map_t = frames_maps[t]
            c = np.floor(true_xy[:, 0]).astype(int)
            r = np.floor(true_xy[:, 1]).astype(int)
            inside = (c >= 0) & (c < camera.width) & (r >= 0) & (r < camera.height)
            ok = np.zeros(N, bool)
            ok[inside] = (part_map_t[r[inside], c[inside]] == index) & (
                np.abs(view_t.depth[r[inside], c[inside]] - true_depth[inside]) < 0.01 + 0.002 * true_depth[inside])
            visible[t] = ok
        visible[0] = True
        if degradation.noise_px:
            xy[1:] += rng.normal(0.0, degradation.noise_px, xy[1:].shape)
        if degradation.dropout:
            visible[1:] &= rng.random(visible[1:].shape) >= degradation.dropout
        xy[0] = queries
        tracks[name] = Tracks(xy, visible)
        anchors[name] = p0
        outliers[name] = outlier
    return SimulatedVideo(camera, values, tracks, anchors, view0.depth, masks0, rendered.images, outliers)
