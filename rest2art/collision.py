"""Collision geometry: convex hulls, boxes for boards, CoACD for the rest.

A convex piece is its hull. A concave one made of boards aligned with the object's frame (a
carcass's walls, shelves and front frame; a drawer's box; a panel door) becomes boxes
(``rest2art.boxes``): fast, a few dozen at most, and hollow where the solid is. Other concave
pieces go to CoACD, per piece (never on the whole object: hulls would bridge moving parts),
with at most ``max_hulls`` hulls, in a subprocess with a timeout because the native code can
crash; its result is cached on disk under a hash of the mesh content and the parameters, so
resumed runs are cheap, and so is a timeout: a decomposition that timed out is not run again
with the same input, parameters and time. When CoACD fails on a hollow piece, its boxes stand
in, never one hull around the hollow.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from rest2art.completion import solid_pieces
from rest2art.config import CollisionConfig, CompletionConfig
from rest2art.geometry import convex_overlap, is_closed_volume, perpendicular_basis, separating_overlaps


def cache_key(mesh: trimesh.Trimesh, params: dict) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(mesh.vertices, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
    h.update(json.dumps(params, sort_keys=True).encode())
    return h.hexdigest()[:32]


def _coacd_params(config: CollisionConfig, watertight: bool, max_hulls: int = -1) -> dict:
    limit = max_hulls if config.coacd_max_hulls < 0 else config.coacd_max_hulls
    return {
        "threshold": config.coacd_threshold, "max_convex_hull": int(limit), "seed": 0,
        "mcts_iterations": config.coacd_mcts_iterations, "mcts_nodes": config.coacd_mcts_nodes,
        "merge": config.coacd_merge or limit > 0,  # CoACD meets a hull limit only by merging
        "preprocess_mode": "auto" if (config.coacd_remesh_open and not watertight) else "off",
    }


def run_coacd(mesh: trimesh.Trimesh, config: CollisionConfig, max_hulls: int = -1
              ) -> tuple[list[trimesh.Trimesh] | None, str]:
    """CoACD hulls of ``mesh`` (cached) with at most ``max_hulls`` (-1: no limit; the
    config's ``coacd_max_hulls`` overrides it), and how it went: "ok", "cached", "timed out
    after N s" (also when an earlier run with this input and at least this time timed out:
    it is not repeated) or "failed (exit N)". Hulls are None unless it went well."""
    params = _coacd_params(config, mesh.is_watertight, max_hulls)
    cache_dir = Path(config.cache_dir).expanduser()
    key = cache_key(mesh, params)
    cached = cache_dir / f"{key}.npz"
    if cached.is_file():
        return _read_hulls(cached), "cached"
    timeout = float(config.coacd_timeout_s)
    timed_out = cache_dir / f"{key}.timeout"
    if timed_out.is_file() and float(timed_out.read_text() or 0.0) >= timeout:
        return None, f"timed out after {timeout:g} s (an earlier run; not repeated)"
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "in.npz", Path(tmp) / "out.npz"
        np.savez(src, vertices=mesh.vertices, faces=mesh.faces)
        try:
            proc = subprocess.run(
                [sys.executable, "-m", "rest2art.collision", str(src), str(dst), json.dumps(params), str(timeout)],
                capture_output=True, timeout=timeout,
            )
        except subprocess.TimeoutExpired:
            cache_dir.mkdir(parents=True, exist_ok=True)
            timed_out.write_text(f"{timeout:g}")
            return None, f"timed out after {timeout:g} s"
        if proc.returncode != 0 or not dst.is_file():
            return None, f"failed (exit {proc.returncode})"
        cache_dir.mkdir(parents=True, exist_ok=True)
        tmp_cache = cached.with_suffix(".tmp.npz")
        tmp_cache.write_bytes(dst.read_bytes())
        tmp_cache.replace(cached)
        return _read_hulls(cached), "ok"


def _read_hulls(path: Path) -> list[trimesh.Trimesh]:
    data = np.load(path)
    hulls = []
    for k in range(int(data["count"])):
        hulls.append(trimesh.Trimesh(data[f"v{k}"], data[f"f{k}"], process=True))
    return hulls


def closed_hull(points: np.ndarray) -> trimesh.Trimesh | None:
    """The convex hull of (N, 3) ``points`` as a closed volume that manifold3d accepts, or None
    when the points are (nearly) flat. Built from scipy's Qhull facets directly, each wound
    along its outward plane normal: trimesh's hull drops near-degenerate facets of thin hulls
    and leaves a hole; the joggled hull ('QJ') is the fallback."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.asarray(points, float)
    if len(points) < 4 or not is_solid_hull(trimesh.Trimesh(points, process=False)):
        return None
    for options in ("Qt", "QJ"):
        try:
            qhull = ConvexHull(points, qhull_options=options)
        except QhullError:
            continue
        faces = qhull.simplices.copy()
        corners = points[faces]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        inward = np.einsum("ij,ij->i", normals, qhull.equations[:, :3]) < 0
        faces[inward] = faces[inward][:, ::-1]
        used, faces = np.unique(faces, return_inverse=True)
        hull = trimesh.Trimesh(points[used], faces.reshape(-1, 3), process=False)
        if hull.is_watertight and is_closed_volume(hull):
            return hull
    return None


