"""Importers on small hand-written models with known answers (no downloads)."""

import numpy as np
import pytest
import trimesh

from rest2art.bench.importers import import_mjcf, import_urdf
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
