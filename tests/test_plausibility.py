"""The plausibility gate: drawer pulls are not knobs, empty ranges and tiny panels are no joints,
and an object with no movable part is static and refused unless the user allows it."""

import dataclasses

import numpy as np
import pytest
import trimesh
from rest2art.validators.validate import validate_folder

from rest2art.config import GateConfig, JointsConfig
from rest2art.export.writers import write_asset
from rest2art.gate.plausibility import (backed_share, enclosing_frames, facing_share, joint_confidence,
                                       open_front_below, open_outline_share, open_share_behind, panel_beside_door,
                                       pull_knob_groups, review)
from rest2art.io.load import load_mesh
from rest2art.joints.rules import JointEstimate, pane_behind
from rest2art.parts.pieces import PartEstimate
from rest2art.pipeline import complete_asset, reconstruct_mesh


def test_pulls_of_stacked_drawers_are_not_controls():
    front = np.tile([0.0, -1.0, 0.0], (6, 1))
    pulls = np.array([[x, -0.3, z] for z in (0.2, 0.45, 0.7) for x in (-0.15, 0.15)])
    groups = pull_knob_groups(pulls, front, GateConfig())
    assert sorted(sorted(g.tolist()) for g in groups) == [[0, 2, 4], [1, 3, 5]]
    stove_row = np.array([[x, -0.3, 0.8] for x in (-0.3, -0.1, 0.1, 0.3)])
    assert pull_knob_groups(stove_row, front[:4], GateConfig()) == []
    cooktop = np.array([[x, y, 0.9] for x in (-0.2, 0.2) for y in (-0.1, 0.1)])
    assert pull_knob_groups(cooktop, np.tile([0.0, 0.0, 1.0], (4, 1)), GateConfig()) == []


def _part(name, semantic, outward):
    return PartEstimate(semantic, [], np.asarray(outward, float), name=name)


def test_review_demotes_empty_ranges_and_tiny_panels_and_keeps_the_rest():
    parts = [_part("base", "base", [0, 0, 0]), _part("drawer_0", "drawer", [0, -1, 0]),
             _part("drawer_1", "drawer", [0, -1, 0]), _part("door_0", "door", [0, -1, 0])]
    y = np.array([0.0, -1.0, 0.0])
    joints = {"drawer_0": JointEstimate("prismatic", y, np.zeros(3), 0.3, {"rule": "drawer: outward normal"}),
              "drawer_1": JointEstimate("prismatic", y, np.zeros(3), 1e-9, {"rule": "drawer: outward normal"}),
              "door_0": JointEstimate("revolute", np.array([0.0, 0, 1]), np.zeros(3), 1.5, {"rule": "opposite the handle"})}
    extents = {"drawer_0": np.array([0.4, 0.3, 0.2]), "drawer_1": np.array([0.4, 0.3, 0.2]),
               "door_0": np.array([0.02, 0.02, 0.02])}
    caps = {"drawer_0": 0.3, "drawer_1": 0.3, "door_0": np.radians(90)}
    result = review(parts, joints, extents, caps, GateConfig())
    assert result.decision == "articulated"
    assert result.demoted == ["door_0", "drawer_1"]
    assert {f.kind for f in result.findings} == {"zero_travel", "tiny_panel"}
    assert set(result.confidence) == {"drawer_0"} and 0.5 < result.confidence["drawer_0"] <= 1.0


def test_a_drawer_that_draws_out_a_fraction_of_its_box_is_stuck():
    parts = [_part("base", "base", [0, 0, 0]), _part("drawer_0", "drawer", [0, -1, 0]),
             _part("drawer_1", "drawer", [0, -1, 0])]
    y = np.array([0.0, -1.0, 0.0])
    # a box's face with a button's stem through it: 2 cm of a 28 cm box; a real drawer: all of it
    joints = {"drawer_0": JointEstimate("prismatic", y, np.zeros(3), 0.019,
                                        {"rule": "drawer: outward normal", "travel": 0.28, "free": 0.019}),
              "drawer_1": JointEstimate("prismatic", y, np.zeros(3), 0.25,
                                        {"rule": "drawer: outward normal", "travel": 0.25, "free": 0.25})}
    extents = {name: np.array([0.3, 0.3, 0.2]) for name in joints}
    result = review(parts, joints, extents, {name: 0.3 for name in joints}, GateConfig())
    assert result.demoted == ["drawer_0"]
    assert [(f.kind, f.parts) for f in result.findings] == [("stuck", ("drawer_0",))]
    assert "1.9 cm of its 28.0 cm box" in result.findings[0].message


