"""Collision geometry: convex hulls, boxes for boards, CoACD for the rest.

A convex piece is its hull. A concave one made of boards aligned with the object's frame (a
carcass's walls, shelves and front frame; a drawer's box; a panel door) becomes boxes
(``rest2art.collision.boxes``): fast, a few dozen at most, and hollow where the solid is. Other concave
pieces go to CoACD, per piece (never on the whole object: hulls would bridge moving parts),
with at most ``max_hulls`` hulls, in a subprocess with a timeout because the native code can
crash; its result is cached on disk under a hash of the mesh content and the parameters, so
resumed runs are cheap, and so is a timeout: a decomposition that timed out is not run again
with the same input, parameters and time. When CoACD gives nothing (a burner grate's hundreds
of holes can outlast any budget), PyBullet's V-HACD, whose time is bounded by its voxel count,
decomposes the piece in the same way; when that fails too, a hollow piece's boxes stand in,
never one hull around the hollow.
"""

from __future__ import annotations

import hashlib
import heapq
import json
import subprocess
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from rest2art.completion.solids import decimated
from rest2art.config import CollisionConfig
from rest2art.geometry.basics import is_closed_volume
from rest2art.io.atomic import scratch_folder
from rest2art.tolerances import SAME_POINT


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
    return _run_cached(mesh, params, float(config.coacd_timeout_s), Path(config.cache_dir).expanduser())


def run_vhacd(mesh: trimesh.Trimesh, config: CollisionConfig) -> tuple[list[trimesh.Trimesh] | None, str]:
    """V-HACD hulls of ``mesh`` (PyBullet's, cached like CoACD's), and how it went (as
    :func:`run_coacd`)."""
    params = {"method": "vhacd", "resolution": int(config.vhacd_resolution),
              "concavity": float(config.vhacd_concavity)}
    return _run_cached(mesh, params, float(config.vhacd_timeout_s), Path(config.cache_dir).expanduser())


def _run_cached(mesh: trimesh.Trimesh, params: dict, timeout: float, cache_dir: Path
                ) -> tuple[list[trimesh.Trimesh] | None, str]:
    """Run the worker of this module on ``mesh`` with ``params`` in a subprocess killed after
    ``timeout`` seconds; results and timeouts are kept in ``cache_dir`` under the content key.
    The mesh is decomposed centred on its bounding box (to ``CENTRED_DECIMALS``), so copies of
    one shape at other places (an oven's four burner grates, a row of knobs) share one run."""
    centre = np.asarray(mesh.bounds, float).mean(axis=0)
    hulls, status = _run_centred(canonical_mesh(np.asarray(mesh.vertices, float) - centre, mesh.faces),
                                 params, timeout, cache_dir)
    for hull in hulls or []:
        hull.apply_translation(centre)
    return hulls, status


CENTRED_DECIMALS = 6
"""Decimals (m) a centred mesh's coordinates keep: translated copies of a shape differ in the
last bits of their coordinates once centred, and their content key must not. (Files write
short decimals, so a centred coordinate often ends in 5 at the eighth: not a place to round.)"""


