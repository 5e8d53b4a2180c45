"""One sweep: a part moved through a joint's range against the rest, sample by sample.

Four questions are asked of it. How far a candidate joint opens before the part meets the rest
of the object (the joint rules and the video grounding, on the part meshes); what space a
collision hull passes through (the clearance, on convex hulls); and how deep the exported hulls
of the moving links go into the others at each sample (the validator, on the URDF). They differ
only in what stands for the part and in how one sample is measured. The sampling of a range,
the stop at the first blocked sample and the last free value are written here once.

On the part meshes the sweep is seam-aware: a fused mesh cut into parts meets its neighbours
along seams that touch at rest, so the faces within ``sweep_seam_radius`` of those seams are
left out (``seam_faces``), and the moving part is shrunk by ``sweep_margin`` so that contact it
already has at rest does not count.
"""

from __future__ import annotations

from typing import Callable, TypeVar

import numpy as np
import trimesh

from rest2art.config import JointsConfig
from rest2art.geometry.basics import joint_transform
from rest2art.geometry.fcl import bvh_object, collides_with_scene, scene_manager, set_pose
from rest2art.geometry.offsets import mitre_offsets

Sample = TypeVar("Sample")


def range_values(lower: float, upper: float, samples: int, with_lower: bool = False) -> np.ndarray:
    """(S,) joint values (rad or m) splitting [``lower``, ``upper``] into ``samples`` equal
    steps: the ``samples`` values after ``lower``, and ``lower`` first when ``with_lower``."""
    values = np.linspace(lower, upper, int(samples) + 1)
    return values if with_lower else values[1:]


def sweep_range(values: np.ndarray, measure: Callable[[float], Sample],
                blocked: Callable[[Sample], bool] | None = None) -> list[Sample]:
    """``measure`` at each of the (S,) joint ``values`` in order, up to and including the first
    sample that is ``blocked`` (every sample when ``blocked`` is None)."""
    out = []
    for value in values:
        out.append(measure(float(value)))
        if blocked is not None and blocked(out[-1]):
            break
    return out


def last_free(values: np.ndarray, samples: list, blocked: Callable[[object], bool], start: float = 0.0) -> float:
    """The last of ``values`` reached before the first blocked one of ``samples`` (measured at
    those values, in order); ``start`` when the first is blocked."""
    free = start
    for value, sample in zip(values, samples):
        if blocked(sample):
            break
        free = float(value)
    return free


def sweep_steps(kind: str, axis: np.ndarray, origin: np.ndarray, upper: float, vertices: np.ndarray,
                config: JointsConfig) -> int:
    """Samples over (0, ``upper``] so that no point of the part (``vertices`` (V, 3)) moves
    more than ``sweep_max_step`` between two of them: a thin panel in the way must not be
    jumped over. At least ``sweep_steps``."""
    if kind == "prismatic":
        travel = abs(upper)
    else:
        offset = vertices - origin
        radius = np.linalg.norm(offset - np.outer(offset @ axis, axis), axis=1).max() if len(vertices) else 0.0
        travel = float(radius) * abs(upper)
    return int(max(config.sweep_steps, np.ceil(travel / config.sweep_max_step)))


def sweep_free_range(moving, manager, kind: str, axis: np.ndarray, origin: np.ndarray,
                     upper: float, steps: int) -> float:
    """Largest sampled joint value in (0, ``upper``] that the fcl object ``moving`` reaches
    before it first touches an object of ``manager`` (a mesh-vs-mesh query says whether two
    surfaces cross, not how deep)."""
    def touches(value: float) -> bool:
        set_pose(moving, joint_transform(kind, axis, origin, value))
        return collides_with_scene(moving, manager)

    values = range_values(0.0, upper, steps)
    hits = sweep_range(values, touches, blocked=bool)
    set_pose(moving, np.eye(4))
    return last_free(values, hits, bool)


