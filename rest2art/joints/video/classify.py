"""Motion type from 2D tracks alone: static, revolute or prismatic.

Two cues, both unit-free:

* the coefficient of variation (CV) of per-point displacement magnitudes: points of a rotating
  part travel in proportion to their distance from the hinge, points of a sliding part all
  travel alike (up to perspective);
* a curvature score: a straight 3D path projects to a straight 2D path, so each moving point's
  path is measured by how far it leaves its best-fitting line (square root of the ratio of its
  two principal variances, after removing the track noise).

A part whose points barely move (against the noise of their smoothed end positions) is static. When the two cues agree
the label stands; when they do not, the caller fits both models and keeps the one with the
lower reprojection error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rest2art.joints.video.tracks import Tracks
from rest2art.tolerances import TINY


@dataclass
class MotionCues:
    displacement_px: float
    """Median over points of the distance from the start to the (smoothed) end position."""
    end_noise_px: float
    """Noise of that smoothed end position (track noise over the square root of the frames
    averaged)."""
    noise_px: float
    """Track noise estimated from second differences of positions."""
    cv: float
    """Coefficient of variation of the moving points' displacement magnitudes."""
    curvature: float
    """Median over moving points of the off-line spread of their path (0 = straight)."""
    moving_points: int


def track_noise(tracks: Tracks) -> float:
    """Robust per-coordinate std of the tracks' jitter (px), from second differences of
    positions visible in three consecutive frames (a smooth path contributes little)."""
    if tracks.n_frames < 3:
        return 0.0
    ok = tracks.visible[:-2] & tracks.visible[1:-1] & tracks.visible[2:]
    second = tracks.xy[2:] - 2 * tracks.xy[1:-1] + tracks.xy[:-2]
    values = np.abs(second[ok]).ravel()
    if not len(values):
        return 0.0
    # median |N(0, 6 s^2)| = 0.6745 * sqrt(6) * s
    return float(np.median(values) / (0.6745 * np.sqrt(6.0)))


def motion_cues(tracks: Tracks) -> MotionCues:
    """The classifier's cues for one part's (truncated) tracks."""
    T = tracks.n_frames
    noise = track_noise(tracks)
    if T < 2 or tracks.n_points == 0:
        return MotionCues(0.0, noise, noise, 0.0, 0.0, 0)
    k = max(1, T // 4)  # the end position is the mean of the last k frames
    tail = tracks.visible[T - k:]
    seen = tail.sum(axis=0)
    usable = (seen > 0) & tracks.visible[0]
    if not usable.any():
        return MotionCues(0.0, noise / np.sqrt(k), noise, 0.0, 0.0, 0)
    end = (tracks.xy[T - k:] * tail[..., None]).sum(axis=0)[usable] / seen[usable, None]
    magnitude = np.linalg.norm(end - tracks.xy[0, usable], axis=1)
    displacement = float(np.median(magnitude))
    moving = magnitude > max(3.0 * noise / np.sqrt(k), 1.0)
    if moving.sum() < 3:
        return MotionCues(displacement, noise / np.sqrt(k), noise, 0.0, 0.0, int(moving.sum()))
    m = magnitude[moving]
    cv = float(np.std(m) / max(np.mean(m), 1e-9))
    curvature = []
    for n in np.flatnonzero(usable)[moving]:
        path = tracks.xy[tracks.visible[:, n], n]
        if len(path) < 3:
            continue
        centred = path - path.mean(axis=0)
        lam = np.sort(np.linalg.eigvalsh(centred.T @ centred / len(path)))
        curvature.append(np.sqrt(max(lam[0] - noise ** 2, 0.0) / max(lam[1], TINY)))
    return MotionCues(displacement, noise / np.sqrt(k), noise, cv, float(np.median(curvature)) if curvature else 0.0,
                      int(moving.sum()))


def classify_motion(cues: MotionCues, static_px: float = 2.0, cv_revolute: float = 0.3,
                    cv_prismatic: float = 0.15, curvature_revolute: float = 0.08,
                    curvature_prismatic: float = 0.03) -> tuple[str, bool]:
    """(label, cues agree). Label: 'static', 'revolute', 'prismatic' or, when the cues do not
    agree, the one the curvature leans to (the caller should then fit both)."""
    if cues.displacement_px < max(static_px, 3.0 * cues.end_noise_px) or cues.moving_points < 3:
        return "static", True
    cv_says = "revolute" if cues.cv >= cv_revolute else "prismatic" if cues.cv <= cv_prismatic else None
    curve_says = ("revolute" if cues.curvature >= curvature_revolute
                  else "prismatic" if cues.curvature <= curvature_prismatic else None)
    if cv_says is not None and cv_says == curve_says:
        return cv_says, True
    lean = curve_says or cv_says or ("revolute" if cues.curvature > (curvature_revolute + curvature_prismatic) / 2
                                     else "prismatic")
    return lean, False
