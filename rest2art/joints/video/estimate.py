"""Joints from motion videos: tracks -> motion type -> fitted joint, over several seeds.

The roles behind the evidence:

* ``motion video`` (image-to-video): ``generate(image, prompt, seed, n_frames)`` returns
  (T, H, W, 3) uint8 frames animating the conditioning image (the chosen view with the movable
  parts' masks blended in, see ``conditioning_image``);
* ``tracks``: see ``rest2art.joints.video.tracks``.

Per video and part the tracks are cut where visibility collapses, their frame-0 positions are
unprojected with the mesh's rendered depth (metric anchors), the motion is classified and the
joint fitted. Over the R videos (multi-seed consensus): when the runs that saw motion agree on
the type, their evidence is fitted jointly; otherwise the best run wins by reprojection error
relative to the displacement; when every part is static in every run, ``extra_seeds`` more
videos are made.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from rest2art.config import ArticulationConfig
from rest2art.joints.video.classify import MotionCues, classify_motion, motion_cues
from rest2art.joints.video.fit import JointFit, Observation, anchors_from_depth, box_starts, fit_joint
from rest2art.joints.video.tracks import Tracks, TracksBackend, grid_queries, truncate
from rest2art.render.camera import Camera
from rest2art.render.raster import blend_masks


class MotionVideoBackend(Protocol):
    """The ``motion video`` role: animate a conditioning image as the prompt describes."""

    def generate(self, image: np.ndarray, prompt: str, seed: int, n_frames: int) -> np.ndarray: ...


@dataclass
class VideoEvidence:
    """One video's tracks, per movable part, with the camera and frame-0 depth of its view."""

    camera: Camera
    depth0: np.ndarray
    """(H, W) depth of the rest mesh rendered from ``camera`` (inf on background)."""
    tracks: dict[str, Tracks]


@dataclass
class PartMotion:
    """What the videos say about one part."""

    name: str
    type: str
    """static, revolute or prismatic."""
    fit: JointFit | None
    runs: list[dict] = field(default_factory=list)
    """Per video: label, whether the cues agreed, cues, rmse, displacement."""
    combined: bool = False
    """The joint was fitted on the evidence of several videos together."""


def conditioning_image(picture: np.ndarray, masks: list[np.ndarray], alpha: float = 0.35) -> np.ndarray:
    """(H, W, 3) uint8 conditioning image of the motion video: the picture with each movable
    part's (H, W) bool mask blended in its own colour (the paper's alpha = 0.35)."""
    return blend_masks(picture, masks, alpha)


def evidence_from_frames(frames: np.ndarray, camera: Camera, depth0: np.ndarray, masks: dict[str, np.ndarray],
                         tracker: TracksBackend, config: ArticulationConfig = ArticulationConfig()) -> VideoEvidence:
    """Track a grid inside each part's (H, W) frame-0 mask through ``frames`` (one tracker
    call for all parts)."""
    queries = {name: grid_queries(mask, config.erosion_fraction, max_points=config.max_track_points)
               for name, mask in masks.items()}
    names = [n for n, q in queries.items() if len(q)]
    if not names:
        return VideoEvidence(camera, depth0, {})
    all_tracks = tracker.track(frames, np.concatenate([queries[n] for n in names]))
    out, start = {}, 0
    for name in names:
        n = len(queries[name])
        out[name] = all_tracks.subset(points=slice(start, start + n))
        start += n
    return VideoEvidence(camera, depth0, out)


def observe(evidence: VideoEvidence, name: str, config: ArticulationConfig) -> Observation | None:
    """The part's truncated tracks with metric anchors, or None without usable tracks."""
    tracks = evidence.tracks.get(name)
    if tracks is None or tracks.n_points == 0:
        return None
    tracks = truncate(tracks, config.visibility_threshold)
    anchors, ok = anchors_from_depth(evidence.camera, tracks.xy[0], evidence.depth0)
    if not ok.any():
        return None
    return Observation(evidence.camera, anchors[ok], tracks.subset(points=ok))


def _reach_ok(fit: JointFit, anchors: np.ndarray, config: ArticulationConfig) -> bool:
    """A revolute fit whose axis passes within reach of the tracked points."""
    extent = float(np.ptp(anchors, axis=0).max()) or 1e-3
    centroid = anchors.mean(axis=0)
    offset = centroid - fit.origin
    offset -= (offset @ fit.axis) * fit.axis
    return float(np.linalg.norm(offset)) <= config.reach_factor * extent


