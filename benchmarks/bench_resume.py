"""A large catalog build killed at a random moment and resumed, against the same build left alone.

    python benchmarks/bench_resume.py [--count 200] [--variant both] [--workers 2] [--out DIR]

Generates ``count`` objects (kinds mixed, as ``bench_catalog.py``), then builds the catalog twice
through the command line, each with its own empty CoACD cache so that the two builds share
nothing: once uninterrupted, once killed with SIGKILL (the whole process group) at a random
moment between 20 % and 90 % of the first build's wall time and started again with the same
command. Reports both wall times, how many objects the kill left built, and every object whose
record or files differ (``rest2art.catalog.store.snapshot``: timings left out). Both catalogs are
kept under ``--out`` for ``benchmarks/bench_engines.py``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_catalog import make_inputs  # noqa: E402


def _command(inputs: Path, catalog: Path, config: Path, workers: int) -> list[str]:
    return [sys.executable, "-m", "rest2art.cli", "catalog", "build", str(inputs), "--catalog", str(catalog),
            "--workers", str(workers), "--config", str(config), "--quiet"]


def _config(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "build.yaml"
    path.write_text(f"collision:\n  cache_dir: {folder / 'coacd-cache'}\n")
    return path


def _run(command: list[str], log: Path) -> float:
    start = time.perf_counter()
    with log.open("a") as out:
        code = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT).returncode
    if code not in (0, 1):  # 1: some object failed, still a finished build
        raise SystemExit(f"{' '.join(command)} exited {code}; see {log}")
    return time.perf_counter() - start


def _killed_run(command: list[str], log: Path, after_s: float) -> float:
    start = time.perf_counter()
    with log.open("a") as out:
        proc = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            proc.wait(timeout=after_s)
            raise SystemExit(f"the build ended before the kill at {after_s:.0f} s")
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--variant", default="both", choices=("asset", "scan", "both"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=None, help="seed of the kill moment (default: random)")
    parser.add_argument("--out", type=Path, default=Path("bench_resume_out"))
    args = parser.parse_args()

    from rest2art.catalog.store import read_index, snapshot, verify

    out = args.out
    inputs = out / "inputs"
    if not inputs.is_dir():
        make_inputs(inputs, args.count, args.variant)
    whole, resumed = out / "uninterrupted", out / "killed"
    whole_cmd = _command(inputs, whole / "catalog", _config(whole), args.workers)
    whole_s = _run(whole_cmd, whole / "build.log")
    print(f"uninterrupted: {whole_s:.0f} s", flush=True)

    kill_at = random.Random(args.seed).uniform(0.2, 0.9) * whole_s
    resumed_cmd = _command(inputs, resumed / "catalog", _config(resumed), args.workers)
    first_s = _killed_run(resumed_cmd, resumed / "build.log", kill_at)
    built_at_kill = len({r["name"] for r in read_index(resumed / "catalog")})
    second_s = _run(resumed_cmd, resumed / "build.log")
    print(f"killed at {first_s:.0f} s with {built_at_kill} indexed; resumed in {second_s:.0f} s", flush=True)

    a, b = snapshot(whole / "catalog"), snapshot(resumed / "catalog")
    differing = {}
    for name in sorted(set(a) | set(b)):
        if a.get(name) != b.get(name):
            if name not in a or name not in b:
                differing[name] = ["only in one catalog"]
                continue
            (ra, ja), (rb, jb) = a[name], b[name]
            fields = sorted(k for k in set(ra) | set(rb) if ra.get(k) != rb.get(k) and k != "files")
            files = sorted(k for k in set(ra["files"]) | set(rb["files"]) if ra["files"].get(k) != rb["files"].get(k))
            differing[name] = fields + [f"file {f}" for f in files] + (["articulation.json"] if ja != jb else [])
    outcomes = dict(Counter(stable["outcome"] for stable, _ in a.values()))
    result = {"objects": len(a), "workers": args.workers, "uninterrupted_s": round(whole_s, 1),
              "killed_after_s": round(first_s, 1), "indexed_at_kill": built_at_kill,
              "resumed_s": round(second_s, 1), "outcomes": outcomes, "differing": differing,
              "index_lines": len(read_index(resumed / "catalog")),
              "verify_problems": {"uninterrupted": verify(whole / "catalog"), "killed": verify(resumed / "catalog")}}
    (out / "resume.json").write_text(json.dumps(result, indent=1))
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
