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


def split_pinched_vertices(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Faces (F, 3) rewritten so that the surface is a manifold with boundary, and (V',) the
    input vertex each output vertex copies. A vertex where fans of faces meet that share no
    edge of two faces around it (a bow-tie: two holes of a culled scan touching at a corner;
    two sheets on one edge, which has three or more faces) gets a copy per fan. Offsetting a
    pinched vertex once for all its fans makes a wall edge shared by four faces."""
    import networkx as nx

    faces = np.array(faces, dtype=np.int64)
    n = int(faces.max()) + 1 if len(faces) else 0
    source = list(range(n))
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    keys, counts = np.unique(edges, axis=0, return_counts=True)
    shared = {tuple(e) for e in keys[counts == 2].tolist()}
    pinched = np.bincount(keys[counts == 1].ravel(), minlength=n) > 2  # more than two rim edges meet
    pinched[keys[counts > 2].ravel()] = True
    corners = np.argsort(faces.ravel(), kind="stable")  # the faces round each vertex, found once
    first = np.searchsorted(faces.ravel()[corners], np.arange(n + 1))
    for vertex in np.flatnonzero(pinched):
        around = np.unique(corners[first[vertex]:first[vertex + 1]] // 3)
        fans = nx.Graph()
        fans.add_nodes_from(around.tolist())
        owner: dict[int, int] = {}  # the other end of each shared edge round the vertex -> a face on it
        for face in around:
            for other in faces[face][faces[face] != vertex].tolist():
                if (min(vertex, other), max(vertex, other)) not in shared:
                    continue
                if other in owner:
                    fans.add_edge(owner[other], int(face))
                owner.setdefault(other, int(face))
        for fan in list(nx.connected_components(fans))[1:]:
            fan = np.fromiter(fan, int)
            faces[fan] = np.where(faces[fan] == vertex, len(source), faces[fan])
            source.append(int(vertex))
    return faces, np.asarray(source, dtype=np.int64)


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