@dataclass(frozen=True)
class Decomposition:
    """The convex pieces of one solid and how they were made."""

    hulls: list[trimesh.Trimesh]
    method: str
    """hull, hull (small part), boxes, coacd, boxes (coacd ...), hull (coacd ...) or none (flat)."""
    hollow: bool = False
    """The solid fills less than ``convexity_ratio`` of its hull: one hull would fill it."""
    failure: str | None = None
    """Why CoACD gave nothing (timed out, failed), when it was run and did."""


def collision_hulls(solid: trimesh.Trimesh, config: CollisionConfig = CollisionConfig(),
                    rotation: np.ndarray | None = None, max_hulls: int = -1) -> tuple[list[trimesh.Trimesh], str]:
    """Convex pieces approximating one closed ``solid``, and how they were made (see
    ``decompose``)."""
    result = decompose(solid, config, rotation, max_hulls)
    return result.hulls, result.method


def decompose(solid: trimesh.Trimesh, config: CollisionConfig = CollisionConfig(),
              rotation: np.ndarray | None = None, max_hulls: int = -1) -> Decomposition:
    """Convex pieces of one closed ``solid``: its hull when it is nearly convex or small;
    with ``strategy`` "boxes" and a frame (``rotation`` (3, 3), rows the object's axes, e.g.
    side, front, up), boxes when at most ``max_hulls`` (-1: ``box_max_count``) of them hold
    ``box_min_covered`` of it; otherwise CoACD with at most ``max_hulls``. When CoACD gives
    nothing, the boxes stand in for a hollow solid (the failure is kept), one hull for the rest."""
    from rest2art.boxes import fit_boxes

    hull = closed_hull(solid.vertices)
    if hull is None:
        return Decomposition([], "none (flat)")
    if solid.volume >= config.convexity_ratio * hull.volume:
        return Decomposition([hull], "hull")
    if np.ptp(solid.vertices, axis=0).max() <= config.hull_only_size:
        return Decomposition([hull], "hull (small part)")
    limit = max_hulls if max_hulls > 0 else config.box_max_count
    boxes = None
    if rotation is not None and solid.is_watertight:
        boxes = fit_boxes(solid, rotation, config.box_pitch, config.box_max_cells, config.box_min_fill,
                          config.box_min_share, config.box_edge_cells, config.box_layer_share)
        if config.strategy == "boxes" and 0 < boxes.boxes <= limit and boxes.covered >= config.box_min_covered:
            return Decomposition(boxes.hulls, "boxes", True)
    hulls, status = run_coacd(simplified(solid, config.coacd_max_faces), config, max_hulls)
    hulls = [closed_hull(h.vertices) for h in (hulls or [])]
    hulls = [h for h in hulls if h is not None and h.volume >= config.min_hull_volume]  # slivers simulators refuse
    if hulls:
        return Decomposition(hulls, "coacd", True)
    failure = f"coacd {status}" if status not in ("ok", "cached") else "coacd gave only slivers"
    if boxes is not None and boxes.boxes:
        return Decomposition(boxes.hulls, f"boxes ({failure})", True, failure)
    return Decomposition([hull], f"hull ({failure})", True, failure)


