"""Peak memory (and time) of reconstruction against face count, fused scan and artist mesh.

    python benchmarks/bench_memory.py [--faces 50000 200000 500000 1000000] [--variant asset scan]
                                      [--inputs DIR] [--out results.json]

Inputs are made once into --inputs (kept between runs, so the largest can be measured alone
later): the artist-style cabinet (generator seed 3, asset variant) subdivided to the face count
(whole-mesh steps, then decimated to it), and the same cabinet's fused scan made at a fine
voxel and decimated to the face count. Each reconstruction runs in a fresh process; its peak
resident memory (``ru_maxrss``) is reported and checked against the config's memory budget
(``load.memory_budget_mb``). CoACD runs in child processes on meshes of at most
``collision.coacd_max_faces`` faces, so they are not counted.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = r"""
import json, resource, sys, time, dataclasses
from rest2art.config import Config
from rest2art.pipeline import reconstruct_file
cfg = Config()
cfg = dataclasses.replace(cfg, collision=dataclasses.replace(cfg.collision, cache_dir=sys.argv[2]))
t = time.perf_counter()
asset, mesh = reconstruct_file(sys.argv[1], cfg)
print(json.dumps({"seconds": round(time.perf_counter() - t, 1), "faces": int(len(mesh.faces)),
                  "peak_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024),
                  "budget_mb": cfg.load.memory_budget_mb, "notes": mesh.notes,
                  "parts": len(asset.parts), "movable": len(asset.movable_joints)}))
"""


def subdivided_to(mesh, faces: int):
    """``mesh`` subdivided to about ``faces`` faces: whole-mesh steps until it has at least that
    many, then quadric decimation down to it. (Subdividing only a share of the faces would leave
    a T-junction on every neighbour of a subdivided face: a mesh cracked into tens of thousands
    of islands, which no modeller exports.)"""
    from rest2art.completion.solids import decimated

    while len(mesh.faces) < faces:
        mesh = mesh.subdivide()
    return decimated(mesh, faces)


def make_input(folder: Path, variant: str, faces: int) -> Path:
    """The input mesh for one (variant, faces), made once into ``folder``."""
    from rest2art.generate import generate_object, write_object

    path = folder / f"{variant}_{faces}.obj"
    if path.is_file():
        return path
    folder.mkdir(parents=True, exist_ok=True)
    if variant == "asset":
        subdivided_to(generate_object("cabinet", 3, "asset").mesh, faces).export(path)
        return path
    voxel = 0.005 * (120_000 / faces) ** 0.5  # fine enough to have more faces than asked, then decimated
    scan = generate_object("cabinet", 3, "scan", scan_voxel=voxel, scan_max_faces=faces)
    written = write_object(scan, folder / f"scan_{faces}")
    Path(written).rename(path)
    return path


def measure(path: Path, cache: Path) -> dict:
    proc = subprocess.run([sys.executable, "-c", CHILD, str(path), str(cache)], capture_output=True, text=True)
    if proc.returncode != 0:
        return {"error": (proc.stderr.strip().splitlines() or ["killed"])[-1], "returncode": proc.returncode}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--faces", type=int, nargs="+", default=[50_000, 200_000, 500_000, 1_000_000])
    parser.add_argument("--variant", nargs="+", choices=["asset", "scan"], default=["asset", "scan"])
    parser.add_argument("--inputs", default="bench_memory_inputs", help="folder of the input meshes (kept)")
    parser.add_argument("--out", help="also write the results as JSON here")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        for faces in args.faces:
            for variant in args.variant:
                path = make_input(Path(args.inputs), variant, faces)
                result = {"variant": variant, "target_faces": faces, **measure(path, Path(cache))}
                rows.append(result)
                print(json.dumps(result), flush=True)
    print("| variant | faces | peak MB | seconds | within budget |")
    print("|---|---|---|---|---|")
    for r in rows:
        if "error" in r:
            print(f"| {r['variant']} | {r['target_faces']:,} | failed: {r['error']} | | no |")
            continue
        print(f"| {r['variant']} | {r['faces']:,} | {r['peak_mb']:,} | {r['seconds']} | "
              f"{'yes' if r['peak_mb'] <= r['budget_mb'] else 'no'} |")
    if args.out:
        Path(args.out).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
