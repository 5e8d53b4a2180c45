"""Renderer speed: the segmentation rig (12 views, 800 x 800) of a ~200k-face scan mesh.

    python benchmarks/bench_render.py [--repeats 3] [--ray-stride 8]

Reports the median time of the 12 views and compares with trimesh ray casting of the same
pixels, measured in the same run: rays are cast through every ``--ray-stride``-th pixel of one
view (casting all 7.7M rays would take too long) and the per-ray cost is scaled to the 12 full
views. The face ids of both are compared on the cast pixels (agreement %).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ray-stride", type=int, default=8)
    args = parser.parse_args()

    from rest2art.config import SegmentConfig
    from rest2art.generate import generate_object
    from rest2art.parts.segment.views import camera_rig
    from rest2art.render.raster import render_views

    mesh = generate_object("cabinet", 3, "scan").mesh  # 200,000 faces
    config = SegmentConfig()
    cameras = camera_rig(mesh.vertices, config)
    times = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        views = render_views(mesh.vertices, mesh.faces, cameras, True)
        times.append(time.perf_counter() - start)
    ours = float(np.median(times))

    view, cam = views[len(views) // 2], cameras[len(views) // 2]
    s = args.ray_stride
    ys, xs = np.mgrid[s // 2:cam.height:s, s // 2:cam.width:s]
    pixel = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
    local = np.concatenate([(pixel - [cam.width / 2, cam.height / 2]) / cam.focal, np.ones((len(pixel), 1))], axis=1)
    directions = local @ cam.rotation
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    start = time.perf_counter()
    hit = mesh.ray.intersects_first(np.tile(cam.eye, (len(directions), 1)), directions)
    ray_seconds = time.perf_counter() - start
    per_ray = ray_seconds / len(directions)
    rays_total = len(cameras) * cam.width * cam.height
    ours_ids = view.face[ys.ravel(), xs.ravel()]
    agree = float(np.mean(ours_ids == hit)) * 100
    print(json.dumps({
        "faces": int(len(mesh.faces)), "views": len(cameras), "size": cam.width,
        "render_median_s": round(ours, 3),
        "ray_engine": type(mesh.ray).__module__,
        "rays_cast": int(len(directions)), "ray_seconds": round(ray_seconds, 3),
        "ray_estimate_12_views_s": round(per_ray * rays_total, 1),
        "speedup": round(per_ray * rays_total / ours, 1),
        "face_id_agreement_pct": round(agree, 2),
    }, indent=1))


if __name__ == "__main__":
    main()