def test_a_panel_that_slides_free_both_ways_is_held_by_nothing():
    parts = [_part("base", "base", [0, 0, 0]), _part("lid_0", "lid", [0, 0, 1]), _part("door_0", "door", [0, -1, 0]),
             _part("door_1", "door", [0, -1, 0])]
    x = np.array([1.0, 0.0, 0.0])
    slides = lambda plus, minus: [{"direction": "u+", "free_m": plus, "width_m": 0.1},  # noqa: E731
                                  {"direction": "u-", "free_m": minus, "width_m": 0.1}]
    # a faucet's handle block on its body; a sliding door stopped by the carcass's side one way;
    # the middle pane of three in a track, free both ways
    joints = {"lid_0": JointEstimate("prismatic", x, np.zeros(3), 0.1, {"rule": "slides", "slides": slides(0.1, 0.1)}),
              "door_0": JointEstimate("prismatic", x, np.zeros(3), 0.094, {"rule": "slides",
                                                                         "slides": slides(0.094, 0.0)}),
              "door_1": JointEstimate("prismatic", x, np.zeros(3), 0.1, {"rule": "slides", "held": ["v-", "v+"],
                                                                       "slides": slides(0.1, 0.1)})}
    extents = {"lid_0": np.array([0.1, 0.1, 0.07]), "door_0": np.array([0.1, 0.02, 0.3]),
               "door_1": np.array([0.1, 0.02, 0.3])}
    result = review(parts, joints, extents, {name: 0.1 for name in joints}, GateConfig())
    assert result.demoted == ["lid_0"]
    assert [(f.kind, f.parts) for f in result.findings] == [("loose_slide", ("lid_0",))]


def test_a_door_is_a_panel_and_a_lever_arm_is_not():
    y = np.array([0.0, -1.0, 0.0])
    slab = trimesh.creation.box([0.4, 0.02, 0.6])
    arm = trimesh.util.concatenate([trimesh.creation.cylinder(0.01, 0.2, sections=24),  # along z
                                    trimesh.creation.icosphere(2, 0.03)])
    config = GateConfig()
    assert facing_share(slab, y, config) > 0.9
    assert facing_share(arm, y, config) < config.min_facing_share
    parts = [_part("base", "base", [0, 0, 0]), _part("door_0", "door", y), _part("door_1", "door", y)]
    joints = {name: JointEstimate("revolute", np.array([0.0, 0, 1]), np.zeros(3), 1.5, {"rule": "opposite the handle"})
              for name in ("door_0", "door_1")}
    extents = {"door_0": slab.extents, "door_1": arm.extents}
    facing = {"door_0": facing_share(slab, y, config), "door_1": facing_share(arm, y, config)}
    result = review(parts, joints, extents, {name: 1.5 for name in joints}, config, facing=facing)
    assert result.demoted == ["door_1"] and [f.kind for f in result.findings] == ["not_a_panel"]


def test_a_panel_closes_its_outline_and_a_table_frame_does_not():
    def box(size, centre):
        return trimesh.creation.box(size).apply_translation(centre)

    y, config = np.array([0.0, -1.0, 0.0]), GateConfig()
    panel = box([0.4, 0.02, 0.6], [0, 0, 0.3])
    framed = trimesh.util.concatenate([box([0.04, 0.02, 0.6], [x, 0, 0.3]) for x in (-0.18, 0.18)]
                                      + [box([0.4, 0.02, 0.04], [0, 0, z]) for z in (0.02, 0.58)])
    pulled = trimesh.util.concatenate([panel, box([0.03, 0.03, 0.2], [0.23, -0.03, 0.3])])  # a grip past its edge
    legs = trimesh.util.concatenate([box([0.04, 0.04, 0.7], [x, 0, 0.35]) for x in (-0.38, 0.38)]
                                    + [box([0.8, 0.02, 0.08], [0, 0, 0.66])])
    assert open_outline_share(panel, y, config) < 0.02
    assert open_outline_share(framed, y, config) < 0.02  # a pane's hole inside a frame is enclosed
    assert open_outline_share(pulled, y, config) < config.max_open_outline
    assert open_outline_share(legs, y, config) > 0.7
    parts = [_part("base", "base", [0, 0, 0]), _part("door_0", "door", y), _part("door_1", "door", y)]
    joints = {name: JointEstimate("revolute", np.array([0.0, 0, 1]), np.zeros(3), 1.5, {"rule": "outer side (no handle)"})
              for name in ("door_0", "door_1")}
    opened = {"door_0": open_outline_share(framed, y, config), "door_1": open_outline_share(legs, y, config)}
    result = review(parts, joints, {"door_0": framed.extents, "door_1": legs.extents}, {n: 1.5 for n in joints},
                    config, open_outline=opened)
    assert result.demoted == ["door_1"] and [f.kind for f in result.findings] == ["open_frame"]


