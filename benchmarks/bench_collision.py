"""Collision stage: time, hull count and MuJoCo speed per object, one strategy against another.

    python benchmarks/bench_collision.py [--kinds cabinet safe ...] [--variants asset scan] [--seed 3]
        [--real-dev DIR] [--strategies coacd boxes] [--settings [--settings-timeout S]] [--check]

Each object is reconstructed once (up to its joints); then, per strategy, back to back in the
same conditions, it is completed and decomposed with an empty CoACD cache (cold) and again with
that cache (warm), exported, and MuJoCo steps it 2,000 times with no robot (steps/s). With
``--check`` the exported asset is validated with refinement (seconds and decision).
``--settings`` also runs CoACD's own settings on each object's largest concave collision solid
(the library default, a hull limit with merging, its manifold preprocessing, a coarser
decimation) against the boxes, with the empty volume each adds (share of the solid's volume,
on a 5 mm grid). Medians are printed; every row goes out as JSON on the last line.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import tempfile
import time
from pathlib import Path

import numpy as np


def empty_share(hulls: list, solid, rotation: np.ndarray, pitch: float = 0.005) -> tuple[float, float]:
    """(share of the solid's volume inside the hulls, empty volume inside them over the
    solid's volume), on the solid's occupancy grid."""
    from rest2art.collision.boxes import grid_pitch, occupancy
    from rest2art.collision.hulls import inside_hulls

    extents = np.ptp(np.asarray(solid.vertices) @ rotation.T, axis=0)
    grid = occupancy(solid.vertices, solid.faces, rotation, grid_pitch(extents, pitch, 4_000_000))
    idx = np.indices(grid.fill.shape).reshape(3, -1).T
    centres = (grid.origin + (idx + 0.5) * grid.pitch) @ rotation
    inside = inside_hulls(hulls, centres)
    fill = grid.fill.reshape(-1)
    volume = max(float(fill.sum()), 1e-12)
    return float(fill[inside].sum()) / volume, float((1.0 - fill[inside]).sum()) / volume


def coacd_once(mesh, params: dict, timeout: float) -> tuple[list | None, str]:
    """One CoACD run with ``params`` (no cache), in the collision stage's worker process."""
    import subprocess
    import sys

    from rest2art.collision.hulls import _read_hulls

    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "in.npz", Path(tmp) / "out.npz"
        np.savez(src, vertices=mesh.vertices, faces=mesh.faces)
        try:
            subprocess.run([sys.executable, "-m", "rest2art.collision.hulls", str(src), str(dst), json.dumps(params),
                            str(timeout)], capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, f"timed out after {timeout:g} s"
        return (_read_hulls(dst), "ok") if dst.is_file() else (None, "failed")


def coacd_settings(asset, config, timeout: float) -> list[dict]:
    """CoACD's own settings and the boxes on the asset's largest concave collision solid."""
    from rest2art.collision.hulls import closed_hull, decompose
    from rest2art.completion.solids import part_solids, simplified
    from rest2art.pipeline import object_axes

    rotation = object_axes(asset.metadata.get("frame"))
    solids = []
    for part in asset.parts:
        others = np.concatenate([p.mesh.vertices for p in asset.parts if p is not part])
        _, pieces, _ = part_solids(part.mesh, others, part.semantic, config.completion, config.collision.coacd_max_faces)
        solids += [s for s in pieces if s.is_watertight and s.volume < 0.92 * s.convex_hull.volume]
    if not solids:
        return []
    solid = max(solids, key=lambda s: s.convex_hull.volume)
    c = config.collision
    project = {"threshold": c.coacd_threshold, "max_convex_hull": -1, "preprocess_mode": "off", "seed": 0,
               "mcts_iterations": c.coacd_mcts_iterations, "mcts_nodes": c.coacd_mcts_nodes, "merge": False}
    variants = {
        "coacd as before (threshold 0.03, no limit, no preprocess)": (project, c.coacd_max_faces),
        "coacd max_convex_hull 32 + merge": ({**project, "max_convex_hull": 32, "merge": True}, c.coacd_max_faces),
        "coacd preprocess on (manifold, resolution 50)": ({**project, "preprocess_mode": "on"}, c.coacd_max_faces),
        "coacd on 2,000 faces": (project, 2000),
        "coacd library defaults": ({"seed": 0}, c.coacd_max_faces),
    }
    rows = []
    for label, (params, faces) in variants.items():
        start = time.perf_counter()
        hulls, status = coacd_once(simplified(solid, faces), params, timeout)
        seconds = time.perf_counter() - start
        hulls = [h for h in (closed_hull(h.vertices) for h in (hulls or [])) if h is not None]
        covered, empty = empty_share(hulls, solid, rotation) if hulls else (0.0, 0.0)
        rows.append({"setting": label, "seconds": seconds, "hulls": len(hulls), "status": status,
                     "covered": covered, "empty": empty})
    start = time.perf_counter()
    boxes = decompose(solid, c, rotation, 32)
    seconds = time.perf_counter() - start
    covered, empty = empty_share(boxes.hulls, solid, rotation)
    rows.append({"setting": f"boxes ({boxes.method})", "seconds": seconds, "hulls": len(boxes.hulls), "status": "ok",
                 "covered": covered, "empty": empty})
    return rows


def one_strategy(pre, name: str, strategy: str, folder: Path, check: bool) -> dict:
    """Complete, decompose (cold, then warm), export and step one reconstructed asset."""
    import copy

    from rest2art.config import Config
    from rest2art.export.writers import write_asset
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import StageTimer, complete_asset
    from rest2art.sim.mujoco_engine import steps_per_second

    base = Config()
    row = {"object": name, "strategy": strategy}
    cache = str(folder / f"cache-{strategy}")
    config = dataclasses.replace(base, collision=dataclasses.replace(base.collision, cache_dir=cache,
                                                                     strategy=strategy))
    for label in ("cold", "warm"):
        asset = copy.deepcopy(pre)
        timer = StageTimer()
        start = time.perf_counter()
        complete_asset(asset, config, timer=timer)
        row[f"{label}_s"] = time.perf_counter() - start
        row[f"{label}_stages"] = dict(timer.times)
    out = folder / f"{name}-{strategy}"
    up = np.asarray(asset.metadata.get("frame", {}).get("up", [0.0, 0.0, 1.0]), float)
    with atomic_folder(out, overwrite=True) as tmp:
        write_asset(asset, tmp, "asset", config.export, up)
    record = asset.metadata["collision"]
    row["hulls"] = int(sum(len(p.collision) for p in asset.parts))
    row["most_per_part"] = int(max(len(p.collision) for p in asset.parts))
    row["failures"] = {k: v["failures"] for k, v in record.items() if v.get("failures")}
    row["steps_per_s"] = steps_per_second(out, "asset")
    if check:
        from rest2art.validators.validate import validate_folder

        start = time.perf_counter()
        report = validate_folder(out, "asset", config, refine=True)
        row["check_s"] = time.perf_counter() - start
        row["decision"] = report.decision.status
        row["reasons"] = [r.message[:120] for r in report.decision.reasons][:3]
    return row


def inputs(kinds: list[str], variants: list[str], seed: int, real_dev: Path | None, folder: Path) -> list[tuple]:
    """(name, mesh path) of every object to measure."""
    from rest2art.generate import generate_object, write_object

    items = []
    for kind in kinds:
        for variant in variants:
            obj = generate_object(kind, seed, variant)
            items.append((f"{kind}_{seed}_{variant}", write_object(obj, folder / f"{kind}_{seed}_{variant}")))
    if real_dev is not None:
        for variant in variants:
            for item in sorted((real_dev / variant).iterdir()):
                if item.name.startswith(("myosuite", "genesis")):
                    continue  # kept for scoring only
                mesh = next((p for p in sorted(item.iterdir()) if p.suffix in (".obj", ".glb", ".ply")), None)
                if mesh is not None:
                    items.append((f"{item.name}_{variant}", mesh))
    return items


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kinds", nargs="*", default=["cabinet", "safe", "stove", "wardrobe"])
    parser.add_argument("--variants", nargs="*", default=["asset", "scan"])
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--real-dev", type=Path, default=None)
    parser.add_argument("--strategies", nargs="*", default=["coacd", "boxes"])
    parser.add_argument("--settings", action="store_true")
    parser.add_argument("--settings-timeout", type=float, default=120.0)
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()

    from rest2art.config import Config
    from rest2art.io.load import load_mesh
    from rest2art.pipeline import StageTimer, reconstruct_mesh

    rows, settings = [], []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name, path in inputs(args.kinds, args.variants, args.seed, args.real_dev, tmp):
            timer = StageTimer()
            start = time.perf_counter()
            try:
                pre = reconstruct_mesh(load_mesh(path, Config().load), Config(), timer=timer)
            except Exception as exc:  # a benchmark reports an input it cannot reconstruct and goes on
                print(f"{name}: {type(exc).__name__}: {exc}", flush=True)
                continue
            reconstruct_s = time.perf_counter() - start
            for strategy in args.strategies:
                row = one_strategy(pre, name, strategy, tmp, args.check)
                row["reconstruct_s"] = reconstruct_s
                rows.append(row)
                print(json.dumps({k: (round(v, 2) if isinstance(v, float) else v) for k, v in row.items()
                                  if not k.endswith("_stages")}), flush=True)
            if args.settings:
                for r in coacd_settings(pre, Config(), args.settings_timeout):
                    settings.append({"object": name, **r})
                    print(json.dumps({k: (round(v, 3) if isinstance(v, float) else v) for k, v in settings[-1].items()}),
                          flush=True)
    print("| strategy | objects | completion + collision cold s | warm s | hulls per asset | most per part "
          "| MuJoCo steps/s |")
    print("|---|---|---|---|---|---|---|")
    for strategy in args.strategies:
        mine = [r for r in rows if r["strategy"] == strategy]
        if mine:
            print(f"| {strategy} | {len(mine)} | {np.median([r['cold_s'] for r in mine]):.1f} | "
                  f"{np.median([r['warm_s'] for r in mine]):.1f} | {np.median([r['hulls'] for r in mine]):.0f} "
                  f"(max {max(r['hulls'] for r in mine)}) | {max(r['most_per_part'] for r in mine)} | "
                  f"{np.median([r['steps_per_s'] for r in mine]):.0f} |")
    print(json.dumps({"rows": rows, "settings": settings}, default=float))


if __name__ == "__main__":
    main()
