"""The evaluation metrics of DESIGN.md.

Predicted parts are matched to ground-truth parts by face-area-weighted IoU (Hungarian). For
each ground-truth movable part: its type is correct if it is matched and the joint types are
equal; the axis angle error (degrees, sign-agnostic) is taken over type-correct parts; the axis
position error (decimetres, distance between the two axis lines) over type-correct revolute
parts. Segmentation mIoU is over all ground-truth parts (0 when unmatched); the part count is
right when the number of predicted movable parts equals the truth.

Beyond DESIGN.md, per object (tolerances in :class:`BenchConfig`): whether the predicted up and
front are right (:func:`frame_verdict`; the truth's front from :func:`opening_front`), whether
the whole reconstruction is *right* (:func:`is_right`: every movable part found with its type,
the right count, axes and mIoU within tolerance) and the first stage that went wrong
(:func:`first_failure`: frame, parts, type, axis, limits, else ok).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
import trimesh
from scipy.optimize import linear_sum_assignment

from rest2art.asset import ArticulatedAsset
from rest2art.geometry.basics import axis_angle_deg, line_distance, transform_points, unit

STAGES = ("frame", "parts", "type", "axis", "limits", "ok")
"""The diagnostic stages in the order they are checked; ``error`` when the run failed."""


@dataclass(frozen=True)
class BenchConfig:
    """Tolerances of the bench's verdicts on one object."""

    right_axis_deg: float = 5.0
    """A type-correct axis within this angle of the truth is right."""
    speed_steps: int = 2000
    """MuJoCo steps (no robot, the asset's own timestep) timed for an asset's simulation speed."""
    right_pos_dm: float = 0.5
    """A revolute axis line within this distance (dm) of the truth is right."""
    right_miou: float = 0.8
    """Segmentation is right when the object's mIoU reaches this."""
    limit_rel_tol: float = 0.5
    """A joint range off by more than this share of the true range is wrong."""
    frame_tol_deg: float = 30.0
    """A predicted up (front) within this angle of the truth is right."""
    front_step: float = 0.01
    """The truth's front: the opening motion is measured at this share of each joint's range."""
    front_in_place: float = 0.3
    """A part whose mean displacement is below this share of its points' mean displacement turns
    in place (a knob, a cap): it says nothing about the front."""
    front_min_horizontal: float = 0.5
    """A part's motion (or, for a lid that first moves up, its hinge-to-centre direction) counts
    for the front when its horizontal component is at least this share of it."""
    front_outward_share: float = 0.25
    """A part sits on one side of the object when its centre is out from the object's centre by
    at least this share of the half extent: a sliding panel or a knob votes for that side, a part
    that slides in from there (a button) faces out."""
    front_min_part_share: float = 0.15
    """Parts smaller (bounding-box diagonal) than this share of the object's do not vote (knobs,
    switches)."""
    front_panel_ratio: float = 0.6
    """A sliding part thinner than this share of its middle extent is a panel (a sliding door or
    window) that faces along its normal..."""
    front_in_plane_cos: float = 0.5
    """... when its motion makes less than this cosine with the panel's normal."""
    front_lid_top_share: float = 0.1
    """A part hinged on a horizontal axis whose first motion is up is a lid when its top lies
    within this share of the object's height of the object's top; lower down it is a lever or a
    latch, whose motion does not say which side is the front."""
    front_agreement: float = 0.5
    """The parts' directions must agree: their area-weighted sum at least this share of the sum
    of their lengths, else the front is unknown."""


def iou_matrix(pred_labels: np.ndarray, gt_labels: np.ndarray, face_area: np.ndarray,
               n_pred: int, n_gt: int) -> np.ndarray:
    """(n_pred, n_gt) face-area-weighted IoU between label sets on the same faces."""
    joint = np.zeros((n_pred, n_gt))
    np.add.at(joint, (pred_labels, gt_labels), face_area)
    pred_area = joint.sum(axis=1, keepdims=True)
    gt_area = joint.sum(axis=0, keepdims=True)
    union = pred_area + gt_area - joint
    return np.divide(joint, union, out=np.zeros_like(joint), where=union > 0)


