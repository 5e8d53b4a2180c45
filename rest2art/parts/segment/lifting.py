"""Evidence lifting and graph refinement (paper: Confidence-Weighted Evidence Lifting,
Graph-Based Refinement).

Labels: 0 is the base, 1..P the parts, in the order of the ``evidence`` list.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from rest2art.config import SegmentConfig
from rest2art.geometry.basics import vertex_graph
from rest2art.render.raster import ViewMaps


@dataclass
class PartEvidence:
    """The masks one part was seen with."""

    masks: dict[int, np.ndarray]
    """view -> (H, W) bool mask."""
    scores: dict[int, float]
    """view -> detection confidence."""
    boost: dict[int, float] | None = None
    """view -> factor >= 1 (a parent seen with more of its children)."""


def view_weights(evidence: PartEvidence, top_k: int) -> dict[int, float]:
    """The part's K best views and their weights: score = confidence x log(mask area in
    pixels) x boost, normalised to the best view."""
    scores = {}
    for v, mask in evidence.masks.items():
        area = float(mask.sum())
        if area < 2:
            continue
        boost = (evidence.boost or {}).get(v, 1.0)
        scores[v] = evidence.scores[v] * np.log(area) * boost
    best = sorted(scores, key=lambda v: -scores[v])[:top_k]
    if not best:
        return {}
    top = scores[best[0]]
    return {v: scores[v] / top for v in best}


def support(view: ViewMaps, mask: np.ndarray) -> np.ndarray:
    """supp(M): the faces seen under ``mask``'s pixels, (k,) int64."""
    faces = view.face[mask]
    return np.unique(faces[faces >= 0])


def lift_evidence(views: list[ViewMaps], parts: list[PartEvidence], n_faces: int,
                  top_k: int | list[int]) -> tuple[np.ndarray, np.ndarray, list[dict[int, float]]]:
    """E(f, p) = sum over the part's top-K views of w * c * [f in supp(M)], label = argmax,
    faces without support -> base (0). ``top_k``: K for every part, or one K per part.

    Returns ((F,) int labels, (F, P + 1) evidence with a zero base column, weights per part)."""
    evidence = np.zeros((n_faces, len(parts) + 1))
    weights = []
    ks = top_k if isinstance(top_k, list) else [top_k] * len(parts)
    for p, (part, k) in enumerate(zip(parts, ks), start=1):
        w = view_weights(part, k)
        weights.append(w)
        for v, wv in w.items():
            evidence[support(views[v], part.masks[v]), p] += wv * part.scores[v]
    labels = np.argmax(evidence, axis=1)
    labels[evidence.max(axis=1) <= 0] = 0
    return labels, evidence, weights


def mask_share(view: ViewMaps, mask: np.ndarray, n_faces: int) -> np.ndarray:
    """(F,) share of each face's pixels in ``view`` that fall inside ``mask``; 1 for faces the
    view does not see (no evidence against them)."""
    return pooled_mask_share([view], [(0, mask)], n_faces)


def mask_outline(view: ViewMaps, mask: np.ndarray, reach: float) -> np.ndarray | None:
    """(2, 2) pixel box [[col, row] min, max] of ``mask`` in ``view``, grown on each side by
    ``reach`` times its size plus 2 px; None for an empty mask."""
    rows, cols = np.nonzero(mask)
    if not len(rows):
        return None
    lo, hi = np.array([cols.min(), rows.min()], float), np.array([cols.max(), rows.max()], float)
    grow = reach * (hi - lo) + 2.0
    return np.stack([lo - grow, hi + grow])


def inside_outline(view: ViewMaps, outline: np.ndarray, points: np.ndarray) -> bool:
    """Whether ``points`` (N, 3, world) all project into the pixel box ``outline``
    (``mask_outline``) of ``view`` (in front of its camera)."""
    xy, depth = view.camera.project(points)
    return bool(np.all(depth > 0) and np.all((xy >= outline[0]) & (xy <= outline[1])))


