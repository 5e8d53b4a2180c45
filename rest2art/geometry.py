"""Small geometric helpers on numpy arrays (rotations, transforms, boxes)."""

from __future__ import annotations

import numpy as np


def unit(v: np.ndarray) -> np.ndarray:
    """v / |v| along the last axis."""
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    """(3, 3) Rodrigues rotation by ``angle`` rad about unit ``axis``."""
    k = unit(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def joint_transform(kind: str, axis: np.ndarray, origin: np.ndarray, value: float) -> np.ndarray:
    """(4, 4) motion of a child at joint value ``value`` (rad or m) in the parent frame."""
    T = np.eye(4)
    if kind == "revolute":
        R = rotation_about(axis, value)
        T[:3, :3] = R
        T[:3, 3] = origin - R @ origin
    elif kind == "prismatic":
        T[:3, 3] = unit(axis) * value
    return T


def transform_points(points: np.ndarray, T: np.ndarray) -> np.ndarray:
    """(N, 3) points moved by the (4, 4) transform ``T``."""
    return points @ T[:3, :3].T + T[:3, 3]


def line_distance(p1: np.ndarray, d1: np.ndarray, p2: np.ndarray, d2: np.ndarray) -> float:
    """Distance between the infinite lines p1 + t d1 and p2 + s d2."""
    d1, d2 = unit(d1), unit(d2)
    n = np.cross(d1, d2)
    nn = np.linalg.norm(n)
    w = np.asarray(p2, float) - np.asarray(p1, float)
    if nn < 1e-8:  # parallel: distance of p2 from line 1
        return float(np.linalg.norm(w - np.dot(w, d1) * d1))
    return float(abs(np.dot(w, n)) / nn)


def axis_angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    """Sign-agnostic angle between two directions, degrees in [0, 90] (atan2 form: exact for
    equal directions, where arccos turns rounding into micro-degrees)."""
    a, b = unit(a), unit(b)
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(float(np.dot(a, b))))))


def opening_axis(axis: np.ndarray, hinge: np.ndarray, centre: np.ndarray, outward: np.ndarray) -> np.ndarray:
    """``axis`` or its negation: the one whose positive rotation about the line through ``hinge``
    moves ``centre`` along ``outward`` (so that positive joint values open)."""
    axis = np.asarray(axis, float)
    velocity = np.cross(axis, np.asarray(centre, float) - np.asarray(hinge, float))
    return axis if float(velocity @ np.asarray(outward, float)) >= 0 else -axis


def is_closed_volume(mesh) -> bool:
    """True when manifold3d accepts ``mesh`` as a solid with positive volume."""
    import manifold3d

    if len(mesh.faces) < 4:
        return False
    solid = manifold3d.Manifold(manifold3d.Mesh(np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.uint32)))
    return solid.status() == manifold3d.Error.NoError and not solid.is_empty() and solid.volume() > 0


def vertex_graph(vertices: np.ndarray, faces: np.ndarray):
    """(V, V) symmetric scipy CSR graph of the mesh's edges, weighted by edge length (m)."""
    import scipy.sparse as sp

    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1) + 1e-12
    n = len(vertices)
    g = sp.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    return g.maximum(g.T)