def hull_signature(hulls: list[trimesh.Trimesh]) -> str:
    """A short hash of ``hulls``' corners (to 0.1 mm, order-free): two decompositions with the
    same signature gave the same result."""
    rows = sorted(np.unique(np.round(np.asarray(h.vertices, float) * 1e4).astype(np.int64), axis=0).tobytes()
                  for h in hulls)
    return hashlib.sha256(b"|".join(rows)).hexdigest()[:16]


def reduced_vertices(hull: trimesh.Trimesh, max_vertices: int) -> trimesh.Trimesh:
    """The convex ``hull`` with at most ``max_vertices`` corners: the hull of its corners
    picked by farthest-point sampling (inside the original, never bulging beyond it)."""
    points = np.asarray(hull.vertices, float)
    if len(points) <= max_vertices:
        return hull
    chosen = [int(np.argmax(np.linalg.norm(points - points.mean(axis=0), axis=1)))]
    distance = np.linalg.norm(points - points[chosen[0]], axis=1)
    while len(chosen) < max_vertices:
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(points - points[chosen[-1]], axis=1))
    smaller = closed_hull(points[chosen])
    return hull if smaller is None else smaller


def merged_hulls(hulls: list[trimesh.Trimesh], count: int, pad: float = 0.01) -> list[trimesh.Trimesh]:
    """``hulls`` merged pairwise into at most ``count`` convex hulls, each time the pair whose
    merged hull adds the least empty volume, among pairs whose boxes (grown by ``pad``, m)
    touch (all pairs when none do)."""
    hulls = [h for h in hulls if h is not None]
    cost: dict[tuple[int, int], tuple[float, trimesh.Trimesh | None]] = {}

    def merge_cost(i: int, j: int) -> tuple[float, trimesh.Trimesh | None]:
        merged = closed_hull(np.concatenate([hulls[i].vertices, hulls[j].vertices]))
        if merged is None:
            return np.inf, None
        return merged.volume - hulls[i].volume - hulls[j].volume, merged

    alive = set(range(len(hulls)))
    while len(alive) > max(count, 1):
        ids = sorted(alive)
        touch = boxes_touch([hulls[k] for k in ids], [hulls[k] for k in ids], pad)
        pairs = [(ids[a], ids[b]) for a, b in zip(*np.nonzero(np.triu(touch, 1)))]
        if not pairs:
            pairs = [(a, b) for n, a in enumerate(ids) for b in ids[n + 1:]]
        for pair in pairs:
            if pair not in cost:
                cost[pair] = merge_cost(*pair)
        (i, j), (_, merged) = min(((pair, cost[pair]) for pair in pairs), key=lambda item: item[1][0])
        if merged is None:
            break
        hulls.append(merged)
        alive -= {i, j}
        alive.add(len(hulls) - 1)
    return [hulls[k] for k in sorted(alive)]


def hull_budget(counts: dict[str, int], max_per_part: int, max_per_asset: int) -> dict[str, int]:
    """Hulls each part may keep: at most ``max_per_part``, and together at most
    ``max_per_asset``, shared by lowering the largest allowances first (each keeps one)."""
    allowed = {name: min(n, max_per_part) for name, n in counts.items()}
    while sum(allowed.values()) > max(max_per_asset, len(allowed)):
        largest = max(allowed, key=allowed.get)
        allowed[largest] -= 1
    return allowed


def within_budget(hulls: dict[str, list[trimesh.Trimesh]], max_per_part: int, max_per_asset: int,
                  max_vertices: int) -> tuple[dict[str, list[trimesh.Trimesh]], dict[str, str]]:
    """Every part's hulls within the budget (``hull_budget``; hulls merged by least added
    volume, corners thinned to ``max_vertices``), and a note per part that had to change."""
    allowed = hull_budget({name: len(h) for name, h in hulls.items()}, max_per_part, max_per_asset)
    out, notes = {}, {}
    for name, part_hulls in hulls.items():
        merged = merged_hulls(part_hulls, allowed[name]) if len(part_hulls) > allowed[name] else list(part_hulls)
        thinned = [reduced_vertices(h, max_vertices) for h in merged]
        changes = []
        if len(merged) < len(part_hulls):
            changes.append(f"{len(part_hulls)} hulls merged into {len(merged)}")
        corners = sum(a is not b for a, b in zip(thinned, merged))
        if corners:
            changes.append(f"{corners} hulls thinned to {max_vertices} corners")
        if changes:
            notes[name] = "; ".join(changes)
        out[name] = thinned
    return out, notes


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
    return small if small is solid or (small.is_watertight and small.volume > 0) else solid


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


