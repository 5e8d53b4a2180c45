"""`rest2art bench`: reconstruct a set of objects with ground truth and score them.

Each object runs in its own worker process (crash isolation, and a per-object peak memory
reading); results land in OUT/results.json and OUT/report.md.
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
from rest2art.bench.metrics import ObjectScore, PartScore, score_object, summarize
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
    """A ground-truth folder (mesh.obj + articulation.json + face_part.npy) to score against."""

    def materialize(self, gt_dir: Path, scan_voxel: float) -> None:
        """Make sure ``gt_dir`` holds the ground truth."""
        if (gt_dir / "articulation.json").is_file():
            return
        if self.source is not None:
            import shutil

            shutil.copytree(self.source, gt_dir, dirs_exist_ok=True)
            return
        from rest2art.generate import generate_object, write_object

        write_object(generate_object(self.kind, self.seed, self.variant, scan_voxel=scan_voxel), gt_dir)


def generated_items(count: int, variant: str, seed: int = 0, kinds: tuple[str, ...] = KINDS) -> list[BenchItem]:
    """``count`` objects cycling through ``kinds`` (seeds seed, seed+1, ...)."""
    items = []
    for k in range(count):
        kind = kinds[k % len(kinds)]
        items.append(BenchItem(f"{kind}_{seed + k:04d}", variant, kind, seed + k))
    return items


def prepared_items(set_root: str | Path, variant: str) -> list[BenchItem]:
    """Items of a prepared set (``rest2art bench prepare``)."""
    folder = Path(set_root) / variant
    names = sorted(p.name for p in folder.iterdir() if (p / "articulation.json").is_file()) if folder.is_dir() else []
    return [BenchItem(name, variant, source=str(folder / name)) for name in names]


def score_folders(pred_dir: str | Path, gt_dir: str | Path, name: str = "") -> ObjectScore:
    """Score a prediction folder against a ground-truth folder (both in the contract); face
    areas come from GT_DIR/mesh.obj read by the same loader, so face order is the one
    face_part.npy indexes."""
    from rest2art.loading import load_mesh

    pred = read_articulation(pred_dir, load_meshes=False)
    gt = read_articulation(gt_dir, load_meshes=False)
    mesh = load_mesh(Path(gt_dir) / "mesh.obj").trimesh()
    return score_object(pred, gt, mesh.area_faces, name or Path(gt_dir).name)


def _run_item(args: tuple) -> dict:
    item, out, config_path, check, scan_voxel = args
    from rest2art.config import load_config
    from rest2art.export import atomic_folder, write_asset
    from rest2art.pipeline import reconstruct_file

    config = load_config(config_path) if config_path else Config()
    out = Path(out)
    gt_dir = out / "gt" / item.name
    pred_dir = out / "pred" / item.name
    record = {"name": item.name, "kind": item.kind, "seed": item.seed, "variant": item.variant}
    try:
        item.materialize(gt_dir, scan_voxel)
        start = time.perf_counter()
        asset, _ = reconstruct_file(gt_dir / "mesh.obj", config)
        with atomic_folder(pred_dir, overwrite=True) as tmp:
            write_asset(asset, tmp, item.name, config.export, np.asarray(asset.metadata["frame"]["up"]))
        record["seconds"] = round(time.perf_counter() - start, 3)
        record["stage_seconds"] = asset.metadata.get("timing_s", {})
        record["score"] = score_folders(pred_dir, gt_dir, item.name).to_dict()
        record["picture"] = write_picture(pred_dir, gt_dir, out / "pictures" / f"{item.name}.png")
        if check:
            record.update(_validate_record(pred_dir, item.name, config))
    except Exception as exc:  # one object's failure must not stop the bench
        record["error"] = f"{type(exc).__name__}: {exc}"
        record["traceback"] = traceback.format_exc()
    record["peak_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)
    return record


def _validate_record(pred_dir: Path, name: str, config: Config) -> dict:
    """Run the validation layer (with refinement) on an exported prediction; what the report needs."""
    from rest2art.validators.validate import validate_folder

    start = time.perf_counter()
    report = validate_folder(pred_dir, name, config, refine=True)
    findings = report.findings
    depths = [s["depth_mm"] for f in findings if f.check == "sweep" for s in f.data.get("samples", [])]
    return {
        "validate_seconds": round(time.perf_counter() - start, 3),
        "decision": report.decision.status,
        "reasons": [f"{r['check']} {r['subject']}: {r['message']}" for r in report.decision.reasons],
        "refinements": [a["done"] for r in report.rounds for a in r["decision"].actions if "done" in a],
        "max_penetration_mm": max(depths, default=None),
        "actuation": {f.subject: f.ok for f in findings if f.check == "actuation"},
        "checks": {f"{f.check}:{f.subject}": f.ok for f in findings},
        "check_failures": [f"{f.check} {f.subject}: {f.message}" for f in findings if not f.ok],
    }


def write_picture(pred_dir: Path, gt_dir: Path, path: Path) -> str:
    """Truth (top) and prediction (bottom), closed and opened, joint axes drawn; returns the
    path relative to the report folder."""
    from rest2art.render import closed_and_open, label, save_png

    truth = read_articulation(gt_dir)
    pred = read_articulation(pred_dir)
    if "frame" in pred.metadata:
        truth.metadata.setdefault("frame", pred.metadata["frame"])  # view both from the same side
    image = np.concatenate([label(closed_and_open(truth, 320, axes=True), "truth: closed | opened"),
                            label(closed_and_open(pred, 320, axes=True), "prediction: closed | opened")], axis=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_png(image, path)
    return f"pictures/{path.name}"


def run_items(items: list[BenchItem], out: str | Path, config_path: str | None = None, check: bool = False,
              workers: int = 1, scan_voxel: float = 0.005, progress=None) -> list[dict]:
    """Reconstruct and score every item, one fresh worker process per item."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ctx = mp.get_context("spawn")
    records = []
    with ctx.Pool(processes=workers, maxtasksperchild=1) as pool:
        jobs = [(item, str(out), config_path, check, scan_voxel) for item in items]
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
    return row


