import numpy as np
import pytest

from rest2art.generate import generate_object
from rest2art.generate.objects import KINDS
from rest2art.io.load import connected_components


@pytest.mark.parametrize("kind", KINDS)
def test_asset_variant_ground_truth(kind):
    obj = generate_object(kind, 1, "asset")
    asset = obj.asset
    asset.validate()
    assert len(obj.face_part) == len(obj.mesh.faces)
    assert set(np.unique(obj.face_part)) == set(range(len(asset.parts)))
    assert asset.parts[0].semantic == "base" and len(asset.movable_joints) >= 1
    for joint in asset.movable_joints:
        assert joint.limit[0] == 0.0 and joint.limit[1] > 0
    # every piece is a closed solid, as an artist would model it
    for part in asset.parts:
        assert part.mesh.is_watertight
    gap = asset.metadata["generator"]["gap"]
    assert 0.002 <= gap <= 0.006


def test_deterministic():
    a = generate_object("cabinet", 7, "asset")
    b = generate_object("cabinet", 7, "asset")
    assert np.array_equal(a.mesh.vertices, b.mesh.vertices) and np.array_equal(a.face_part, b.face_part)
    c = generate_object("cabinet", 8, "asset")
    assert a.mesh.vertices.shape != c.mesh.vertices.shape or not np.allclose(a.mesh.vertices, c.mesh.vertices)


def test_scan_variant_is_one_fused_surface():
    obj = generate_object("microwave", 2, "scan", scan_voxel=0.008)
    faces = obj.mesh.faces
    assert connected_components(faces, len(obj.mesh.vertices)).max() == 0
    assert obj.mesh.is_watertight
    # the labels still cover the door, seen through the fused surface
    assert set(np.unique(obj.face_part)) == {0, 1}


def test_opening_moves_parts_outward():
    """Positive joint values open: the moving part's centre moves out of the carcass."""
    obj = generate_object("cabinet", 4, "asset")
    lo, hi = obj.asset.parts[0].mesh.bounds
    for joint in obj.asset.movable_joints:
        mesh = obj.asset.part(joint.child).mesh
        before = mesh.vertices.mean(axis=0)
        T = joint.transform(0.5 * joint.limit[1])
        after = (mesh.vertices @ T[:3, :3].T + T[:3, 3]).mean(axis=0)
        assert after[1] < before[1] - 0.01  # towards -y, the front