def is_solid_hull(mesh: trimesh.Trimesh) -> bool:
    """True when the points span a volume (CoACD can return flat slivers of 3 points)."""
    points = np.asarray(mesh.vertices)
    if len(points) < 4:
        return False
    centred = points - points.mean(axis=0)
    return bool(np.linalg.svd(centred, compute_uv=False)[-1] > 1e-9 * max(1.0, np.abs(centred).max()))


def _exit_with_parent(seconds: float) -> None:
    """Never outlive the process that asked for the work: on Linux the kernel kills this
    process when its parent dies (CoACD holds the interpreter lock, so no Python watcher could
    run), and everywhere a run past its CPU-time budget is stopped by the kernel."""
    import ctypes
    import os
    import resource
    import signal

    limit = int(seconds * (os.cpu_count() or 1)) + 5  # CPU seconds: every core may be busy
    resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))
    try:
        pr_set_pdeathsig = 1
        ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, int(signal.SIGKILL), 0, 0, 0)
    except (OSError, AttributeError):  # not Linux: the CPU limit still applies
        return
    if os.getppid() == 1:  # the parent died before the request was registered
        os._exit(3)


def _worker(src: str, dst: str, params_json: str, timeout_s: str = "600") -> None:
    _exit_with_parent(float(timeout_s))
    import coacd

    coacd.set_log_level("error")
    params = json.loads(params_json)
    data = np.load(src)
    parts = coacd.run_coacd(coacd.Mesh(data["vertices"], data["faces"]), **params)
    arrays = {"count": np.array(len(parts))}
    for k, (v, f) in enumerate(parts):
        arrays[f"v{k}"], arrays[f"f{k}"] = np.asarray(v), np.asarray(f)
    np.savez(dst, **arrays)


def shrink_hull(hull: trimesh.Trimesh, distance: float) -> trimesh.Trimesh | None:
    """The convex ``hull`` with every face plane moved inward by ``distance`` (m): a true
    inward offset, unlike scaling, which barely thins a flat panel. None when nothing is left."""
    from scipy.spatial import HalfspaceIntersection, QhullError

    hull = hull.convex_hull
    normals = hull.face_normals
    offsets = -np.einsum("ij,ij->i", normals, hull.triangles[:, 0]) + distance  # n.x + c <= 0 inside
    centre = hull.vertices.mean(axis=0)
    if np.any(normals @ centre + offsets >= 0):  # thinner than 2 x distance somewhere
        return None
    try:
        corners = HalfspaceIntersection(np.column_stack([normals, offsets]), centre).intersections
    except QhullError:
        return None
    small = closed_hull(corners)
    return small if small is not None and small.volume >= 1e-9 else None


def clip_hull(hull: trimesh.Trimesh, normal: np.ndarray, offset: float, min_volume: float = 1e-9
              ) -> tuple[trimesh.Trimesh | None, np.ndarray]:
    """The part of the convex ``hull`` where normal . x <= ``offset`` (m), or None when too
    little is left, and the (K, 3) corners of the part cut away (empty when nothing was)."""
    v = np.asarray(hull.vertices, float)
    side = v @ normal - offset
    if np.all(side <= 0):
        return hull, np.zeros((0, 3))
    edges = np.asarray(hull.edges_unique)
    sa, sb = side[edges[:, 0]], side[edges[:, 1]]
    crossing = (sa > 0) != (sb > 0)
    t = sa[crossing] / (sa[crossing] - sb[crossing])
    cut = v[edges[crossing, 0]] + t[:, None] * (v[edges[crossing, 1]] - v[edges[crossing, 0]])
    removed = np.concatenate([v[side > 0], cut])
    small = closed_hull(np.concatenate([v[side <= 0], cut]))
    return (small if small is not None and small.volume >= min_volume else None), removed


