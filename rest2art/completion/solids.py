"""Completion: every part becomes closed solids with mass and inertia.

Pieces are told apart by position, not by vertex index (an STL or a flat-shaded export repeats
every corner, and each triangle would be a shell of its own). Closed pieces (watertight,
positive volume) stay as they are. An open shell is thickened
inward: each vertex moves against its normal by min(delta, 0.45 * distance to the nearest
vertex of another part), never below the floor, and side walls close the rim. If that still
is not a valid volume, the piece's convex hull stands in (reported in the part's notes).
"""

from __future__ import annotations


import numpy as np
import trimesh
from scipy.spatial import cKDTree

from rest2art.asset import MassProperties
from rest2art.config import CompletionConfig
from rest2art.geometry.basics import signed_volume
from rest2art.geometry.offsets import boundary_edges, boundary_smoothed_normals, mitre_offsets, split_pinched_vertices
from rest2art.io.load import merged_vertex_ids
from rest2art.tolerances import TINY


def solidify_shell(mesh: trimesh.Trimesh, thickness: np.ndarray, smoothing_rings: int = 0) -> trimesh.Trimesh:
    """Close an open shell by offsetting it inward by ``thickness`` (V,) metres, with normals
    smoothed over ``smoothing_rings`` rings along its open boundary. Pinched vertices are split
    first and nothing is merged after: the result is closed by construction wherever every
    edge of the shell has at most two faces."""
    f, source = split_pinched_vertices(np.asarray(mesh.faces))
    thickness = np.asarray(thickness)[source]
    mesh = trimesh.Trimesh(np.asarray(mesh.vertices)[source], f, process=False)
    v = np.asarray(mesh.vertices)
    inner = v - mitre_offsets(mesh, thickness, normals=boundary_smoothed_normals(mesh, smoothing_rings))
    n = len(v)
    walls = []
    for a, b in boundary_edges(f):
        walls.append([b, a, a + n])
        walls.append([b, a + n, b + n])
    faces = np.concatenate([f, f[:, ::-1] + n, np.array(walls, dtype=np.int64).reshape(-1, 3)])
    return trimesh.Trimesh(np.concatenate([v, inner]), faces, process=False)


def capped_shell(shell: trimesh.Trimesh) -> trimesh.Trimesh | None:
    """A bump-like open shell (a knob cut from a fused surface) closed by a fan across each
    boundary loop, so that it sits on the surface it was cut from instead of being thickened
    into it. None when a loop is not a simple cycle or the result is not a volume."""
    import networkx as nx

    from rest2art.geometry.basics import is_closed_volume

    v, f = np.asarray(shell.vertices), np.asarray(shell.faces)
    edges = boundary_edges(f)
    if len(edges) == 0:
        return None
    graph = nx.Graph()
    graph.add_edges_from(map(tuple, edges))
    if any(d != 2 for _, d in graph.degree()):
        return None
    vertices, faces = [v], [f]
    for k, loop in enumerate(nx.connected_components(graph)):
        loop = np.fromiter(loop, int)
        centre = len(v) + k
        vertices.append(v[loop].mean(axis=0)[None])
        mine = edges[np.isin(edges[:, 0], loop)]
        faces.append(np.column_stack([mine[:, 1], mine[:, 0], np.full(len(mine), centre)]))
    solid = trimesh.Trimesh(np.concatenate(vertices), np.concatenate(faces), process=True)
    if not solid.is_watertight:
        return None
    if signed_volume(solid) < 0:
        solid.invert()
    return solid if is_closed_volume(solid) else None


