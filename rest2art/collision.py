"""Collision geometry: convex hulls, CoACD for concave pieces.

CoACD runs per piece (never on the whole object: hulls would bridge moving parts), in a
subprocess with a timeout because the native code can crash, and its result is cached on disk
under a hash of the mesh content and the parameters, so resumed runs are cheap.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import trimesh

from rest2art.completion import solid_pieces
from rest2art.config import CollisionConfig, CompletionConfig


def cache_key(mesh: trimesh.Trimesh, params: dict) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(mesh.vertices, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
    h.update(json.dumps(params, sort_keys=True).encode())
    return h.hexdigest()[:32]


def _coacd_params(config: CollisionConfig, watertight: bool) -> dict:
    return {
        "threshold": config.coacd_threshold, "max_convex_hull": config.coacd_max_hulls, "seed": 0,
        "mcts_iterations": config.coacd_mcts_iterations, "mcts_nodes": config.coacd_mcts_nodes,
        "merge": config.coacd_merge,
        "preprocess_mode": "auto" if (config.coacd_remesh_open and not watertight) else "off",
    }


def run_coacd(mesh: trimesh.Trimesh, config: CollisionConfig) -> list[trimesh.Trimesh] | None:
    """CoACD hulls of ``mesh`` (cached), or None if it failed or timed out."""
    params = _coacd_params(config, mesh.is_watertight)
    cache_dir = Path(config.cache_dir).expanduser()
    key = cache_key(mesh, params)
    cached = cache_dir / f"{key}.npz"
    if cached.is_file():
        return _read_hulls(cached)
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "in.npz", Path(tmp) / "out.npz"
        np.savez(src, vertices=mesh.vertices, faces=mesh.faces)
        try:
            proc = subprocess.run(
                [sys.executable, "-m", "rest2art.collision", str(src), str(dst), json.dumps(params),
                 str(config.coacd_timeout_s)],
                capture_output=True, timeout=config.coacd_timeout_s,
            )
        except subprocess.TimeoutExpired:
            return None
        if proc.returncode != 0 or not dst.is_file():
            return None
        cache_dir.mkdir(parents=True, exist_ok=True)
        tmp_cache = cached.with_suffix(".tmp.npz")
        tmp_cache.write_bytes(dst.read_bytes())
        tmp_cache.replace(cached)
        return _read_hulls(cached)


def _read_hulls(path: Path) -> list[trimesh.Trimesh]:
    data = np.load(path)
    hulls = []
    for k in range(int(data["count"])):
        hulls.append(trimesh.Trimesh(data[f"v{k}"], data[f"f{k}"], process=True))
    return hulls


def collision_hulls(solid: trimesh.Trimesh, config: CollisionConfig = CollisionConfig()) -> tuple[list[trimesh.Trimesh], str]:
    """Convex pieces approximating one closed ``solid``, and how they were made."""
    hull = solid.convex_hull
    if solid.volume >= config.convexity_ratio * hull.volume:
        return [hull], "hull"
    if np.ptp(solid.vertices, axis=0).max() <= config.hull_only_size:
        return [hull], "hull (small part)"
    hulls = run_coacd(simplified(solid, config.coacd_max_faces), config)
    hulls = [h.convex_hull for h in (hulls or []) if is_solid_hull(h)]
    hulls = [h for h in hulls if h.volume >= config.min_hull_volume]  # slivers that simulators refuse
    if not hulls:
        return [hull], "hull (coacd failed)"
    return hulls, "coacd"


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
    ``shell`` is decimated first and thickened again, which is watertight by construction."""
    small = [simplified(s, max_faces) for s in solids]
    if all(len(s.faces) <= max_faces for s in small):
        return small
    rebuilt, _ = solid_pieces(decimated(shell, max_faces // 2), other_vertices, completion)
    return rebuilt or small


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
    from scipy.spatial import HalfspaceIntersection
    from scipy.spatial.qhull import QhullError

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
    small = trimesh.Trimesh(corners).convex_hull
    return small if is_solid_hull(small) and small.volume >= 1e-9 else None


if __name__ == "__main__":
    _worker(*sys.argv[1:5])