@dataclass
class PartScore:
    gt_part: str
    pred_part: str | None
    iou: float
    movable: bool
    gt_type: str | None = None
    pred_type: str | None = None
    type_correct: bool = False
    axis_angle_deg: float | None = None
    axis_pos_dm: float | None = None
    limit_rel_error: float | None = None
    """|predicted range - true range| / true range, over type-correct parts."""


@dataclass
class ObjectScore:
    """Scores of one object."""

    name: str
    parts: list[PartScore] = field(default_factory=list)
    n_gt_movable: int = 0
    n_pred_movable: int = 0

    @property
    def miou(self) -> float:
        return float(np.mean([p.iou for p in self.parts])) if self.parts else 0.0

    @property
    def count_correct(self) -> bool:
        return self.n_gt_movable == self.n_pred_movable

    def to_dict(self) -> dict:
        return {"name": self.name, "miou": self.miou, "count_correct": self.count_correct,
                "n_gt_movable": self.n_gt_movable, "n_pred_movable": self.n_pred_movable,
                "parts": [asdict(p) for p in self.parts]}


def score_object(pred: ArticulatedAsset, gt: ArticulatedAsset, face_area: np.ndarray, name: str = "") -> ObjectScore:
    """Score ``pred`` against ``gt``; both label the same faces (``face_area`` (F,), m^2)."""
    if pred.face_part is None or gt.face_part is None or len(pred.face_part) != len(gt.face_part):
        raise ValueError(f"{name}: prediction and truth must label the same {len(face_area)} faces")
    ious = iou_matrix(pred.face_part, gt.face_part, face_area, len(pred.parts), len(gt.parts))
    rows, cols = linear_sum_assignment(-ious)
    match = {int(c): int(r) for r, c in zip(rows, cols) if ious[r, c] > 0}
    score = ObjectScore(name, n_gt_movable=len(gt.movable_joints), n_pred_movable=len(pred.movable_joints))
    for g, gpart in enumerate(gt.parts):
        gjoint = gt.joint_for(gpart.name)
        movable = gjoint is not None and gjoint.type != "fixed"
        r = match.get(g)
        ps = PartScore(gpart.name, pred.parts[r].name if r is not None else None,
                       float(ious[r, g]) if r is not None else 0.0, movable)
        if movable:
            ps.gt_type = gjoint.type
            pjoint = pred.joint_for(pred.parts[r].name) if r is not None else None
            ps.pred_type = pjoint.type if pjoint is not None else None
            ps.type_correct = pjoint is not None and pjoint.type == gjoint.type
            if ps.type_correct:
                ps.axis_angle_deg = axis_angle_deg(pjoint.axis, gjoint.axis)
                if gjoint.type == "revolute":
                    ps.axis_pos_dm = 10.0 * line_distance(pjoint.origin, pjoint.axis, gjoint.origin, gjoint.axis)
                true_range = gjoint.limit[1] - gjoint.limit[0]
                if true_range > 0:
                    ps.limit_rel_error = abs(pjoint.limit[1] - pjoint.limit[0] - true_range) / true_range
        score.parts.append(ps)
    return score


def summarize(scores: list[ObjectScore]) -> dict:
    """Pooled metrics over objects: type accuracy (%), mean axis angle (deg) and position (dm),
    mIoU over all ground-truth parts, part-count accuracy (%)."""
    parts = [p for s in scores for p in s.parts]
    movable = [p for p in parts if p.movable]
    angles = [p.axis_angle_deg for p in movable if p.axis_angle_deg is not None]
    positions = [p.axis_pos_dm for p in movable if p.axis_pos_dm is not None]
    return {
        "objects": len(scores),
        "movable_parts": len(movable),
        "type_accuracy_pct": 100.0 * np.mean([p.type_correct for p in movable]) if movable else float("nan"),
        "axis_angle_deg": float(np.mean(angles)) if angles else float("nan"),
        "axis_pos_dm": float(np.mean(positions)) if positions else float("nan"),
        "miou": float(np.mean([p.iou for p in parts])) if parts else float("nan"),
        "part_count_pct": 100.0 * np.mean([s.count_correct for s in scores]) if scores else float("nan"),
    }


