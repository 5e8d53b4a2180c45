"""``rest2art catalog build | summary | verify``: the command-line side of catalogs."""

from __future__ import annotations

import os
import time
from collections import Counter
from pathlib import Path

EXIT_FAILED = 3
"""Exit code of a build in which some object failed, and of a verify that found a problem."""


def add_catalog_parser(sub) -> None:
    """Add the ``catalog`` command and its sub-commands to the CLI's sub-parsers."""
    from rest2art.cli import add_config_options

    p = sub.add_parser("catalog", help="build, summarise and verify a catalog of assets",
                       description="Build a catalog of simulation-ready assets from many meshes (resumable, one "
                                   "worker process per object), print its summary, or verify its files.")
    csub = p.add_subparsers(dest="catalog_command", required=True, metavar="CATALOG_COMMAND")
    b = csub.add_parser("build", help="reconstruct, validate and publish every input into the catalog",
                        description="Each input object (mesh files; folders, searched recursively; manifests "
                                    "(.jsonl: path, name, units, up, front, category per line)) is reconstructed, "
                                    "validated and refined in its own worker process with a time and memory limit "
                                    "(config section 'catalog'), and ends published (CATALOG/NAME), rejected "
                                    "(CATALOG/rejected/NAME with its reasons), static (no movable part) or failed. "
                                    "Objects whose content key is already in the catalog are skipped, so a killed "
                                    "build resumes where it stopped. Writes CATALOG/index.jsonl and "
                                    "CATALOG/index.html. Exit 0 when no object failed, 3 otherwise.")
    b.add_argument("inputs", nargs="+", help="mesh files, folders or .jsonl manifests")
    b.add_argument("--catalog", default="assets_out", help="catalog folder (default: assets_out)")
    b.add_argument("--workers", type=int, default=max(1, os.cpu_count() or 1),
                   help="worker processes at a time (default: the number of CPUs)")
    b.add_argument("--ray", metavar="ADDRESS",
                   help="run the objects as Ray tasks instead: 'auto' (the running cluster), 'local' (start one "
                        "here) or HOST:PORT; needs the ray extra (pip install -e \".[ray]\")")
    add_config_options(b)
    b.add_argument("--retry-failed", action="store_true", help="run failed objects again (they are skipped otherwise)")
    b.add_argument("--allow-static", action="store_true",
                   help="publish objects in which no movable part was found as rigid assets (default: outcome static)")
    b.add_argument("--quiet", action="store_true", help="a log line per object instead of the progress bar")
    s = csub.add_parser("summary", help="counts per outcome and category, failures and the slowest objects")
    s.add_argument("--catalog", default="assets_out", help="catalog folder (default: assets_out)")
    s.add_argument("--top", type=int, default=10, help="slowest objects to list (default 10)")
    v = csub.add_parser("verify", help="re-check every entry's files against its hashes",
                        description="Re-hash every file of every entry and compare with entry.json and the index; "
                                    "exit 3 when anything is missing, changed or unlisted.")
    v.add_argument("--catalog", default="assets_out", help="catalog folder (default: assets_out)")


def _counts_text(counts: Counter) -> str:
    return " ".join(f"{o} {counts.get(o, 0)}" for o in ("published", "rejected", "static", "failed"))