def pooled_mask_share(views: list[ViewMaps], masks: list[tuple[int, np.ndarray]], n_faces: int) -> np.ndarray:
    """(F,) share of each face's pixels, over all the ``(view, mask)`` pairs' views, that fall
    inside the masks; 1 for faces none of the views sees."""
    total, inside = np.zeros(n_faces), np.zeros(n_faces)
    for v, mask in masks:
        seen = views[v].face >= 0
        total += np.bincount(views[v].face[seen], minlength=n_faces)
        inside += np.bincount(views[v].face[seen & mask], minlength=n_faces)
    return np.where(total > 0, inside / np.maximum(total, 1), 1.0)


def face_adjacency_graph(faces: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """(F, F) faces sharing an edge (vertex ids as given: merge duplicates before)."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    face_of = np.tile(np.arange(len(faces)), 3)
    key = edges[:, 0].astype(np.int64) * n_vertices + edges[:, 1]
    order = np.argsort(key, kind="stable")
    key, face_of = key[order], face_of[order]
    same = np.flatnonzero(key[1:] == key[:-1])
    a, b = face_of[same], face_of[same + 1]
    n = len(faces)
    return sp.coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n)).tocsr()


def dominant_components(labels: np.ndarray, adjacency: sp.csr_matrix, area: np.ndarray) -> np.ndarray:
    """(F,) bool: faces in the largest-area connected component of their own label."""
    rows, cols = adjacency.nonzero()
    same = labels[rows] == labels[cols]
    n = len(labels)
    graph = sp.coo_matrix((np.ones(same.sum()), (rows[same], cols[same])), shape=(n, n))
    _, component = connected_components(graph, directed=False)
    comp_area = np.bincount(component, area)
    keep = np.zeros(n, bool)
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        comps = np.unique(component[members])
        best = comps[np.argmax(comp_area[comps])]
        keep[members[component[members] == best]] = True
    return keep


def refine_labels(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray, n_labels: int,
                  views: list[ViewMaps], best_masks: dict[int, tuple[int, np.ndarray]],
                  all_masks: dict[int, list[tuple[int, np.ndarray]]] | None = None,
                  normals: dict[int, np.ndarray] | None = None, max_depth: float = np.inf,
                  reach: float = 0.25) -> tuple[np.ndarray, dict]:
    """Graph refinement of lifted face labels.

    Seeds: the dominant connected component of each label. Every other face joins a pool and
    takes the label of the nearest seed by shortest path over the vertex graph (mean over its
    corners); a face relabelled to part p is checked in p's best view (``best_masks``: label
    -> (view, mask)) and, when it is seen there outside p's mask, goes to the next nearest part.
    A face no seed reaches (a primitive of its own) whose corners project past the outline of its
    label's mask in the label's best view (its box grown by ``reach``, a share of its size: a
    sash's bar its mask missed lies within that, a board's edge running past a door does not)
    keeps its lifted label only when most of its pixels that the label's views see
    (``all_masks``: label -> [(view, mask)], default the best view) lie in the label's masks:
    one board's wall, seen mostly through an open shelf beside a door and at one corner under
    the door's mask, is no part of the door (a sash's bar, a shell of its own within the sash's
    outline, is the sash's however it is seen). Nor is, for
    a panel label with an outward normal (``normals``: label -> (3,)), a face reaching more than
    ``max_depth`` (m) behind the front of the label's seed: a shelf's top seen through a door's
    gap runs deep into the carcass, a door's own faces never do.
    Returns the refined (F,) labels and counts for the log."""
    tri = vertices[faces]
    area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1) / 2
    adjacency = face_adjacency_graph(faces, len(vertices))
    seed = dominant_components(labels, adjacency, area)
    pool = np.flatnonzero(~seed)
    if not len(pool):
        return labels.copy(), {"pool": 0, "moved": 0, "rejected_by_mask": 0}
    graph = vertex_graph(vertices, faces)
    present = [k for k in range(n_labels) if (seed & (labels == k)).any()]
    distance = np.full((n_labels, len(pool)), np.inf)
    for k in present:
        sources = np.unique(faces[seed & (labels == k)])
        d = dijkstra(graph, directed=False, indices=sources, min_only=True)
        distance[k] = d[faces[pool]].mean(axis=1)
    order = np.argsort(distance, axis=0)
    share = {k: mask_share(views[view], mask, len(faces)) for k, (view, mask) in best_masks.items()}
    lone = None  # what a face no part reaches is judged by: made on first need (a scan rarely has one)
    out = labels.copy()
    rejected = 0
    for column, f in enumerate(pool):
        for k in order[:, column]:
            if not np.isfinite(distance[k, column]):
                # no part reached it (a primitive of its own): its lifted label stands unless it
                # runs deep behind a panel, or past the label's outline seen mostly outside its masks
                if lone is None:
                    lone = _lone_face_evidence(vertices, faces, labels, seed, views, best_masks, all_masks,
                                               normals, reach)
                pooled, fronts, outlines = lone
                own = labels[f]
                deep = own in fronts and fronts[own] - float((tri[f] @ normals[own]).min()) > max_depth
                beyond = own in outlines and outlines[own] is not None and not inside_outline(
                    views[best_masks[own][0]], outlines[own], tri[f])
                if deep or (beyond and own in pooled and pooled[own][f] < 0.5):
                    rejected += 1
                    out[f] = 0
                break
            if k in share and share[k][f] < 0.5:  # seen in the part's best view, outside its mask
                rejected += 1
                continue
            out[f] = k
            break
    return out, {"pool": int(len(pool)), "moved": int((out[pool] != labels[pool]).sum()), "rejected_by_mask": rejected}


def _lone_face_evidence(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray, seed: np.ndarray,
                        views: list[ViewMaps], best_masks: dict[int, tuple[int, np.ndarray]],
                        all_masks: dict[int, list[tuple[int, np.ndarray]]] | None,
                        normals: dict[int, np.ndarray] | None, reach: float) -> tuple[dict, dict, dict]:
    """Per label, for :func:`refine_labels`' faces no part reaches: the (F,) pooled share of
    each face's pixels in the label's masks, the front of its seed along its normal (panels
    only, m) and its best view's grown mask box (``mask_outline``)."""
    pooled = {k: pooled_mask_share(views, pairs, len(faces))
              for k, pairs in (all_masks or {k: [vm] for k, vm in best_masks.items()}).items()}
    fronts = {k: float((vertices[np.unique(faces[seed & (labels == k)])] @ n).max())
              for k, n in (normals or {}).items() if (seed & (labels == k)).any()}
    outlines = {k: mask_outline(views[view], mask, reach) for k, (view, mask) in best_masks.items()}
    return pooled, fronts, outlines


