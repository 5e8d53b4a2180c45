"""Loading an input mesh: formats, scene flattening, per-face source ids, sanity checks.

Supported: OBJ, PLY, STL, OFF, GLB and GLTF. Everything is triangulated.

Face order (what ``face_part.npy`` indexes): the geometries of the file in the order the scene
graph lists them (file order for OBJ objects and GLTF nodes), each geometry's faces in file
order, polygons fanned into triangles in place. Each face keeps

* ``face_node``: index of the scene node / OBJ object it came from, and
* ``face_component``: a global index of its connected piece (a connected component of one node),

because artist meshes carry part hints in both.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh

from rest2art.config import LoadConfig
from rest2art.errors import InputError
from rest2art.tolerances import TINY

SUFFIXES = {".obj": "obj", ".ply": "ply", ".stl": "stl", ".off": "off", ".glb": "glb", ".gltf": "gltf"}
UNIT_SCALE = {"m": 1.0, "cm": 0.01, "mm": 0.001}


@dataclass
class LoadedMesh:
    """A triangle mesh as loaded, in metres, with per-face source ids."""

    vertices: np.ndarray
    """(V, 3) float64, metres."""
    faces: np.ndarray
    """(F, 3) int64."""
    face_node: np.ndarray
    """(F,) int32 scene node / object index."""
    face_component: np.ndarray
    """(F,) int32 connected piece index (global over nodes)."""
    node_names: list[str] = field(default_factory=list)
    path: Path | None = None
    scale_to_metres: float = 1.0
    """Factor applied to the file's coordinates (1 unless ``units`` was given)."""
    notes: list[str] = field(default_factory=list)
    """Non-fatal observations (degenerate faces, decimation ...)."""

    def trimesh(self) -> trimesh.Trimesh:
        """The mesh as a trimesh object (no processing, face order kept)."""
        return trimesh.Trimesh(self.vertices, self.faces, process=False)


