"""Segmentation ablation: lifting only / + graph refinement / + co-refinement.

    python benchmarks/bench_segment.py --variant scan --count 50 [--workers 2] [--out DIR]

Each generated object is reconstructed up to its parts and joints (completion and collision do
not change the face labels, so they are skipped) under the three settings, and scored with the
project bench's metrics (Hungarian-matched mIoU over ground-truth parts, part-count accuracy).
Ground truth is written under ``--out`` once and reused. Prints a markdown table and writes
``ablation_<variant>.json``.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np

SETTINGS = {
    "lifting only": {"corefinement": False, "graph_refinement": False},
    "+ graph refinement": {"corefinement": False, "graph_refinement": True},
    "+ co-refinement": {"corefinement": True, "graph_refinement": True},
}


def run_object(args: tuple) -> dict:
    item, gt_root = args
    import dataclasses

    from rest2art.asset import read_articulation
    from rest2art.bench.metrics import score_object
    from rest2art.config import Config
    from rest2art.io.load import load_mesh
    from rest2art.pipeline import reconstruct_mesh

    gt_dir = Path(gt_root) / item.name
    item.materialize(gt_dir, 0.005)
    mesh = load_mesh(gt_dir / "mesh.obj")
    truth = read_articulation(gt_dir, load_meshes=False)
    area = mesh.trimesh().area_faces
    record = {"name": item.name, "kind": item.kind}
    for setting, overrides in SETTINGS.items():
        base = Config()
        config = dataclasses.replace(base, segment=dataclasses.replace(base.segment, **overrides))
        start = time.perf_counter()
        pred = reconstruct_mesh(mesh, config)
        score = score_object(pred, truth, area, item.name)
        record[setting] = {"part_iou": [p.iou for p in score.parts], "count_correct": score.count_correct,
                           "seconds": round(time.perf_counter() - start, 2)}
    return record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--variant", choices=["asset", "scan"], default="scan")
    parser.add_argument("--count", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="bench_out/ablation")
    args = parser.parse_args()

    from rich.progress import track

    from rest2art.bench import generated_items

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    items = generated_items(args.count, args.variant, args.seed)
    jobs = [(item, str(out / "gt" / args.variant)) for item in items]
    with mp.get_context("spawn").Pool(args.workers, maxtasksperchild=1) as pool:
        records = list(track(pool.imap(run_object, jobs), total=len(jobs), description=f"ablation ({args.variant})"))

    print(f"\n{args.variant} variant, {len(records)} objects\n")
    print("| setting | mIoU | part-count acc. | median s/object |")
    print("|---|---|---|---|")
    summary = {}
    for setting in SETTINGS:
        miou = float(np.mean([iou for r in records for iou in r[setting]["part_iou"]]))  # pooled, as the bench
        count = 100.0 * float(np.mean([r[setting]["count_correct"] for r in records]))
        seconds = float(np.median([r[setting]["seconds"] for r in records]))
        summary[setting] = {"miou": miou, "part_count_pct": count, "median_s": seconds}
        print(f"| {setting} | {miou:.3f} | {count:.0f} % | {seconds:.1f} |")
    (out / f"ablation_{args.variant}.json").write_text(json.dumps({"summary": summary, "objects": records}, indent=1))


if __name__ == "__main__":
    main()
