"""`rest2art bench`: reconstruct a set of objects with ground truth and score them.

Each object runs in its own worker process (crash isolation, and a per-object peak memory
reading); results land in OUT/results.json and OUT/report.md: the DESIGN.md metrics overall and
per source (where the ground truth comes from: a package, or the generator), up and front
correctness, the yield (objects right, and published right or wrong with ``--check``), and per
object the first stage that went wrong.
"""

from __future__ import annotations

import json
import multiprocessing as mp
import resource
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rest2art.asset import read_articulation
from rest2art.bench.metrics import (
    STAGES,
    BenchConfig,
    ObjectScore,
    PartScore,
    first_failure,
    frame_verdict,
    is_right,
    score_object,
    summarize,
)
from rest2art.config import Config
from rest2art.generate.objects import KINDS


@dataclass(frozen=True)
class BenchItem:
    """One object with ground truth: generated from (kind, seed), or a prepared folder."""

    name: str
    variant: str
    kind: str | None = None
    seed: int | None = None
    source: str | None = None
    """A ground-truth folder (mesh.obj + articulation.json + face_part.npy) to score against
    (the origin a report groups by is the ``source`` of that ground truth's metadata)."""
    mix: str | None = None
    """A generator mix (``real-like``, ``furniture``): the object is ``seed`` of that mix."""

    def materialize(self, gt_dir: Path, scan_voxel: float) -> None:
        """Make sure ``gt_dir`` holds the ground truth."""
        if (gt_dir / "articulation.json").is_file():
            return
        if self.source is not None:
            import shutil

            shutil.copytree(self.source, gt_dir, dirs_exist_ok=True)
            return
        from rest2art.generate import generate_mix_object, generate_object, write_object

        if self.mix is not None:
            write_object(generate_mix_object(self.mix, self.seed, self.variant, scan_voxel=scan_voxel), gt_dir)
            return
        write_object(generate_object(self.kind, self.seed, self.variant, scan_voxel=scan_voxel), gt_dir)


def generated_items(count: int, variant: str, seed: int = 0, kinds: tuple[str, ...] = KINDS) -> list[BenchItem]:
    """``count`` objects cycling through ``kinds`` (seeds seed, seed+1, ...)."""
    items = []
    for k in range(count):
        kind = kinds[k % len(kinds)]
        items.append(BenchItem(f"{kind}_{seed + k:04d}", variant, kind, seed + k))
    return items


def mix_items(mix: str, count: int, variant: str, seed: int = 0) -> list[BenchItem]:
    """``count`` objects of a generator mix (seeds seed, seed+1, ...), e.g. ``real-like``."""
    from rest2art.generate import MIX_KINDS
    from rest2art.generate.variation import mix_entry

    entries = [mix_entry(mix, seed + k, MIX_KINDS[mix]) for k in range(count)]
    return [BenchItem(e.name, variant, e.kind, e.seed, mix=mix) for e in entries]


def prepared_items(set_root: str | Path, variant: str, sources: list[str] | None = None) -> list[BenchItem]:
    """Items of a prepared set (``rest2art bench prepare``), only those whose ground truth
    comes from one of ``sources`` when given."""
    folder = Path(set_root) / variant
    names = sorted(p.name for p in folder.iterdir() if (p / "articulation.json").is_file()) if folder.is_dir() else []
    if sources:
        names = [n for n in names if item_source(read_articulation(folder / n, load_meshes=False)) in sources]
    return [BenchItem(name, variant, source=str(folder / name)) for name in names]


def item_source(gt) -> str:
    """Where a ground truth comes from: its metadata's ``source`` (a package), ``generated``
    for the generator's objects, else ``unknown``."""
    return gt.metadata.get("source") or ("generated" if "generator" in gt.metadata else "unknown")