DENT_PAIRS_PER_CHUNK = 2_000_000
"""Face-neighbour pairs :func:`surface_dent` holds at once (about 150 MB): memory stays bounded
whatever the face density (a 1M-face scan has hundreds of faces within a groove radius)."""

DENT_MAX_NEIGHBOURS = 256
"""Most faces :func:`surface_dent` averages over per face: on a denser mesh it averages over a
seeded random share of the faces (an unbiased estimate of the same area-weighted mean), so its
time grows with the face count, not with its square (a subdivided 1M-face cabinet has ~6,000
faces within a groove radius)."""


def surface_dent(centres: np.ndarray, normals: np.ndarray, area: np.ndarray, radius: float) -> np.ndarray:
    """(F,) how far (m) the faces within ``radius`` of each face stand above it along its
    normal, area-weighted: about 0 on a flat, positive in a groove or an inside corner,
    negative on a convex edge. ``centres``, ``normals`` (F, 3), ``area`` (F,)."""
    from scipy.spatial import cKDTree

    n = len(centres)
    tree = cKDTree(centres)
    sample = centres[:: max(1, n // 2000)]
    mean_neighbours = max(float(tree.query_ball_point(sample, radius, return_length=True).mean()), 1.0)
    if mean_neighbours > DENT_MAX_NEIGHBOURS:
        # dense mesh: keep each face with a chance in proportion to its area (every face of at
        # least a disc's share), weighted by area / chance: the same area-weighted mean, unbiased,
        # from about DENT_MAX_NEIGHBOURS faces per disc wherever the faces are small
        share = np.pi * radius**2 / DENT_MAX_NEIGHBOURS
        chance = np.minimum(area / share, 1.0)
        kept = np.random.default_rng(0).random(n) < chance
        centres_kept, area_kept = centres[kept], np.maximum(area[kept], share)
        tree = cKDTree(centres_kept)
        mean_neighbours = max(float(tree.query_ball_point(sample, radius, return_length=True).mean()), 1.0)
    else:
        centres_kept, area_kept = centres, area
    chunk = max(1, int(DENT_PAIRS_PER_CHUNK / mean_neighbours))
    height_sum, area_sum = np.zeros(n), np.zeros(n)
    for start in range(0, n, chunk):  # the neighbour lists of all faces at once grow with density squared
        rows = np.arange(start, min(start + chunk, n))
        neighbours = tree.query_ball_point(centres[rows], radius)
        counts = np.fromiter((len(k) for k in neighbours), np.int64, len(neighbours))
        local = np.repeat(np.arange(len(rows)), counts)
        other = np.concatenate(neighbours).astype(np.int64)
        del neighbours
        owner = rows[local]
        height = np.einsum("ij,ij->i", centres_kept[other] - centres[owner], normals[owner]) * area_kept[other]
        height_sum[rows] = np.bincount(local, height, len(rows))
        area_sum[rows] = np.bincount(local, area_kept[other], len(rows))
    return height_sum / np.maximum(area_sum, 1e-18)


def grow_edge_strips(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray, normals: dict[int, np.ndarray],
                     config: SegmentConfig, fused: bool = True) -> tuple[np.ndarray, dict]:
    """Give each panel the edge strips the views could not: the sides, top and bottom of a door
    or drawer front are seen at grazing angles, thin, and fall in the edge band of every view,
    so lifting leaves them with the base.

    From each panel label k (outward ``normals[k]``, (3,)), base faces are claimed across mesh
    edges that are convex or concave by less than ``strip_concave_stop_deg``, never into a
    groove (faces lying ``groove_depth`` (m) below their surroundings within
    ``strip_groove_radius``, ``surface_dent``) nor, on the strip, over a ridge as far above them
    (``strip_ridge_facing``, ``strip_ridge_behind``): a strip ends at an inside corner or at the
    seam that parts it from a coplanar carcass side. Claimed faces face sideways, or the panel's
    way only ``strip_outline_margin`` or more behind its front (a rounded corner; a carcass
    frame coplanar with an inset door lies across a groove too shallow to stop anything), lie
    less than ``panel_max_thickness`` (m) behind the panel's front, lie inside its outline seen
    along the normal (grown by ``strip_outline_margin``, m), and lie further than
    ``strip_groove_radius`` from any other part (the walls of the groove between two doors are
    neither's: a door swinging out would scrape its neighbour's wall). All tolerances are
    ``config``'s (SegmentConfig). On a ``fused`` surface (one piece, ``fused_piece_share``) a
    panel also takes the back sheet its strips reach round to (``panel_back_margin``); on a mesh
    of pieces a piece's back goes with the piece.
    Returns the new (F,) labels and the faces claimed per label."""
    import trimesh
    from scipy.spatial import cKDTree

    from rest2art.geometry.basics import box_distance, perpendicular_basis

    max_depth, outline_margin, groove_depth = config.panel_max_thickness, config.strip_outline_margin, config.groove_depth
    concave_stop_deg, groove_radius = config.strip_concave_stop_deg, config.strip_groove_radius
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    all_pairs = np.asarray(mesh.face_adjacency)
    passable = np.asarray(mesh.face_adjacency_convex) | (np.asarray(mesh.face_adjacency_angles)
                                                         < np.radians(concave_stop_deg))
    pairs = all_pairs[passable]
    n = len(faces)
    graph = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n)).tocsr()
    graph = graph + graph.T
    centres, face_normals = mesh.triangles_center, mesh.face_normals
    dent = surface_dent(centres, face_normals, mesh.area_faces, groove_radius) if normals else np.zeros(n)
    out = labels.copy()
    claimed = {}
    frontals = {k: (labels == k) & (face_normals @ normal > config.strip_frontal_cos) for k, normal in normals.items()}
    for k, normal in normals.items():
        mine = labels == k
        frontal = frontals[k]
        if frontal.sum() < 3:
            continue
        front = float(np.percentile(centres[frontal] @ normal, 95))
        basis = perpendicular_basis(normal)
        flat = centres @ basis.T  # (F, 2) in the panel's plane
        lo = flat[frontal].min(axis=0) - outline_margin
        hi = flat[frontal].max(axis=0) + outline_margin
        facing = face_normals @ normal
        behind = front - centres @ normal
        # a seam is a groove, or on the strip itself (facing sideways, clear of the rounded
        # corner from the front, which is convex by nature) a ridge
        ridge = ((np.abs(facing) < config.strip_ridge_facing) & (dent < -groove_depth)
                 & (behind > config.strip_ridge_behind * groove_radius))
        seam = (dent > groove_depth) | ridge
        sideways = (np.abs(facing) < 0.5) | ((facing >= 0.5) & (behind > outline_margin))
        allowed = ((out == 0) & ~seam & sideways & (behind <= max_depth)
                   & np.all((flat >= lo) & (flat <= hi), axis=1))
        panels_near = np.isin(labels, [j for j in normals if j != k])
        others = (labels > 0) & (labels != k) & ~panels_near
        if others.any() and allowed.any():  # nothing next to a knob or handle part
            near, _ = cKDTree(centres[others]).query(centres[allowed], distance_upper_bound=groove_radius)
            allowed[np.flatnonzero(allowed)[np.isfinite(near)]] = False
        if panels_near.any() and allowed.any():
            # next to another panel, a face is k's only when it lies nearer k's front than
            # theirs (seen along k's normal): each takes its own wall of the groove between
            # them and its own rounded corner down to the seam, neither the other's
            near, _ = cKDTree(centres[panels_near]).query(centres[allowed], distance_upper_bound=groove_radius)
            contested = np.flatnonzero(allowed)[np.isfinite(near)]
            own_gap = box_distance(flat[contested], lo + outline_margin, hi - outline_margin)
            for j, other_frontal in frontals.items():
                if j != k and other_frontal.any():
                    other = flat[other_frontal]
                    other_gap = box_distance(flat[contested], other.min(axis=0), other.max(axis=0))
                    allowed[contested[other_gap <= own_gap]] = False
        grown = grow_region(graph, mine, allowed) & ~mine
        grown[grown] = even_strips(flat[grown], behind[grown], lo + outline_margin, hi - outline_margin,
                                   config.strip_even_min_cover, config.strip_even_min_depth,
                                   config.strip_even_excess)
        out[grown] = k
        claimed[int(k)] = int(grown.sum())
    # base islands left inside a panel's strips (a face the seam rules held back) would be
    # scraped by the panel's first degree of motion: they join the panel around them
    base, component = base_components(out, all_pairs)
    border = base[all_pairs[:, 0]] != base[all_pairs[:, 1]]
    island = np.where(base[all_pairs[border, 0]], component[all_pairs[border, 0]], component[all_pairs[border, 1]])
    around = np.where(base[all_pairs[border, 0]], out[all_pairs[border, 1]], out[all_pairs[border, 0]])
    size = np.bincount(component[base], minlength=component.max() + 1)
    for c in np.unique(island):
        labels_around = np.unique(around[island == c])
        if len(labels_around) == 1 and labels_around[0] in normals and size[c] < config.strip_island_share * n:
            members = base & (component == c)
            out[members] = labels_around[0]
            claimed[int(labels_around[0])] = claimed.get(int(labels_around[0]), 0) + int(members.sum())
    # base faces inside a panel's box join it where they hang together with it (a cavity wall
    # seen through the panel is a separate shell and stays)
    enclosed, in_front = enclosed_base_faces(vertices, faces, out, normals, max_depth,
                                             frontal_cos=config.strip_frontal_cos,
                                             back_margin=config.panel_back_margin if fused else 0.0,
                                             back_outline_margin=config.panel_back_outline_margin)
    adjacency = sp.coo_matrix((np.ones(len(all_pairs)), (all_pairs[:, 0], all_pairs[:, 1])), shape=(n, n)).tocsr()
    adjacency = adjacency + adjacency.T
    for k in normals:
        members = grow_region(adjacency, out == k, enclosed == k) & (out != k)
        out[members] = k
        claimed[int(k)] = claimed.get(int(k), 0) + int(members.sum())
    # a bit of surface in front of a closed panel that hangs together with nothing else (the
    # back of a handle's bar, seen in slivers between the holes a scan has where no camera
    # looked) is the panel's too: whole components of base faces, every face in front
    base, component = base_components(out, all_pairs)
    for k in normals:
        front_faces = base & in_front & (enclosed == k)
        if not front_faces.any():
            continue
        whole = np.bincount(component[front_faces], minlength=component.max() + 1) == \
            np.bincount(component[base], minlength=component.max() + 1)
        members = front_faces & whole[component]
        out[members] = k
        claimed[int(k)] = claimed.get(int(k), 0) + int(members.sum())
    return out, {"claimed": claimed}


