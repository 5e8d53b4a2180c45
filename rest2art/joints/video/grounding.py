"""Mesh-grounded judgement of joint hypotheses: the mesh overrules the motion evidence.

The geometric enumerator lists every plausible joint of a part from its shape alone: hinge lines
on the four edges of the part's front and back faces (the faces across its outward direction),
the part's own outward axis (a knob), and slide directions (the outward normal first, then the
part's other box axes). A fitted joint is then judged against them and against the mesh:

* snap: a fit within ``snap_angle_deg`` and ``snap_distance`` of a candidate of its type takes
  the candidate's line (carcass edges are where real hinges sit);
* blend: an unsnapped axis close to the principal direction of the part's boundary with its
  parent is pulled softly towards it;
* collision: an opening that drives the part into its parent within half its range is
  overruled by the nearest candidate of the same type that opens freely;
* limit: the opening's first collision, capped by ``cap``.

All coordinates are canonical (+z up), metres; part and parent meshes as trimesh objects.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from rest2art.config import ArticulationConfig, JointsConfig
from rest2art.geometry.basics import axis_angle_deg, faces_at_extreme, outer_plane, principal_axes, unit
from rest2art.joints.rules import hinge_candidates
from rest2art.joints.sweep import sweep_free_range, sweep_objects, sweep_steps
from rest2art.joints.video.fit import JointFit

AXES = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])


@dataclass
class JointHypothesis:
    type: str
    axis: np.ndarray
    origin: np.ndarray
    source: str


@dataclass
class GroundedJoint:
    type: str
    axis: np.ndarray
    origin: np.ndarray
    upper: float
    evidence: dict = field(default_factory=dict)


def exposed_outward(part: trimesh.Trimesh, parent: trimesh.Trimesh,
                    config: ArticulationConfig = ArticulationConfig()) -> np.ndarray:
    """(3,) the axis direction the part faces: the one with the most part area facing it (normals
    within ``acos(config.outward_min_cos)``) that lies within ``config.outward_band`` (m) of the
    whole object's extreme in that direction."""
    extreme = np.concatenate([part.vertices, parent.vertices])
    best, best_area = AXES[3], -1.0
    for d in AXES:
        facing = faces_at_extreme(part, d, config.outward_band, float((extreme @ d).max()), config.outward_min_cos)
        area = float(part.area_faces[facing].sum())
        if area > best_area:
            best, best_area = d, area
    return best.copy()


def geometric_candidates(part: trimesh.Trimesh, outward: np.ndarray) -> list[JointHypothesis]:
    """Every plausible joint of ``part`` from its axis-aligned box and ``outward`` direction:
    hinges on the edges of its front and back faces, its own axis, slide directions."""
    lo, hi = part.bounds
    depth = float(np.ptp(part.vertices @ outward))
    # the faces' planes are where most area faces out / in (a handle's tip is not the front)
    planes = {"front": outer_plane(part, outward, depth), "back": -outer_plane(part, -outward, depth)}
    out = [JointHypothesis("revolute", c.axis, c.point, f"edge {c.name}")
           for c in hinge_candidates(lo, hi, outward, planes).values()]
    centre = (lo + hi) / 2
    out.append(JointHypothesis("revolute", outward.copy(), centre, "own axis"))
    out.append(JointHypothesis("prismatic", outward.copy(), centre, "outward normal"))
    for d in np.eye(3):
        if abs(d @ outward) < 0.5:
            out.append(JointHypothesis("prismatic", d, centre, "box axis"))
    return out


def boundary_direction(part: trimesh.Trimesh, parent: trimesh.Trimesh, distance: float,
                       samples: int = 4000, seed: int = 0) -> np.ndarray | None:
    """(3,) principal direction of the part's surface lying within ``distance`` of the parent
    (their shared boundary), or None when they do not meet."""
    rng = np.random.default_rng(seed)
    part_pts = trimesh.sample.sample_surface(part, samples, seed=rng)[0]
    parent_pts = trimesh.sample.sample_surface(parent, samples * 4, seed=rng)[0]
    near = cKDTree(parent_pts).query(part_pts, distance_upper_bound=distance)[0] < distance
    if near.sum() < 10:
        return None
    return principal_axes(part_pts[near])[2]