def opening_front(asset: ArticulatedAsset, up: np.ndarray, config: BenchConfig = BenchConfig()) -> np.ndarray | None:
    """(3,) unit horizontal direction the movable parts of ``asset`` (part meshes needed) open
    towards, or None when it cannot be told.

    Each part that is not small votes, weighted by its area. A revolute part votes with the
    area-weighted mean displacement of its faces at the start of its opening (``front_step`` of
    the range), made horizontal: a door's free edge swings out, an open laptop lid swings
    forward; a lid whose first motion is straight up votes from its hinge line to its centre (a
    lever or latch hinged lower down, whose arm may point anywhere, does not); an arm flat along
    its axis (a faucet handle) sweeps sideways and does not vote either. A sliding part votes
    with its motion (a drawer slides out), reversed for a part pressed in from the outside (a
    button); a panel sliding in its own plane (a sliding door or window)
    votes along its normal for the side of the object it sits on. A knob turning in place on a
    horizontal axis votes along its axis for its side. Parts that turn in place on a vertical
    axis or only move up and down do not vote. None when no part votes or the votes disagree
    (``front_agreement``)."""
    up = unit(np.asarray(up, float))
    meshes = [p.mesh for p in asset.parts if p.mesh is not None and len(p.mesh.faces)]
    if not meshes:
        return None
    points = np.concatenate([m.vertices for m in meshes])
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    heights = points @ up
    lid_top = heights.max() - config.front_lid_top_share * np.ptp(heights)  # a lid's top reaches this high

    def horizontal(v: np.ndarray) -> np.ndarray | None:
        """The horizontal part of ``v``, unit; None when ``v`` is mostly vertical."""
        h = v - (v @ up) * up
        return unit(h) if np.linalg.norm(h) >= config.front_min_horizontal * np.linalg.norm(v) > 0 else None

    def side(direction: np.ndarray | None, offset: np.ndarray) -> np.ndarray | None:
        """``direction`` (unit) signed towards the side of the object a part sits on (``offset``:
        its centre from the object's); None when it sits in the middle along it."""
        if direction is None or abs(offset @ direction) < config.front_outward_share * (np.abs(direction) @ half):
            return None
        return np.sign(offset @ direction) * direction

    votes = []
    for joint in asset.movable_joints:
        mesh = asset.part(joint.child).mesh
        if (mesh is None or not len(mesh.faces) or joint.limit[1] <= joint.limit[0]
                or np.linalg.norm(mesh.extents) < config.front_min_part_share * np.linalg.norm(hi - lo)):
            continue
        weights = mesh.area_faces / mesh.area_faces.sum()
        faces = mesh.triangles_center
        offset = weights @ faces - centre
        value = joint.limit[0] + config.front_step * (joint.limit[1] - joint.limit[0])
        move = transform_points(faces, joint.transform(value)) - faces
        mean, spread = weights @ move, weights @ np.linalg.norm(move, axis=1)
        if spread <= 0:
            continue
        direction = horizontal(mean)
        if np.linalg.norm(mean) < config.front_in_place * spread:  # turns in place: a knob faces along its axis
            direction = side(horizontal(joint.axis), offset) if joint.type == "revolute" else None
        elif joint.type == "revolute" and direction is None:
            if (mesh.vertices @ up).max() >= lid_top:
                arm = offset + centre - joint.origin  # a lid: hinge line to centre
                direction = horizontal(arm - (arm @ joint.axis) * joint.axis)
            # lower down, a lever or a latch: its motion does not say which side is the front
        elif joint.type == "revolute" and np.ptp(mesh.vertices @ joint.axis) < np.ptp(mesh.vertices @ direction):
            direction = None  # an arm flat along its axis sweeps sideways (a faucet handle): no front
        elif joint.type == "prismatic":
            to_local, extents = trimesh.bounds.oriented_bounds(mesh)
            order = np.argsort(extents)
            normal = to_local[order[0], :3]
            facing = horizontal(normal)
            if (facing is not None and extents[order[0]] < config.front_panel_ratio * extents[order[1]]
                    and abs(normal @ unit(mean)) < config.front_in_plane_cos):
                direction = side(facing, offset)  # a panel sliding in its own plane faces along its normal
            elif direction is not None and offset @ direction < -config.front_outward_share * (np.abs(direction) @ half):
                direction = -direction  # pressed in from the outside
        if direction is not None:
            votes.append(mesh.area * direction)
    if not votes:
        return None
    total = np.sum(votes, axis=0)
    if np.linalg.norm(total) < config.front_agreement * sum(np.linalg.norm(v) for v in votes):
        return None
    return unit(total)