def canonical_mesh(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh:
    """The mesh with ``vertices`` (V, 3) rounded to ``CENTRED_DECIMALS`` and sorted, and
    ``faces`` (F, 3) renumbered, each started at its lowest corner (winding kept) and sorted:
    one array content for one shape, whatever order its file listed it in."""
    vertices = np.round(vertices, CENTRED_DECIMALS)
    order = np.lexsort(vertices.T[::-1])
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    faces = rank[np.asarray(faces, np.int64)]
    first = np.argmin(faces, axis=1)
    faces = np.take_along_axis(faces, (first[:, None] + np.arange(3)) % 3, axis=1)
    faces = faces[np.lexsort(faces.T[::-1])]
    return trimesh.Trimesh(vertices[order], faces, process=False)


def _run_centred(mesh: trimesh.Trimesh, params: dict, timeout: float, cache_dir: Path
                 ) -> tuple[list[trimesh.Trimesh] | None, str]:
    key = cache_key(mesh, params)
    with _KEYS_LOCK:
        lock = _KEY_LOCKS.setdefault(key, threading.Lock())
    with lock:  # a copy decomposed in another thread: wait for its result instead of a second run
        return _run_once(mesh, params, timeout, cache_dir, key)


_KEY_LOCKS: dict[str, threading.Lock] = {}
"""One lock per content key: parts are decomposed in threads, and copies of a shape meet."""
_KEYS_LOCK = threading.Lock()


def _run_once(mesh: trimesh.Trimesh, params: dict, timeout: float, cache_dir: Path, key: str
              ) -> tuple[list[trimesh.Trimesh] | None, str]:
    cached = cache_dir / f"{key}.npz"
    if cached.is_file():
        return _read_hulls(cached), "cached"
    timed_out = cache_dir / f"{key}.timeout"
    if timed_out.is_file() and float(timed_out.read_text() or 0.0) >= timeout:
        return None, f"timed out after {timeout:g} s (an earlier run; not repeated)"
    with scratch_folder("rest2art-coacd-run") as tmp:
        src, dst = tmp / "in.npz", tmp / "out.npz"
        np.savez(src, vertices=mesh.vertices, faces=mesh.faces)
        with _RUNNING_LOCK:
            if _STOPPED.is_set():
                return None, "not run (the stage was interrupted)"
            proc = subprocess.Popen(
                [sys.executable, "-m", "rest2art.collision.hulls", str(src), str(dst), json.dumps(params), str(timeout)],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            )
            _RUNNING.add(proc)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            cache_dir.mkdir(parents=True, exist_ok=True)
            timed_out.write_text(f"{timeout:g}")
            return None, f"timed out after {timeout:g} s"
        except BaseException:  # interrupted while waiting in this thread
            proc.kill()
            raise
        finally:
            with _RUNNING_LOCK:
                _RUNNING.discard(proc)
        if proc.returncode != 0 or not dst.is_file():
            return None, f"failed (exit {proc.returncode})"
        cache_dir.mkdir(parents=True, exist_ok=True)
        tmp_cache = cached.with_suffix(".tmp.npz")
        tmp_cache.write_bytes(dst.read_bytes())
        tmp_cache.replace(cached)
        return _read_hulls(cached), "ok"


_RUNNING: set[subprocess.Popen] = set()
"""CoACD runs of this process still going (each waited on by a decomposition thread)."""
_RUNNING_LOCK = threading.Lock()
_STOPPED = threading.Event()
"""Set by ``stop_coacd_runs``: no new run starts until ``allow_coacd_runs``."""


def allow_coacd_runs() -> None:
    """Let CoACD runs start again after ``stop_coacd_runs`` (a new collision stage)."""
    _STOPPED.clear()


def stop_coacd_runs() -> None:
    """Kill every CoACD run of this process that is still going and start no new one, so that
    an interrupted collision stage returns at once: its threads wait on their runs, and the
    interpreter waits for its threads before it exits (CoACD itself never looks at a signal)."""
    with _RUNNING_LOCK:
        _STOPPED.set()
        running = list(_RUNNING)
    for proc in running:
        try:
            proc.kill()
        except OSError:  # already gone
            pass


_NPZ_LOCK = threading.Lock()
"""Parts are decomposed in threads; numpy reads an array's header with ``ast.literal_eval``,
which CPython 3.11 can fail with a spurious SystemError when threads parse at once (gh-106905)."""


def _read_hulls(path: Path) -> list[trimesh.Trimesh]:
    with _NPZ_LOCK, np.load(path) as data:
        arrays = [(data[f"v{k}"], data[f"f{k}"]) for k in range(int(data["count"]))]
    return [trimesh.Trimesh(vertices, faces, process=True) for vertices, faces in arrays]


def closed_hull(points: np.ndarray) -> trimesh.Trimesh | None:
    """The convex hull of (N, 3) ``points`` as a closed volume that manifold3d accepts, or None
    when the points are (nearly) flat. Built from scipy's Qhull facets directly, each wound
    along its outward plane normal: trimesh's hull drops near-degenerate facets of thin hulls
    and leaves a hole; the joggled hull ('QJ') and then manifold3d's hull are the fallbacks."""
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
    return _manifold_hull(points)


def _manifold_hull(points: np.ndarray) -> trimesh.Trimesh | None:
    """manifold3d's own convex hull of (N, 3) ``points`` (single precision), or None when it is
    empty: the last resort when Qhull's triangulation of a facet keeps collinear corners as a
    zero-area triangle that manifold3d refuses (a box-like scan solid whose decimated side
    holds points along its edge)."""
    import manifold3d

    mesh = manifold3d.Manifold.hull_points(np.asarray(points, np.float32)).to_mesh()
    if len(mesh.tri_verts) < 4:
        return None
    hull = trimesh.Trimesh(np.asarray(mesh.vert_properties, float)[:, :3], np.asarray(mesh.tri_verts), process=False)
    return hull if hull.is_watertight and is_closed_volume(hull) else None


@dataclass(frozen=True)
class Decomposition:
    """The convex pieces of one solid and how they were made."""

    hulls: list[trimesh.Trimesh]
    method: str
    """hull, hull (small part), boxes, coacd, vhacd (coacd ...), boxes (coacd ...), hull (coacd ...)
    or none (flat)."""
    hollow: bool = False
    """The solid fills less than ``convexity_ratio`` of its hull: one hull would fill it."""
    failure: str | None = None
    """Why no decomposition came (CoACD, and V-HACD after it, timed out or failed) and a stand-in
    (boxes or one hull) was used."""


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
    side, front, up), boxes when at most ``box_merge_factor`` times ``max_hulls`` (-1:
    ``box_max_count``) of them hold ``box_min_covered`` of it (merged down to ``max_hulls``);
    otherwise CoACD with at most ``max_hulls``. When CoACD gives nothing, V-HACD (with
    ``vhacd_fallback``); when that gives nothing too, the boxes stand in for a hollow solid (the
    failure is kept), one hull for the rest."""
    from rest2art.collision.boxes import fit_boxes

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
                          config.box_min_share, config.box_edge_cells, config.box_layer_share,
                          config.box_surface_cells, config.box_surface_samples, config.box_surface_panel_ratio)
        if config.strategy == "boxes" and 0 < boxes.boxes <= config.box_merge_factor * limit \
                and boxes.covered >= config.box_min_covered:
            if boxes.boxes <= limit:
                return Decomposition(boxes.hulls, "boxes", True)
            # a few boxes over the budget: the nearest merge by least added volume, as the
            # export's budget would, unless that fills space the boxes left empty (two walls
            # merged across a cavity); CoACD on such a board-like solid takes tens of seconds
            merged = merged_hulls(boxes.hulls, limit)
            if added_volume(boxes.hulls, merged, solid.bounds) <= config.box_merge_max_growth:
                return Decomposition(merged, "boxes (merged)", True)
    small = decimated(solid, config.coacd_max_faces)
    if small is not solid and not (small.is_watertight and small.volume > 0) and not config.coacd_remesh_open:
        # decimating opened it and CoACD may not remesh: every face of the solid, however slow.
        # Otherwise CoACD's own remeshing closes the decimated surface again, far faster than
        # CoACD on every face of a scan (a window's 89k-face frame: over 50 s)
        small = solid
    hulls, status = run_coacd(small, config, max_hulls)
    hulls = solid_hulls(hulls, config.min_hull_volume)
    if hulls:
        return Decomposition(hulls, "coacd", True)
    failure = f"coacd {status}" if status not in ("ok", "cached") else "coacd gave only slivers"
    if config.vhacd_fallback:
        # V-HACD voxelises, so the closed solid (not a decimation that opened it) keeps its
        # openings open and its time does not grow with the faces
        fallback, fallback_status = run_vhacd(solid if solid.is_watertight else small, config)
        fallback = solid_hulls(fallback, config.min_hull_volume)
        if fallback:  # a decomposition still, not a stand-in: no failure to report
            return Decomposition(fallback, f"vhacd ({failure})", True)
        failure += f"; vhacd {fallback_status}" if fallback_status not in ("ok", "cached") else "; vhacd gave only slivers"
    if boxes is not None and boxes.boxes:
        return Decomposition(boxes.hulls, f"boxes ({failure})", True, failure)
    return Decomposition([hull], f"hull ({failure})", True, failure)


def solid_hulls(hulls: list[trimesh.Trimesh] | None, min_volume: float) -> list[trimesh.Trimesh]:
    """``hulls`` rebuilt as closed convex volumes, without the slivers (under ``min_volume``,
    m^3) that simulators refuse."""
    closed = [closed_hull(h.vertices) for h in (hulls or [])]
    return [h for h in closed if h is not None and h.volume >= min_volume]


def inside_hulls(hulls: list[trimesh.Trimesh], points: np.ndarray) -> np.ndarray:
    """(N,) bool: which of ``points`` (N, 3) lie inside at least one of the convex ``hulls``."""
    inside = np.zeros(len(points), bool)
    for hull in hulls:
        offsets = np.einsum("ij,ij->i", hull.face_normals, hull.triangles[:, 0])
        lo, hi = hull.bounds
        near = np.all((points >= lo) & (points <= hi), axis=1)  # only these can be inside
        inside[near] |= np.all(points[near] @ hull.face_normals.T <= offsets + SAME_POINT, axis=1)
    return inside


def added_volume(before: list[trimesh.Trimesh], after: list[trimesh.Trimesh], bounds: np.ndarray,
                 samples: int = 20000) -> float:
    """How much space ``after`` holds that ``before`` did not, as a share of what ``before``
    holds: both sets of convex hulls tested on ``samples`` seeded random points in ``bounds``
    ((2, 3), m)."""
    points = np.random.default_rng(0).uniform(bounds[0], bounds[1], (samples, 3))
    held = inside_hulls(before, points)
    return float((inside_hulls(after, points) & ~held).sum()) / max(int(held.sum()), 1)


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


def box_gaps(lo: np.ndarray, hi: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray) -> np.ndarray:
    """(A, B) distances (m) between axis-aligned boxes ``lo, hi`` (A, 3) and ``lo_b, hi_b`` (B, 3);
    0 where they touch or overlap."""
    gap = np.maximum(lo[:, None] - hi_b[None], lo_b[None] - hi[:, None])
    return np.linalg.norm(np.maximum(gap, 0.0), axis=2)


MERGE_ROWS = 256
"""Hulls whose box gaps to all others :func:`merged_hulls` holds at once: (rows, hulls, 3)
floats, about 60 MB for 10,000 hulls where all rows at once took 6 GB."""


def merged_hulls(hulls: list[trimesh.Trimesh], count: int, neighbours: int = 8) -> list[trimesh.Trimesh]:
    """``hulls`` merged pairwise into at most ``count`` convex hulls, each time the pair whose
    merged hull adds the least empty volume among each hull's ``neighbours`` nearest hulls (by
    the gap between their bounding boxes). Only merge costs are kept, in a heap with stale
    entries skipped, so a carcass of thousands of pieces costs time and memory linear in its
    hull count times ``neighbours``, not quadratic."""
    from scipy.spatial import ConvexHull, QhullError

    hulls = [h for h in hulls if h is not None]
    lo = [np.asarray(h.bounds[0]) for h in hulls]
    hi = [np.asarray(h.bounds[1]) for h in hulls]
    volume = [float(h.volume) for h in hulls]
    alive: set[int] = set(range(len(hulls)))
    heap: list[tuple[float, int, int]] = []

    def merged(i: int, j: int) -> trimesh.Trimesh | None:
        return closed_hull(np.concatenate([hulls[i].vertices, hulls[j].vertices]))

    def merged_volume(i: int, j: int) -> float | None:
        """Qhull's volume alone: a merge's cost needs no mesh (10x cheaper than building it)."""
        try:
            return float(ConvexHull(np.concatenate([hulls[i].vertices, hulls[j].vertices])).volume)
        except QhullError:  # flat: no merge
            return None

    def push_nearest(ids: list[int]) -> None:
        others = np.array(sorted(alive))
        gaps = box_gaps(np.array([lo[i] for i in ids]), np.array([hi[i] for i in ids]),
                        np.array([lo[k] for k in others]), np.array([hi[k] for k in others]))
        for row, i in enumerate(ids):
            gaps[row, others == i] = np.inf
            for pos in np.argsort(gaps[row], kind="stable")[:neighbours]:
                j = int(others[pos])
                joint = merged_volume(i, j) if np.isfinite(gaps[row, pos]) else None
                if joint is not None:
                    heapq.heappush(heap, (joint - volume[i] - volume[j], min(i, j), max(i, j)))

    start = sorted(alive)
    for first in range(0, len(start), MERGE_ROWS):  # gaps to every hull: rows at a time
        push_nearest(start[first:first + MERGE_ROWS])
    while len(alive) > max(count, 1) and heap:
        _, i, j = heapq.heappop(heap)
        if i not in alive or j not in alive:
            continue
        hull = merged(i, j)
        if hull is None:
            continue
        hulls.append(hull)
        lo.append(np.asarray(hull.bounds[0]))
        hi.append(np.asarray(hull.bounds[1]))
        volume.append(float(hull.volume))
        alive -= {i, j}
        alive.add(len(hulls) - 1)
        push_nearest([len(hulls) - 1])
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


def is_solid_hull(mesh: trimesh.Trimesh) -> bool:
    """True when the points span a volume (CoACD can return flat slivers of 3 points)."""
    points = np.asarray(mesh.vertices)
    if len(points) < 4:
        return False
    centred = points - points.mean(axis=0)
    return bool(np.linalg.svd(centred, compute_uv=False)[-1] > SAME_POINT * max(1.0, np.abs(centred).max()))


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
    import signal

    _exit_with_parent(float(timeout_s))
    signal.signal(signal.SIGINT, signal.SIG_DFL)  # Ctrl-C reaches the whole process group: end now
    params = json.loads(params_json)
    data = np.load(src)
    if params.pop("method", "coacd") == "vhacd":
        parts = _vhacd_parts(data["vertices"], data["faces"], Path(dst).parent, params)
    else:
        import coacd

        coacd.set_log_level("error")
        parts = coacd.run_coacd(coacd.Mesh(data["vertices"], data["faces"]), **params)
    arrays = {"count": np.array(len(parts))}
    for k, (v, f) in enumerate(parts):
        arrays[f"v{k}"], arrays[f"f{k}"] = np.asarray(v), np.asarray(f)
    np.savez(dst, **arrays)


def _vhacd_parts(vertices: np.ndarray, faces: np.ndarray, folder: Path, params: dict
                 ) -> list[tuple[np.ndarray, np.ndarray]]:
    """PyBullet's V-HACD on one mesh, through OBJ files in ``folder`` (its only interface): the
    hulls as (vertices, faces), read from the objects ('o') of the OBJ it writes."""
    import pybullet

    source, result = folder / "vhacd_in.obj", folder / "vhacd_out.obj"
    trimesh.Trimesh(vertices, faces, process=False).export(source)
    pybullet.vhacd(str(source), str(result), str(folder / "vhacd.log"), **params)
    parts, points, triangles, offset = [], [], [], 0
    for line in result.read_text().splitlines() + ["o end"]:
        if line.startswith("o ") and points:
            parts.append((np.array(points, float), np.array(triangles, int) - 1 - offset))
            offset += len(points)
            points, triangles = [], []
        elif line.startswith("v "):
            points.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            triangles.append([int(x.split("/")[0]) for x in line.split()[1:4]])
    return parts


if __name__ == "__main__":
    _worker(*sys.argv[1:5])