def offset_from_line(point: np.ndarray, line_point: np.ndarray, line_axis: np.ndarray) -> float:
    """Distance (m) of ``point`` from the line through ``line_point`` along ``line_axis``.

    Used instead of the distance between two infinite lines, which is small for any two
    almost-parallel lines that cross far from the part."""
    a = unit(line_axis)
    d = np.asarray(point, float) - np.asarray(line_point, float)
    return float(np.linalg.norm(d - (d @ a) * a))


def _distance(fit_axis: np.ndarray, fit_origin: np.ndarray, kind: str, cand: JointHypothesis,
              config: ArticulationConfig) -> float:
    """How far a candidate is from the fit, in snap tolerances (angle, and for revolute joints
    the offset of the candidate's edge midpoint from the fitted line)."""
    score = axis_angle_deg(fit_axis, cand.axis) / config.snap_angle_deg
    if kind == "revolute":
        score += offset_from_line(cand.origin, fit_origin, fit_axis) / config.snap_distance
    return score


def ground_joint(fit: JointFit, part: trimesh.Trimesh, parent: trimesh.Trimesh, outward: np.ndarray,
                 cap: float, config: ArticulationConfig = ArticulationConfig(),
                 joints_config: JointsConfig = JointsConfig()) -> GroundedJoint:
    """The fitted joint after snapping, blending and the collision check, with its limit
    (``cap``: rad or m)."""
    kind = fit.type
    axis, origin = unit(fit.axis), fit.origin.copy()
    candidates = [c for c in geometric_candidates(part, outward) if c.type == kind]
    ranked = sorted(candidates, key=lambda c: _distance(axis, origin, kind, c, config))
    evidence = {"fit_rmse_px": round(fit.rmse_px, 3), "snapped": False, "blended": False, "overruled": False}
    near = ranked[0] if ranked else None
    if near is not None and axis_angle_deg(axis, near.axis) <= config.snap_angle_deg and (
            kind == "prismatic" or offset_from_line(near.origin, origin, axis) <= config.snap_distance):
        axis = unit(near.axis) * (1.0 if near.axis @ axis >= 0 else -1.0)
        origin = near.origin.copy() if kind == "revolute" else origin
        evidence.update(snapped=True, candidate=near.source)
    else:
        direction = boundary_direction(part, parent, config.boundary_distance)
        if direction is not None and axis_angle_deg(axis, direction) <= config.blend_max_deg:
            direction = direction if direction @ axis >= 0 else -direction
            axis = unit((1 - config.blend_weight) * axis + config.blend_weight * direction)
            evidence["blended"] = True
    # the same sweep as the geometric rules: shrunk by the margin, seams of a fused mesh left out,
    # sampled finely enough that no thin panel is jumped over
    moving, others = sweep_objects({"part": part, "parent": parent}, "part", joints_config)

    def free(a, o):
        return sweep_free_range(moving, others, kind, a, o, cap, sweep_steps(kind, a, o, cap, part.vertices,
                                                                             joints_config))

    opened = free(axis, origin)
    if opened < 0.5 * cap:
        flipped = free(-axis, origin)
        if flipped > opened:  # the tracks' sign was wrong (a monocular ambiguity)
            axis, opened = -axis, flipped
            evidence["flipped"] = True
    if opened < 0.5 * cap:  # overruled: the candidate that opens furthest, the nearest among equals
        best = None
        for rank, cand in enumerate(ranked):
            for sign in (1.0, -1.0):
                a = sign * unit(cand.axis) * (1.0 if cand.axis @ axis >= 0 else -1.0)
                f = free(a, cand.origin)
                if f >= 0.5 * cap and (best is None or f > best[0] + 1e-9):
                    best = (f, a, cand)
        if best is not None:
            opened, axis, cand = best
            origin = cand.origin.copy() if kind == "revolute" else origin
            evidence.update(overruled=True, candidate=cand.source)
    evidence["free"] = round(float(opened), 4)
    return GroundedJoint(kind, axis, origin, float(max(opened, config.grounded_min_share * cap)), evidence)