def cmd_build(args, console) -> int:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from rest2art.catalog.build import build_catalog
    from rest2art.cli import config_from_args

    config = config_from_args(args)
    started = {"t": time.perf_counter(), "skipped": 0, "total": 0}
    bar = None if args.quiet else Progress(
        TextColumn("catalog"), BarColumn(), MofNCompleteColumn(), TextColumn("{task.fields[counts]}"),
        TextColumn("{task.fields[rate]}"), TimeElapsedColumn(), console=console, transient=False)
    task = None

    def on_start(total: int, skipped: int, counts: Counter) -> None:
        nonlocal task
        started.update(t=time.perf_counter(), skipped=skipped, total=total)
        if bar is not None:
            bar.start()
            task = bar.add_task("catalog", total=total, completed=skipped, counts=_counts_text(counts), rate="")
        else:
            print(f"catalog {args.catalog}: {total} objects, {skipped} already built", flush=True)

    def on_result(record: dict, counts: Counter) -> None:
        done = sum(counts.values()) - started["skipped"]
        minutes = (time.perf_counter() - started["t"]) / 60
        per_min = done / minutes if minutes > 0 else 0.0
        left = started["total"] - started["skipped"] - done
        eta = f"ETA {left / per_min:.0f} min" if per_min > 0 else "ETA -"
        if bar is not None:
            bar.update(task, advance=1, counts=_counts_text(counts), rate=f"{per_min:.1f} obj/min {eta}")
        else:
            reason = f": {record['error']}" if record.get("error") else ""
            seconds = record.get("timings", {}).get("total_s", 0.0)
            print(f"{record['name']}: {record['outcome']} ({seconds:.1f} s){reason} [{_counts_text(counts)}; "
                  f"{per_min:.1f} obj/min, {eta}]", flush=True)

    try:
        report = build_catalog(args.inputs, args.catalog, config, args.workers, args.ray, args.retry_failed,
                               on_start, on_result)
    finally:
        if bar is not None:
            bar.stop()
    print(f"{args.catalog}: {report.jobs} objects ({report.skipped} already built): {_counts_text(report.outcomes)}; "
          f"{Path(args.catalog) / 'index.html'}")
    for name in report.failed:
        record = next((r for r in report.records if r["name"] == name), None)
        if record is not None:
            print(f"  failed: {name}: {record['error']}")
    return EXIT_FAILED if report.failed else 0


def cmd_summary(args) -> int:
    from rest2art.catalog.store import INDEX, latest_records, read_index
    from rest2art.errors import InputError

    root = Path(args.catalog)
    if not (root / INDEX).is_file():
        raise InputError(f"{root}: not a catalog (no {INDEX})")
    records = list(latest_records(read_index(root)).values())
    print(f"{root}: {len(records)} objects: {_counts_text(Counter(r['outcome'] for r in records))}")
    by_category = Counter((r.get("category") or "unknown", r["outcome"]) for r in records)
    for category in sorted({c for c, _ in by_category}):
        print(f"  {category}: " + ", ".join(f"{n} {o}" for (c, o), n in sorted(by_category.items()) if c == category))
    total = [r.get("timings", {}).get("total_s", 0.0) for r in records]
    if total:
        print(f"time per object: median {sorted(total)[len(total) // 2]:.1f} s, total {sum(total) / 60:.1f} min")
    slowest = sorted(records, key=lambda r: -r.get("timings", {}).get("total_s", 0.0))[:args.top]
    if slowest:
        print(f"slowest {len(slowest)}:")
        for r in slowest:
            print(f"  {r['timings'].get('total_s', 0.0):8.1f} s  {r['name']} ({r['outcome']})")
    for r in records:
        if r["outcome"] == "failed":
            print(f"failed: {r['name']}: {r['error']}")
    return 0


def cmd_verify(args) -> int:
    from rest2art.catalog.store import INDEX, latest_records, read_index, verify
    from rest2art.errors import InputError

    root = Path(args.catalog)
    if not (root / INDEX).is_file():
        raise InputError(f"{root}: not a catalog (no {INDEX})")
    problems = verify(root)
    for problem in problems:
        print(f"{root}/{problem}")
    entries = sum(1 for r in latest_records(read_index(root)).values() if r.get("path"))
    print(f"{root}: {entries} entries checked, {len(problems)} problems")
    return EXIT_FAILED if problems else 0


def run_catalog(args, console) -> int:
    """Dispatch ``rest2art catalog SUBCOMMAND``."""
    if args.catalog_command == "build":
        return cmd_build(args, console)
    if args.catalog_command == "summary":
        return cmd_summary(args)
    return cmd_verify(args)