def solid_pieces(mesh: trimesh.Trimesh, other_vertices: np.ndarray | None,
                 config: CompletionConfig = CompletionConfig(), cap: bool = False
                 ) -> tuple[list[trimesh.Trimesh], list[str]]:
    """Closed solids that make up ``mesh`` and notes on what was done; with ``cap``, open
    pieces are first closed across their rim (protrusions such as knobs)."""
    notes = []
    solids = []
    others = cKDTree(other_vertices) if other_vertices is not None and len(other_vertices) else None
    for piece in welded(mesh).split(only_watertight=False):
        if piece.is_watertight:
            volume = signed_volume(piece)
            if volume < 0:
                piece.invert()
            if abs(volume) > TINY:
                solids.append(piece)
                continue
        if cap:
            capped = capped_shell(piece)
            if capped is not None:
                solids.append(capped)
                notes.append(f"open shell of {len(piece.faces)} faces capped across its rim")
                continue
        thickness = np.full(len(piece.vertices), config.thickness)
        if others is not None:  # one tree for all pieces: a scan can have thousands
            d, _ = others.query(piece.vertices)
            thickness = np.minimum(thickness, config.thickness_gap_share * d)
        thickness = np.maximum(thickness, config.thickness_floor)
        solid = solidify_shell(piece, thickness, config.boundary_smoothing_rings)
        if solid.is_watertight and signed_volume(solid) > 0:
            solids.append(solid)
            notes.append(f"open shell of {len(piece.faces)} faces thickened inward")
        elif len(piece.vertices) >= 4:
            solids.append(piece.convex_hull)
            notes.append(f"piece of {len(piece.faces)} faces replaced by its convex hull")
    return solids, notes


def welded(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """``mesh`` with corners at the same position (``merged_vertex_ids``) made one vertex;
    faces keep their order."""
    ids = merged_vertex_ids(mesh.vertices)
    first = np.unique(ids, return_index=True)[1]
    return trimesh.Trimesh(mesh.vertices[first], ids[mesh.faces], process=False)


def drawer_tray(front: trimesh.Trimesh, opening: np.ndarray, up: np.ndarray, carcass_back: float,
                config: CompletionConfig = CompletionConfig()) -> trimesh.Trimesh | None:
    """An open-top box behind a drawer front (paper: 0.75x the drawer's extents, depth = the free
    space to the carcass back, wall thickness delta), or None when the drawer already has depth
    or there is no room. ``opening`` (3,) is the unit direction the drawer slides out, ``up``
    (3,) the object's up, ``carcass_back`` the carcass's rearmost coordinate along ``opening``
    (m). Returns a watertight solid in the same frame as ``front``."""
    a = opening / np.linalg.norm(opening)
    w = np.cross(up, a)
    w /= np.linalg.norm(w)
    u = np.cross(a, w)
    local = np.asarray(front.vertices) @ np.column_stack([a, w, u])
    if np.ptp(local[:, 0]) > config.tray_min_depth:
        return None  # a modelled drawer box already
    back = local[:, 0].min()
    depth = back - carcass_back - config.thickness - config.tray_clearance
    width, height = config.tray_scale * np.ptp(local[:, 1]), config.tray_scale * np.ptp(local[:, 2])
    wall = config.thickness
    if depth < 3 * wall or min(width, height) < 3 * wall:
        return None
    centre_w, centre_u = local[:, 1].min() + np.ptp(local[:, 1]) / 2, local[:, 2].min() + np.ptp(local[:, 2]) / 2
    outer = trimesh.creation.box((depth, width, height))
    inner = trimesh.creation.box((depth - 2 * wall, width - 2 * wall, height))
    inner.apply_translation([0.0, 0.0, wall])  # open at the top, floor of thickness wall
    tray = trimesh.boolean.difference([outer, inner], engine="manifold")
    T = np.eye(4)
    T[:3, :3] = np.column_stack([a, w, u])
    T[:3, 3] = (back - depth / 2) * a + centre_w * w + centre_u * u
    tray.apply_transform(T)
    return tray if tray.is_watertight and signed_volume(tray) > 0 else None


def mass_properties(solids: list[trimesh.Trimesh], density: float,
                    config: CompletionConfig = CompletionConfig()) -> MassProperties:
    """Mass, centre of mass and inertia of a union of disjoint solids of uniform ``density``."""
    masses, coms, inertias = [], [], []
    for s in solids:
        props = s.mass_properties
        vol = float(props["volume"])
        if vol <= 0:
            continue
        masses.append(vol * density)
        coms.append(np.asarray(props["center_mass"]))
        inertias.append(np.asarray(props["inertia"]) * density)  # trimesh: about the COM
    notes = []
    if not masses:
        notes.append("no volume: minimum mass used")
        return MassProperties(config.min_mass, np.zeros(3), np.eye(3) * config.min_inertia, notes)
    m = np.array(masses)
    total = float(m.sum())
    com = (np.array(coms) * m[:, None]).sum(axis=0) / total
    inertia = np.zeros((3, 3))
    for mi, ci, Ii in zip(m, coms, inertias):
        r = ci - com
        inertia += Ii + mi * (r @ r * np.eye(3) - np.outer(r, r))
    if total < config.min_mass:
        inertia *= config.min_mass / total
        total = config.min_mass
        notes.append("mass raised to the minimum")
    evals, evecs = np.linalg.eigh((inertia + inertia.T) / 2)  # ascending
    evals = np.maximum(evals, config.min_inertia)
    # MuJoCo checks I1 + I2 >= I3. True solids satisfy it, but a thin panel is at equality and
    # clamping or the 6 digits written to URDF/MJCF can break it: keep a small relative margin.
    deficit = evals[2] * (1 + 1e-4) - evals[0] - evals[1]
    if deficit > 0:
        evals[:2] += deficit / 2
    inertia = evecs @ np.diag(evals) @ evecs.T
    return MassProperties(total, com, inertia, notes)


def decimated(mesh: trimesh.Trimesh, max_faces: int) -> trimesh.Trimesh:
    """``mesh`` reduced to at most about ``max_faces`` faces by quadric decimation (unchanged
    when it is already small enough). Watertightness is not guaranteed."""
    if len(mesh.faces) <= max_faces:
        return mesh
    import fast_simplification

    v, f = fast_simplification.simplify(np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.int32),
                                        target_reduction=1.0 - max_faces / len(mesh.faces))
    return trimesh.Trimesh(v.astype(np.float64), f, process=True)