def _object_row(r: dict) -> dict:
    s = r["score"]
    mov = [p for p in s["parts"] if p["movable"]]
    ang = [p["axis_angle_deg"] for p in mov if p["axis_angle_deg"] is not None]
    pos = [p["axis_pos_dm"] for p in mov if p["axis_pos_dm"] is not None]
    checks = "-" if "decision" not in r else r["decision"] + (": " + "; ".join(r["reasons"]) if r["reasons"] else "")
    return {"object": r["name"], "GT movable": s["n_gt_movable"], "pred movable": s["n_pred_movable"],
            "mIoU": f"{s['miou']:.3f}", "type ok": f"{sum(p['type_correct'] for p in mov)}/{len(mov)}",
            "max axis angle (deg)": f"{max(ang, default=0):.2f}", "max axis pos (dm)": f"{max(pos, default=0):.3f}",
            "time (s)": f"{r['seconds']:.1f}", "peak MB": f"{r['peak_mb']:.0f}", "validation": checks}


def write_report(records: list[dict], out: str | Path, title: str) -> Path:
    """results.json, report.md and report.html (summary first, then one row and one picture
    per object)."""
    import html

    out = Path(out)
    summary = summary_row(records)
    (out / "results.json").write_text(json.dumps({"title": title, "summary": summary, "objects": records}, indent=1,
                                                 default=float))
    rows = [_object_row(r) for r in records if "score" in r]
    errors = [r for r in records if "score" not in r]
    fmt = lambda v: f"{v:.3f}" if isinstance(v, float) else str(v)  # noqa: E731
    lines = [f"# {title}", "", "| metric | value |", "|---|---|"]
    lines += [f"| {k} | {fmt(v)} |" for k, v in summary.items()]
    if rows:
        lines += ["", "| " + " | ".join(rows[0]) + " | picture |", "|" + "---|" * (len(rows[0]) + 1)]
        for row, r in zip(rows, [r for r in records if "score" in r]):
            lines.append("| " + " | ".join(str(v) for v in row.values()) + f" | [png]({r.get('picture', '')}) |")
    for r in errors:
        lines.append(f"\n**{r['name']}**: {r.get('error', '?')}")
    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")

    e = html.escape
    parts = [f"<!doctype html><meta charset='utf-8'><title>{e(title)}</title>",
             "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
             "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}img{max-width:100%}"
             ".item{margin:2em 0}</style>", f"<h1>{e(title)}</h1><table>"]
    parts += [f"<tr><th>{e(k)}</th><td>{e(fmt(v))}</td></tr>" for k, v in summary.items()]
    parts.append("</table>")
    if rows:
        parts.append("<h2>Objects</h2><table><tr>" + "".join(f"<th>{e(k)}</th>" for k in rows[0]) + "</tr>")
        for row in rows:
            parts.append("<tr>" + "".join(f"<td><a href='#{e(row['object'])}'>{e(str(v))}</a></td>" if k == "object"
                                          else f"<td>{e(str(v))}</td>" for k, v in row.items()) + "</tr>")
        parts.append("</table>")
    for r in records:
        parts.append(f"<div class='item' id='{e(r['name'])}'><h3>{e(r['name'])}</h3>")
        if "error" in r:
            parts.append(f"<pre>{e(r['error'])}</pre>")
        if r.get("picture"):
            parts.append(f"<img src='{e(r['picture'])}' alt='{e(r['name'])}'>")
        parts.append("</div>")
    (out / "report.html").write_text("\n".join(parts) + "\n")
    return path