def true_frame(gt) -> dict | None:
    """The truth's up and front in its file frame ({"up": (3,), "front": (3,) or None}): written
    by the development-set importer, or the generator's pose of its canonical frame (+z up,
    -y front); None when the ground truth does not say."""
    if "frame_truth" in gt.metadata:
        return gt.metadata["frame_truth"]
    generator = gt.metadata.get("generator")
    if not generator:
        return None
    from rest2art.generate import file_pose

    R = file_pose(generator.get("up", "z"), float(generator.get("yaw_deg", 0.0)))[:3, :3]
    return {"up": (R @ [0.0, 0.0, 1.0]).tolist(), "front": (R @ [0.0, -1.0, 0.0]).tolist()}


def score_folders(pred_dir: str | Path, gt_dir: str | Path, name: str = "") -> ObjectScore:
    """Score a prediction folder against a ground-truth folder (both in the contract); face
    areas come from GT_DIR/mesh.obj read by the same loader, so face order is the one
    face_part.npy indexes."""
    from rest2art.io.load import load_mesh

    pred = read_articulation(pred_dir, load_meshes=False)
    gt = read_articulation(gt_dir, load_meshes=False)
    mesh = load_mesh(Path(gt_dir) / "mesh.obj").trimesh()
    return score_object(pred, gt, mesh.area_faces, name or Path(gt_dir).name)


