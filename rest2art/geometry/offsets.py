"""Moving a mesh's vertices along its normals: open boundaries and mitred offsets.

Used where a surface is given a thickness (completion thickens open shells, the joint rules
measure how far a panel can be inset) without the offset surface crossing itself at corners.
"""

from __future__ import annotations

import numpy as np
import trimesh

from rest2art.tolerances import TINY


def boundary_edges(faces: np.ndarray) -> np.ndarray:
    """(B, 2) directed edges used by exactly one face (as oriented in that face)."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return edges[counts[inverse.ravel()] == 1]


def boundary_smoothed_normals(mesh: trimesh.Trimesh, rings: int, iterations: int = 25) -> np.ndarray:
    """(V, 3) vertex normals where the band of ``rings`` edge rings along the open boundary (a
    cut edge, often ragged on a scan) takes its normals from the interior: each band vertex is
    repeatedly set to the mean normal of its neighbours, the interior held fixed."""
    normals = np.array(mesh.vertex_normals, dtype=float)
    boundary = np.unique(boundary_edges(np.asarray(mesh.faces)))
    if rings <= 0 or len(boundary) == 0:
        return normals
    from rest2art.geometry.basics import vertex_graph

    adjacency = vertex_graph(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    adjacency.data[:] = 1.0  # neighbours, unweighted
    n = len(mesh.vertices)
    band = np.zeros(n, bool)
    band[boundary] = True
    for _ in range(rings - 1):
        band |= (adjacency @ band.astype(float)) > 0
    if band.all():
        return normals  # nothing interior to borrow from
    for _ in range(iterations):
        mean = adjacency @ normals
        length = np.linalg.norm(mean, axis=1, keepdims=True)
        ok = band & (length[:, 0] > TINY)
        normals[ok] = mean[ok] / length[ok]
    return normals


def mitre_offsets(mesh: trimesh.Trimesh, thickness: np.ndarray, max_scale: float = 3.0,
                  normals: np.ndarray | None = None) -> np.ndarray:
    """(V, 3) inward displacements that move every adjacent face plane by ``thickness``:
    along the vertex normal (``normals``, default the mesh's), lengthened by
    1 / min cos(vertex normal, face normal) (capped)."""
    normals = mesh.vertex_normals if normals is None else normals
    cos = np.einsum("ij,ij->i", normals[mesh.faces.ravel()], np.repeat(mesh.face_normals, 3, axis=0))
    min_cos = np.ones(len(mesh.vertices))
    np.minimum.at(min_cos, mesh.faces.ravel(), cos)
    scale = 1.0 / np.clip(min_cos, 1.0 / max_scale, 1.0)
    return normals * (thickness * scale)[:, None]