def test_a_flap_hinged_along_its_short_edge_is_no_door():
    parts = [_part("base", "base", [0, 0, 0]), _part("door_0", "door", [0, -1, 0]),
             _part("door_1", "door", [0, -1, 0]), _part("door_2", "door", [0, -1, 0])]
    x, z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    rule = {"rule": "opposite the handle"}
    joints = {"door_0": JointEstimate("revolute", x, np.zeros(3), 1.5, rule),   # a control strip, bottom hinged
              "door_1": JointEstimate("revolute", x, np.zeros(3), 1.5, rule),   # an oven's door
              "door_2": JointEstimate("revolute", z, np.zeros(3), 1.5, rule)}   # a tall door on a side hinge
    extents = {"door_0": np.array([0.14, 0.01, 0.26]), "door_1": np.array([0.55, 0.05, 0.45]),
               "door_2": np.array([0.14, 0.01, 0.26])}
    result = review(parts, joints, extents, {name: 1.5 for name in joints}, GateConfig())
    assert result.demoted == ["door_0"]
    assert [(f.kind, f.parts) for f in result.findings] == [("narrow_flap", ("door_0",))]


def test_a_lid_no_deeper_than_a_strip_is_a_frames_top_bar():
    """Real-like window 436 scanned: its frame's top bar, seen alone from above with a groove
    under its front edge, was read as a lid 1 m wide and 11 cm deep and published. A box's or a
    laptop's cover is at least a third as deep as it is wide."""
    parts = [_part("base", "base", [0, 0, 0]), _part("lid_0", "lid", [0, 0, 1]), _part("lid_1", "lid", [0, 0, 1])]
    x = np.array([1.0, 0.0, 0.0])
    joints = {name: JointEstimate("revolute", x, np.zeros(3), 1.5, {"rule": "lid: back edge"}) for name in ("lid_0", "lid_1")}
    extents = {"lid_0": np.array([0.996, 0.106, 0.048]), "lid_1": np.array([0.6, 0.2, 0.02])}  # a bar, a long box's lid
    result = review(parts, joints, extents, {name: 1.5 for name in joints}, GateConfig())
    assert result.demoted == ["lid_0"] and [(f.kind, f.parts) for f in result.findings] == [("lid_strip", ("lid_0",))]


def test_a_guessed_hinge_side_is_less_confident_than_a_handle():
    config = GateConfig()
    handle = joint_confidence({"rule": "opposite the handle"}, "revolute", 1.5, 1.5, config)
    guess = joint_confidence({"rule": "outer side (no handle)"}, "revolute", 1.5, 1.5, config)
    stuck = joint_confidence({"rule": "opposite the handle"}, "revolute", 0.3, 1.5, config)
    assert guess < stuck < handle


def test_a_hinge_against_its_pairs_slide_stays_below_the_publish_floor():
    """A door of a pair in two tracks that could not slide is hinged with a doubt no handle or
    full opening lifts over the validator's floor; a guessed side does not raise it either."""
    config = GateConfig()
    for rule in ("hinged against its pair: opposite the handle", "hinged against its pair: outer side (no handle)"):
        assert joint_confidence({"rule": rule}, "revolute", 1.5, 1.5, config) < config.min_publish_confidence, rule


def test_a_rigid_object_is_static_and_refused_unless_allowed(tmp_path, config):
    box = trimesh.creation.box([0.5, 0.4, 0.8])
    box.apply_translation([0, 0, 0.4])
    path = tmp_path / "block.obj"
    box.export(path)
    asset = reconstruct_mesh(load_mesh(path), config)
    assert asset.metadata["gate"]["decision"] == "static" and not asset.movable_joints
    complete_asset(asset, config)
    (tmp_path / "out").mkdir()
    write_asset(asset, tmp_path / "out", "block", config.export, np.array([0.0, 0.0, 1.0]))
    report = validate_folder(tmp_path / "out", "block", config)
    assert report.decision.status == "reject"
    assert any(r.check == "structure" and "static" in r.message for r in report.decision.reasons)
    allowed = dataclasses.replace(config, gate=dataclasses.replace(config.gate, allow_static=True))
    report = validate_folder(tmp_path / "out", "block", allowed)
    structure = next(f for f in report.findings if f.check == "structure")
    assert structure.ok and report.decision.status == "publish"