def _run_item(args: tuple) -> dict:
    item, out, config_path, check, scan_voxel, cold = args
    import dataclasses
    import shutil
    import tempfile

    from rest2art.config import load_config
    from rest2art.export.writers import write_asset
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import reconstruct_file

    config = load_config(config_path) if config_path else Config()
    cold_cache = tempfile.mkdtemp(prefix="rest2art-coacd-") if cold else None
    if cold_cache:  # an empty CoACD cache of its own: every decomposition runs, as for a new catalog
        config = dataclasses.replace(config, collision=dataclasses.replace(config.collision, cache_dir=cold_cache))
    # the catalog's per-object memory limit: past it an allocation fails in this worker (an error
    # record) instead of the kernel killing it, which would leave the pool waiting forever
    limit = int(config.catalog.memory_limit_mb) * 2 ** 20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    bench = BenchConfig()
    out = Path(out)
    gt_dir = out / "gt" / item.name
    pred_dir = out / "pred" / item.name
    record = {"name": item.name, "kind": item.kind, "seed": item.seed, "variant": item.variant}
    try:
        item.materialize(gt_dir, scan_voxel)
        gt = read_articulation(gt_dir, load_meshes=False)
        record["source"] = item_source(gt)
        start = time.perf_counter()
        asset, _ = reconstruct_file(gt_dir / "mesh.obj", config)
        record["gate"] = asset.metadata.get("gate")
        record["frame"] = frame_verdict(asset.metadata.get("frame"), true_frame(gt), bench)
        with atomic_folder(pred_dir, overwrite=True) as tmp:
            write_asset(asset, tmp, item.name, config.export, asset.up)
        record["seconds"] = round(time.perf_counter() - start, 3)
        record["stage_seconds"] = asset.metadata.get("timing_s", {})
        record["collision_failures"] = sorted({f for part in asset.metadata.get("collision", {}).values()
                                               for f in part.get("failures", [])})
        record["collision_fallbacks"] = sorted({m for part in asset.metadata.get("collision", {}).values()
                                                for m in part.get("methods", []) if m.startswith("vhacd")})
        score = score_folders(pred_dir, gt_dir, item.name)
        record["score"] = score.to_dict()
        record["right"] = is_right(score, bench)
        stage, detail = first_failure(score, record["frame"], bench)
        record["first_failure"] = {"stage": stage, "detail": detail}
        record["picture"] = write_picture(pred_dir, gt_dir, out / "pictures" / f"{item.name}.png")
        if check:
            record.update(_validate_record(pred_dir, item.name, config))
    except Exception as exc:  # one object's failure must not stop the bench
        record["error"] = f"{type(exc).__name__}: {exc}"
        record["traceback"] = traceback.format_exc()
        record["right"] = False
        record["first_failure"] = {"stage": "error", "detail": record["error"]}
    finally:
        if cold_cache:
            shutil.rmtree(cold_cache, ignore_errors=True)
    record["peak_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)
    return record


def _validate_record(pred_dir: Path, name: str, config: Config) -> dict:
    """Run the validation layer (with refinement) on an exported prediction; what the report needs."""
    from rest2art.sim.mujoco_engine import steps_per_second
    from rest2art.validators.validate import validate_folder

    start = time.perf_counter()
    report = validate_folder(pred_dir, name, config, refine=True)
    seconds = time.perf_counter() - start
    findings = report.findings
    depths = [s["depth_mm"] for f in findings if f.check == "sweep" for s in f.data.get("samples", [])]
    hulls = next((f.data["hulls"] for f in findings if f.check == "collision" and f.subject == "hulls"), {})
    rest = next((f for f in findings if f.check == "sweep" and f.subject == "rest"), None)
    try:
        speed = round(steps_per_second(pred_dir, name, BenchConfig().speed_steps))
    except Exception:  # an asset MuJoCo cannot load has its reason in the checks
        speed = None
    return {
        "validate_seconds": round(seconds, 3),
        "hulls": int(sum(hulls.values())), "most_hulls_per_part": max(hulls.values(), default=0),
        "rest_depth_mm": rest.data.get("max_depth_mm") if rest else None, "rest_clean": rest.ok if rest else None,
        "steps_per_s": speed,
        "decision": report.decision.status,
        "reasons": [str(r) for r in report.decision.reasons],
        "refinements": [a.done for a in report.refinements],
        "max_penetration_mm": max(depths, default=None),
        "actuation": {f.subject: f.ok for f in findings if f.check == "actuation"},
        "checks": {f"{f.check}:{f.subject}": f.ok for f in findings},
        "check_failures": [f"{f.check} {f.subject}: {f.message}" for f in findings if not f.ok],
    }


def write_picture(pred_dir: Path, gt_dir: Path, path: Path) -> str:
    """Truth (top) and prediction (bottom), closed and opened, joint axes drawn; returns the
    path relative to the report folder."""
    from rest2art.render.pictures import closed_and_open, label, save_png

    truth = read_articulation(gt_dir)
    pred = read_articulation(pred_dir)
    if "frame" in pred.metadata:
        truth.metadata["frame"] = pred.metadata["frame"]  # view both from the same side
    image = np.concatenate([label(closed_and_open(truth, 320, axes=True), "truth: closed | opened"),
                            label(closed_and_open(pred, 320, axes=True), "prediction: closed | opened")], axis=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_png(image, path)
    return f"pictures/{path.name}"


def run_items(items: list[BenchItem], out: str | Path, config_path: str | None = None, check: bool = False,
              workers: int = 1, scan_voxel: float = 0.005, progress=None, cold: bool = False) -> list[dict]:
    """Reconstruct and score every item, one fresh worker process per item; ``cold``: each with
    an empty CoACD cache of its own (the time a new catalog pays)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ctx = mp.get_context("spawn")
    records = []
    with ctx.Pool(processes=workers, maxtasksperchild=1) as pool:
        jobs = [(item, str(out), config_path, check, scan_voxel, cold) for item in items]
        for record in pool.imap(_run_item, jobs):
            records.append(record)
            if progress:
                progress(record)
    return records


def _scores(records: list[dict]) -> list[ObjectScore]:
    scores = []
    for r in records:
        if "score" not in r:
            continue
        s = r["score"]
        scores.append(ObjectScore(s["name"], [PartScore(**p) for p in s["parts"]], s["n_gt_movable"], s["n_pred_movable"]))
    return scores


def summary_row(records: list[dict]) -> dict:
    """Summary metrics, check pass rate, failures and median runtime of a bench run."""
    row = summarize(_scores(records))
    row["errors"] = sum("error" in r for r in records)
    times = [r["seconds"] for r in records if "seconds" in r]
    row["median_seconds"] = float(np.median(times)) if times else float("nan")
    row["max_peak_mb"] = max((r["peak_mb"] for r in records), default=0.0)
    for key in ("up", "front"):
        known = [r["frame"][f"{key}_ok"] for r in records if r.get("frame", {}).get(f"{key}_ok") is not None]
        row[f"{key}_known"] = len(known)
        row[f"{key}_ok_pct"] = 100.0 * np.mean(known) if known else float("nan")
    row["right_pct"] = 100.0 * np.mean([bool(r.get("right")) for r in records]) if records else float("nan")
    checked = [r for r in records if "decision" in r]
    if checked:
        published = [r for r in checked if r["decision"] == "publish"]
        row["published_pct"] = 100.0 * len(published) / len(checked)
        row["refined_then_published"] = sum(bool(r["refinements"]) for r in published)
        row["rejected"] = len(checked) - len(published)
        depths = [r["max_penetration_mm"] for r in published if r["max_penetration_mm"] is not None]
        row["published_max_penetration_mm"] = max(depths, default=0.0)
        row["published_over_1mm"] = sum(d > 1.0 for d in depths)
        joints = [ok for r in checked for ok in r["actuation"].values()]
        row["actuation_pass_pct"] = 100.0 * np.mean(joints) if joints else float("nan")
        row["median_validate_seconds"] = float(np.median([r["validate_seconds"] for r in checked]))
        row.update(speed_row(checked))
        # the yield, over every object of the run (a failed run is neither)
        row["published_right_pct"] = 100.0 * sum(bool(r.get("right")) for r in published) / len(records)
        row["published_wrong_pct"] = 100.0 * sum(not r.get("right") for r in published) / len(records)
    return row


def speed_row(checked: list[dict]) -> dict:
    """What an object costs to make and to simulate, over validated records: end-to-end seconds
    (reconstruct, export, checks with refinement; median and 95th percentile), the median seconds
    of each stage, decompositions that timed out (a stand-in used), objects where V-HACD
    decomposed what CoACD could not in its time, hulls per asset (median and most), MuJoCo
    steps/s (median) and published assets whose rest pose is not clean (a movable part inside
    its parent's collision)."""
    done = [r for r in checked if "seconds" in r]
    if not done:
        return {}
    total = [r["seconds"] + r["validate_seconds"] for r in done]
    stages = sorted({k for r in done for k in r.get("stage_seconds", {})})
    speeds = [r["steps_per_s"] for r in done if r.get("steps_per_s")]
    hulls = [r["hulls"] for r in done if "hulls" in r]  # records written before hulls were counted have none
    return {
        "median_total_seconds": float(np.median(total)),
        "p95_total_seconds": float(np.percentile(total, 95)),
        "median_stage_seconds": {k: float(np.median([r.get("stage_seconds", {}).get(k, 0.0) for r in done]))
                                 for k in stages},
        "decomposition_timeouts": sum(any("timed out" in f for f in r.get("collision_failures", [])) for r in done),
        "coacd_fallbacks": sum(bool(r.get("collision_fallbacks")) for r in done),
        "median_hulls": float(np.median(hulls)) if hulls else float("nan"),
        "max_hulls": max(hulls, default=0),
        "median_steps_per_s": float(np.median(speeds)) if speeds else float("nan"),
        "published_rest_not_clean": sum(r["decision"] == "publish" and r.get("rest_clean") is False for r in done),
    }


def by_source(records: list[dict]) -> dict[str, list[dict]]:
    """Records grouped by the source of their ground truth, sources in order of appearance."""
    groups: dict[str, list[dict]] = {}
    for r in records:
        groups.setdefault(r.get("source") or "unknown", []).append(r)
    return groups


def failure_counts(records: list[dict]) -> dict[str, int]:
    """How many objects first went wrong at each stage (``error``: the run failed)."""
    counts = {stage: 0 for stage in (*STAGES, "error")}
    for r in records:
        counts[r.get("first_failure", {}).get("stage", "error")] += 1
    return counts


def _object_row(r: dict) -> dict:
    s = r["score"]
    mov = [p for p in s["parts"] if p["movable"]]
    ang = [p["axis_angle_deg"] for p in mov if p["axis_angle_deg"] is not None]
    pos = [p["axis_pos_dm"] for p in mov if p["axis_pos_dm"] is not None]
    checks = "-" if "decision" not in r else r["decision"] + (": " + "; ".join(r["reasons"]) if r["reasons"] else "")
    return {"object": r["name"], "source": r.get("source", "-"), "GT movable": s["n_gt_movable"],
            "pred movable": s["n_pred_movable"], "mIoU": f"{s['miou']:.3f}",
            "type ok": f"{sum(p['type_correct'] for p in mov)}/{len(mov)}",
            "max axis angle (deg)": f"{max(ang, default=0):.2f}", "max axis pos (dm)": f"{max(pos, default=0):.3f}",
            "time (s)": f"{r['seconds']:.1f}", "peak MB": f"{r['peak_mb']:.0f}", "validation": checks}


def _verdict(ok: bool | None, angle: float | None) -> str:
    return "-" if ok is None else f"{'ok' if ok else 'wrong'} ({angle:.0f} deg)"


def _diagnosis_row(r: dict) -> dict:
    """One object's first failing stage, frame verdicts, gate and decision."""
    frame, gate = r.get("frame") or {}, r.get("gate")
    return {"object": r["name"], "source": r.get("source", "-"), "first failure": r["first_failure"]["stage"],
            "detail": r["first_failure"]["detail"] or "-",
            "up": _verdict(frame.get("up_ok"), frame.get("up_deg")),
            "front": _verdict(frame.get("front_ok"), frame.get("front_deg")),
            "right": "yes" if r.get("right") else "no",
            "gate": gate.get("decision", "-") if isinstance(gate, dict) else "-", "decision": r.get("decision", "-")}


def _source_row(source: str, records: list[dict]) -> dict:
    """The headline figures of one source's objects."""
    row = summary_row(records)
    pct = lambda v: "-" if v != v else f"{v:.1f} %"  # noqa: E731  (NaN: nothing to count)
    out = {"source": source, "objects": row["objects"] + row["errors"], "movable parts": row["movable_parts"],
           "type acc.": pct(row["type_accuracy_pct"]),
           "axis angle": "-" if row["axis_angle_deg"] != row["axis_angle_deg"] else f"{row['axis_angle_deg']:.2f} deg",
           "axis pos.": "-" if row["axis_pos_dm"] != row["axis_pos_dm"] else f"{row['axis_pos_dm']:.3f} dm",
           "mIoU": "-" if row["miou"] != row["miou"] else f"{row['miou']:.3f}", "part count": pct(row["part_count_pct"]),
           "up ok": f"{pct(row['up_ok_pct'])} of {row['up_known']}",
           "front ok": f"{pct(row['front_ok_pct'])} of {row['front_known']}", "right": pct(row["right_pct"])}
    if "published_pct" in row:
        out.update({"published right": pct(row["published_right_pct"]), "published wrong": pct(row["published_wrong_pct"])})
    out["errors"] = row["errors"]
    return out


def _md_table(rows: list[dict]) -> list[str]:
    if not rows:
        return []
    lines = ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    return lines + ["| " + " | ".join(str(v).replace("|", "/") for v in row.values()) + " |" for row in rows]


def write_report(records: list[dict], out: str | Path, title: str) -> Path:
    """results.json, report.md and report.html: the summary of all objects, one row per source,
    the count of first failing stages per source, one diagnosis row per object, then one row
    and one picture per object."""
    import html

    out = Path(out)
    summary = summary_row(records)
    groups = by_source(records)
    sources = [_source_row(name, group) for name, group in groups.items()]
    if len(groups) > 1:
        sources.append(_source_row("all", records))
    failures = [{"source": name, **failure_counts(group)} for name, group in groups.items()]
    if len(groups) > 1:
        failures.append({"source": "all", **failure_counts(records)})
    (out / "results.json").write_text(json.dumps({
        "title": title, "summary": summary, "by_source": {name: summary_row(g) for name, g in groups.items()},
        "first_failure": {row["source"]: {k: v for k, v in row.items() if k != "source"} for row in failures},
        "objects": records}, indent=1, default=float))
    rows = [_object_row(r) for r in records if "score" in r]
    diagnosis = [_diagnosis_row(r) for r in records]
    errors = [r for r in records if "score" not in r]
    def fmt(v) -> str:
        if isinstance(v, dict):
            return ", ".join(f"{k} {fmt(x)}" for k, x in v.items())
        return f"{v:.3f}" if isinstance(v, float) else str(v)
    lines = [f"# {title}", "", "| metric | value |", "|---|---|"]
    lines += [f"| {k} | {fmt(v)} |" for k, v in summary.items()]
    lines += ["", "## Per source", "", *_md_table(sources)]
    lines += ["", "*right*: every movable part found with its joint type, the right count, axes within "
              f"{BenchConfig().right_axis_deg:g} deg and {BenchConfig().right_pos_dm:g} dm, mIoU at least "
              f"{BenchConfig().right_miou:g}; *published right / wrong*: validated and published, as a share "
              "of all objects. Up and front are scored where the ground truth says (front: the side its "
              "movable parts open towards)."]
    lines += ["", "## First failing stage", "", "Checked in this order: frame (up or front), parts (count, "
              "matching, mIoU), type, axis, limits; ok when none failed.", "", *_md_table(failures)]
    lines += ["", "## Diagnosis per object", "", *_md_table(diagnosis)]
    if rows:
        lines += ["", "## Objects", "", "| " + " | ".join(rows[0]) + " | picture |", "|" + "---|" * (len(rows[0]) + 1)]
        for row, r in zip(rows, [r for r in records if "score" in r]):
            lines.append("| " + " | ".join(str(v) for v in row.values()) + f" | [png]({r.get('picture', '')}) |")
    for r in errors:
        lines.append(f"\n**{r['name']}**: {r.get('error', '?')}")
    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")

    e = html.escape

    def html_table(table: list[dict], link: str | None = None) -> str:
        if not table:
            return ""
        head = "<table><tr>" + "".join(f"<th>{e(k)}</th>" for k in table[0]) + "</tr>"
        body = ["<tr>" + "".join(f"<td><a href='#{e(str(v))}'>{e(str(v))}</a></td>" if k == link
                                 else f"<td>{e(str(v))}</td>" for k, v in row.items()) + "</tr>" for row in table]
        return head + "".join(body) + "</table>"

    parts = [f"<!doctype html><meta charset='utf-8'><title>{e(title)}</title>",
             "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
             "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}img{max-width:100%}"
             ".item{margin:2em 0}</style>", f"<h1>{e(title)}</h1><table>"]
    parts += [f"<tr><th>{e(k)}</th><td>{e(fmt(v))}</td></tr>" for k, v in summary.items()]
    parts.append("</table>")
    parts += ["<h2>Per source</h2>", html_table(sources), "<h2>First failing stage</h2>", html_table(failures),
              "<h2>Diagnosis per object</h2>", html_table(diagnosis, "object")]
    if rows:
        parts += ["<h2>Objects</h2>", html_table(rows, "object")]
    for r in records:
        parts.append(f"<div class='item' id='{e(r['name'])}'><h3>{e(r['name'])}</h3>")
        if "error" in r:
            parts.append(f"<pre>{e(r['error'])}</pre>")
        if r.get("picture"):
            parts.append(f"<img src='{e(r['picture'])}' alt='{e(r['name'])}'>")
        parts.append("</div>")
    (out / "report.html").write_text("\n".join(parts) + "\n")
    return path
