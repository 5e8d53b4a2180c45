"""Metric definitions on hand-made cases with known answers."""

import copy

import numpy as np
import pytest
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part
from rest2art.bench.metrics import iou_matrix, score_object, summarize
from rest2art.geometry.basics import rotation_about


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


# ---- frame, yield and first failing stage ------------------------------------------------------

from rest2art.bench.metrics import BenchConfig, first_failure, frame_verdict, is_right, opening_front  # noqa: E402


def _box_asset(parts: list[tuple[str, trimesh.Trimesh, Joint | None]]) -> ArticulatedAsset:
    """An asset from (name, mesh, joint) triples; the first is the base; faces labelled in order."""
    assets = [Part(name, "base" if joint is None else "door", None if joint is None else joint.parent, mesh)
              for name, mesh, joint in parts]
    joints = [joint for _, _, joint in parts if joint is not None]
    face_part = np.concatenate([np.full(len(m.faces), k, np.int32) for k, (_, m, _) in enumerate(parts)])
    return ArticulatedAsset(assets, joints, face_part)


def _slab(size, centre) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(size)
    mesh.apply_translation(centre)
    return mesh


UP = np.array([0.0, 0.0, 1.0])
CARCASS = _slab([0.6, 0.4, 0.8], [0, 0, 0.4])


def test_generated_objects_front_is_their_true_front():
    from rest2art.bench import true_frame
    from rest2art.generate import generate_object

    for kind, up, yaw in (("cabinet", "z", 0.0), ("fridge", "z", 37.0), ("laptop", "z", -60.0), ("oven", "y", 90.0),
                          ("box", "z", 0.0), ("microwave", "y", 0.0)):
        obj = generate_object(kind, 3, "asset", up=up, yaw_deg=yaw)
        truth = true_frame(obj.asset)
        front = opening_front(obj.asset, truth["up"])
        assert front is not None, kind
        assert frame_verdict({"up": truth["up"], "front": front}, truth)["front_deg"] < 10.0, kind  # handles tilt it


def test_front_of_a_door_a_flat_lid_a_sliding_panel_and_a_button():
    door = Joint("door_joint", "revolute", "base", "door", [0, 0, 1], [0.3, -0.21, 0], (0, 1.5))
    asset = _box_asset([("base", CARCASS, None), ("door", _slab([0.6, 0.02, 0.8], [0, -0.21, 0.4]), door)])
    assert np.allclose(opening_front(asset, UP), [0, -1, 0], atol=0.01)  # its free edge swings out to -y

    # a laptop lid lying flat, hinged along its back edge (+y): its first motion is straight up
    lid = Joint("lid_joint", "revolute", "base", "lid", [-1, 0, 0], [0, 0.2, 0.02], (0, 1.9))
    laptop = _box_asset([("base", _slab([0.3, 0.4, 0.02], [0, 0, 0.01]), None),
                         ("lid", _slab([0.3, 0.4, 0.01], [0, 0, 0.025]), lid)])
    assert np.allclose(opening_front(laptop, UP), [0, -1, 0], atol=0.01)

    # a panel sliding sideways along the +x face of a carcass faces +x, not along its motion
    slide = Joint("panel_joint", "prismatic", "base", "panel", [0, 1, 0], [0.31, 0, 0.4], (0, 0.3))
    cabinet = _box_asset([("base", CARCASS, None), ("panel", _slab([0.02, 0.2, 0.7], [0.31, -0.1, 0.4]), slide)])
    assert np.allclose(opening_front(cabinet, UP), [1, 0, 0], atol=0.01)

    # a button on the -y face pushed in (+y) faces out (-y)
    push = Joint("button_joint", "prismatic", "base", "button", [0, 1, 0], [0, -0.22, 0.4], (0, 0.02))
    box = _box_asset([("base", CARCASS, None), ("button", _slab([0.2, 0.04, 0.2], [0, -0.22, 0.4]), push)])
    assert np.allclose(opening_front(box, UP), [0, -1, 0], atol=0.01)


