"""Reconstruct time and peak memory for a ~50k-face cabinet (median of repeated runs).

    python benchmarks/bench_reconstruct.py [--repeats 5] [--faces 50000]

Both variants are measured: the artist-style asset mesh subdivided to about --faces faces
(same geometry, more triangles), and the fused scan mesh decimated to about --faces faces. Each
run is a fresh process (peak RSS is per run); the CoACD cache is cleared before the first run,
so run 1 is cold and the rest are warm, as on a resumed catalog build.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CHILD = r"""
import json, resource, sys, time, dataclasses
from rest2art.config import Config
from rest2art.pipeline import reconstruct_file
cfg = Config()
cfg = dataclasses.replace(cfg, collision=dataclasses.replace(cfg.collision, cache_dir=sys.argv[2]))
t = time.perf_counter()
asset, mesh = reconstruct_file(sys.argv[1], cfg)
print(json.dumps({"seconds": time.perf_counter() - t, "faces": int(len(mesh.faces)),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "stages": asset.metadata["timing_s"]}))
"""


def make_inputs(folder: Path, faces: int) -> dict[str, Path]:
    from rest2art.generate import generate_object, write_object

    asset = generate_object("cabinet", 3, "asset")
    mesh = asset.mesh
    while len(mesh.faces) * 4 <= faces:
        mesh = mesh.subdivide()
    asset_path = folder / "asset.obj"
    mesh.export(asset_path)
    scan = generate_object("cabinet", 3, "scan", scan_max_faces=faces)
    scan_path = write_object(scan, folder / "scan")
    return {"asset": asset_path, "scan": scan_path}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--faces", type=int, default=50_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        inputs = make_inputs(tmp, args.faces)
        results = {}
        for variant, path in inputs.items():
            cache = tmp / f"cache-{variant}"
            shutil.rmtree(cache, ignore_errors=True)
            runs = []
            for _ in range(args.repeats):
                out = subprocess.run([sys.executable, "-c", CHILD, str(path), str(cache)], capture_output=True,
                                     text=True, check=True)
                runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
            seconds = [r["seconds"] for r in runs]
            results[variant] = {
                "faces": runs[0]["faces"],
                "cold_seconds": round(seconds[0], 2),
                "median_seconds": round(float(np.median(seconds)), 2),
                "median_warm_seconds": round(float(np.median(seconds[1:])), 2) if len(seconds) > 1 else None,
                "peak_mb_max": round(max(r["peak_mb"] for r in runs), 1),
                "stages_cold": runs[0]["stages"],
            }
            print(variant, json.dumps(results[variant]), flush=True)
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
