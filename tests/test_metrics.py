"""Metric definitions on hand-made cases with known answers."""

import copy

import numpy as np
import pytest
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part
from rest2art.bench.metrics import iou_matrix, score_object, summarize
from rest2art.geometry import rotation_about


def _truth():
    base = trimesh.creation.box([1, 1, 1])
    parts = [Part("base", "base", None, base), Part("door_0", "door", "base"), Part("drawer_0", "drawer", "base")]
    joints = [Joint("door_0_joint", "revolute", "base", "door_0", [0, 0, 1], [0.5, -0.5, 0], (0, 1.5)),
              Joint("drawer_0_joint", "prismatic", "base", "drawer_0", [0, -1, 0], [0, -0.5, 0.3], (0, 0.3))]
    face_part = np.array([0] * 6 + [1] * 3 + [2] * 3, np.int32)
    return ArticulatedAsset(parts, joints, face_part)


AREA = np.ones(12)


def test_perfect_prediction():
    gt = _truth()
    s = summarize([score_object(copy.deepcopy(gt), gt, AREA)])
    assert s["type_accuracy_pct"] == 100.0 and s["axis_angle_deg"] == 0.0 and s["axis_pos_dm"] == 0.0
    assert s["miou"] == 1.0 and s["part_count_pct"] == 100.0


def test_axis_rotated_ten_degrees():
    gt = _truth()
    pred = copy.deepcopy(gt)
    pred.joints[0].axis = rotation_about(np.array([1.0, 0, 0]), np.radians(10)) @ gt.joints[0].axis
    score = score_object(pred, gt, AREA)
    door = next(p for p in score.parts if p.gt_part == "door_0")
    assert door.axis_angle_deg == pytest.approx(10.0)
    assert door.axis_pos_dm == pytest.approx(0.0, abs=1e-9)  # both lines pass through the origin point


def test_reversed_axis_is_not_an_error():
    gt = _truth()
    pred = copy.deepcopy(gt)
    pred.joints[1].axis = -gt.joints[1].axis
    drawer = next(p for p in score_object(pred, gt, AREA).parts if p.gt_part == "drawer_0")
    assert drawer.axis_angle_deg == pytest.approx(0.0)


def test_origin_shifted_across_axis():
    gt = _truth()
    pred = copy.deepcopy(gt)
    pred.joints[0].origin = gt.joints[0].origin + np.array([0.05, 0, 0.2])  # 5 cm across, 20 cm along
    door = next(p for p in score_object(pred, gt, AREA).parts if p.gt_part == "door_0")
    assert door.axis_pos_dm == pytest.approx(0.5)


def test_permuted_names_still_match():
    gt = _truth()
    pred = copy.deepcopy(gt)
    pred.parts = [pred.parts[0], pred.parts[2], pred.parts[1]]
    for p, new in zip(pred.parts[1:], ["x_1", "x_2"]):
        for j in pred.joints:
            if j.child == p.name:
                j.child = new
        p.name = new
    pred.face_part = np.array([0] * 6 + [2] * 3 + [1] * 3, np.int32)
    s = summarize([score_object(pred, gt, AREA)])
    assert s["type_accuracy_pct"] == 100.0 and s["miou"] == 1.0


def test_missing_part_counts_as_wrong_and_zero_iou():
    gt = _truth()
    pred = copy.deepcopy(gt)
    pred.parts = pred.parts[:2]
    pred.joints = pred.joints[:1]
    pred.face_part = np.array([0] * 6 + [1] * 3 + [0] * 3, np.int32)
    score = score_object(pred, gt, AREA)
    drawer = next(p for p in score.parts if p.gt_part == "drawer_0")
    assert drawer.iou == 0.0 and not drawer.type_correct and drawer.pred_part is None
    s = summarize([score])
    assert s["type_accuracy_pct"] == 50.0 and s["part_count_pct"] == 0.0
    assert s["miou"] == pytest.approx((6 / 9 + 1.0 + 0.0) / 3)  # base absorbs the drawer faces


def test_area_weighting():
    pred = np.array([0, 0, 1, 1])
    gt = np.array([0, 1, 1, 1])
    area = np.array([1.0, 10.0, 1.0, 1.0])
    ious = iou_matrix(pred, gt, area, 2, 2)
    assert ious[1, 1] == pytest.approx(2 / 12)  # pred 1 covers the small faces of gt 1 only
    assert ious[0, 1] == pytest.approx(10 / 13)
