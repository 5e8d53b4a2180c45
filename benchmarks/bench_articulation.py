"""Joint fitting from simulated motion videos, against ground truth, under degradations.

    python benchmarks/bench_articulation.py --count 50 [--workers 2] [--frames 16] [--out DIR]
                                            [--lk 10] [--extra]

For each generated object (kinds in turn, seed = index // number of kinds; the asset variant's
ground truth), or each prepared real model with ``--set pypi-dev``, the
view that sees most of the movable parts is chosen from the segmentation rig, every movable
joint is opened together and rendered (``rest2art.generate.videos``), and the tracks of each
part go through the estimator exactly as a generated video's would: truncation, metric anchors
from the rendered depth, motion-type classification, reprojection fitting, R = 2 seed consensus
(the seeds differ in their noise, dropout and hallucination draws). Each setting is scored twice:
the fitted joint as is, and after mesh-grounded refinement (snap / blend / collision check
against the ground-truth parent). ``--lk N`` also tracks the textured frames of the first N
objects with the offline Lucas-Kanade backend (no added noise).

Metrics follow the project bench: type accuracy over movable parts (static counts as wrong), mean
axis angle (deg, sign-agnostic) over type-correct parts, mean axis-line distance (dm) over
type-correct revolute parts. Prints markdown tables and writes ``articulation.json``.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np

SETTINGS = {
    "noise 0 px": dict(noise_px=0.0),
    "noise 1 px": dict(noise_px=1.0),
    "noise 2 px": dict(noise_px=2.0),
    "noise 4 px": dict(noise_px=4.0),
    "dropout 20 % (1 px)": dict(noise_px=1.0, dropout=0.2),
    "dropout 40 % (1 px)": dict(noise_px=1.0, dropout=0.4),
    "hallucinated region 25 % (1 px)": dict(noise_px=1.0, hallucinated=0.25),
    "early stop at 35 % (1 px)": dict(noise_px=1.0, stop_fraction=0.35),
}
EXTRA_SETTINGS = {
    "wobble 5 mm (1 px)": dict(noise_px=1.0, wobble_m=0.005),
    "camera drift 1 deg (1 px)": dict(noise_px=1.0, drift_deg=1.0),
}


def _score(joint, pred_type: str, axis, origin) -> dict:
    from rest2art.geometry.basics import axis_angle_deg, line_distance

    row = {"gt_type": joint.type, "pred_type": pred_type, "type_correct": pred_type == joint.type,
           "angle_deg": None, "pos_dm": None}
    if row["type_correct"]:
        row["angle_deg"] = axis_angle_deg(axis, joint.axis)
        if joint.type == "revolute":
            row["pos_dm"] = 10.0 * line_distance(origin, axis, joint.origin, joint.axis)
    return row


def run_object(args: tuple) -> list[dict]:
    kind, seed, n_frames, lk, extra, source = args
    from rest2art.config import ArticulationConfig, JointsConfig, SegmentConfig
    from rest2art.generate import generate_object
    from rest2art.generate.videos import Degradation, choose_view, render_motion, simulate_video
    from rest2art.joints.rules import opening_caps
    from rest2art.joints.video.estimate import VideoEvidence, estimate_part_motions, evidence_from_frames
    from rest2art.joints.video.grounding import exposed_outward, ground_joint
    from rest2art.joints.video.tracks import LucasKanadeTracker
    from rest2art.parts.segment.views import camera_rig
    from rest2art.render.camera import Camera

    config, joints_config = ArticulationConfig(), JointsConfig()
    if source is None:
        asset = generate_object(kind, seed, "asset").asset
        small = SegmentConfig(image_size=200)
    else:  # a prepared real model: its front is not known, so the view may come from any side
        from rest2art.asset import read_articulation

        asset = read_articulation(source)
        small = SegmentConfig(image_size=200, azimuth_deg=157.5, azimuth_steps=8)
    vertices = np.concatenate([p.mesh.vertices for p in asset.parts])
    chosen = choose_view(asset, camera_rig(vertices, small))
    size = SegmentConfig().image_size
    camera = Camera(chosen.eye, chosen.rotation, chosen.focal * size / small.image_size, size, size)
    names = [j.child for j in asset.movable_joints]
    caps = {j.child: opening_caps(asset.part(j.child).semantic, kind, float(np.ptp(vertices @ np.abs(j.axis))),
                                  joints_config)[j.type] for j in asset.movable_joints}
    renders = {}
    records = []

    def evaluate(setting: str, make) -> None:
        start = time.perf_counter()
        motions = estimate_part_motions(make, names, config)
        seconds = time.perf_counter() - start
        for j in asset.movable_joints:
            m = motions[j.child]
            part = asset.part(j.child)
            raw = _score(j, m.type, *(m.fit.axis, m.fit.origin) if m.fit else (None, None))
            rec = {"setting": setting, "object": f"{kind}_{seed}" if source is None else kind, "kind": kind, "part": j.child,
                   "semantic": part.semantic, "combined": m.combined, "seconds": seconds / len(names),
                   "fit": raw, "runs": [r.get("cue_label", r["label"]) for r in m.runs]}
            if m.fit is not None:
                parent = asset.part(j.parent).mesh
                cap = caps[j.child] if m.fit.type == j.type else (
                    np.radians(joints_config.door_limit_deg) if m.fit.type == "revolute" else 0.3)
                grounded = ground_joint(m.fit, part.mesh, parent, exposed_outward(part.mesh, parent), cap,
                                        config, joints_config)
                rec["grounded"] = _score(j, grounded.type, grounded.axis, grounded.origin)
                rec["grounding"] = {k: grounded.evidence[k] for k in ("snapped", "blended", "overruled")}
            else:
                rec["grounded"] = raw
            records.append(rec)

    for setting, params in {**SETTINGS, **(EXTRA_SETTINGS if extra else {})}.items():
        degradation = Degradation(**params)
        key = degradation.stop_fraction
        if key not in renders:
            renders[key] = render_motion(asset, camera, n_frames, stop_fraction=key)

        def make(s, degradation=degradation, rendered=renders[key]):
            v = simulate_video(asset, camera, n_frames, degradation, seed=1000 * s + seed, rendered=rendered,
                               erosion_fraction=config.erosion_fraction, max_points=config.max_track_points)
            return VideoEvidence(v.camera, v.depth0, v.tracks)

        evaluate(setting, make)
    if lk:
        rendered = render_motion(asset, camera, n_frames, render_images=True)
        video = simulate_video(asset, camera, n_frames, rendered=rendered)
        masks = {n: video.masks0[n] for n in names}
        evidence = evidence_from_frames(rendered.images, camera, video.depth0, masks, LucasKanadeTracker(), config)
        evaluate("Lucas-Kanade on rendered frames", lambda s: evidence)
    return records


def summarize(records: list[dict], stage: str) -> dict:
    rows = [r[stage] for r in records]
    angles = [r["angle_deg"] for r in rows if r["angle_deg"] is not None]
    positions = [r["pos_dm"] for r in rows if r["pos_dm"] is not None]
    return {"parts": len(rows), "type_accuracy_pct": 100.0 * np.mean([r["type_correct"] for r in rows]),
            "axis_angle_deg": float(np.mean(angles)) if angles else float("nan"),
            "axis_pos_dm": float(np.mean(positions)) if positions else float("nan")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=50, help="generated objects (kinds in turn)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--frames", type=int, default=16, help="frames per simulated video")
    parser.add_argument("--lk", type=int, default=0, help="also track the rendered frames of the first N objects with Lucas-Kanade")
    parser.add_argument("--extra", action="store_true", help="also the wobble and camera-drift settings")
    parser.add_argument("--set", choices=["generated", "pypi-dev"], default="generated",
                        help="pypi-dev: the prepared real models (rest2art bench prepare) instead of generated objects")
    parser.add_argument("--cache", help="cache of prepared sets (default: ~/.cache/rest2art/devsets)")
    parser.add_argument("--out", default="bench_out/articulation")
    args = parser.parse_args()
    from rest2art.generate.objects import KINDS

    if args.set == "pypi-dev":
        from rest2art.bench import prepared_items
        from rest2art.bench.devset import default_cache

        root = Path(args.cache) if args.cache else default_cache()
        items = prepared_items(root / "sets" / "pypi-dev", "asset")[:args.count]
        if not items:
            raise SystemExit(f"no prepared pypi-dev set under {root}: run `rest2art bench prepare --set pypi-dev` first")
        jobs = [(item.name, 0, args.frames, k < args.lk, args.extra, item.source) for k, item in enumerate(items)]
    else:
        jobs = [(KINDS[k % len(KINDS)], k // len(KINDS), args.frames, k < args.lk, args.extra, None)
                for k in range(args.count)]
    start = time.perf_counter()
    records = []
    with mp.get_context("spawn").Pool(args.workers) as pool:
        for k, rows in enumerate(pool.imap_unordered(run_object, jobs)):
            records.extend(rows)
            print(f"[{k + 1}/{len(jobs)}] {rows[0]['object']}", flush=True)
    wall = time.perf_counter() - start
    settings = list(dict.fromkeys(r["setting"] for r in records))
    table = {}
    print(f"\n{args.count} objects, {args.frames} frames, {wall:.0f} s wall\n")
    print("| setting | parts | type acc. (fit) | angle (fit) | pos. (fit) | type acc. (grounded) | angle (grounded) | pos. (grounded) | snapped |")
    print("|---|---|---|---|---|---|---|---|---|")
    for setting in settings:
        rows = [r for r in records if r["setting"] == setting]
        fit, grounded = summarize(rows, "fit"), summarize(rows, "grounded")
        snapped = [r["grounding"]["snapped"] for r in rows if "grounding" in r]
        table[setting] = {"fit": fit, "grounded": grounded, "snapped_pct": 100.0 * np.mean(snapped) if snapped else 0.0,
                          "seconds_per_part": float(np.median([r["seconds"] for r in rows]))}
        print(f"| {setting} | {fit['parts']} | {fit['type_accuracy_pct']:.1f} % | {fit['axis_angle_deg']:.2f}° | "
              f"{fit['axis_pos_dm']:.3f} dm | {grounded['type_accuracy_pct']:.1f} % | {grounded['axis_angle_deg']:.2f}° | "
              f"{grounded['axis_pos_dm']:.3f} dm | {table[setting]['snapped_pct']:.0f} % |")
    main_rows = [r for r in records if r["setting"] == "noise 1 px"]
    print("\nPer kind and part (noise 1 px, fitted):\n")
    print("| group | parts | type acc. | angle | pos. |")
    print("|---|---|---|---|---|")
    for key in ("kind", "semantic"):
        for value in sorted({r[key] for r in main_rows}):
            s = summarize([r for r in main_rows if r[key] == value], "fit")
            print(f"| {value} | {s['parts']} | {s['type_accuracy_pct']:.1f} % | {s['axis_angle_deg']:.2f}° | {s['axis_pos_dm']:.3f} dm |")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "articulation.json").write_text(json.dumps({"count": args.count, "frames": args.frames, "wall_s": wall,
                                                       "table": table, "records": records}, indent=1, default=str))


if __name__ == "__main__":
    main()