def simplified(solid: trimesh.Trimesh, max_faces: int) -> trimesh.Trimesh:
    """``solid`` decimated to at most ``max_faces`` faces when that keeps it watertight (CoACD's
    time grows with the face count; collision geometry does not need a scan's detail)."""
    small = decimated(solid, max_faces)
    return small if small is solid or (small.is_watertight and signed_volume(small) > 0) else solid


def collision_solids(shell: trimesh.Trimesh, solids: list[trimesh.Trimesh], other_vertices: np.ndarray | None,
                     completion: CompletionConfig, max_faces: int) -> list[trimesh.Trimesh]:
    """Closed solids to decompose for one part: its completed ``solids`` when they are small or
    decimate cleanly; otherwise (a thick scan shell decimates into non-manifold walls) the open
    ``shell`` is decimated first and thickened again, which is watertight by construction
    unless the decimated shell folds over itself: then its convex hull would stand in for a
    hollow part, and the completed solids are kept as they are."""
    small = [simplified(s, max_faces) for s in solids]
    if all(len(s.faces) <= max_faces for s in small):
        return small
    rebuilt, notes = solid_pieces(decimated(shell, max_faces // 2), other_vertices, completion)
    if any("convex hull" in note for note in notes):
        return small
    return rebuilt or small


def part_solids(mesh: trimesh.Trimesh, others: np.ndarray | None, semantic: str, completion: CompletionConfig,
                max_faces: int) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh], list[str]]:
    """One part's closed solids (for mass), the solids to decompose for collision, and notes.
    ``mesh`` is the part's surface, ``others`` (N, 3) the vertices of every other part (they
    cap the thickening), ``semantic`` its class (knobs and the like are capped, not thickened)."""
    solids, notes = solid_pieces(mesh, others, completion, cap=semantic in completion.cap_semantics)
    return solids, collision_solids(mesh, solids, others, completion, max_faces), notes
