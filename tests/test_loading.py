import numpy as np
import pytest
import trimesh

from rest2art.config import LoadConfig
from rest2art.errors import InputError
from rest2art.generate import generate_object, write_object
from rest2art.io.load import load_mesh


@pytest.fixture(scope="module")
def cabinet(tmp_path_factory):
    obj = generate_object("cabinet", 3, "asset")
    folder = tmp_path_factory.mktemp("cab")
    return obj, write_object(obj, folder)


def test_obj_keeps_face_order_and_pieces(cabinet):
    obj, path = cabinet
    mesh = load_mesh(path)
    assert np.allclose(mesh.vertices[mesh.faces], obj.mesh.vertices[obj.mesh.faces], atol=1e-6)  # 7 decimals in OBJ
    assert mesh.face_node.max() + 1 == len(obj.piece_faces)  # one OBJ object per piece
    assert len(np.unique(mesh.face_component)) == len(obj.piece_faces)


@pytest.mark.parametrize("suffix", [".ply", ".stl", ".off", ".glb"])
def test_other_formats_load_same_geometry(cabinet, tmp_path, suffix):
    obj, _ = cabinet
    path = tmp_path / f"m{suffix}"
    obj.mesh.export(path)
    mesh = load_mesh(path)
    assert len(mesh.faces) == len(obj.mesh.faces)
    assert np.isclose(mesh.trimesh().area, obj.mesh.area, rtol=1e-5)


def test_triangle_soup_pieces_connect_by_position(cabinet, tmp_path):
    """STL repeats every corner: pieces must still be the modelled solids, not triangles."""
    obj, _ = cabinet
    path = tmp_path / "soup.stl"
    obj.mesh.export(path)
    mesh = load_mesh(path)
    assert len(np.unique(mesh.vertices, axis=0)) < len(mesh.vertices)  # really a soup
    assert len(np.unique(mesh.face_component)) == len(obj.piece_faces)



def test_pieces_a_mirrored_export_winds_inward_are_turned_outward(tmp_path):
    """A mirrored export winds every piece inward: the cameras round it see a closed door and
    a carcass modelled as a shell open at its front from behind (the carcass's inside through
    its opening from the front), and a box shut inside another is not seen at all. Loaded,
    every one faces out again; a piece wound outward is left alone, and so is the inward shell
    round a cavity inside a solid when the object is wound outward."""
    carcass = trimesh.creation.box([0.6, 0.4, 0.8])
    carcass = trimesh.Trimesh(carcass.vertices, carcass.faces[carcass.face_normals[:, 1] > -0.99], process=False)
    door = trimesh.creation.box([0.58, 0.02, 0.78])
    door.apply_translation([0.0, -0.215, 0.0])
    knob = trimesh.creation.cylinder(0.015, 0.03)
    knob.apply_translation([0.2, -0.24, 0.0])
    shut = trimesh.creation.box([0.3, 0.3, 0.3])
    shut.apply_translation([1.0, 0.0, 0.0])
    hidden = trimesh.creation.box([0.1, 0.1, 0.1])  # inside the shut box: no camera sees it
    hidden.apply_translation([1.0, 0.0, 0.0])
    mirrored = trimesh.util.concatenate([carcass, door, shut, hidden])
    mirrored.faces = mirrored.faces[:, ::-1]
    written = trimesh.util.concatenate([mirrored, knob])  # the knob kept its outward winding
    path = tmp_path / "mirrored.obj"
    written.export(path)
    loaded = load_mesh(path).trimesh()
    expected = np.concatenate([-mirrored.face_normals, knob.face_normals])
    assert np.allclose(loaded.face_normals, expected, atol=1e-6)
    assert sum("wound inward" in note for note in load_mesh(path).notes) == 1
    slab = trimesh.creation.box([0.3, 0.3, 0.1])
    void = trimesh.creation.box([0.1, 0.1, 0.02])
    void.faces = void.faces[:, ::-1]  # the cavity's shell faces into the slab's material
    (tmp_path / "void.obj").write_text(trimesh.util.concatenate([slab, void]).export(file_type="obj"))
    hollow = load_mesh(tmp_path / "void.obj").trimesh()
    assert np.allclose(hollow.face_normals[len(slab.faces):], void.face_normals, atol=1e-6)


def test_glb_scene_graph_is_flattened_with_transforms(tmp_path):
    scene = trimesh.Scene()
    box = trimesh.creation.box([0.2, 0.2, 0.2])
    T = np.eye(4)
    T[:3, 3] = [1.0, 0.0, 0.0]
    scene.add_geometry(box, node_name="a")
    scene.add_geometry(box, node_name="b", transform=T)
    path = tmp_path / "s.glb"
    scene.export(path)
    mesh = load_mesh(path)
    assert len(mesh.faces) == 24 and mesh.face_node.max() == 1
    assert np.isclose(mesh.vertices[:, 0].max(), 1.1, atol=1e-6)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match=r"nope\.obj: file not found"):
        load_mesh(tmp_path / "nope.obj")


def test_empty_and_garbage_files(tmp_path):
    empty = tmp_path / "e.obj"
    empty.write_text("")
    with pytest.raises(InputError, match=r"e\.obj: file is empty"):
        load_mesh(empty)
    text = tmp_path / "t.stl"
    text.write_text("this is not a mesh\n" * 5)
    with pytest.raises(InputError, match=r"t\.stl"):
        load_mesh(text)
    with pytest.raises(InputError, match="unsupported file type '.txt'"):
        p = tmp_path / "a.txt"
        p.write_text("x")
        load_mesh(p)


def test_nan_vertices(tmp_path):
    path = tmp_path / "nan.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n")
    with pytest.raises(InputError, match="NaN or infinite"):
        load_mesh(path)


def test_only_degenerate_faces(tmp_path):
    path = tmp_path / "deg.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    with pytest.raises(InputError, match="zero area"):
        load_mesh(path)


def test_point_cloud(tmp_path):
    path = tmp_path / "pc.ply"
    trimesh.PointCloud(np.random.default_rng(0).random((50, 3))).export(path)
    with pytest.raises(InputError, match="point cloud"):
        load_mesh(path)


def test_too_many_faces_refused_or_decimated(tmp_path):
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=0.3)  # 5120 faces
    path = tmp_path / "big.ply"
    mesh.export(path)
    with pytest.raises(InputError, match="5,120 faces is over the limit of 1,000"):
        load_mesh(path, LoadConfig(max_faces=1000))
    small = load_mesh(path, LoadConfig(max_faces=1000, decimate_large=True))
    assert len(small.faces) <= 1000 and any("decimated" in n for n in small.notes)


def test_millimetres_are_reported_not_rescaled(cabinet, tmp_path):
    obj, _ = cabinet
    mm = obj.mesh.copy()
    mm.apply_scale(1000.0)
    path = tmp_path / "mm.stl"
    mm.export(path)
    with pytest.raises(InputError, match="--units mm"):
        load_mesh(path)
    mesh = load_mesh(path, units="mm")
    assert np.isclose(np.ptp(mesh.vertices, axis=0).max(), np.ptp(obj.mesh.vertices, axis=0).max(), rtol=1e-5)