def seam_faces(meshes: dict[str, trimesh.Trimesh], name: str, radius: float) -> dict[str, np.ndarray]:
    """Per part, the (F,) faces within ``radius`` (m) of a vertex that part ``name`` shares
    with another part (the seam of a fused mesh cut into parts); all False without seams."""
    from scipy.spatial import cKDTree

    from rest2art.io.load import merged_vertex_ids

    own = meshes[name].vertices
    others = [m.vertices for n, m in meshes.items() if n != name]
    ids = merged_vertex_ids(np.concatenate([own, *others]))
    shared = np.isin(ids[: len(own)], ids[len(own):])
    if not shared.any():
        return {n: np.zeros(len(m.faces), bool) for n, m in meshes.items()}
    tree = cKDTree(own[shared])
    out = {}
    for n, m in meshes.items():
        near, _ = tree.query(m.vertices, distance_upper_bound=radius)
        out[n] = np.isfinite(near)[m.faces].any(axis=1)
    return out


def sweep_objects(meshes: dict[str, trimesh.Trimesh], name: str, config: JointsConfig):
    """The fcl object of part ``name`` for its opening sweep, shrunk by ``sweep_margin``, and
    a broad-phase manager over the other parts; both without the faces along their seams
    with this part (``seam_faces``). Where the shrunk part still meets the rest at rest, the
    shrink doubles until it does not, up to ``sweep_max_margin``."""
    seams = seam_faces(meshes, name, config.sweep_seam_radius)
    mesh = meshes[name]
    own = mesh.faces[~seams[name]]
    kept = {n: m.faces[~seams[n]] for n, m in meshes.items() if n != name}
    others = scene_manager([bvh_object(meshes[n].vertices, faces) for n, faces in kept.items() if len(faces)])
    # shrunk a little: contact the part already has at rest (real assets' doors often touch
    # their carcass, or sit a few millimetres into it) must not count, a swing into the carcass
    # still does
    margin = config.sweep_margin
    while True:
        shrunk = mesh.vertices - mitre_offsets(mesh, np.full(len(mesh.vertices), margin))
        moving = bvh_object(shrunk, own if len(own) else mesh.faces)  # a part that is all seam keeps it
        if margin >= config.sweep_max_margin or not collides_with_scene(moving, others):
            return moving, others
        margin = min(2.0 * margin, config.sweep_max_margin)


def free_range(meshes: dict[str, trimesh.Trimesh], name: str, kind: str, axis: np.ndarray, origin: np.ndarray,
               upper: float, config: JointsConfig) -> float:
    """How far (rad or m, within ``upper``) part ``name`` of ``meshes`` moves about or along
    ``axis`` through ``origin`` before it meets another part (``sweep_objects``)."""
    moving, others = sweep_objects(meshes, name, config)
    steps = sweep_steps(kind, axis, origin, upper, meshes[name].vertices, config)
    return sweep_free_range(moving, others, kind, axis, origin, upper, steps)


def farthest_along(vertices: np.ndarray, joint, direction: np.ndarray) -> float:
    """Largest ``direction`` . x (m) that any of ``vertices`` (V, 3) reaches over ``joint``'s
    range (its ``type``, unit ``axis``, ``origin`` and ``limit``), exactly: a slide's extreme
    lies at an end of its range; a point turning by t about a hinge has
    d . x(t) = A cos t + B sin t + C, largest at t = atan2(B, A) when that lies in the range."""
    lower, upper = (float(v) for v in joint.limit)
    axis, origin = np.asarray(joint.axis, float), np.asarray(joint.origin, float)
    d = np.asarray(direction, float)
    if joint.type == "prismatic":
        return float((vertices @ d).max() + max(lower * (axis @ d), upper * (axis @ d)))
    r = np.asarray(vertices, float) - origin
    along = r @ axis
    a = r @ d - along * (axis @ d)
    b = np.cross(axis, r) @ d
    c = along * (axis @ d) + origin @ d
    ends = np.maximum(a * np.cos(lower) + b * np.sin(lower), a * np.cos(upper) + b * np.sin(upper))
    peak = np.arctan2(b, a)
    peak = peak + 2 * np.pi * np.ceil((lower - peak) / (2 * np.pi))  # the first peak at or after the lower limit
    inside = peak <= upper
    best = np.where(inside, np.hypot(a, b), ends)
    return float((best + c).max())


def swept_points(vertices: np.ndarray, motion: Callable[[float], np.ndarray], values: np.ndarray) -> np.ndarray:
    """(S * V, 3): the (V, 3) ``vertices`` at every joint value of ``values`` (S,), moved by
    ``motion(value)``, a (4, 4) transform."""
    return np.concatenate([trimesh.transform_points(vertices, motion(float(v))) for v in values])
