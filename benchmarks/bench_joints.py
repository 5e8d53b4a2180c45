"""Time to estimate every joint of a 10-part object on the offline path (target: <= 10 s).

    python benchmarks/bench_joints.py [--repeats 3] [--kind cabinet --seed 53]

The generated object (cabinet 53 has a base and nine movable parts) is reconstructed up to its
joints in both variants; the joint stage (geometric hypotheses judged by collision sweeps
against the mesh) is timed on its own by the pipeline's stage timer. Reports the median over
repeats, the ratio to the 10 s target, and how many joints were found against ground truth.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kind", default="cabinet")
    parser.add_argument("--seed", type=int, default=53)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    import tempfile
    from pathlib import Path

    from rest2art.generate import generate_object, write_object
    from rest2art.io.load import load_mesh
    from rest2art.pipeline import StageTimer, reconstruct_mesh

    rows = {}
    for variant in ("asset", "scan"):
        obj = generate_object(args.kind, args.seed, variant)
        with tempfile.TemporaryDirectory() as folder:
            mesh = load_mesh(write_object(obj, Path(folder)))
        joint_s, total_s, found = [], [], 0
        for _ in range(args.repeats):
            timer = StageTimer()
            start = time.perf_counter()
            asset = reconstruct_mesh(mesh, timer=timer)
            total_s.append(time.perf_counter() - start)
            joint_s.append(timer.times["joints"])
            found = len(asset.movable_joints)
        rows[variant] = {"parts_gt": len(obj.asset.parts), "joints_gt": len(obj.asset.movable_joints),
                         "joints_found": found, "faces": int(len(obj.mesh.faces)),
                         "joints_median_s": float(np.median(joint_s)), "target_ratio": float(np.median(joint_s)) / 10.0,
                         "reconstruct_median_s": float(np.median(total_s))}
    print("| variant | faces | joints (found / true) | joint stage, median | / 10 s target | parts + joints, median |")
    print("|---|---|---|---|---|---|")
    for variant, r in rows.items():
        print(f"| {variant} | {r['faces']} | {r['joints_found']} / {r['joints_gt']} | {r['joints_median_s']:.2f} s | "
              f"{r['target_ratio']:.2f} | {r['reconstruct_median_s']:.1f} s |")
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
