"""Importers on small hand-written models with known answers (no downloads)."""

import numpy as np
import pytest
import trimesh

from rest2art.bench.importers import ImportConfig, import_mjcf, import_urdf, prune_parts
from rest2art.bench.metrics import score_object, summarize
from rest2art.errors import InputError
from rest2art.generate.scan import fuse_meshes

CABINET_MJCF = """
<mujoco model="cab">
  <compiler angle="radian"/>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <body name="loose"><freejoint/><geom type="sphere" size="0.05" pos="1 1 1"/></body>
    <body name="carcass" pos="0 0 0.4">
      <geom type="box" size="0.3 0.2 0.4" contype="0" conaffinity="0"/>
      <geom type="box" size="0.3 0.2 0.4" group="3"/>
      <body name="trim" pos="0 0 0.42"><geom type="box" size="0.3 0.2 0.02" contype="0" conaffinity="0"/></body>
      <body name="door" pos="-0.3 -0.21 0">
        <joint name="hinge" type="hinge" axis="0 0 1" range="-1.5 0"/>
        <geom type="box" size="0.3 0.01 0.38" pos="0.3 0 0" contype="0" conaffinity="0"/>
        <body name="handle" pos="0.55 -0.03 0"><geom type="capsule" size="0.01 0.1" contype="0" conaffinity="0"/></body>
      </body>
      <body name="drawer" pos="0 -0.2 -0.3">
        <joint name="slide" type="slide" axis="0 1 0" range="-0.3 0"/>
        <geom type="box" size="0.25 0.15 0.05" pos="0 0.15 0" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture()
def cabinet(tmp_path):
    path = tmp_path / "cab.xml"
    path.write_text(CABINET_MJCF)
    return import_mjcf(path)


def test_mjcf_parts_and_merging(cabinet):
    names = [p.name for p in cabinet.asset.parts]
    assert names == ["base", "door", "drawer"]  # handle merged into door, trim into base; floor and loose ball dropped
    labels = np.bincount(cabinet.face_part)
    assert len(labels) == 3 and labels.min() > 0
    # visual geoms only: the carcass box once, not its collision twin
    assert len(cabinet.piece_faces) == 5
    assert cabinet.mesh.bounds[1][2] == pytest.approx(0.84)


def test_mjcf_axes_open_positive(cabinet):
    door = cabinet.asset.joint_for("door")
    drawer = cabinet.asset.joint_for("drawer")
    # ranges [-1.5, 0] and [-0.3, 0] with rest 0: opening is negative, so axes are negated
    assert np.allclose(door.axis, [0, 0, -1]) and door.limit == pytest.approx((0.0, 1.5))
    assert np.allclose(drawer.axis, [0, -1, 0]) and drawer.limit == pytest.approx((0.0, 0.3))
    assert np.allclose(door.origin, [-0.3, -0.21, 0.4])
    # opening moves the door's free edge out of the front (-y)
    mesh = cabinet.asset.part("door").mesh
    T = door.transform(0.5)
    moved = mesh.vertices @ T[:3, :3].T + T[:3, 3]
    assert moved[:, 1].min() < mesh.vertices[:, 1].min() - 0.1


def test_ground_truth_scores_perfectly_against_itself(cabinet):
    s = summarize([score_object(cabinet.asset, cabinet.asset, cabinet.mesh.area_faces)])
    assert (s["type_accuracy_pct"], s["axis_angle_deg"], s["axis_pos_dm"], s["miou"], s["part_count_pct"]) == \
        (100.0, 0.0, 0.0, 1.0, 100.0)


def test_mjcf_without_joints_is_refused(tmp_path):
    path = tmp_path / "static.xml"
    path.write_text("<mujoco><worldbody><body><geom type='box' size='.1 .1 .1'/></body></worldbody></mujoco>")
    with pytest.raises(InputError, match="no hinge or slide joint"):
        import_mjcf(path)
    bad = tmp_path / "bad.xml"
    bad.write_text("<mujoco><worldbody><body><geom type='mesh' mesh='nope'/></body></worldbody></mujoco>")
    with pytest.raises(InputError, match="bad.xml: MuJoCo could not compile it"):
        import_mjcf(bad)


URDF = """<robot name="r">
  <link name="base"><visual><geometry><box size="0.6 0.4 0.8"/></geometry></visual></link>
  <link name="top"><visual><geometry><box size="0.6 0.4 0.02"/></geometry></visual></link>
  <link name="door"><visual><origin xyz="0.3 0 0"/><geometry><box size="0.6 0.02 0.7"/></geometry></visual></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="top"/><origin xyz="0 0 0.41"/></joint>
  <joint name="door_joint" type="revolute"><parent link="base"/><child link="door"/>
    <origin xyz="-0.3 -0.21 0"/><axis xyz="0 0 1"/><limit lower="-1.2" upper="0" effort="1" velocity="1"/></joint>
