"""CoTracker3 as the tracks role (``models.cotracker``). CoTracker3 is not on PyPI; two ways in:

* a TorchScript export (a ``.pt`` file) called as ``model(video, queries) -> (tracks, visibility)``
  with video (1, T, 3, H, W) float in [0, 255], queries (1, N, 3) as (frame, x, y) and outputs
  (1, T, N, 2) pixels and (1, T, N) bool or probability;
* a checkout of the co-tracker repository (the folder holding its ``cotracker`` package) and a
  checkpoint (``scaled_offline.pth``): ``CoTrackerPredictor(checkpoint)`` with the same call and
  ``backward_tracking=True`` (the paper tracks both ways from frame 0).

Pixel centres are at integers there and at +0.5 in ``Tracks``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from rest2art.backends.registry import register, require_path, resolve_device
from rest2art.errors import ConfigError


class CoTrackerTracks:
    """``track(frames, queries) -> Tracks`` through a CoTracker3 model."""

    def __init__(self, config):
        import torch

        self.config = config
        self.device = resolve_device(config.device)
        path = Path(require_path(config.path, "models.cotracker.path",
                                 "CoTracker3 TorchScript file or co-tracker checkout"))
        self.scripted = path.is_file()
        if self.scripted:
            self.model = torch.jit.load(str(path), map_location=self.device).eval()
        else:
            if not (path / "cotracker" / "predictor.py").is_file():
                raise ConfigError(f"models.cotracker.path: {path} holds no cotracker/predictor.py "
                                  "(expected a co-tracker checkout or a TorchScript .pt file)")
            checkpoint = require_path(config.checkpoint, "models.cotracker.checkpoint",
                                      "CoTracker3 checkpoint (scaled_offline.pth)")
            if str(path) not in sys.path:
                sys.path.insert(0, str(path))
            from cotracker.predictor import CoTrackerPredictor

            self.model = CoTrackerPredictor(checkpoint=checkpoint).to(self.device).eval()

    def track(self, frames: np.ndarray, queries: np.ndarray):
        """(T, H, W, 3) uint8 frames and (N, 2) frame-0 pixel queries -> Tracks."""
        import torch

        from rest2art.joints.video.tracks import Tracks

        video = torch.from_numpy(np.ascontiguousarray(frames)).permute(0, 3, 1, 2)[None].float().to(self.device)
        q = np.concatenate([np.zeros((len(queries), 1)), np.asarray(queries, float) - 0.5], axis=1)
        q = torch.from_numpy(q[None]).float().to(self.device)
        with torch.no_grad():
            if self.scripted:
                xy, visible = self.model(video, q)
            else:
                xy, visible = self.model(video, queries=q, backward_tracking=True)
        xy = xy[0].float().cpu().numpy() + 0.5
        visible = visible[0].cpu().numpy()
        if visible.dtype != bool:
            visible = visible > self.config.visibility_threshold
        visible[0] = True
        return Tracks(xy.astype(float), visible)


@register("tracks", "cotracker3", "CoTracker3 from a TorchScript export or a local checkout (models.cotracker)",
          packages=("torch",), extra="tracks",
          weights=lambda models: {"CoTracker3 model": models.cotracker.path,
                                  **({"CoTracker3 checkpoint": models.cotracker.checkpoint}
                                     if models.cotracker.path and not models.cotracker.path.endswith(".pt") else {})},
          hints={"CoTracker3 model": "clone facebookresearch/co-tracker and set models.cotracker.path to it "
                                     "(or to a TorchScript export)",
                 "CoTracker3 checkpoint": "download scaled_offline.pth and set models.cotracker.checkpoint"})
def make_cotracker(models):
    return CoTrackerTracks(models.cotracker)
