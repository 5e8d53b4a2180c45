"""`rest2art envs solve PATH`: the scripted policy on every movable joint of every published
asset under PATH (a catalog folder, or one asset folder), opening and then closing each."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

from rest2art.config import EnvConfig
from rest2art.errors import InputError


def asset_folders(path: str | Path) -> list[Path]:
    """``path`` itself when it is an asset folder (articulation.json), else the published
    assets of the catalog it holds."""
    from rest2art.sim.envs.scene import catalog_assets

    path = Path(path)
    if (path / "articulation.json").is_file():
        return [path]
    return catalog_assets(path)


def solve_joint(folder: Path, joint: str, config: EnvConfig, seed: int, randomize: bool) -> dict:
    """Open then close one joint with the scripted policy (one episode each)."""
    from rest2art.sim.envs import CloseArticulationEnv, OpenArticulationEnv
    from rest2art.sim.policies.scripted import ScriptedPolicy, run_episode

    record = {}
    for mode, env_class in (("open", OpenArticulationEnv), ("close", CloseArticulationEnv)):
        env = env_class(asset=folder, joint=joint, randomize=randomize, config=config)
        record[mode] = run_episode(env, ScriptedPolicy(mode, config), seed=seed)
        env.close()
    return record


def solve(path: str | Path, config: EnvConfig = EnvConfig(), randomize: bool = False, progress=None) -> list[dict]:
    """One record per movable joint of every asset under ``path``: asset, category, joint,
    type, grasp mode, and the open and close episodes (success, final fraction, reason)."""
    from rest2art.sim.envs.scene import load_scene

    records = []
    for folder in asset_folders(path):
        try:
            scene = load_scene(str(folder.resolve()), config)
        except InputError as exc:
            records.append({"asset": folder.name, "error": str(exc)})
            continue
        for k, (name, task) in enumerate(scene.tasks.items()):
            record = {"asset": folder.name, "category": scene.category, "joint": name, "type": task.type,
                      "grasp": task.grasp.mode}
            record.update(solve_joint(folder, name, config, seed=k, randomize=randomize))
            record["success"] = record["open"]["success"] and record["close"]["success"]
            records.append(record)
            if progress:
                progress(record)
    return records


def summary(records: list[dict]) -> dict:
    """Success shares (%) over the joints: open, close, both; failures by reason."""
    joints = [r for r in records if "error" not in r]
    n = max(1, len(joints))
    reasons: dict[str, int] = {}
    for r in joints:
        for mode in ("open", "close"):
            if not r[mode]["success"]:
                key = f"{mode}: {re.sub(r'[0-9.-]+', 'N', r[mode]['reason'])}"
                reasons[key] = reasons.get(key, 0) + 1
    return {"assets": len({r["asset"] for r in records}), "joints": len(joints),
            "asset_errors": len(records) - len(joints),
            "open_pct": 100.0 * sum(r["open"]["success"] for r in joints) / n,
            "close_pct": 100.0 * sum(r["close"]["success"] for r in joints) / n,
            "success_pct": 100.0 * sum(r["success"] for r in joints) / n, "failures": reasons}


def write_json(records: list[dict], path: Path) -> None:
    """records and summary to ``path``, written under a temporary name and renamed."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(json.dumps({"summary": summary(records), "joints": records}, indent=1, default=float))
    tmp.replace(path)


def print_table(records: list[dict], console) -> None:
    """The success table, one row per joint; the last line gives the overall success."""
    from rich.table import Table

    if not console.is_terminal:
        console.width = max(console.width, 160)
    table = Table(title="scripted policy: open to the target, then close")
    for column in ("asset", "joint", "type", "grasp", "open", "close", "reason"):
        table.add_column(column)
    for r in records:
        if "error" in r:
            table.add_row(r["asset"], "-", "-", "-", "-", "-", r["error"])
            continue
        cells = [f"{'ok' if r[m]['success'] else 'FAIL'} {100 * r[m]['final_fraction']:.0f} %" for m in ("open", "close")]
        reason = "; ".join(f"{m}: {r[m]['reason']}" for m in ("open", "close") if r[m]["reason"])
        table.add_row(r["asset"], r["joint"], r["type"], r["grasp"], *cells, reason)
    console.print(table)
    s = summary(records)
    for reason, count in sorted(s["failures"].items(), key=lambda kv: -kv[1]):
        console.print(f"  {count} x {reason}")
    console.print(f"opened {s['open_pct']:.1f} %, closed {s['close_pct']:.1f} % of {s['joints']} joints "
                  f"({s['assets']} assets)")
    print(f"overall success: {s['success_pct']:.1f} % ({sum(r.get('success', False) for r in records)} of "
          f"{s['joints']} joints opened and closed)")


def main_envs(args, console) -> int:
    """The ``envs`` command: ``solve PATH [-o FILE] [--randomize] [--config FILE]``."""
    from rest2art.config import load_config

    config = (load_config(args.config) if args.config else load_config()).envs
    out = Path(args.out)
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as bar:
        task = bar.add_task("solving", total=None)
        records = solve(args.path, config, args.randomize, progress=lambda r: bar.advance(task))
    write_json(records, out)
    console.print(f"written: {out}")
    print_table(records, console)
    return 0