def split_around_axis(hull: trimesh.Trimesh, origin: np.ndarray, axis: np.ndarray, radius: float,
                      min_volume: float = 1e-9) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh]]:
    """Cut the convex ``hull`` by the square prism of half-width ``radius`` (m) around the line
    through ``origin`` along unit ``axis``: (pieces inside the prism, pieces outside), all convex
    (at most one inside and four outside)."""
    u, v = perpendicular_basis(axis)
    inside, outside = [hull], []
    for direction in (u, v):
        centre = float(origin @ direction)
        next_inside = []
        for piece in inside:
            high, _ = clip_hull(piece, -direction, -(centre + radius), min_volume)  # direction.x >= centre + r
            low, _ = clip_hull(piece, direction, centre - radius, min_volume)  # direction.x <= centre - r
            middle, _ = clip_hull(piece, direction, centre + radius, min_volume)
            middle = clip_hull(middle, -direction, -(centre - radius), min_volume)[0] if middle is not None else None
            outside += [p for p in (high, low) if p is not None]
            next_inside += [middle] if middle is not None else []
        inside = next_inside
    return inside, outside


def boxes_touch(hulls_a: list[trimesh.Trimesh], hulls_b: list[trimesh.Trimesh], pad: float = 0.0) -> np.ndarray:
    """(A, B) bool: whose axis-aligned bounding boxes (those of A grown by ``pad``, m) touch."""
    lo_a = np.array([h.bounds[0] for h in hulls_a]) - pad
    hi_a = np.array([h.bounds[1] for h in hulls_a]) + pad
    lo_b = np.array([h.bounds[0] for h in hulls_b])
    hi_b = np.array([h.bounds[1] for h in hulls_b])
    return np.all((lo_a[:, None] <= hi_b[None]) & (lo_b[None] <= hi_a[:, None]), axis=2)


@dataclass
class ClearanceLog:
    """What clearing did to one part's hulls."""

    clipped: int = 0
    dropped: int = 0
    split: int = 0
    """Hulls cut around a hinge axis so that only the piece next to it gives way."""
    deepest_mm: float = 0.0
    """The deepest overlap removed."""
    left: int = 0
    """Overlaps not removed: deeper than allowed, or (sweeps) away from the hinge."""

    def to_dict(self) -> dict:
        return {"clipped": int(self.clipped), "dropped": int(self.dropped), "split": int(self.split),
                "deepest_mm": round(float(self.deepest_mm), 2), "left": int(self.left)}