def test_a_keypad_is_not_a_column_of_drawer_pulls():
    front = np.tile([0.0, -1.0, 0.0], (9, 1))
    keys = np.array([[x, -0.1, z] for z in (0.10, 0.13, 0.16) for x in (-0.03, 0.0, 0.03)])
    assert pull_knob_groups(keys, front, GateConfig()) == []


def test_a_part_as_large_as_the_object_is_the_carcass():
    parts = [_part("base", "base", [0, 0, 0]), _part("door_0", "door", [0, -1, 0]), _part("door_1", "door", [0, -1, 0])]
    z = np.array([0.0, 0.0, 1.0])
    joints = {n: JointEstimate("revolute", z, np.zeros(3), 1.5, {"rule": "opposite the handle"}) for n in ("door_0", "door_1")}
    extents = {"base": np.array([1.0, 0.6, 1.9]), "door_0": np.array([0.5, 0.05, 1.85]),
               "door_1": np.array([1.0, 0.55, 1.9])}
    result = review(parts, joints, extents, {"door_0": 1.5, "door_1": 1.5}, GateConfig())
    assert result.demoted == ["door_1"] and result.findings[0].kind == "carcass_sized"


def test_a_doubtful_joint_is_not_published():
    """A hinge side guessed for a door that then opens a fifth of its range: the structure
    check rejects it; a handle-side door passes."""
    from rest2art.validators.static_checks import check_structure

    config = GateConfig()
    guessed = joint_confidence({"rule": "outer side (no handle)"}, "revolute", 0.3, 1.5, config)
    handled = joint_confidence({"rule": "opposite the handle"}, "revolute", 1.5, 1.5, config)
    assert guessed < config.min_publish_confidence <= handled
    bad = check_structure(1, {"confidence": {"door_0": guessed}}, False, config.min_publish_confidence)
    good = check_structure(1, {"confidence": {"door_0": handled}}, False, config.min_publish_confidence)
    assert not bad.ok and "door_0" in bad.message and good.ok


def _with_plate(tmp_path, seed: int = 0):
    """A generated microwave with a separate trim plate floating 6 mm in front of the solid
    control panel beside its door (as real models carry one): the plate opens onto nothing."""
    from rest2art.generate import generate_object, write_mesh_obj

    obj = generate_object("microwave", seed)
    p = obj.spec.params
    door = obj.asset.part("door_0").mesh.bounds
    lo = [door[1, 0] + 0.008, -p["depth"] / 2 - 0.010, 0.01]
    hi = [p["width"] / 2 - 0.004, -p["depth"] / 2 - 0.006, p["height"] - 0.01]
    plate = trimesh.creation.box(bounds=[lo, hi])
    mesh = trimesh.util.concatenate([obj.mesh, plate])
    pieces = [*obj.piece_faces, ("plate", len(obj.mesh.faces), len(mesh.faces))]
    path = tmp_path / "microwave_plate.obj"
    write_mesh_obj(mesh, pieces, path, "microwave with a control plate")
    return path


def test_a_plate_on_solid_carcass_is_a_facade_not_a_door(tmp_path, config):
    path = _with_plate(tmp_path)
    asset = reconstruct_mesh(load_mesh(path), config)
    assert [j.child for j in asset.movable_joints] == ["door_0"]
    findings = asset.metadata["gate"]["findings"]
    assert any(f["kind"] == "no_opening" for f in findings), findings
    # without the room test (and the side panel rule, which finds the same plate bare and
    # stepped behind the door) the plate is published as a second door: the case this guards
    lax = dataclasses.replace(config, gate=dataclasses.replace(config.gate, min_open_share=0.0,
                                                               side_panel_max_share=0.0, side_panel_narrow_share=0.0))
    assert len(reconstruct_mesh(load_mesh(path), lax).movable_joints) == 2


