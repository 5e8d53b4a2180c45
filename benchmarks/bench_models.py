"""Time each model stage of the paper's configuration, where a GPU and the weights exist.

    python benchmarks/bench_models.py --config paper.yaml [--kind cabinet --seed 2 --variant scan]

The config names the backends (``segment.hierarchy_backend``, ``segment.masks_backend``,
``articulation.prompt_backend``, ``video_backend``, ``tracks_backend``) and where their weights
are (``models``); every role left at its offline default is timed as well. On one generated
object, from its rendered views: loading each backend, the hierarchy's proposal over the views,
the masks of every view for every category of the tree, the video prompt, one video (seed 0)
and the tracks of every movable part through it. Prints one line per stage (seconds and, on
CUDA, the peak GPU memory) and writes them as JSON with ``-o``. Compare with the paper's
per-stage means (co-refinement 30 s, prompt 18 s, video 172 s, tracking 6 s on an H200).
"""

from __future__ import annotations

import argparse
import json
import time


def _peak_gb() -> float | None:
    try:
        import torch
    except ImportError:
        return None
    if not torch.cuda.is_available():
        return None
    peak = torch.cuda.max_memory_allocated() / 2 ** 30
    torch.cuda.reset_peak_memory_stats()
    return round(peak, 2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--config", help="YAML config naming the backends and their weights")
    parser.add_argument("--kind", default="cabinet")
    parser.add_argument("--seed", type=int, default=2)
    parser.add_argument("--variant", default="scan", choices=["asset", "scan"])
    parser.add_argument("-o", "--out", help="JSON file for the timings")
    args = parser.parse_args()

    from rest2art.backends import create
    from rest2art.config import load_config
    from rest2art.generate import generate_object
    from rest2art.joints.video.estimate import conditioning_image, evidence_from_frames
    from rest2art.joints.video.source import video_view
    from rest2art.parts.segment.views import render_rig

    config = load_config(args.config)
    obj = generate_object(args.kind, args.seed, args.variant)
    m = obj.mesh
    rows: list[dict] = []

    def timed(stage: str, backend: str, fn, *a):
        start = time.perf_counter()
        result = fn(*a)
        rows.append({"stage": stage, "backend": backend, "seconds": round(time.perf_counter() - start, 3),
                     "peak_gpu_gb": _peak_gb()})
        print(f"{stage:<22} {backend:<13} {rows[-1]['seconds']:>9.2f} s"
              + (f"  {rows[-1]['peak_gpu_gb']} GB" if rows[-1]["peak_gpu_gb"] is not None else ""), flush=True)
        return result

    seg, art, models = config.segment, config.articulation, config.models
    views = timed("render views", "-", render_rig, m.vertices, m.faces, seg)
    masks = timed("load masks", seg.masks_backend, create, "masks", seg.masks_backend, views, None, seg, models)
    hierarchy = timed("load hierarchy", seg.hierarchy_backend, create, "hierarchy", seg.hierarchy_backend, views,
                      None, masks, seg, models)
    tree = timed("hierarchy proposal", seg.hierarchy_backend, hierarchy.propose, views)
    timed("masks, all views", seg.masks_backend,
          lambda: [masks.segment(v, s) for v in range(len(views)) for s in tree.prompts()])

    truth = obj.asset
    names = [p.name for p in truth.parts]
    movable = [p.name for p in truth.parts if p.parent is not None]
    vv = video_view(m.vertices, m.faces, truth.face_part, names, movable, config)
    image = conditioning_image(vv.view.shaded(), list(vv.masks.values()), art.overlay_alpha)
    writer = timed("load prompt writer", art.prompt_backend, create, "prompt", art.prompt_backend, models)
    prompt = timed("video prompt", art.prompt_backend, writer, image,
                   {p.name: p.semantic for p in truth.parts if p.parent is not None})
    video = timed("load video model", art.video_backend, create, "video", art.video_backend, models)
    tracker = timed("load tracker", art.tracks_backend, create, "tracks", art.tracks_backend, models)
    if video is not None:
        frames = timed("video, one seed", art.video_backend, video.generate, image, prompt, 0, art.video_frames)
        timed("tracks, one video", art.tracks_backend, evidence_from_frames, frames, vv.camera, vv.view.depth,
              vv.masks, tracker, art)
    else:
        print("video: backend 'none' (no video model configured): video and tracking not timed")
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"object": obj.name, "prompt": prompt, "tree": tree.counts(), "stages": rows}, f, indent=1)


if __name__ == "__main__":
    main()