def even_strips(flat: np.ndarray, behind: np.ndarray, lo: np.ndarray, hi: np.ndarray, min_cover: float,
                min_depth: float, excess: float, corner: float = 0.1) -> np.ndarray:
    """(S,) bool: which of a panel's strip faces to keep, the panel being one thickness all
    round. ``flat`` (S, 2): the faces' centres in the panel's plane; ``behind`` (S,): how far
    each lies behind its front, m; ``lo``, ``hi`` (2,): the front's outline. Each face belongs
    to the outline edge it lies nearest; away from the corners (``corner``: a share of the edge
    at each end, where one side's strip meets the next), the strips spanning at least
    ``min_cover`` of that length (their faces' extent along it) and reaching ``min_depth`` (m)
    behind the front or more (less is a rim or a sliver in the front's plane, no side) give the
    panel's depth, the shallowest (95th percentile) of them; faces more than ``excess`` (m)
    deeper go. Fewer than two such edges: all stay. (Faces kept that the growth reached only
    through dropped ones stay; a strip's depth grows away from its front, so there are few.)"""
    keep = np.ones(len(flat), bool)
    if len(flat) == 0:
        return keep
    gaps = np.abs(np.stack([flat[:, 0] - lo[0], hi[0] - flat[:, 0], flat[:, 1] - lo[1], hi[1] - flat[:, 1]], 1))
    edge = np.argmin(gaps, axis=1)
    depths = []
    for e in range(4):
        axis = 1 if e < 2 else 0
        start, length = lo[axis] + corner * (hi[axis] - lo[axis]), (1 - 2 * corner) * (hi[axis] - lo[axis])
        along = flat[:, axis] - start
        on = (edge == e) & (along >= 0) & (along <= length)
        if on.any() and np.ptp(along[on]) >= min_cover * length:
            depth = float(np.percentile(behind[on], 95))
            if depth >= min_depth:
                depths.append(depth)
    if len(depths) < 2:
        return keep
    return behind <= min(depths) + excess