def test_room_behind_a_door_and_a_plate():
    """Rays through a door over a cavity find room; through a plate on a block they do not."""
    config = GateConfig()
    front = np.array([0.0, -1.0, 0.0])
    shell = trimesh.creation.box(bounds=[[-0.3, 0.0, 0.0], [0.3, 0.4, 0.02]])  # only a floor and a back
    back = trimesh.creation.box(bounds=[[-0.3, 0.38, 0.0], [0.3, 0.4, 0.5]])
    cavity = trimesh.util.concatenate([shell, back])
    door = trimesh.creation.box(bounds=[[-0.3, -0.02, 0.02], [0.3, 0.0, 0.5]]).vertices
    assert open_share_behind(door, front, cavity, 0.42, config) > 0.8
    block = trimesh.creation.box(bounds=[[-0.3, 0.0, 0.0], [0.3, 0.4, 0.5]])
    assert open_share_behind(door, front, block, 0.42, config) == 0.0


def test_a_panel_standing_free_has_nothing_to_draw_out_of():
    """A drawer front over its cabinet has the cabinet behind all of its face; a screen standing
    on a keyboard plate, facing the keyboard, has nothing behind it: as a drawer it is demoted."""
    config = GateConfig()
    front = np.array([0.0, -1.0, 0.0])
    cabinet = _box([-0.3, 0.0, 0.0], [0.3, 0.4, 0.5])
    drawer = _box([-0.25, -0.02, 0.3], [0.25, 0.0, 0.45]).vertices
    assert backed_share(drawer, front, cabinet, config) == 1.0
    plate = _box([-0.15, -0.25, 0.0], [0.15, 0.0, 0.02])
    screen = _box([-0.15, 0.0, 0.02], [0.15, 0.01, 0.25]).vertices  # faces -y, over the plate's back edge
    assert backed_share(screen, front, plate, config) == 0.0
    parts = [_part("base", "base", [0, 0, 0]), _part("drawer_0", "drawer", front)]
    joints = {"drawer_0": JointEstimate("prismatic", front, np.zeros(3), 0.2, {"rule": "drawer: outward normal"})}
    extents = {"base": np.array([0.3, 0.26, 0.25]), "drawer_0": np.array([0.3, 0.01, 0.23])}
    result = review(parts, joints, extents, {}, config, backed={"drawer_0": 0.0})
    assert result.demoted == ["drawer_0"] and result.findings[0].kind == "unbacked"
    assert review(parts, joints, extents, {}, config, backed={"drawer_0": 1.0}).demoted == []


def test_a_scanned_open_laptop_screen_is_no_drawer(tmp_path, config):
    """Real-like open laptop 38, scanned, its screen standing upright (3 degrees back) facing the
    keyboard: the views cut the screen out as a drawer front, which drew out 22 cm into the air
    and was published. With nothing behind the screen it is no drawer."""
    from rest2art.generate import generate_mix_object, write_mesh_obj

    obj = generate_mix_object("real-like", 38, "scan")
    path = tmp_path / "open_laptop.obj"
    write_mesh_obj(obj.mesh, obj.piece_faces, path, "open laptop")
    asset = reconstruct_mesh(load_mesh(path), config)
    assert all(j.type != "prismatic" for j in asset.movable_joints), [(j.child, j.type) for j in asset.movable_joints]
    # without the check the screen draws out as a drawer: the case this guards (with no room
    # closing it at the back, nor does the board-over-open-space check ``open_below`` ask)
    lax = dataclasses.replace(config, gate=dataclasses.replace(config.gate, min_backed_share=0.0,
                                                               open_below_min_share=1.01))
    assert [j.type for j in reconstruct_mesh(load_mesh(path), lax).movable_joints] == ["prismatic"]


def test_a_control_at_the_floor_is_a_foot():
    parts = [_part("base", "base", [0, 0, 0]), _part("knob_0", "knob", [0, 0, 1]), _part("knob_1", "knob", [0, -1, 0])]
    joints = {n: JointEstimate("revolute", np.array([0.0, 0, 1]), np.zeros(3), 4.7, {"rule": "knob"})
              for n in ("knob_0", "knob_1")}
    extents = {"base": np.array([0.3, 0.4, 0.25]), "knob_0": np.array([0.015, 0.015, 0.007]),
               "knob_1": np.array([0.03, 0.02, 0.03])}
    result = review(parts, joints, extents, {}, GateConfig(), floor_heights={"knob_0": 0.011, "knob_1": 0.15})
    assert result.demoted == ["knob_0"] and result.findings[0].kind == "floor_control"