def fit_observations(observations: list[Observation], label: str, agree: bool, config: ArticulationConfig,
                     starts: dict[str, list] | None = None, seed: int = 0) -> JointFit | None:
    """The joint for one part: the classified model, or both models when the cues disagree
    (revolute must beat prismatic by ``revolute_margin`` and pass near the part)."""
    anchors = np.concatenate([o.anchors for o in observations])
    starts = starts or {}
    kinds = [label] if agree else ["revolute", "prismatic"]
    fits = {k: fit_joint(k, observations, starts.get(k) or box_starts(k, anchors), config, seed) for k in kinds}
    rev, pri = fits.get("revolute"), fits.get("prismatic")
    if rev is not None and not _reach_ok(rev, anchors, config):
        pri = pri or fit_joint("prismatic", observations, starts.get("prismatic") or box_starts("prismatic", anchors),
                               config, seed)
        rev = None
    if rev is not None and pri is not None:
        return rev if rev.rmse_px < config.revolute_margin * pri.rmse_px else pri
    return rev or pri


def _score(fit: JointFit | None, cues: MotionCues) -> float:
    """Lower is better: reprojection error relative to the displacement it explains."""
    if fit is None:
        return float("inf")
    return fit.rmse_px / max(cues.displacement_px, 1.0)


def estimate_part_motions(make_evidence: Callable[[int], VideoEvidence], names: list[str],
                          config: ArticulationConfig = ArticulationConfig(),
                          starts: dict[str, dict[str, list]] | None = None) -> dict[str, PartMotion]:
    """Multi-seed consensus over videos made by ``make_evidence(seed)`` for the parts ``names``.

    ``starts``: per part, optional starting hypotheses per model type (e.g. the geometric
    enumerator's); the anchors' box is used otherwise."""
    starts = starts or {}
    evidence = [make_evidence(seed) for seed in range(config.seeds)]
    per_part = {name: _runs(name, evidence, config, starts.get(name)) for name in names}
    if names and all(all(r["label"] == "static" for r in runs) for runs, _ in per_part.values()):
        evidence += [make_evidence(seed) for seed in range(config.seeds, config.seeds + config.extra_seeds)]
        per_part = {name: _runs(name, evidence, config, starts.get(name)) for name in names}
    out = {}
    for name in names:
        runs, fits = per_part[name]
        moving = [k for k, r in enumerate(runs) if r["label"] != "static" and fits[k] is not None]
        if not moving:
            out[name] = PartMotion(name, "static", None, runs)
            continue
        types = [fits[k].type for k in moving]
        majority = max(set(types), key=types.count)
        agreeing = [k for k in moving if fits[k].type == majority]
        if len(agreeing) >= 2 and types.count(majority) > len(types) / 2:
            observations = [runs[k]["observation"] for k in agreeing]
            joint = fit_joint(majority, observations, (starts.get(name) or {}).get(majority)
                              or box_starts(majority, np.concatenate([o.anchors for o in observations])), config)
            out[name] = PartMotion(name, majority, joint, runs, combined=True)
        else:
            best = min(moving, key=lambda k: _score(fits[k], runs[k]["cues"]))
            out[name] = PartMotion(name, fits[best].type, fits[best], runs)
        for r in runs:
            r.pop("observation", None)
    return out


def _runs(name: str, evidence: list[VideoEvidence], config: ArticulationConfig,
          starts: dict[str, list] | None) -> tuple[list[dict], list[JointFit | None]]:
    runs, fits = [], []
    for k, ev in enumerate(evidence):
        obs = observe(ev, name, config)
        if obs is None or obs.tracks.n_frames < 3:
            runs.append({"label": "static", "agree": True, "frames": 0 if obs is None else obs.tracks.n_frames})
            fits.append(None)
            continue
        cues = motion_cues(obs.tracks)
        label, agree = classify_motion(cues, config.static_px, config.cv_revolute, config.cv_prismatic,
                                       config.curvature_revolute, config.curvature_prismatic)
        fit = None if label == "static" else fit_observations([obs], label, agree, config, starts, seed=k)
        runs.append({"label": label if fit is None else fit.type, "cue_label": label, "agree": agree,
                     "cues": cues, "frames": obs.tracks.n_frames, "observation": obs,
                     "rmse_px": None if fit is None else round(fit.rmse_px, 3)})
        fits.append(fit)
    return runs, fits
