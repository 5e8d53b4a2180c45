"""The evaluation metrics of DESIGN.md.

Predicted parts are matched to ground-truth parts by face-area-weighted IoU (Hungarian). For
each ground-truth movable part: its type is correct if it is matched and the joint types are
equal; the axis angle error (degrees, sign-agnostic) is taken over type-correct parts; the axis
position error (decimetres, distance between the two axis lines) over type-correct revolute
parts. Segmentation mIoU is over all ground-truth parts (0 when unmatched); the part count is
right when the number of predicted movable parts equals the truth.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment

from rest2art.asset import ArticulatedAsset
from rest2art.geometry import axis_angle_deg, line_distance


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