def test_the_part_an_open_laptop_stands_on_is_its_base():
    """The segmentation of a laptop standing open can take the keyboard's top for a lid hinged on
    its back edge, leaving the bottom plate and the screen as the base. The keyboard holds the
    floor: it becomes the base, and the screen closes forward about the same hinge."""
    from rest2art.config import Config
    from rest2art.generate import generate_object
    from rest2art.generate.variation import Variation
    from rest2art.geometry.basics import axis_angle_deg
    from rest2art.parts.pieces import split_pieces
    from rest2art.pipeline import stand_on_support

    for seed in range(3):
        obj = generate_object("open_laptop", seed, "asset", variation=Variation(primitives=True))
        component = np.concatenate([np.full(end - start, k) for k, (_, start, end) in enumerate(obj.piece_faces)])
        pieces = split_pieces(np.asarray(obj.mesh.vertices), np.asarray(obj.mesh.faces), component)
        names = [name for name, _, _ in obj.piece_faces]
        plate, top = (names.index(n) for n in names if n.startswith("base"))
        screen = [k for k, n in enumerate(names) if not n.startswith("base")]
        lid = PartEstimate("lid", [top], np.array([0.0, 0.0, 1.0]), top, name="lid_0")
        parts = [PartEstimate("base", [plate, *screen], name="base"), lid]
        back_bottom = np.array([0.0, pieces[top].hi[1], 0.0])
        joints = {"lid_0": JointEstimate("revolute", np.array([-1.0, 0.0, 0.0]), back_bottom, 0.5,
                                         {"rule": "lid: back edge"})}
        finding = stand_on_support(parts, pieces, joints, "cabinet", Config())
        assert finding is not None and finding.kind == "support" and finding.action == "swapped"
        assert sorted(parts[0].pieces) == sorted([plate, top]) and sorted(parts[1].pieces) == sorted(screen)
        truth = obj.asset.joint_for("lid_0")
        joint = joints["lid_0"]
        assert axis_angle_deg(joint.axis, truth.axis) < 1e-6 and joint.axis @ truth.axis > 0  # closes forward
        offset = joint.origin - truth.origin
        assert np.linalg.norm(offset - (offset @ truth.axis) * truth.axis) < 0.03
        assert joint.upper > np.radians(80.0)
        # a lid that holds no floor (a box's lid on top) is left as it is
        assert stand_on_support([PartEstimate("base", [top, plate], name="base"),
                                 PartEstimate("lid", screen, np.array([0.0, 0.0, 1.0]), screen[0], name="lid_0")],
                                pieces, dict(joints), "cabinet", Config()) is None


def _box(lo, hi):
    return trimesh.creation.box(bounds=[lo, hi])


def _write_groups(groups: dict[str, list], path):
    """Write named groups of meshes as one OBJ with one object per mesh."""
    from rest2art.generate import write_mesh_obj

    meshes = [m for boxes in groups.values() for m in boxes]
    names = [f"{name}{k}" for name, boxes in groups.items() for k in range(len(boxes))]
    ends = np.cumsum([len(m.faces) for m in meshes])
    pieces = [(name, int(end - len(m.faces)), int(end)) for name, m, end in zip(names, meshes, ends)]
    write_mesh_obj(trimesh.util.concatenate(meshes), pieces, path, path.stem)
    return path


def test_a_frame_holding_panels_is_no_panel():
    """A window's casing found as a movable part holds its sashes in its own box; a door does
    not hold the knob mounted on it, nor a drawer beside it."""
    lo = np.array([[-0.2, 0.74, 0.0], [-0.15, 0.8, 0.25], [-0.15, 0.775, 0.05], [0.3, 0.74, 0.0], [0.35, 0.73, 0.2]])
    hi = np.array([[0.2, 0.86, 0.48], [0.15, 0.824, 0.45], [0.15, 0.8, 0.25], [0.6, 0.86, 0.48], [0.38, 0.75, 0.23]])
    assert enclosing_frames(lo, hi, [None, None, None, None, None], 0.002) == [0]
    assert enclosing_frames(lo[3:], hi[3:], [None, None], 0.002) == []
    inside = np.array([[0.35, 0.75, 0.2]]), np.array([[0.38, 0.8, 0.23]])  # a knob sunk into the door
    assert enclosing_frames(np.vstack([lo[3:4], inside[0]]), np.vstack([hi[3:4], inside[1]]), [None, 0], 0.002) == []


