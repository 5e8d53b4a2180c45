"""Catalog build throughput: objects per hour with 1 and 2 local workers and through Ray.

    python benchmarks/bench_catalog.py [--count 8] [--variant asset] [--workers 1 2] [--ray]

Generates ``count`` objects (kinds mixed), then builds the same catalog from scratch once per
setting, each with a fresh CoACD cache (every build is cold, so they compare). Reports per
setting: wall time, objects per hour, the speed-up over one worker, and where the time went:

* pipeline: the seconds the workers spent in reconstruct + validate + pictures (the records'
  ``timings.total_s``);
* outside: everything else an object cost (forking its worker, sending its record back,
  packing and unpacking files for Ray, committing it into the catalog) plus the driver's serial
  work (reading and hashing inputs, repairing the catalog, writing the pages), as a share of
  all the time spent (target: <= 5 %);
* utilisation: pipeline seconds / (wall time x workers); the rest is also workers idling at the
  end of a build with fewer objects left than workers.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path


def make_inputs(folder: Path, count: int, variant: str) -> None:
    from rest2art.generate import VARIANTS, generate_object, write_object
    from rest2art.generate.objects import KINDS

    variants = list(VARIANTS) if variant == "both" else [variant]
    for k in range(count):
        kind, v = KINDS[k % len(KINDS)], variants[k % len(variants)]
        write_object(generate_object(kind, k, v), folder / f"{kind}_{k:04d}_{v}")


def one_build(inputs: Path, folder: Path, workers: int, ray: bool, config_file: str | None) -> dict:
    from rest2art.catalog.build import build_catalog
    from rest2art.catalog.store import read_index
    from rest2art.config import load_config

    config = load_config(config_file, {"collision": {"cache_dir": str(folder / "coacd-cache")}})
    start = time.perf_counter()
    report = build_catalog([inputs], folder / "catalog", config, workers=workers,
                           ray_address="auto" if ray else None)
    wall = time.perf_counter() - start
    records = {r["name"]: r for r in read_index(folder / "catalog")}
    pipeline = sum(records[n]["timings"]["total_s"] for n in report.job_wall_s)
    slots = sum(report.job_wall_s.values())
    serial = report.setup_s + report.pages_s
    outside = slots - pipeline + serial
    return {"objects": report.jobs, "wall_s": round(wall, 1), "objects_per_hour": round(3600 * report.jobs / wall, 1),
            "pipeline_s": round(pipeline, 1), "outside_s": round(outside, 2),
            "outside_share_pct": round(100 * outside / (slots + serial), 2),
            "per_object_outside_s": round((slots - pipeline) / max(1, len(report.job_wall_s)), 3),
            "serial_s": round(serial, 2), "utilisation_pct": round(100 * pipeline / (wall * workers), 1),
            "outcomes": dict(report.outcomes)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=8)
    parser.add_argument("--variant", choices=["asset", "scan", "both"], default="asset")
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--ray", action="store_true", help="also build through Ray on a local runtime (all CPUs)")
    parser.add_argument("--config", help="YAML config overrides")
    parser.add_argument("--out", help="keep the builds here (default: a temporary folder)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(args.out or tmp)
        make_inputs(root / "inputs", args.count, args.variant)
        rows = {}
        for workers in args.workers:
            rows[f"local, {workers} worker(s)"] = one_build(root / "inputs", root / f"local-{workers}", workers, False,
                                                            args.config)
            print(json.dumps({f"local, {workers} worker(s)": rows[f"local, {workers} worker(s)"]}), flush=True)
        if args.ray:
            import os

            import ray

            cpus = os.cpu_count() or 1
            ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
            rows[f"ray, one node, {cpus} CPUs"] = one_build(root / "inputs", root / "ray", cpus, True, args.config)
            ray.shutdown()
        one = rows.get("local, 1 worker(s)")
        print("\n| setting | objects | wall (s) | objects/hour | speed-up | outside the pipeline | utilisation |")
        print("|---|---|---|---|---|---|---|")
        for name, row in rows.items():
            speedup = f"{row['objects_per_hour'] / one['objects_per_hour']:.2f}x" if one else "-"
            print(f"| {name} | {row['objects']} | {row['wall_s']} | {row['objects_per_hour']} | {speedup} | "
                  f"{row['outside_share_pct']} % ({row['per_object_outside_s']} s/object + {row['serial_s']} s) | "
                  f"{row['utilisation_pct']} % |")


if __name__ == "__main__":
    main()