def merged_vertex_ids(vertices: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """(V,) one id per distinct position (to ``tol`` relative to the size): STL and other
    triangle soups repeat every corner, so connectivity must not rely on vertex indices."""
    scale = max(float(np.abs(vertices).max()), TINY)
    keys = np.round(vertices / (tol * scale)).astype(np.int64)
    _, ids = np.unique(keys, axis=0, return_inverse=True)
    return ids.ravel()


def first_copies(vertices: np.ndarray, faces: np.ndarray, face_node: np.ndarray, share: float) -> np.ndarray:
    """(F,) for each face of a double-sided node the index of the first face of that node with
    the same three corners (by position, wound either way); elsewhere, and for the first of
    its copies, a face's own index. A node is double-sided when at least ``share`` of its
    faces repeat another (an export that writes every face twice, wound both ways); a stray
    repeated facet elsewhere is kept."""
    ids = np.sort(merged_vertex_ids(vertices)[faces], axis=1)
    _, first, inverse = np.unique(np.column_stack([face_node, ids]), axis=0, return_index=True, return_inverse=True)
    first = first[inverse.ravel()]
    repeated = first != np.arange(len(faces))
    nodes = np.bincount(face_node)
    doubled = np.bincount(face_node, repeated, minlength=len(nodes)) >= share * np.maximum(nodes, 1) / 2
    return np.where(doubled[face_node], first, np.arange(len(faces)))


def connected_components(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(F,) component label per face; faces sharing a vertex index are connected (pass faces
    re-indexed with :func:`merged_vertex_ids` to connect by position)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components as cc

    n_faces = len(faces)
    rows = np.repeat(np.arange(n_faces), 3)
    graph = coo_matrix((np.ones(rows.size), (rows, faces.ravel() + n_faces)),
                       shape=(n_faces + n_vertices, n_faces + n_vertices))
    _, labels = cc(graph, directed=False)
    face_labels = labels[:n_faces]
    _, compact = np.unique(face_labels, return_inverse=True)
    return compact.astype(np.int32)


def outward_wound(vertices: np.ndarray, faces: np.ndarray, face_component: np.ndarray,
                  config: LoadConfig = LoadConfig()) -> tuple[np.ndarray, int]:
    """(F, 3) ``faces`` with every piece (``face_component``) wound outward, and how many pieces
    were turned. A mirrored export winds its pieces inward, and every normal would point into
    the object. A piece is turned when cameras around the object (``winding_views``) see its
    faces from behind over ``winding_back_ratio`` times as often as from the front: a carcass
    open at its front shows its inside through the opening but its outside everywhere else, and
    the inward shell round a cavity inside a solid is never seen; the pieces no camera sees are
    turned with the rest when the whole object is seen from behind that often. Only pieces whose
    faces face the object's centre more than away from it (negative volume enclosed with the
    centre) are looked at: most faces of a piece wound outward face away from it."""
    tri = vertices[faces] - vertices.mean(axis=0)
    n_pieces = int(face_component.max()) + 1
    volume = np.bincount(face_component, np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0,
                         minlength=n_pieces)
    suspect = volume < 0
    if not suspect.any():
        return faces, 0
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    front, back = seen_sides(vertices, faces, normals, config)
    front, back = (np.bincount(face_component, side, minlength=n_pieces) for side in (front, back))
    turn = suspect & (back > config.winding_back_ratio * front)
    if back.sum() > config.winding_back_ratio * front.sum():
        # the file as a whole is seen from behind: a mirrored export winds every piece the same
        # way, the ones no camera sees (a drawer's box inside the carcass) too
        turn |= suspect & (front + back == 0)
    if not turn.any():
        return faces, 0
    out = faces.copy()
    flip = turn[face_component]
    out[flip] = out[flip][:, ::-1]
    return out, int(turn.sum())


def seen_sides(vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray,
               config: LoadConfig) -> tuple[np.ndarray, np.ndarray]:
    """(F,) pixels at which cameras spread over a sphere around the mesh see each face from
    the side its ``normals`` (F, 3) point to, and (F,) from the other side where no face
    seen from its front lies as near (within a pixel): two coincident faces wound against
    each other, a solid's face and the shell of a cavity cut flush with it, are seen from
    the front."""
    from rest2art.render.camera import cameras_around
    from rest2art.render.raster import render_views

    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2) or 1.0
    cameras = cameras_around(centre, config.winding_camera_radius * radius, config.winding_views,
                             config.winding_fov_deg, config.winding_view_size)
    front, back = np.zeros(len(faces)), np.zeros(len(faces))
    facing = render_views(vertices, faces, cameras, cull_backfaces=True)
    for view, fronts in zip(render_views(vertices, faces, cameras, cull_backfaces=False), facing):
        hit = view.face >= 0
        seen = view.face[hit]
        towards = np.einsum("ij,ij->i", normals[seen], view.points[hit] - view.camera.eye) < 0
        front_as_near = fronts.depth[hit] <= view.depth[hit] + view.camera.pixel_size(view.depth[hit])
        front += np.bincount(seen[towards], minlength=len(faces))
        back += np.bincount(seen[~towards & ~front_as_near], minlength=len(faces))
    return front, back


def _components_within(faces: np.ndarray, vertices: np.ndarray, face_node: np.ndarray) -> np.ndarray:
    """Global piece ids: connected components (by position), never spanning two nodes."""
    n_vertices = len(vertices)
    out = np.empty(len(faces), np.int32)
    offset = 0
    ids = merged_vertex_ids(vertices)
    for node in np.unique(face_node):
        idx = np.flatnonzero(face_node == node)
        comp = connected_components(ids[faces[idx]], n_vertices)
        out[idx] = comp + offset
        offset += int(comp.max()) + 1
    return out


def _read_geometries(path: Path) -> tuple[list[trimesh.Trimesh], list[str]]:
    file_type = SUFFIXES[path.suffix.lower()]
    try:
        loaded = trimesh.load(path, file_type=file_type, process=False, force="scene",
                              maintain_order=True)
    except Exception as exc:  # trimesh raises many kinds of errors on bad files
        raise InputError(f"{path}: could not be read as a {file_type.upper()} mesh ({exc})") from None
    meshes, names = [], []
    for node in loaded.graph.nodes_geometry:
        transform, geom_name = loaded.graph[node]
        geom = loaded.geometry[geom_name]
        if isinstance(geom, trimesh.PointCloud):
            raise InputError(f"{path}: holds a point cloud, not a mesh; mesh it first (e.g. Poisson)")
        if not isinstance(geom, trimesh.Trimesh):
            continue
        mesh = geom.copy()
        mesh.apply_transform(transform)
        meshes.append(mesh)
        names.append(str(node))
    return meshes, names


def obj_face_objects(path: Path, n_faces: int) -> tuple[np.ndarray, list[str]] | None:
    """(F,) object index per triangle of an OBJ file, from its ``o`` (else ``g``) statements,
    with polygons fanned into triangles; None when the count does not match ``n_faces``."""
    names: list[str] = []
    counts: list[int] = []
    keyword = None
    with open(path, "r", errors="replace") as handle:
        lines = handle.readlines()
    if any(line.startswith("o ") for line in lines):
        keyword = "o"
    elif any(line.startswith("g ") for line in lines):
        keyword = "g"
    for line in lines:
        if keyword and line.startswith(keyword + " "):
            names.append(line[2:].strip() or f"object_{len(names)}")
            counts.append(0)
        elif line.startswith("f "):
            if not counts:
                names.append("object_0")
                counts.append(0)
            counts[-1] += max(len(line.split()) - 3, 0)
    if sum(counts) != n_faces or not counts:
        return None
    keep = [k for k, c in enumerate(counts) if c]
    labels = np.repeat(np.arange(len(keep), dtype=np.int32), [counts[k] for k in keep])
    return labels, [names[k] for k in keep]


def load_mesh(path: str | Path, config: LoadConfig = LoadConfig(), units: str | None = None) -> LoadedMesh:
    """Load and check a mesh file; see the module docstring for the face order.

    ``units`` ('mm', 'cm' or 'm') declares the file's unit and scales it to metres. Without it
    nothing is rescaled: an implausible size raises :class:`InputError` with a hint.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: file not found")
    if path.is_dir():
        raise InputError(f"{path}: is a folder, expected a mesh file ({', '.join(SUFFIXES)})")
    if path.suffix.lower() not in SUFFIXES:
        raise InputError(
            f"{path}: unsupported file type '{path.suffix}'. Supported: {', '.join(SUFFIXES)}"
        )
    if units is not None and units not in UNIT_SCALE:
        raise InputError(f"--units {units}: expected one of {', '.join(UNIT_SCALE)}")
    if path.stat().st_size == 0:
        raise InputError(f"{path}: file is empty")
    meshes, names = _read_geometries(path)
    meshes_with_faces = [(m, n) for m, n in zip(meshes, names) if len(m.faces)]
    if not meshes_with_faces:
        raise InputError(f"{path}: contains no triangles (empty mesh or a point cloud)")

    vertices, faces, face_node, face_comp = [], [], [], []
    offset, comp_offset = 0, 0
    for node_index, (mesh, _) in enumerate(meshes_with_faces):
        v = np.asarray(mesh.vertices, dtype=np.float64)
        f = np.asarray(mesh.faces, dtype=np.int64)
        if not np.all(np.isfinite(v)):
            bad = int((~np.isfinite(v).all(axis=1)).sum())
            raise InputError(f"{path}: {bad} vertices are NaN or infinite; repair the mesh first")
        ids = merged_vertex_ids(v)
        comp = connected_components(ids[f], len(v))
        vertices.append(v)
        faces.append(f + offset)
        face_node.append(np.full(len(f), node_index, np.int32))
        face_comp.append(comp + comp_offset)
        offset += len(v)
        comp_offset += int(comp.max()) + 1
    loaded = LoadedMesh(
        np.concatenate(vertices), np.concatenate(faces), np.concatenate(face_node),
        np.concatenate(face_comp), [n for _, n in meshes_with_faces], path,
    )
    if path.suffix.lower() == ".obj" and len(meshes_with_faces) == 1:
        # trimesh keeps OBJ face order only when it does not split objects: read them here
        objects = obj_face_objects(path, len(loaded.faces))
        if objects is not None:
            loaded.face_node, loaded.node_names = objects
            loaded.face_component = _components_within(loaded.faces, loaded.vertices, loaded.face_node)
    check_mesh(loaded, config, units)
    loaded.faces, turned = outward_wound(loaded.vertices, loaded.faces, loaded.face_component, config)
    if turned:
        loaded.notes.append(f"{turned} pieces wound inward (a mirrored export) turned outward")
    return loaded


def check_mesh(mesh: LoadedMesh, config: LoadConfig, units: str | None) -> None:
    """Degenerate faces, size, units; scales to metres when ``units`` is given (in place)."""
    path = mesh.path
    largest = float(np.ptp(mesh.vertices[np.unique(mesh.faces)], axis=0).max())
    if largest > config.max_height / min(UNIT_SCALE.values()):  # too large in every unit: and squares overflow
        raise InputError(f"{path}: the object is {largest:.3g} units across, implausible in any unit "
                         f"({', '.join(UNIT_SCALE)}); check the file's coordinates")
    tri = mesh.vertices[mesh.faces]
    areas = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    extent = np.ptp(mesh.vertices[np.unique(mesh.faces)], axis=0)
    degenerate = areas <= 1e-12 * max(float(extent.max()) ** 2, 1e-30)
    if degenerate.all():
        raise InputError(f"{path}: all {len(areas)} faces have zero area (degenerate mesh)")
    if degenerate.any():
        mesh.notes.append(f"{int(degenerate.sum())} zero-area faces kept (labelled with their neighbours' part)")
    if len(mesh.faces) > config.max_faces:
        if not config.decimate_large:
            raise InputError(
                f"{path}: {len(mesh.faces):,} faces is over the limit of {config.max_faces:,}; "
                "decimate it first or set load.decimate_large: true in a --config file"
            )
        decimate(mesh, config.max_faces)
    if units is not None:
        mesh.scale_to_metres = UNIT_SCALE[units]
        mesh.vertices = mesh.vertices * mesh.scale_to_metres
        size = float(extent.max()) * mesh.scale_to_metres
        if not config.min_size <= size <= config.max_height:  # a declared unit is checked too
            raise InputError(
                f"{path}: with --units {units} the object is {size:.4g} m across, outside "
                f"[{config.min_size:g}, {config.max_height:g}] m; check the unit of the file"
            )
        return
    size = float(extent.max())
    if size > config.max_height:
        raise InputError(
            f"{path}: the object is {size:.1f} units across; in metres that is implausible. "
            "If the file is in millimetres or centimetres pass --units mm or --units cm"
        )
    if size < config.min_size:
        raise InputError(
            f"{path}: the object is only {size:.4f} units across; if it is not in metres "
            "pass --units (mm|cm|m) to declare its unit"
        )


def decimate(mesh: LoadedMesh, max_faces: int) -> None:
    """Quadric decimation to at most ``max_faces`` faces (in place; source ids recomputed)."""
    import fast_simplification

    ratio = 1.0 - max_faces / len(mesh.faces)
    v, f = fast_simplification.simplify(mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32),
                                        target_reduction=ratio)
    before = len(mesh.faces)
    mesh.vertices, mesh.faces = v.astype(np.float64), f.astype(np.int64)
    mesh.face_component = connected_components(merged_vertex_ids(mesh.vertices)[mesh.faces], len(mesh.vertices))
    mesh.face_node = np.zeros(len(mesh.faces), np.int32)
    mesh.notes.append(f"decimated from {before:,} to {len(mesh.faces):,} faces")