</robot>"""


def test_urdf_import(tmp_path):
    path = tmp_path / "mobility.urdf"
    path.write_text(URDF)
    obj = import_urdf(path)
    assert [p.name for p in obj.asset.parts] == ["base", "door"]
    joint = obj.asset.joint_for("door")
    assert np.allclose(joint.axis, [0, 0, -1]) and joint.limit == pytest.approx((0.0, 1.2))
    assert np.allclose(joint.origin, [-0.3, -0.21, 0.0])
    assert np.bincount(obj.face_part).tolist() == [24, 12]  # base + fixed top, door


def test_fuse_closes_a_thin_gap_and_keeps_labels():
    a = trimesh.creation.box([0.4, 0.3, 0.4])
    b = trimesh.creation.box([0.36, 0.02, 0.36])
    b.apply_translation([0, -0.15 - 0.003 - 0.01, 0])  # a door 3 mm in front of a carcass
    mesh, labels = fuse_meshes([a, b], voxel=0.004, offset=0.003)
    assert mesh.body_count == 1
    assert set(np.unique(labels)) == {0, 1}
    front = mesh.triangles_center[:, 1] < -0.17
    assert (labels[front] == 1).mean() > 0.9


def test_fuse_keeps_only_what_a_camera_outside_sees():
    # a carcass of thin walls with no front, a door 3 mm in front of it: the walls' inner
    # surfaces and the door's back join the fused outer shell, and no camera outside sees them
    walls = [([0.4, 0.02, 0.4], [0, 0.14, 0]), ([0.02, 0.3, 0.4], [-0.19, 0, 0]), ([0.02, 0.3, 0.4], [0.19, 0, 0]),
             ([0.4, 0.3, 0.02], [0, 0, 0.19]), ([0.4, 0.3, 0.02], [0, 0, -0.19])]
    carcass = trimesh.util.concatenate([trimesh.creation.box(size, trimesh.transformations.translation_matrix(at))
                                        for size, at in walls])
    door = trimesh.creation.box([0.38, 0.02, 0.4], trimesh.transformations.translation_matrix([-0.01, -0.163, 0]))
    whole, _ = fuse_meshes([carcass, door], voxel=0.006, offset=0.004, outside_views=0)
    seen, labels = fuse_meshes([carcass, door], voxel=0.006, offset=0.004)

    def inner_area(mesh):
        inside = np.all(np.abs(mesh.triangles_center - [0, -0.005, 0]) < [0.178, 0.135, 0.178], axis=1)
        return mesh.area_faces[inside].sum()

    def door_back(mesh):
        return (np.abs(mesh.triangles_center[:, 1] + 0.149) < 0.004) & (mesh.face_normals[:, 1] > 0.9)

    assert inner_area(whole) > 0.4 and door_back(whole).sum() > 1000
    assert inner_area(seen) == 0 and not door_back(seen).any()
    assert np.allclose(seen.bounds, whole.bounds)  # the outside is all there
    front = seen.triangles_center[:, 1] < -0.172
    assert (labels[front] == 1).mean() > 0.9


NESTED_MJCF = """
<mujoco model="safe">
  <compiler angle="radian"/>
  <worldbody>
    <body name="carcass">
      <geom type="box" size="0.3 0.2 0.4" pos="0 0 0.4"/>
      <body name="door" pos="0.3 -0.21 0.4">
        <joint name="door_hinge" type="hinge" axis="0 0 1" range="0 1.5"/>
        <geom type="box" size="0.3 0.01 0.38" pos="-0.3 0 0"/>
        <body name="latch" pos="-0.5 -0.02 0">
          <joint name="latch_hinge" type="hinge" axis="0 1 0" range="0 1.2"/>
          <geom type="box" size="0.06 0.01 0.015"/>
        </body>
      </body>
      <body name="rail" pos="0 0.2 0.8">
        <joint name="rail_slide" type="slide" axis="1 0 0" range="0 0.2"/>
        <inertial pos="0 0 0" mass="0.1" diaginertia="0.001 0.001 0.001"/>
        <body name="flap lid">
          <joint name="flap_hinge" type="hinge" axis="1 0 0" range="-1 0"/>
          <geom type="box" size="0.25 0.15 0.01" pos="0 -0.15 0.01"/>
        </body>
      </body>
      <body name="screw" pos="0.2 -0.2 0.1">
        <joint name="screw_turn" type="hinge" axis="0 1 0"/>
        <geom type="sphere" size="0.004"/>
      </body>
      <body name="stuck" pos="-0.2 -0.2 0.1">
        <joint name="stuck_slide" type="slide" axis="0 -1 0" range="0 0.0005"/>
        <geom type="box" size="0.05 0.01 0.05"/>
        <body name="stuck_knob" pos="0 -0.02 0">
          <joint name="knob_turn" type="hinge" axis="0 1 0" range="0 3"/>
          <geom type="cylinder" size="0.03 0.01" euler="1.57 0 0" pos="0.02 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture()