def base_components(labels: np.ndarray, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F,) bool base faces (label 0) of (F,) ``labels`` and (F,) the id of the connected
    component of base faces each face belongs to, over the (E, 2) face ``pairs`` that share an
    edge (a face of another label is a component of its own)."""
    n = len(labels)
    base = labels == 0
    inner = base[pairs[:, 0]] & base[pairs[:, 1]]
    _, component = connected_components(sp.coo_matrix((np.ones(inner.sum()), (pairs[inner, 0], pairs[inner, 1])),
                                                      shape=(n, n)), directed=False)
    return base, component


def grow_region(graph, seed: np.ndarray, allowed: np.ndarray) -> np.ndarray:
    """(F,) the ``seed`` faces and every ``allowed`` face reached from them over the
    symmetric (F, F) sparse ``graph``, breadth first."""
    region = seed.copy()
    frontier = np.flatnonzero(seed)
    while len(frontier):
        reached = np.asarray(graph[frontier].sum(axis=0)).ravel() > 0
        new = reached & allowed & ~region
        region |= new
        frontier = np.flatnonzero(new)
    return region


def enclosed_base_faces(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray,
                        normals: dict[int, np.ndarray], max_depth: float, tolerance: float = 1e-4,
                        frontal_cos: float = 0.7, back_margin: float = 0.0,
                        back_outline_margin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(F,) panel label for each base face (label 0) whose corners all lie inside exactly one
    panel's box, shrunk by ``tolerance`` (m): within the outline of the panel's faces seen
    along its normal ``normals[k]`` (3,), no deeper than their deepest point nor ``max_depth``
    (m) behind the panel's face (the area-weighted median height of its faces that face along
    the normal within ``frontal_cos``), and anywhere in front of it; or, facing away from the
    normal, within the outline grown by ``back_outline_margin`` (m) and within ``back_margin``
    (m) of that deepest point (not deeper than ``max_depth``).

    Behind the face, such a face is the panel's own material that the seam rules held back: a
    rounded corner, a fillet next to a groove, or the back sheet of a slab standing free (a
    door in a frame) and its rounded edge. In front of it, it is a handle's post or bar the
    views left to the base (nothing fixed can stand in front of a closed panel: it would stop
    it opening). Left to the base it would stand in the panel's way from its first degree of
    motion. 0 where no panel, or more than one, encloses the face; and (F,) bool, True where
    the face's corners all lie in front of the face of the panel that encloses it.
    ``vertices`` (V, 3), ``faces`` (F, 3)."""
    from rest2art.geometry.basics import perpendicular_basis

    owner = np.zeros(len(faces), np.int64)
    count = np.zeros(len(faces), np.int64)
    in_front = np.zeros(len(faces), bool)
    base = labels == 0
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(cross, axis=1) / 2
    unit = cross / np.maximum(2 * area, 1e-18)[:, None]
    centres = tri.mean(axis=1)
    for k, normal in normals.items():
        region = labels == k
        if region.sum() < 3:
            continue
        frame = np.column_stack([perpendicular_basis(normal).T, normal])  # (3, 3): plane axes, normal
        local = vertices @ frame
        own = local[np.unique(faces[region])]
        lo, hi = own.min(axis=0), own.max(axis=0)
        frontal = region & (unit @ normal > frontal_cos)
        if frontal.any():
            height = centres[frontal] @ normal
            order = np.argsort(height)
            weight = np.cumsum(area[frontal][order])
            face_plane = height[order][np.searchsorted(weight, weight[-1] / 2)]
        else:
            face_plane = hi[2]
        deepest = lo[2]
        lo[2] = max(lo[2], face_plane - max_depth)
        hi[2] = np.inf
        inside_vertex = np.all((local > lo + tolerance) & (local < hi - tolerance), axis=1)
        inside = base & inside_vertex[faces].all(axis=1)
        if back_margin > 0:  # the back sheet faces away (what faces forward there is a carcass behind)
            band_lo = np.append(lo[:2] - back_outline_margin, max(deepest - back_margin, face_plane - max_depth))
            band_hi = np.append(hi[:2] + back_outline_margin, deepest + back_margin)
            in_band = np.all((local > band_lo + tolerance) & (local < band_hi - tolerance), axis=1)
            inside |= base & in_band[faces].all(axis=1) & (unit @ normal < 0)
        owner[inside] = k
        count[inside] += 1
        in_front[inside] = (local[:, 2] > face_plane)[faces[inside]].all(axis=1)
    owner[count != 1] = 0
    return owner, in_front & (owner > 0)
