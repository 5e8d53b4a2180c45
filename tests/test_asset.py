import json

import numpy as np
import pytest
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, MassProperties, Part, read_articulation, write_articulation
from rest2art.errors import InputError


def _asset() -> ArticulatedAsset:
    base = trimesh.creation.box([1, 0.5, 1])
    drawer = trimesh.creation.box([0.4, 0.02, 0.2])
    drawer.apply_translation([0, -0.3, 0.3])
    return ArticulatedAsset(
        [Part("base", "base", None, base), Part("drawer_0", "drawer", "base", drawer)],
        [Joint("drawer_0_joint", "prismatic", "base", "drawer_0", [0, -2, 0], [0.0, -0.3, 0.3], (0.0, 0.25))],
        np.array([0] * len(base.faces) + [1] * len(drawer.faces), np.int32),
        {"note": "test"},
    )


def test_round_trip(tmp_path):
    asset = _asset()
    write_articulation(asset, tmp_path)
    data = json.loads((tmp_path / "articulation.json").read_text())
    assert data["format"] == "rest2art/1" and data["units"] == "m" and data["frame"] == "input"
    assert data["joints"][0]["axis"] == [0.0, -1.0, 0.0]  # normalised
    assert data["parts"][1] == {"name": "drawer_0", "semantic": "drawer", "parent": "base", "mesh": "parts/drawer_0.obj"}
    back = read_articulation(tmp_path)
    assert [p.name for p in back.parts] == ["base", "drawer_0"]
    assert np.array_equal(back.face_part, asset.face_part)
    assert back.joints[0].limit == (0.0, 0.25)
    assert np.allclose(back.part("drawer_0").mesh.bounds, asset.part("drawer_0").mesh.bounds)
    assert back.metadata == {"note": "test"}


def test_mass_properties_round_trip_and_bad_ones_name_the_file(tmp_path):
    asset = _asset()
    inertia = np.array([[0.02, 0.001, 0.0], [0.001, 0.03, 0.0], [0.0, 0.0, 0.04]])
    asset.part("drawer_0").inertial = MassProperties(1.25, np.array([0.0, -0.3, 0.3]), inertia)
    write_articulation(asset, tmp_path)
    back = read_articulation(tmp_path, load_meshes=False)
    assert back.part("base").inertial is None
    drawer = back.part("drawer_0").inertial
    assert drawer.mass == 1.25 and np.allclose(drawer.com, [0.0, -0.3, 0.3]) and np.allclose(drawer.inertia, inertia)
    data = json.loads((tmp_path / "articulation.json").read_text())
    data["parts"][1]["inertial"]["mass"] = -1.0
    (tmp_path / "articulation.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="articulation.json: part 'drawer_0': bad inertial"):
        read_articulation(tmp_path, load_meshes=False)


def test_joint_transform_opens_along_axis():
    j = Joint("j", "revolute", "a", "b", [0, 0, 1], [1.0, 0.0, 0.0], (0, 1.6))
    T = j.transform(np.pi / 2)
    assert np.allclose(T[:3, :3] @ [2.0, 0, 0] + T[:3, 3], [1.0, 1.0, 0.0])


def test_invalid_tree_is_reported(tmp_path):
    asset = _asset()
    asset.joints[0].parent = "nope"
    with pytest.raises(ValueError, match="refers to part 'nope'"):
        asset.validate()
    with pytest.raises(ValueError, match="type 'ball'"):
        Joint("j", "ball", "a", "b", [0, 0, 1], [0, 0, 0])


def test_read_reports_missing_and_bad_files(tmp_path):
    with pytest.raises(InputError, match="articulation.json: not found"):
        read_articulation(tmp_path)
    (tmp_path / "articulation.json").write_text("{bad json")
    with pytest.raises(InputError, match="not valid JSON"):
        read_articulation(tmp_path)