def test_panes_meet_behind_one_another_only_one_way():
    config = JointsConfig()
    front = np.array([-0.2, 0.775, 0.05]), np.array([0.0, 0.799, 0.35])
    back = np.array([0.0, 0.801, 0.05]), np.array([0.2, 0.825, 0.35])
    out = np.array([0.0, -1.0, 0.0])
    assert pane_behind(*front, out, *back, config) == "u-"  # -y front: u runs towards -x
    assert pane_behind(*back, out, *front, config) is None  # the front one is not behind
    far = back[0] + [0.0, 0.03, 0.0], back[1] + [0.0, 0.03, 0.0]
    assert pane_behind(*front, out, *far, config) is None  # a plane well behind: not its track
    short = back[0] + [0.0, 0.0, 0.2], back[1]
    assert pane_behind(*front, out, *short, config) is None  # meets along a third of the edge


def test_a_sash_slides_over_the_fixed_pane_behind_it(tmp_path, config):
    """A window without grooves (as simulation models draw one): a casing, a front sash with a
    pull and a pane behind it. The front sash slides up over the pane; the pane stays."""
    groups = {"casing": [_box([-0.2, 0, 0], [-0.17, 0.06, 0.5]), _box([0.17, 0, 0], [0.2, 0.06, 0.5]),
                         _box([-0.17, 0, 0], [0.17, 0.06, 0.03]), _box([-0.17, 0, 0.47], [0.17, 0.06, 0.5])],
              "sash": [_box([-0.169, 0.01, 0.031], [0.169, 0.03, 0.25]), _box([-0.05, -0.02, 0.05], [0.05, 0.01, 0.07])],
              "pane": [_box([-0.169, 0.031, 0.25], [0.169, 0.051, 0.469])]}
    path = _write_groups(groups, tmp_path / "window.obj")
    asset = reconstruct_mesh(load_mesh(path), config)
    [joint] = asset.movable_joints
    assert joint.type == "prismatic" and np.allclose(joint.axis, [0, 0, 1])
    assert joint.limit[1] == pytest.approx(0.219, abs=0.005)
    assert asset.part(joint.child).mesh.bounds[0, 1] == pytest.approx(-0.02)  # the sash with its pull
    assert [f["kind"] for f in asset.metadata["gate"]["findings"]] == ["fixed_pane"]
    # a pane with a pull of its own is moved by hand: both stay parts
    groups["pane"].append(_box([-0.02, 0.011, 0.4], [0.02, 0.031, 0.42]))
    pulled = _write_groups(groups, tmp_path / "window_pulled.obj")
    assert len(reconstruct_mesh(load_mesh(pulled), config).movable_joints) == 2
    # without the rule (nor the bypass rule, which slides both) both panes turn on hinges
    lax = dataclasses.replace(config, joints=dataclasses.replace(config.joints, pane_gap=-1.0, bypass_min_step=1.0))
    assert {j.type for j in reconstruct_mesh(load_mesh(path), lax).movable_joints} == {"revolute"}


