"""Validation time per object: CoACD collision decomposition + every check + refinement.

    python benchmarks/bench_validate.py [--count 10] [--variant asset]

Each generated object's ground truth is completed and decomposed (CoACD, in a fresh cache
folder: cold), exported, and validated with refinement; then the same again with the cache
now warm. Reports the median seconds per object for both, and the share of the cold time spent
in CoACD. Targets: <= 45 s cold, <= 10 s warm.

Both variants validate the generator's ground-truth parts, which are clean part meshes; the
cost of decomposing parts cut from a fused scan is measured by bench_reconstruct.py (its
"collision" stage) and by ``rest2art bench run --variant scan --check``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import tempfile
import time
from pathlib import Path

import numpy as np


def one_object(kind: str, seed: int, variant: str, cache: str, folder: Path) -> dict:
    from rest2art.validators.validate import validate_folder

    from rest2art.config import Config
    from rest2art.export.writers import write_asset
    from rest2art.generate import generate_object
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import StageTimer, complete_asset

    base = Config()
    config = dataclasses.replace(base, collision=dataclasses.replace(base.collision, cache_dir=cache))
    asset = generate_object(kind, seed, variant).asset
    timer = StageTimer()
    start = time.perf_counter()
    complete_asset(asset, config, timer=timer)
    with atomic_folder(folder, overwrite=True) as tmp:
        write_asset(asset, tmp, kind, config.export, np.array([0.0, 0.0, 1.0]))
    checks_start = time.perf_counter()
    report = validate_folder(folder, kind, config, refine=True)
    end = time.perf_counter()
    return {"object": f"{kind}_{seed}", "seconds": end - start, "coacd_seconds": timer.times["collision"],
            "checks_seconds": end - checks_start, "rounds": len(report.rounds), "decision": report.decision.status}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=int, default=10)
    parser.add_argument("--variant", choices=["asset", "scan"], default="asset")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    from rest2art.generate.objects import KINDS

    items = [(KINDS[k % len(KINDS)], args.seed + k) for k in range(args.count)]
    with tempfile.TemporaryDirectory() as tmp:
        cache = str(Path(tmp) / "coacd-cache")
        runs = {}
        for label in ("cold", "warm"):
            runs[label] = [one_object(kind, seed, args.variant, cache, Path(tmp) / f"{kind}_{seed}")
                           for kind, seed in items]
    cold, warm = runs["cold"], runs["warm"]
    share = float(np.sum([r["coacd_seconds"] for r in cold]) / np.sum([r["seconds"] for r in cold]))
    print(f"{len(items)} objects ({args.variant} ground truth), seconds per object, median")
    print("| cache | total | CoACD (collision stage) | checks + refinement |")
    print("|---|---|---|---|")
    for label, rs in runs.items():
        print(f"| {label} | {np.median([r['seconds'] for r in rs]):.1f} | "
              f"{np.median([r['coacd_seconds'] for r in rs]):.1f} | {np.median([r['checks_seconds'] for r in rs]):.1f} |")
    print(f"share of the cold time in CoACD: {100 * share:.0f} %")
    print(json.dumps({"cold": cold, "warm": warm}, default=float))


if __name__ == "__main__":
    main()
