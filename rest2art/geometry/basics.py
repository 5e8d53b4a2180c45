"""Small geometric helpers on numpy arrays (rotations, transforms, boxes)."""

from __future__ import annotations

import numpy as np

from rest2art.tolerances import FACING_COS, TINY


def unit(v: np.ndarray) -> np.ndarray:
    """v / |v| along the last axis."""
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def rotation_about(axis: np.ndarray, angle: float) -> np.ndarray:
    """(3, 3) Rodrigues rotation by ``angle`` rad about unit ``axis``."""
    k = unit(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def perpendicular_basis(direction: np.ndarray) -> np.ndarray:
    """(2, 3) two unit vectors orthogonal to ``direction`` and to each other."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    helper = np.eye(3)[int(np.argmin(np.abs(d)))]
    e1 = np.cross(d, helper)
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(d, e1)])


def panel_frame(outward: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two in-plane unit axes (u, v) of a panel facing ``outward``: u horizontal, v 'up'."""
    if abs(outward[2]) > 0.5:  # facing up: u = x, v = y (towards the back)
        return np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    v = np.array([0.0, 0.0, 1.0])
    u = np.cross(v, outward)
    return -u / np.linalg.norm(u), v


def protrusion_size(vertices: np.ndarray, outward: np.ndarray) -> tuple[float, float]:
    """(how far, how wide) a protrusion's (N, 3) ``vertices`` extend along ``outward`` (3,) and
    across it (the larger extent in its plane), m."""
    basis = perpendicular_basis(outward)
    return float(np.ptp(vertices @ outward)), float(np.ptp(vertices @ basis.T, axis=0).max())


def signed_volume(mesh) -> float:
    """Volume (m^3) a closed ``mesh`` (trimesh.Trimesh) encloses, negative when it is wound
    inward; 0 for a flat one, without the warning trimesh's centre of mass divides it into."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return float(mesh.volume)


def principal_axes(points: np.ndarray) -> np.ndarray:
    """(3, 3) unit principal axes of the (N, 3) ``points`` about their mean, as rows, the
    least spread first and the longest last (signs arbitrary)."""
    centred = points - points.mean(axis=0)
    return np.linalg.eigh(centred.T @ centred)[1].T


def footprint_spread(points: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(2,) standard deviations (m), larger first, of the area inside the convex outline of
    ``points`` (N, 3) seen along ``direction`` (3,): the footprint's spread along its principal
    axes, whatever the density of the vertices (a disc's rim and a bar's many corners weigh by
    the area they enclose). Zeros for a footprint without area."""
    return footprint_axes(points, direction)[0]


def footprint_axes(points: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((2,) spreads (m), larger first, (2, 3) unit axes along them) of the area inside the
    convex outline of ``points`` (N, 3) seen along ``direction`` (3,) (``footprint_spread``);
    zeros and the plane's basis for a footprint without area."""
    import shapely
    from trimesh.path.polygons import second_moments

    basis = perpendicular_basis(direction)
    outline = shapely.MultiPoint(points @ basis.T).convex_hull
    if outline.geom_type != "Polygon" or outline.area <= 0:
        return np.zeros(2), basis
    (ixx, iyy, ixy), _, _, _ = second_moments(outline, return_centered=True)  # ixx: of y, iyy: of x
    variance, vectors = np.linalg.eigh(np.array([[iyy, ixy], [ixy, ixx]]) / outline.area)
    return np.sqrt(np.maximum(variance[::-1], 0.0)), vectors[:, ::-1].T @ basis


def inner_grid(share: float, count: int) -> np.ndarray:
    """(count,) evenly spaced fractions over the middle ``share`` of [0, 1] (a grid of rays over
    the inner part of a panel, clear of its rounded edges)."""
    margin = (1.0 - share) / 2
    return np.linspace(margin, 1.0 - margin, count)


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


def thin_along(size: np.ndarray, outward: np.ndarray, flatness: float) -> bool:
    """Whether an object of box ``size`` (3,), m, is at least ``flatness`` times as wide or tall
    as it is deep along the axis nearest ``outward`` (3,): a window in its frame, whose panes
    may be sashes and whose glass sits sunk in its bars; a cabinet is a deep box."""
    facing = int(np.argmax(np.abs(outward)))
    return bool(np.delete(size, facing).max() >= flatness * size[facing])


def box_distance(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(N,) Euclidean distance of (N, D) points to the axis-aligned box [lo, hi] (0 inside)."""
    return np.linalg.norm(np.maximum(np.maximum(lo - points, points - hi), 0.0), axis=1)


def inside_box(lo: np.ndarray, hi: np.ndarray, box_lo: np.ndarray, box_hi: np.ndarray, tolerance: float) -> np.ndarray:
    """(N,) bool: which boxes (``lo``, ``hi`` (N, 3), m) lie inside the box (``box_lo``,
    ``box_hi`` (3,)) grown by ``tolerance``."""
    return np.all((lo >= box_lo - tolerance) & (hi <= box_hi + tolerance), axis=1)


def boxes_overlap(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray) -> np.ndarray:
    """(A, B) bool: which axis-aligned boxes ``lo_a, hi_a`` (A, 3) touch or overlap which boxes
    ``lo_b, hi_b`` (B, 3)."""
    return np.all((lo_a[:, None] <= hi_b[None]) & (lo_b[None] <= hi_a[:, None]), axis=2)


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


def separating_overlaps(va: np.ndarray, na: np.ndarray, vb: np.ndarray, nb: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Separating-axis test of two convex polytopes over both sets of face normals: (K,) overlap
    of their projections on each axis (m, <= 0 where the axis separates them) and the (K, 3)
    unit axes oriented from A into B, smallest overlap first. Moving B by the overlap along an
    axis, or cutting A back by it, separates them. ``va``, ``vb`` (N, 3) vertices and ``na``,
    ``nb`` (F, 3) unit face normals, one frame."""
    normals = np.concatenate([na, nb])
    pa, pb = va @ normals.T, vb @ normals.T
    a_below = pa.max(axis=0) - pb.min(axis=0)  # overlap when A lies on the low side of the axis
    b_below = pb.max(axis=0) - pa.min(axis=0)
    overlap = np.minimum(a_below, b_below)
    axes = np.where((a_below <= b_below)[:, None], normals, -normals)
    order = np.argsort(overlap, kind="stable")
    return overlap[order], axes[order]


def convex_overlap(va: np.ndarray, na: np.ndarray, vb: np.ndarray, nb: np.ndarray) -> tuple[float, np.ndarray]:
    """Penetration of two convex polytopes: (depth in m, (3,) unit axis from A into B); 0 when a
    face normal separates them (see ``separating_overlaps``). The depth is exact when the
    deepest contact is face-to-face and never below the true depth otherwise (edge-edge axes
    are left out)."""
    overlaps, axes = separating_overlaps(va, na, vb, nb)
    return max(0.0, float(overlaps[0])), axes[0]


def faces_at_extreme(mesh, direction: np.ndarray, band: float, extreme: float | None = None,
                     min_cos: float = FACING_COS) -> np.ndarray:
    """(F,) bool: faces of ``mesh`` whose normal is within ``acos(min_cos)`` of unit
    ``direction`` and whose centre lies within ``band`` (m) of the extreme along it (the mesh's
    own, or ``extreme`` (m) when given)."""
    along = mesh.triangles_center @ direction
    top = along.max() if extreme is None else extreme
    return (mesh.face_normals @ direction > min_cos) & (along >= top - band)


def outer_plane(mesh, direction: np.ndarray, band: float, resolution: float = 0.001) -> float:
    """Position along ``direction`` of the plane holding the most area facing it within
    ``band`` of the mesh's extreme (the carcass front, not the back wall of a cavity), m."""
    facing = faces_at_extreme(mesh, direction, band)
    if not facing.any():
        return float((mesh.vertices @ direction).max())
    return densest_plane(mesh, facing, direction, resolution)


def densest_plane(mesh, faces: np.ndarray, direction: np.ndarray, resolution: float = 0.001) -> float:
    """Position along ``direction`` (m, to ``resolution``) of the plane across it holding the
    most area of the (F,) bool ``faces`` of ``mesh`` (at least one)."""
    along = np.round(mesh.triangles_center[faces] @ direction / resolution).astype(np.int64)
    bins, inverse = np.unique(along, return_inverse=True)
    area = np.bincount(inverse.ravel(), weights=mesh.area_faces[faces])
    return float(bins[np.argmax(area)] * resolution)


def first_hits(mesh, origins: np.ndarray, direction: np.ndarray,
               solid: bool | np.ndarray = True) -> tuple[np.ndarray, np.ndarray]:
    """(N,) distance (m) from each of ``origins`` (N, 3) along the unit ``direction`` (3,) to
    the first surface of the trimesh ``mesh`` it meets (inf where it meets none), and (N,)
    whether that surface is turned away from the ray and bounds a solid (``solid``: for the
    whole mesh or (F,) per face): the ray started inside that solid."""
    locations, index_ray, index_tri = mesh.ray.intersects_location(origins, np.tile(direction, (len(origins), 1)),
                                                                   multiple_hits=False)
    distance = np.full(len(origins), np.inf)
    distance[index_ray] = (locations - origins[index_ray]) @ direction
    inside = np.zeros(len(origins), bool)
    inside[index_ray] = (mesh.face_normals[index_tri] @ direction > 0.0) & np.broadcast_to(solid, len(mesh.faces))[index_tri]
    return distance, inside


def ray_distances(mesh, origins: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(N,) distance (m) from each of ``origins`` (N, 3) along the unit ``direction`` (3,) to
    the first surface of the trimesh ``mesh`` it meets; inf where it meets none."""
    return first_hits(mesh, origins, direction)[0]


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
    length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1) + TINY
    n = len(vertices)
    g = sp.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    return g.maximum(g.T)