def separate_hulls(hulls_a: list[trimesh.Trimesh], hulls_b: list[trimesh.Trimesh], share_a: float, clearance: float,
                   max_depth: float, log_a: ClearanceLog, log_b: ClearanceLog | None = None,
                   accept=None, min_volume: float = 1e-9, candidates: int = 8,
                   motions: tuple[tuple[str, np.ndarray], ...] = (), sweep_a=None, sweep_b=None
                   ) -> tuple[list[trimesh.Trimesh], list[trimesh.Trimesh]]:
    """Clip two sets of convex hulls (one frame) until no hull of A overlaps a hull of B.

    Each overlapping pair is cut by a plane normal to one of its separating-axis candidates
    (``geometry.separating_overlaps``, the ``candidates`` smallest overlaps) with a gap of
    ``clearance`` (m): the cut that keeps most volume among those ``accept(cut-away corners)``
    allows. A gives up ``share_a`` of the overlap, B the rest (1.0: only A is cut, e.g. a
    carcass around its door; 0.5: two siblings meet half-way). An overlap deeper than
    ``max_depth`` (m), or one no allowed cut removes, is left for the validator to find. Hulls
    cut down to nothing are dropped.

    ``motions``: (joint type, (3,) unit axis) of the joints that move A or B. A cut that stays
    a cut while they move (a plane normal to every hinge axis and parallel to every slide:
    the projection on its normal does not change) is taken before any other, and each hinge
    axis is a candidate of its own. ``sweep_a`` / ``sweep_b`` (hull -> convex hull of the
    space it sweeps) also find the pairs that only meet in motion; those are cut only by a
    plane that holds. Returns the new lists."""
    a, b = list(hulls_a), list(hulls_b)
    if not a or not b:
        return a, b

    def holds(axis: np.ndarray) -> bool:
        return bool(motions) and all(abs(axis @ m) > 0.999 if kind == "revolute" else abs(axis @ m) < 0.02
                                     for kind, m in motions)

    sweeping = sweep_a is not None or sweep_b is not None
    reach_a = [sweep_a(h) if sweep_a else h for h in a]
    reach_b = [sweep_b(h) if sweep_b else h for h in b]
    for i, j in zip(*np.nonzero(boxes_touch(reach_a, reach_b, clearance))):
        if a[i] is None or b[j] is None:
            continue
        at_rest, rest_axes = separating_overlaps(a[i].vertices, a[i].face_normals, b[j].vertices, b[j].face_normals)
        directions = list(rest_axes[:candidates])
        if sweeping:
            in_motion, motion_axes = separating_overlaps(reach_a[i].vertices, reach_a[i].face_normals,
                                                         reach_b[j].vertices, reach_b[j].face_normals)
            if in_motion[0] <= 0.0:
                continue
            directions += [axis for axis in motion_axes[:candidates] if holds(axis)]
        elif at_rest[0] <= 0.0:
            continue
        if at_rest[0] > max_depth:
            log_a.left += 1
            continue
        directions += [axis for kind, axis in motions if kind == "revolute"]
        best, best_kept, best_holds = None, -1.0, False
        for direction in directions:
            # depth and side from the hulls at rest: along a plane that holds, motion does not change them
            depth, axis = convex_overlap(a[i].vertices, direction[None], b[j].vertices, np.zeros((0, 3)))
            if depth > max_depth or depth <= 0.0 or (sweeping and at_rest[0] <= 0.0 and not holds(axis)):
                continue
            cut_a = float((a[i].vertices @ axis).max()) - share_a * (depth + clearance)  # A keeps axis.x <= cut_a
            cut_b = cut_a + clearance  # B keeps axis.x >= cut_b
            new_a, removed_a = clip_hull(a[i], axis, cut_a, min_volume) if share_a > 0 else (a[i], np.zeros((0, 3)))
            new_b, removed_b = (clip_hull(b[j], -axis, -cut_b, min_volume) if share_a < 1
                                else (b[j], np.zeros((0, 3))))
            if accept is not None and not accept(np.concatenate([removed_a, removed_b])):
                continue
            kept = sum(h.volume for h in (new_a, new_b) if h is not None)
            if (holds(axis), kept) > (best_holds, best_kept):
                best, best_kept, best_holds = (new_a, new_b, float(depth)), kept, holds(axis)
        if best is None:
            log_a.left += int(at_rest[0] > 0.0)  # a pair that only meets in motion is the validator's to judge
            continue
        new_a, new_b, depth = best
        for new, old, hulls, reach, sweep, k, log in ((new_a, a[i], a, reach_a, sweep_a, i, log_a),
                                                      (new_b, b[j], b, reach_b, sweep_b, j, log_b)):
            if new is old or log is None:
                continue
            hulls[k] = new
            reach[k] = sweep(new) if sweep and new is not None else new
            log.clipped += new is not None
            log.dropped += new is None
            log.deepest_mm = max(log.deepest_mm, 1000 * depth)
    return [h for h in a if h is not None], [h for h in b if h is not None]


def swept_hull(hull: trimesh.Trimesh, joint, samples: int) -> trimesh.Trimesh:
    """Convex hull of the space ``hull`` passes through over ``joint``'s range: the hull of
    its corners at ``samples`` + 1 poses (a slide's end poses are enough). For a hinge it
    holds a little more than the swept space, never less at the sampled poses."""
    count = 2 if joint.type == "prismatic" else samples + 1
    values = np.linspace(joint.limit[0], joint.limit[1], count)
    corners = np.concatenate([trimesh.transform_points(hull.vertices, joint.transform(value)) for value in values])
    swept = closed_hull(corners)
    return hull if swept is None else swept


def _split_hit_hulls(hulls: list[trimesh.Trimesh], swept: list[list[trimesh.Trimesh]], joint,
                     config: CollisionConfig, log: ClearanceLog) -> list[trimesh.Trimesh]:
    """``hulls`` with every one that a swept pose overlaps and that reaches beyond the hinge
    prism cut around the joint axis (``split_around_axis``), so that a clip next to the hinge
    does not shave a whole panel."""
    posed = [h for hs in swept for h in hs]
    if not posed or not hulls:
        return hulls
    near = boxes_touch(hulls, posed)
    out = []
    for hull, row in zip(hulls, near):
        hit = any(convex_overlap(hull.vertices, hull.face_normals, posed[k].vertices, posed[k].face_normals)[0] > 0
                  for k in np.flatnonzero(row))
        if not hit:
            out.append(hull)
            continue
        inside, outside = split_around_axis(hull, joint.origin, joint.axis, config.hinge_clearance_radius,
                                            config.min_hull_volume)
        if not outside:
            out.append(hull)
            continue
        log.split += 1
        out += inside + outside
    return out


