"""What an asset costs: end-to-end seconds, memory, hulls and simulation speed, cold cache.

    python benchmarks/bench_speed.py [--count 20] [--variants asset scan] [--real-dev]
        [--before 4] [--workers 1] [-o bench_speed]

Every object runs as `rest2art bench run --cold --check` runs it: in a fresh worker process, with
an empty CoACD cache of its own, reconstructed, exported and validated with refinement. Sets:
``--count`` generated objects per variant (kinds mixed) and, with ``--real-dev``, the prepared
real development set (``rest2art bench prepare``). One object at a time by default
(``--workers 1``), so the seconds are an object's own on this machine.

``--before N`` also runs the first N generated objects of each variant with the collision stage
as it was before the box decomposition and the hull budget (CoACD on every solid, a 120 s limit,
no hull limit: ``benchmarks/collision_before.yaml``) in the same run, for the ratio.

Per set it prints the median and 95th percentile of end-to-end seconds, the median seconds per
stage, the peak memory of the worker (CoACD's child processes work on at most
``collision.coacd_max_faces`` faces), decompositions that timed out (CoACD and V-HACD: a stand-in
used), objects where V-HACD decomposed what CoACD could not in its time, hulls per asset (median, most), MuJoCo steps/s (median; 2,000 steps, no robot) and the
published assets whose rest pose is not clean; all rows go to OUT/speed.json.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

BEFORE_CONFIG = Path(__file__).with_name("collision_before.yaml")


def run_set(name: str, items: list, out: Path, workers: int, config: str | None = None) -> dict:
    """Run ``items`` cold with checks into OUT/NAME; the speed summary of all of them."""
    from rest2art.bench import run_items, summary_row, write_report

    folder = out / name
    records = run_items(items, folder, config, check=True, workers=workers, cold=True,
                        progress=lambda r: print(f"  {name}: {r['name']} {r.get('seconds', 0) + r.get('validate_seconds', 0):.1f} s "
                                                 f"{r.get('decision', r.get('error', ''))}", flush=True))
    write_report(records, folder, f"bench_speed {name}")
    row = summary_row(records)
    keys = ("objects", "errors", "median_total_seconds", "p95_total_seconds", "median_stage_seconds", "max_peak_mb",
            "decomposition_timeouts", "coacd_fallbacks", "median_hulls", "max_hulls", "median_steps_per_s", "published_pct",
            "published_rest_not_clean")
    return {"set": name, **{k: row.get(k) for k in keys},
            "objects_seconds": {r["name"]: r.get("seconds", 0) + r.get("validate_seconds", 0) for r in records}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=int, default=20)
    parser.add_argument("--variants", nargs="*", default=["asset", "scan"])
    parser.add_argument("--real-dev", action="store_true")
    parser.add_argument("--before", type=int, default=0)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("-o", "--out", type=Path, default=Path("bench_speed"))
    args = parser.parse_args()

    from rest2art.bench import devset, generated_items, prepared_items

    rows = []
    for variant in args.variants:
        items = generated_items(args.count, variant)
        rows.append(run_set(f"generated-{variant}", items, args.out, args.workers))
        if args.before:
            before = run_set(f"generated-{variant}-before", items[:args.before], args.out, args.workers,
                             str(BEFORE_CONFIG))
            now = [rows[-1]["objects_seconds"][i.name] for i in items[:args.before]]
            then = [before["objects_seconds"][i.name] for i in items[:args.before]]
            before["ratio_now_to_before"] = sum(now) / max(sum(then), 1e-9)
            rows.append(before)
        if args.real_dev:
            root = devset.default_cache() / "sets" / "real-dev"
            rows.append(run_set(f"real-dev-{variant}", prepared_items(root, variant), args.out, args.workers))
    print("| set | objects | median s | p95 s | peak MB | timeouts | V-HACD after CoACD | hulls median (most) "
          "| steps/s median | published | rest not clean |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['set']} | {r['objects']} | {r['median_total_seconds']:.1f} | {r['p95_total_seconds']:.1f} | "
              f"{r['max_peak_mb']:.0f} | {r['decomposition_timeouts']} | {r['coacd_fallbacks']} | "
              f"{r['median_hulls']:.0f} ({r['max_hulls']}) | {r['median_steps_per_s']:.0f} | "
              f"{r['published_pct']:.0f} % | {r['published_rest_not_clean']} |")
    for r in rows:
        stages = ", ".join(f"{k} {v:.1f}" for k, v in (r["median_stage_seconds"] or {}).items())
        print(f"{r['set']}: median stage seconds: {stages}"
              + (f"; now / before = {r['ratio_now_to_before']:.2f}" if "ratio_now_to_before" in r else ""))
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "speed.json").write_text(json.dumps(rows, indent=1, default=float))


if __name__ == "__main__":
    main()