def _signed_angle_deg(a, b) -> float:
    a, b = unit(np.asarray(a, float)), unit(np.asarray(b, float))
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), float(a @ b))))


def frame_verdict(pred: dict | None, truth: dict | None, config: BenchConfig = BenchConfig()) -> dict:
    """Angles (degrees) between the predicted and the true up and front ({"up": (3,), "front":
    (3,) or None} each, same frame) and whether each is within ``frame_tol_deg``; None where
    either side does not say."""
    verdict = {}
    for key in ("up", "front"):
        p, t = (pred or {}).get(key), (truth or {}).get(key)
        angle = None if p is None or t is None else _signed_angle_deg(p, t)
        verdict[f"{key}_deg"] = angle
        verdict[f"{key}_ok"] = None if angle is None else bool(angle <= config.frame_tol_deg)
    return verdict


def is_right(score: ObjectScore, config: BenchConfig = BenchConfig()) -> bool:
    """Every true movable part found with its joint type, the right number of movable parts,
    every axis within ``right_axis_deg`` and ``right_pos_dm``, and mIoU at least ``right_miou``."""
    movable = [p for p in score.parts if p.movable]
    return (score.count_correct and score.miou >= config.right_miou
            and all(p.type_correct for p in movable)
            and all(p.axis_angle_deg <= config.right_axis_deg for p in movable)
            and all(p.axis_pos_dm is None or p.axis_pos_dm <= config.right_pos_dm for p in movable))


def first_failure(score: ObjectScore, frame: dict | None = None, config: BenchConfig = BenchConfig()) -> tuple[str, str]:
    """The first stage (of :data:`STAGES`) that went wrong, and why, in one line: frame (up or
    front wrong, where the truth says), parts (movable part count wrong, a movable part
    unmatched, or mIoU below ``right_miou``), type (a matched movable part with the wrong joint
    type), axis (angle or position beyond tolerance), limits (range off by more than
    ``limit_rel_tol``), else ok."""
    frame = frame or {}
    wrong = [k for k in ("up", "front") if frame.get(f"{k}_ok") is False]
    if wrong:
        return "frame", ", ".join(f"{k} off by {frame[f'{k}_deg']:.0f} deg" for k in wrong)
    movable = [p for p in score.parts if p.movable]
    unmatched = [p.gt_part for p in movable if p.pred_part is None]
    if not score.count_correct or unmatched or score.miou < config.right_miou:
        detail = f"{score.n_pred_movable} movable parts for {score.n_gt_movable}, mIoU {score.miou:.2f}"
        return "parts", detail + (f", unmatched: {', '.join(unmatched)}" if unmatched else "")
    mistyped = [f"{p.gt_part} {p.gt_type} as {p.pred_type or 'static'}" for p in movable if not p.type_correct]
    if mistyped:
        return "type", "; ".join(mistyped)
    off_axis = [f"{p.gt_part} {p.axis_angle_deg:.1f} deg" + ("" if p.axis_pos_dm is None else f" {p.axis_pos_dm:.2f} dm")
                for p in movable if p.axis_angle_deg > config.right_axis_deg
                or (p.axis_pos_dm is not None and p.axis_pos_dm > config.right_pos_dm)]
    if off_axis:
        return "axis", "; ".join(off_axis)
    off_range = [f"{p.gt_part} off by {100 * p.limit_rel_error:.0f} %" for p in movable
                 if p.limit_rel_error is not None and p.limit_rel_error > config.limit_rel_tol]
    if off_range:
        return "limits", "; ".join(off_range)
    return "ok", ""