def clear_asset_hulls(asset, config: CollisionConfig = CollisionConfig()) -> dict[str, dict]:
    """Clip the collision hulls of an ``ArticulatedAsset`` (in place) so that no two parts
    overlap at rest and no revolute part hits its ancestors near its hinge while it swings.

    Hull approximations bulge by millimetres to centimetres (CoACD's concavity threshold is a
    share of the piece's size) and a fused scan gives a door and its frame only a groove between
    them: without this, a correct asset starts interpenetrating. At rest, a part's ancestor gives
    way to it and siblings meet half-way. Over each revolute range (``clearance_sweep_samples``
    poses, denser than the validator's) only ancestor hulls within ``hinge_clearance_radius`` of
    the axis are cut, the space the door's back edge sweeps next to its hinge; an overlap
    further out or deeper than ``clearance_max_depth`` means a wrong part or joint and is left
    for the validator. Returns the per-part log."""
    parents = {p.name: p.parent for p in asset.parts}

    def ancestors(name: str) -> list[str]:
        chain, parent = [], parents.get(name)
        while parent is not None:
            chain.append(parent)
            parent = parents.get(parent)
        return chain

    names = [p.name for p in asset.parts]
    hulls = {p.name: list(p.collision) for p in asset.parts}
    logs = {name: ClearanceLog() for name in names}
    args = dict(clearance=config.clearance, max_depth=config.clearance_max_depth, min_volume=config.min_hull_volume)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if a in ancestors(b):
                hulls[a], hulls[b] = separate_hulls(hulls[a], hulls[b], 1.0, log_a=logs[a], **args)
            elif b in ancestors(a):
                hulls[b], hulls[a] = separate_hulls(hulls[b], hulls[a], 1.0, log_a=logs[b], **args)
            else:  # siblings: cut apart where they meet at rest or in motion, by a plane that holds
                joints = [j if j is not None and j.type in ("revolute", "prismatic") and j.limit[1] > j.limit[0]
                          else None for j in map(asset.joint_for, (a, b))]
                motions = tuple((j.type, np.asarray(j.axis, float)) for j in joints if j is not None)
                sweeps = [None if j is None else (lambda h, j=j: swept_hull(h, j, config.sibling_sweep_samples))
                          for j in joints]
                hulls[a], hulls[b] = separate_hulls(hulls[a], hulls[b], 0.5, log_a=logs[a], log_b=logs[b],
                                                    motions=motions, sweep_a=sweeps[0], sweep_b=sweeps[1], **args)
    for joint in asset.movable_joints:
        if joint.type != "revolute" or joint.limit[1] <= joint.limit[0]:
            continue
        moving = [n for n in names if n == joint.child or joint.child in ancestors(n)]
        poses = [joint.transform(value) for value in np.linspace(*joint.limit, config.clearance_sweep_samples + 1)[1:]]
        swept = [[h.copy().apply_transform(T) for n in moving for h in hulls[n]] for T in poses]
        reach = config.hinge_clearance_radius * np.sqrt(2.0) + 1e-9  # the prism's corner

        def near_hinge(points: np.ndarray, joint=joint) -> bool:
            offset = points - joint.origin
            radial = offset - np.outer(offset @ joint.axis, joint.axis)
            return bool(len(points) == 0 or np.linalg.norm(radial, axis=1).max() <= reach)

        for ancestor in ancestors(joint.child):
            hulls[ancestor] = _split_hit_hulls(hulls[ancestor], swept, joint, config, logs[ancestor])
            for posed in swept:
                hulls[ancestor], _ = separate_hulls(hulls[ancestor], posed, 1.0, log_a=logs[ancestor],
                                                    accept=near_hinge, **args)
    for part in asset.parts:
        part.collision = hulls[part.name]
    return {name: log.to_dict() for name, log in logs.items()}


if __name__ == "__main__":
    _worker(*sys.argv[1:5])