def test_a_demoted_face_leaves_the_stem_it_held_to_the_button_on_it():
    """A box's face with a button's stem through it, cut out as a drawer with the stem as its
    fitting, and the button's cap a piece of its own 4 mm off the stem's end: when the gate
    demotes the face, the stem goes with the cap; the face goes to the base."""
    from rest2art.parts.pieces import make_piece
    from rest2art.pipeline import demote

    face = trimesh.creation.box([0.2, 0.01, 0.2])
    stem = trimesh.creation.cylinder(0.01, 0.06, transform=trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    stem.apply_translation([0.0, -0.035, 0.0])
    cap = trimesh.creation.cylinder(0.03, 0.02, transform=trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    cap.apply_translation([0.0, -0.079, 0.0])
    far = trimesh.creation.box([0.02, 0.02, 0.02])
    far.apply_translation([0.08, -0.03, 0.08])  # a fitting of the face that holds no control
    scene = trimesh.util.concatenate([face, stem, cap, far])
    counts = np.cumsum([0, len(face.faces), len(stem.faces), len(cap.faces), len(far.faces)])
    pieces = [make_piece(k, np.arange(counts[k], counts[k + 1]), scene.vertices, scene.faces) for k in range(4)]
    base = PartEstimate("base", [], name="base")
    drawer = PartEstimate("drawer", [0, 1, 3], np.array([0.0, -1.0, 0.0]), 0, "drawer_0", {"fittings": [1, 3]})
    button = PartEstimate("button", [2], np.array([0.0, -1.0, 0.0]), 2, "button_0")
    kept = demote([base, drawer, button], ["drawer_0"], pieces, GateConfig().fitting_reach)
    assert [p.name for p in kept] == ["base", "button_0"]
    assert sorted(kept[1].pieces) == [1, 2] and sorted(kept[0].pieces) == [0, 3]


def test_doors_stepped_apart_slide_past_each_other_and_a_glass_door_beside_a_thick_one_does_not():
    """Two doors meeting along an edge run in two tracks when one stands a door's thickness in
    front of the other, fronts and backs; a glass door beside a thicker one, both on one carcass
    front, steps only in front: both hinge. Side by side in one plane: both hinge."""
    from rest2art.joints.rules import bypass_pairs
    from rest2art.parts.pieces import make_piece

    def pair(a_front_y: float, a_depth: float, b_front_y: float, b_depth: float) -> dict[str, str]:
        a = _box([-0.4, a_front_y, 0.0], [0.01, a_front_y + a_depth, 0.8])  # a overlaps b by 1 cm
        b = _box([0.0, b_front_y, 0.0], [0.4, b_front_y + b_depth, 0.8])
        scene = trimesh.util.concatenate([a, b])
        pieces = [make_piece(k, np.arange(12 * k, 12 * k + 12), scene.vertices, scene.faces) for k in range(2)]
        y = np.array([0.0, -1.0, 0.0])
        parts = [PartEstimate("door", [k], y, k, name=f"door_{k}") for k in range(2)]
        return bypass_pairs(parts, pieces, JointsConfig())

    assert pair(-0.04, 0.02, -0.02, 0.02) == {"door_0": "u-", "door_1": "u+"}  # u runs to -x facing -y
    assert pair(-0.025, 0.005, -0.04, 0.02) == {}  # a 5 mm glass door beside a 20 mm one, backs at -0.02
    assert pair(-0.02, 0.02, -0.02, 0.02) == {}


def test_a_bare_narrow_panel_behind_a_doors_face_is_the_carcass_beside_it():
    """A microwave's control panel (12 cm, 6 cm behind its door's face; or level with it and a
    quarter of its width) beside the door is no door; French doors' passive leaf (as wide, one
    plane), a leaf half as wide in the same plane and a bare door across the room from the
    handled one are."""
    config = GateConfig()
    door = (np.array([[-0.3, 0.0], [0.17, 0.28]]), 0.247)
    panel = (np.array([[0.173, 0.0], [0.3, 0.27]]), 0.182)
    assert panel_beside_door(panel, door, config)
    assert panel_beside_door((panel[0], 0.242), door, config)  # level with the door, 13 of 47 cm
    leaf = (np.array([[0.175, 0.0], [0.6, 0.28]]), 0.247)
    assert not panel_beside_door(leaf, door, config)
    half = (np.array([[0.175, 0.0], [0.4, 0.28]]), 0.245)
    assert not panel_beside_door(half, door, config)
    apart = (panel[0] + [[0.2, 0.0], [0.2, 0.0]], 0.182)
    assert not panel_beside_door(apart, door, config)
    below = (panel[0] + [[0.0, 0.3], [0.0, 0.3]], 0.182)
    assert not panel_beside_door(below, door, config)


def test_what_lies_in_front_below_a_front_tells_an_apron_board_from_a_drawer_in_a_stack():
    """Rays cast inward from under a front's bottom edge: under a desk's apron board they run
    into the knee room, under a drawer in a stack they meet the next drawer's face."""
    config = GateConfig()
    board = trimesh.creation.box((0.4, 0.02, 0.1))
    board.apply_translation([0.0, -0.29, 0.7])  # its face at y = -0.3, its bottom at z = 0.65
    back = trimesh.creation.box((1.0, 0.02, 0.75))
    back.apply_translation([0.0, 0.29, 0.375])  # the desk's back panel, 60 cm behind
    lower = trimesh.creation.box((0.4, 0.02, 0.1))
    lower.apply_translation([0.0, -0.29, 0.59])  # the next drawer, 1 cm under the board
    outward = np.array([0.0, -1.0, 0.0])
    assert open_front_below(board.vertices, outward, back, config) == 1.0
    assert open_front_below(board.vertices, outward, trimesh.util.concatenate([back, lower]), config) == 0.0
    # a front down to the object's bottom (a microwave's door, a stack's lowest drawer): the rays
    # pass under the object, which says nothing of knee room
    door = trimesh.creation.box((0.4, 0.02, 0.3))
    door.apply_translation([0.0, -0.29, 0.16])  # its bottom 1 cm over the object's, at z = 0
    assert open_front_below(door.vertices, outward, trimesh.util.concatenate([door, back]), config) == 0.0