def nested(tmp_path):
    path = tmp_path / "safe.xml"
    path.write_text(NESTED_MJCF)
    return import_mjcf(path)


def test_mjcf_nesting_and_joints_without_geometry(nested):
    asset = nested.asset
    parents = {p.name: p.parent for p in asset.parts}
    # the latch stays on the door; the rail has no geometry: its joint is dropped and the flap
    # (its name made file-safe) hangs on the carcass
    assert parents == {"base": None, "door": "base", "latch": "door", "flap_lid": "base", "screw": "base",
                       "stuck": "base", "stuck_knob": "stuck"}
    assert asset.joint_for("latch").parent == "door"
    flap = asset.joint_for("flap_lid")
    assert flap.limit == pytest.approx((0.0, 1.0)) and np.allclose(flap.axis, [-1, 0, 0])


def test_prune_merges_parts_too_small_or_that_barely_move(nested):
    pruned, reasons = prune_parts(nested, ImportConfig())
    names = [p.name for p in pruned.asset.parts]
    assert names == ["base", "door", "latch", "flap_lid", "stuck_knob"]
    assert any(r.startswith("screw: too small") for r in reasons)
    assert any(r.startswith("stuck: barely moves (0.50 mm") for r in reasons)
    # the knob on the stuck slide keeps its joint and now hangs on the base, which took the slide's faces
    assert pruned.asset.part("stuck_knob").parent == "base" == pruned.asset.joint_for("stuck_knob").parent
    before = np.bincount(nested.face_part, minlength=len(nested.asset.parts))
    after = np.bincount(pruned.face_part, minlength=len(pruned.asset.parts))
    old = {p.name: k for k, p in enumerate(nested.asset.parts)}
    assert after[0] == before[0] + before[old["screw"]] + before[old["stuck"]]
    assert pruned.asset.metadata["merged_parts"] == reasons
    assert prune_parts(pruned)[1] == []  # nothing left to merge


PARTNET_URDF = """<robot name="bottle">
  <link name="base"/>
  <link name="body"><visual><geometry><cylinder radius="0.05" length="0.2"/></geometry></visual></link>
  <link name="cap_helper"/>
  <link name="cap"><visual><origin xyz="0 0 0.11"/><geometry><cylinder radius="0.02" length="0.03"/></geometry></visual></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="body"/><origin xyz="0 0 0.1"/></joint>
  <joint name="lift" type="prismatic"><parent link="body"/><child link="cap_helper"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.05"/></joint>
  <joint name="turn" type="continuous"><parent link="cap_helper"/><child link="cap"/><axis xyz="0 0 1"/></joint>
</robot>"""


def test_urdf_helper_link_without_geometry_is_dropped(tmp_path):
    path = tmp_path / "mobility.urdf"
    path.write_text(PARTNET_URDF)
    obj = import_urdf(path)
    assert [(p.name, p.parent) for p in obj.asset.parts] == [("base", None), ("cap", "base")]
    joint = obj.asset.joint_for("cap")
    assert joint.type == "revolute" and joint.limit == pytest.approx((0.0, np.pi))  # continuous: a half turn each way
    assert np.allclose(np.abs(joint.axis), [0, 0, 1]) and np.allclose(joint.origin, [0, 0, 0.1])
    assert set(np.unique(obj.face_part)) == {0, 1}


def test_wrapper_loads_a_model_whose_fixed_frame_is_a_body_of_its_own(tmp_path):
    from rest2art.bench.devset import Wrapper

    (tmp_path / "desk_body.xml").write_text("""<mujocoinclude>
      <body name="desk"><geom type="box" size="0.5 0.3 0.02" pos="0 0 0.7"/></body>
      <body name="drawer" pos="0 -0.3 0.6"><joint type="slide" axis="0 1 0" range="-0.3 0"/>
        <geom type="box" size="0.2 0.25 0.05" pos="0 0.25 0"/></body>
    </mujocoinclude>""")
    for one_body, base_faces in ((False, 0), (True, 12)):
        path = tmp_path / f"desk_{one_body}.xml"
        path.write_text(Wrapper('angle="radian"', (), ("desk_body.xml",), one_body).text("desk"))
        obj = import_mjcf(path)
        assert int((obj.face_part == 0).sum()) == base_faces  # alone, the desk is a top-level body with no joint
        assert obj.asset.joint_for("drawer").limit == pytest.approx((0.0, 0.3))