def test_front_of_knobs_turning_in_place():
    for axis in ([0, 1, 0], [0, -1, 0]):  # either sign of the axis: the knob sits on the -y face
        knob = Joint("knob_joint", "revolute", "base", "knob", axis, [0, -0.22, 0.6], (0, 3.0))
        cylinder = trimesh.creation.cylinder(0.1, 0.04, transform=trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
        front = _box_asset([("base", CARCASS, None), ("knob", cylinder.apply_translation([0, -0.22, 0.6]), knob)])
        assert np.allclose(opening_front(front, UP), [0, -1, 0], atol=0.01)


def test_front_is_unknown_for_a_knob_on_top_or_parts_that_disagree():
    knob = Joint("knob_joint", "revolute", "base", "knob", [0, 0, 1], [0, 0, 0.85], (0, 3.0))
    top = _box_asset([("base", CARCASS, None), ("knob", trimesh.creation.cylinder(0.2, 0.1).apply_translation([0, 0, 0.85]), knob)])
    assert opening_front(top, UP) is None  # turns in place about the vertical
    a = Joint("a_joint", "prismatic", "base", "a", [0, -1, 0], [0, -0.21, 0.2], (0, 0.3))
    b = Joint("b_joint", "prismatic", "base", "b", [0, 1, 0], [0, 0.21, 0.6], (0, 0.3))
    both = _box_asset([("base", CARCASS, None), ("a", _slab([0.5, 0.3, 0.3], [0, -0.1, 0.2]), a),
                       ("b", _slab([0.5, 0.3, 0.3], [0, 0.1, 0.6]), b)])
    assert opening_front(both, UP) is None  # two equal drawers, one out of each side


def test_front_is_unknown_for_a_latch_low_on_a_face_or_an_arm_flat_along_its_axis():
    # a latch bar on the -y face, hinged at one end about the face's normal: it first moves down,
    # and its arm (+x) says nothing of the face it is on; a lid at the same place would vote +x
    latch = Joint("latch_joint", "revolute", "base", "latch", [0, 1, 0], [0, -0.22, 0.6], (0, 1.57))
    bar = _box_asset([("base", CARCASS, None), ("latch", _slab([0.25, 0.04, 0.03], [0.12, -0.22, 0.6]), latch)])
    assert opening_front(bar, UP) is None
    # a faucet's arm, flat along its vertical axis, sweeps sideways
    arm = Joint("arm_joint", "revolute", "base", "arm", [0, 0, 1], [0, 0, 0.82], (0, 1.57))
    faucet = _box_asset([("base", _slab([0.1, 0.1, 0.8], [0, 0, 0.4]), None),
                         ("arm", _slab([0.05, 0.4, 0.04], [0, -0.2, 0.82]), arm)])
    assert opening_front(faucet, UP) is None
    # the same arm as tall as it is long is a door: its free edge swings out
    door = _box_asset([("base", _slab([0.1, 0.1, 0.8], [0, 0, 0.4]), None),
                       ("arm", _slab([0.02, 0.4, 0.8], [0, -0.2, 0.4]), arm)])
    assert np.allclose(opening_front(door, UP), [1, 0, 0], atol=0.01)


def test_frame_verdict():
    truth = {"up": [0, 0, 1], "front": [0, -1, 0]}
    v = frame_verdict({"up": [0, 0, 1], "front": [1, 0, 0]}, truth)
    assert v["up_ok"] and v["up_deg"] == pytest.approx(0.0)
    assert not v["front_ok"] and v["front_deg"] == pytest.approx(90.0)
    assert frame_verdict({"up": [0, 0, -1], "front": [0, 1, 0]}, truth)["up_deg"] == pytest.approx(180.0)  # signed
    unknown = frame_verdict({"up": [0, 0, 1], "front": [0, -1, 0]}, {"up": [0, 0, 1], "front": None})
    assert unknown["front_ok"] is None and unknown["up_ok"] is True
    assert frame_verdict(None, truth)["up_ok"] is None


def _first(pred, gt=None, frame=None):
    score = score_object(pred, gt or _truth(), AREA)
    return first_failure(score, frame)[0], is_right(score)


def test_first_failure_order_and_yield():
    gt = _truth()
    assert _first(copy.deepcopy(gt)) == ("ok", True)
    # frame comes first, even when everything else is right; 'right' does not look at the frame
    assert _first(copy.deepcopy(gt), frame={"up_ok": True, "front_ok": False, "front_deg": 90.0}) == ("frame", True)

    limits = copy.deepcopy(gt)
    limits.joints[1].limit = (0.0, 0.1)  # 0.3 m of travel found as 0.1 m: off by 67 %
    assert _first(limits) == ("limits", True)
    assert score_object(limits, gt, AREA).parts[2].limit_rel_error == pytest.approx(2 / 3)

    axis = copy.deepcopy(gt)
    axis.joints[0].axis = rotation_about(np.array([1.0, 0, 0]), np.radians(6)) @ gt.joints[0].axis
    assert _first(axis) == ("axis", False)
    assert first_failure(score_object(axis, gt, AREA), None, BenchConfig(right_axis_deg=7.0))[0] == "ok"

    far = copy.deepcopy(gt)
    far.joints[0].origin = gt.joints[0].origin + np.array([0.06, 0, 0])  # 0.6 dm off
    assert _first(far) == ("axis", False)

    typed = copy.deepcopy(gt)
    typed.joints[1].type = "revolute"
    assert _first(typed) == ("type", False)

    missing = copy.deepcopy(gt)
    missing.parts, missing.joints = missing.parts[:2], missing.joints[:1]
    missing.face_part = np.array([0] * 6 + [1] * 3 + [0] * 3, np.int32)
    stage, right = _first(missing)
    assert (stage, right) == ("parts", False)
    assert "unmatched: drawer_0" in first_failure(score_object(missing, gt, AREA))[1]
