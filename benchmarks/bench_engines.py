"""Do PyBullet and MuJoCo agree on actuation? Read from built catalogs.

    python benchmarks/bench_engines.py CATALOG [CATALOG ...] [--json OUT]

Every object of a catalog that reached validation keeps ``validation.json`` (published entries
in their folder, rejected ones under ``rejected/``). Each actuation finding there says whether
MuJoCo and PyBullet each pushed the joint open and shut again (self-collision on in both: the
MJCF and PyBullet leave out only each joint's parent/child pair). Reports per group (the last
``_`` field of the object's name, e.g. ``asset`` or ``scan`` for generated inputs), for the
first validation round (the asset as reconstructed) and the last (after refinement): objects,
joints, both pass, both fail, only MuJoCo fails, only PyBullet fails, and every disagreement
with its finding's message. A catalog built before findings named each engine's verdict
(``mujoco_ok`` / ``pybullet_ok``) cannot be read.
"""

from __future__ import annotations

import argparse
import json
from collections import Counter, defaultdict
from pathlib import Path

ENGINES = ("mujoco", "pybullet")


def verdict(finding: dict) -> str:
    """'both pass', 'both fail', 'only mujoco fails' or 'only pybullet fails' of one finding."""
    ok = {engine: finding["data"][f"{engine}_ok"] for engine in ENGINES}
    if all(ok.values()):
        return "both pass"
    if not any(ok.values()):
        return "both fail"
    return "only " + next(e for e, v in ok.items() if not v) + " fails"


def actuation_verdicts(report: dict, round_index: int) -> list[tuple[str, str, str]]:
    """(joint, verdict, message) of one validation round's per-joint actuation findings."""
    findings = report["rounds"][round_index]["findings"]
    return [(f["subject"], verdict(f), f["message"]) for f in findings
            if f["check"] == "actuation" and f.get("data") and "mujoco_ok" in f["data"]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("catalogs", nargs="+", type=Path)
    parser.add_argument("--json", type=Path, default=None, help="write the tables here too")
    args = parser.parse_args()

    from rest2art.catalog.store import latest_records, read_index

    tables: dict[str, dict] = defaultdict(lambda: {"objects": 0, "first": Counter(), "last": Counter(),
                                                   "disagreements": []})
    for root in args.catalogs:
        for record in latest_records(read_index(root)).values():
            if record["outcome"] not in ("published", "rejected"):
                continue
            report = json.loads((root / record["path"] / "validation.json").read_text())
            group = tables[record["name"].rsplit("_", 1)[-1]]
            group["objects"] += 1
            for key, index in (("first", 0), ("last", -1)):
                for joint, result, message in actuation_verdicts(report, index):
                    group[key][result] += 1
                    if key == "last" and result.startswith("only"):
                        group["disagreements"].append(f"{record['name']} ({record['outcome']}) {joint}: {message}")
    for name, group in sorted(tables.items()):
        print(f"== {name}: {group['objects']} objects validated")
        for key in ("first", "last"):
            counts = group[key]
            joints = sum(counts.values())
            agree = counts["both pass"] + counts["both fail"]
            print(f"  {key} round: {joints} joints, agree {agree} ({100 * agree / max(1, joints):.1f} %): "
                  + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
        for line in group["disagreements"]:
            print("   ", line)
    if args.json:
        args.json.write_text(json.dumps({k: {**v, "first": dict(v["first"]), "last": dict(v["last"])}
                                         for k, v in tables.items()}, indent=1))


if __name__ == "__main__":
    main()
