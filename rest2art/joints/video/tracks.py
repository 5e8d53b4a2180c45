"""Point tracks: where they start, how long they are trusted, and the trackers behind the role.

Tracks start on a grid inside each part's mask in frame 0, eroded by a fraction of the mask's
bounding-box short side so that points on the part's outline (which a tracker confuses with the
background or a neighbour) are left out. A track sequence is cut at the first frame where fewer
than ``visibility_threshold`` of the points visible in frame 0 are still visible: generated
videos degrade over time and trackers drift, and both show as points being lost.

The ``tracks`` role: any object with ``track(frames, queries) -> Tracks``. The offline backend is
pyramidal Lucas-Kanade with a forward-backward check; a model backend (a point tracker such as
CoTracker3 loaded from a local checkpoint) returns the same structure.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np


@dataclass
class Tracks:
    """2D point tracks over a frame sequence."""

    xy: np.ndarray
    """(T, N, 2) pixel positions (u right, v down)."""
    visible: np.ndarray
    """(T, N) bool; positions of invisible points are not to be trusted."""

    @property
    def n_frames(self) -> int:
        return int(self.xy.shape[0])

    @property
    def n_points(self) -> int:
        return int(self.xy.shape[1])

    def subset(self, points: np.ndarray | None = None, frames: np.ndarray | slice | None = None) -> "Tracks":
        """The tracks of ``points`` (index or mask) over ``frames``."""
        points = slice(None) if points is None else points
        frames = slice(None) if frames is None else frames
        return Tracks(self.xy[frames][:, points], self.visible[frames][:, points])


class TracksBackend(Protocol):
    """The ``tracks`` role: (T, H, W, 3) uint8 frames and (N, 2) frame-0 queries -> Tracks."""

    def track(self, frames: np.ndarray, queries: np.ndarray) -> Tracks: ...


def grid_queries(mask: np.ndarray, erosion_fraction: float = 0.02, spacing_px: float | None = None,
                 max_points: int = 400) -> np.ndarray:
    """(N, 2) pixel centres on a regular grid inside the (H, W) bool ``mask``, eroded by
    ``erosion_fraction`` of its bounding box's short side (at least one pixel). The spacing
    defaults to the one giving about ``max_points`` points."""
    import cv2

    rows, cols = np.nonzero(mask)
    if not len(rows):
        return np.zeros((0, 2))
    short = min(np.ptp(rows), np.ptp(cols)) + 1
    radius = max(int(round(erosion_fraction * short)), 1)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    eroded = cv2.erode(mask.astype(np.uint8), kernel).astype(bool)
    if not eroded.any():
        eroded = mask
    area = int(eroded.sum())
    step = spacing_px or max(np.sqrt(area / max_points), 1.0)
    step = max(int(np.ceil(step)), 1)
    grid = np.zeros_like(eroded)
    r0, c0 = np.nonzero(eroded)
    grid[r0.min()::step, c0.min()::step] = True
    r, c = np.nonzero(grid & eroded)
    return np.stack([c + 0.5, r + 0.5], axis=1).astype(float)


def truncation_frame(visible: np.ndarray, threshold: float = 0.5) -> int:
    """Number of leading frames to keep: up to (not including) the first frame whose count of
    visible points falls below ``threshold`` times frame 0's."""
    counts = visible.sum(axis=1)
    if counts[0] == 0:
        return 0
    below = np.flatnonzero(counts < threshold * counts[0])
    return int(below[0]) if len(below) else int(len(counts))


def truncate(tracks: Tracks, threshold: float = 0.5) -> Tracks:
    """``tracks`` cut at ``truncation_frame``."""
    return tracks.subset(frames=slice(0, truncation_frame(tracks.visible, threshold)))


@dataclass
class LucasKanadeTracker:
    """Offline ``tracks`` backend: OpenCV pyramidal Lucas-Kanade, chained frame to frame.

    A point is lost (invisible from then on) when the tracker fails, when it leaves the image or
    when tracking it back from the new frame misses its old position by more than
    ``forward_backward_px``."""

    window_px: int = 21
    levels: int = 3
    forward_backward_px: float = 1.0

    def track(self, frames: np.ndarray, queries: np.ndarray) -> Tracks:
        import cv2

        grey = [cv2.cvtColor(f, cv2.COLOR_RGB2GRAY) if f.ndim == 3 else f for f in frames]
        T, N = len(grey), len(queries)
        xy = np.zeros((T, N, 2))
        visible = np.zeros((T, N), bool)
        xy[0] = queries
        visible[0] = True
        h, w = grey[0].shape
        params = dict(winSize=(self.window_px, self.window_px), maxLevel=self.levels,
                      criteria=(cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 30, 0.01))
        for t in range(1, T):
            xy[t] = xy[t - 1]
            alive = np.flatnonzero(visible[t - 1])
            if not len(alive):
                continue
            # OpenCV's pixel centres are at integers, ours at +0.5
            before = (xy[t - 1, alive] - 0.5).astype(np.float32).reshape(-1, 1, 2)
            after, ok, _ = cv2.calcOpticalFlowPyrLK(grey[t - 1], grey[t], before, None, **params)
            back, ok_back, _ = cv2.calcOpticalFlowPyrLK(grey[t], grey[t - 1], after, None, **params)
            after, back = after.reshape(-1, 2), back.reshape(-1, 2)
            error = np.linalg.norm(back - before.reshape(-1, 2), axis=1)
            inside = (after[:, 0] >= 0) & (after[:, 0] < w) & (after[:, 1] >= 0) & (after[:, 1] < h)
            good = ok.ravel().astype(bool) & ok_back.ravel().astype(bool) & inside & (error <= self.forward_backward_px)
            xy[t, alive] = after + 0.5
            visible[t, alive] = good
        return Tracks(xy, visible)
