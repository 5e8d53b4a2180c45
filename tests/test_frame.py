import json

import numpy as np
import pytest

from rest2art.frame.canonical import estimate_frame
from rest2art.generate import file_pose, generate_object


@pytest.mark.parametrize("kind", ["cabinet", "oven", "fridge", "microwave"])
@pytest.mark.parametrize("variant", ["asset", "scan"])
@pytest.mark.parametrize("yaw", [90.0, 180.0])
def test_front_found_from_relief_under_rotation(kind, variant, yaw):
    obj = generate_object(kind, 11, variant, scan_voxel=0.008, yaw_deg=yaw)
    frame = estimate_frame(obj.mesh, prior_up="+z")
    R = file_pose("z", yaw)[:3, :3]
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0])
    assert frame.evidence["front"] == "relief"


def test_y_up_file_uses_its_convention():
    obj = generate_object("cabinet", 12, "asset", up="y", yaw_deg=0.0)
    frame = estimate_frame(obj.mesh, prior_up="+y")
    R = file_pose("y", 0.0)[:3, :3]
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0])


def test_overrides_win():
    obj = generate_object("cabinet", 13, "asset")
    frame = estimate_frame(obj.mesh, up="+x", front="-z")
    assert np.allclose(frame.up, [1, 0, 0]) and np.allclose(frame.front, [0, 0, -1])
    assert np.allclose(frame.rotation @ frame.up, [0, 0, 1])
    assert np.allclose(frame.rotation @ frame.front, [0, -1, 0])


@pytest.mark.parametrize("kind, seed", [("box", 4), ("laptop", 11)])
def test_an_overhanging_lid_seen_from_below_does_not_make_the_bottom_the_front(kind, seed):
    obj = generate_object(kind, seed, "scan", yaw_deg=0.0)
    frame = estimate_frame(obj.mesh, prior_up="+z")
    assert np.allclose(frame.up, [0, 0, 1])
    assert abs(frame.front[2]) < 0.5



def test_an_l_shaped_object_keeps_the_files_axes():
    """The hull of an open laptop (flat base, upright lid at the back) is a right triangular
    prism: a box tilted by 45 degrees fits it as tightly as the file's own axes, which stay."""
    from rest2art.config import FrameConfig
    from rest2art.frame.canonical import candidate_axes

    triangle = np.array([[0.0, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 0.3]])
    prism = np.concatenate([triangle, triangle + [0.4, 0.0, 0.0]])
    assert np.allclose(candidate_axes(prism, FrameConfig()), np.eye(3))
    tilted = candidate_axes(prism, FrameConfig(min_obb_gain=-1.0))  # the OBB alone tilts
    assert not np.allclose(np.abs(tilted), np.eye(3)[[1, 0, 2]]) and not np.allclose(np.abs(tilted), np.eye(3))


def test_a_rotated_object_still_gets_its_own_box():
    """A cabinet modelled at 30 degrees of yaw: the oriented box is much tighter, so its axes win."""
    from rest2art.config import FrameConfig
    from rest2art.frame.canonical import candidate_axes

    box = trimesh_box_points([0.6, 0.4, 0.9])
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    axes = candidate_axes(box @ R.T, FrameConfig())
    assert np.allclose(np.abs(axes @ R[:, 0]).max(), 1.0, atol=1e-3)


def trimesh_box_points(extents):
    import trimesh

    return trimesh.creation.box(extents).vertices


def _boxes(*specs):
    import trimesh

    parts = []
    for extents, centre in specs:
        b = trimesh.creation.box(extents)
        b.apply_translation(centre)
        parts.append(b)
    return trimesh.util.concatenate(parts)


def test_a_flat_object_faces_along_its_thin_side():
    """A door between two posts, modelled facing +-x in a z-up file: it is three times wider
    than deep, so its front is one of its broad sides, not the file's -y."""
    door = _boxes(([0.04, 0.6, 0.8], [0, 0, 0.45]), ([0.06, 0.06, 0.9], [0, -0.33, 0.45]),
                  ([0.06, 0.06, 0.9], [0, 0.33, 0.45]), ([0.05, 0.02, 0.02], [-0.045, 0.2, 0.45]))
    frame = estimate_frame(door, prior_up="+z")
    assert np.allclose(frame.up, [0, 0, 1]) and abs(frame.front[0]) == 1.0
    assert frame.evidence["flat"] >= 2.5


def test_a_flat_objects_latch_outweighs_millimetre_relief_on_its_back():
    """The same door with its latch on the -x side and, on its +x side, a grid of studs 3 mm
    high (what a scan's noise or a panel's rivets show): the file's -y front says nothing
    between the two broad sides, and the latch standing out 5 cm decides, not the longer run of
    millimetre steps on the back (counted even stud by stud, as specks)."""
    studs = [([0.003, 0.012, 0.012], [0.0215, y, z]) for y in np.linspace(-0.25, 0.25, 12)
             for z in np.linspace(0.1, 0.8, 14)]
    door = _boxes(([0.04, 0.6, 0.8], [0, 0, 0.45]), ([0.06, 0.06, 0.9], [0, -0.33, 0.45]),
                  ([0.06, 0.06, 0.9], [0, 0.33, 0.45]), ([0.05, 0.02, 0.02], [-0.045, 0.2, 0.45]), *studs)
    from rest2art.config import FrameConfig

    every_speck = FrameConfig(relief_min_edge=0.0)
    for config in (FrameConfig(), every_speck):
        frame = estimate_frame(door, config, prior_up="+z")
        assert np.allclose(frame.front, [-1, 0, 0]), frame.evidence
    relief = frame.evidence["front_relief"]
    assert relief["[1.0, 0.0, 0.0]"] > relief["[-1.0, -0.0, -0.0]"]  # more millimetre steps on the back


def test_a_frame_on_a_thin_bar_is_not_turned_upside_down():
    """A window frame stands on a bar no wider than its top one: the file's +z up stays."""
    window = _boxes(([0.8, 0.05, 0.03], [0, 0, 0.015]), ([0.8, 0.05, 0.03], [0, 0, 0.985]),
                    ([0.03, 0.05, 1.0], [-0.385, 0, 0.5]), ([0.03, 0.05, 1.0], [0.385, 0, 0.5]),
                    ([0.74, 0.02, 0.94], [0, 0.0, 0.5]))
    frame = estimate_frame(window, prior_up="+z")
    assert np.allclose(frame.up, [0, 0, 1])


def test_a_laptop_standing_open_keeps_its_up_and_front():
    """A leaned-back screen makes a tilted box fit the whole tighter than the file's axes, and
    seen from above the screen's slope changes depth on every pixel. The laptop stands on its
    file's bottom, so that up stays (the box only turns about it), and a slope is not relief:
    +z up and -y front, in both variants."""
    from rest2art.config import FrameConfig
    from rest2art.frame.canonical import estimate_frame
    from rest2art.generate import generate_object

    for seed in range(3):
        for variant in ("asset", "scan"):
            mesh = generate_object("open_laptop", seed, variant).mesh
            frame = estimate_frame(mesh, FrameConfig())
            assert np.allclose(frame.up, [0.0, 0.0, 1.0]) and np.allclose(frame.front, [0.0, -1.0, 0.0]), \
                (seed, variant, frame.evidence)


def _y_up_real_like_frame(seed: int):
    """The frame estimated for real-like object ``seed``, filed +y up in an OBJ file (read +z
    up), and the (3, 3) rotation the file applied to it."""
    from rest2art.generate import MIX_KINDS
    from rest2art.generate.variation import mix_entry

    entry = mix_entry("real-like", seed, MIX_KINDS["real-like"])
    assert entry.up == "y"
    obj = generate_object(entry.kind, entry.seed, "asset", variation=entry.variation, up=entry.up,
                          yaw_deg=entry.yaw_deg)
    return estimate_frame(obj.mesh, prior_up="+z"), file_pose(entry.up, entry.yaw_deg)[:3, :3]


@pytest.mark.parametrize("seed", [3, 30])
def test_a_y_up_obj_file_that_cannot_stand_on_its_z_bottom_is_read_y_up(seed):
    """Real-like oven 3 and box 30, stored +y up in an OBJ file (read +z up) and turned 180
    degrees: the +z-up reading stands them on their fronts, which their handles and lids keep
    from carrying them, while -y carries them. The file follows the other common convention;
    they were read lying on their backs."""
    frame, R = _y_up_real_like_frame(seed)
    assert np.allclose(frame.up, R @ [0, 0, 1]), (frame.up, frame.evidence)
    assert "convention" in frame.evidence


@pytest.mark.parametrize("seed", [9, 45])
def test_a_y_up_obj_file_with_its_base_centred_on_the_origin_is_read_y_up(seed):
    """Real-like stove 9 and sliding cabinet 45, stored +y up in an OBJ file (read +z up) and
    turned about their up: boxes that stand as well on their backs as on their bottoms, so
    support cannot tell. The file stands each on the plane y = 0 with its base centred there,
    as asset files put their pivot: that is the file's up (they were read lying on their
    backs)."""
    frame, R = _y_up_real_like_frame(seed)
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence
    assert "origin" in frame.evidence["convention"]


def test_the_floor_a_file_stands_an_object_on():
    """The axis whose origin plane carries the object's base, centred there; none for an object
    placed anywhere else (a model cut out of a scene) or centred on the origin."""
    from rest2art.config import FrameConfig
    from rest2art.frame.canonical import floor_axis

    box = np.array([[x, y, z] for x in (-0.3, 0.3) for y in (-0.2, 0.2) for z in (0.0, 0.8)])
    assert floor_axis(box, FrameConfig()) == "+z"
    assert floor_axis(box[:, [0, 2, 1]], FrameConfig()) == "+y"
    assert floor_axis(box + [1.2, 0.4, 0.75], FrameConfig()) is None
    assert floor_axis(box - [0.0, 0.0, 0.4], FrameConfig()) is None


def test_a_y_up_control_panel_whose_top_reaches_forward_stands_on_its_centred_footprint(tmp_path):
    """Real-like button panel 411, filed +y up: its base stands centred on the origin plane, but
    its sloped top reaches 6 cm further forward than its back, so the middle of its box is off
    centre and the file read as +z up, its buttons facing the ceiling. The middle of what stands
    on the floor, its footprint, is centred."""
    from rest2art.config import FrameConfig
    from rest2art.frame.canonical import floor_axis

    base = np.array([[x, y, z] for x in (-0.15, 0.15) for y in (0.0, 0.2) for z in (-0.12, 0.12)])
    slope = np.array([[x, 0.28, z] for x in (-0.15, 0.15) for z in (-0.12, 0.19)])
    assert floor_axis(np.concatenate([base, slope]), FrameConfig()) == "+y"
    frame, R, entry = _real_like_file_frame(411, "button_panel", tmp_path)
    assert entry.up == "y" and np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0])


@pytest.mark.parametrize("seed", [24, 37])
def test_a_front_differs_from_its_back_while_a_side_matches_the_other(seed, tmp_path):
    """Real-like wardrobes 24 and 37, turned 90 and 270 degrees, as read from their files: their
    two sides show the same relief (the doors' and drawers' edges: the depth maps of opposite
    sides sample the same lines of sight and mark a step alike), the front more and the back
    none. A side's relief beyond its opposite side's is nothing, the front's is all of it."""
    frame, R, entry = _real_like_file_frame(seed, "wardrobe", tmp_path)
    assert entry.yaw_deg in (90.0, 270.0)
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence
    assert frame.evidence["front"].startswith("relief"), frame.evidence
    relief = {tuple(np.round(json.loads(k), 3)): v for k, v in frame.evidence["front_relief"].items()}
    left, right = (relief[tuple(np.round(R @ [s, 0.0, 0.0], 3) + 0.0)] for s in (-1.0, 1.0))
    assert left > 0 and left == pytest.approx(right, rel=0.05)


def _real_like_file_frame(seed: int, kind: str, folder):
    """The frame estimated for real-like object ``seed`` (of ``kind``) as read from its OBJ file
    (+z up), the (3, 3) rotation the file applied to it, and its mix entry."""
    from rest2art.generate import MIX_KINDS, write_object
    from rest2art.generate.variation import mix_entry
    from rest2art.io.load import load_mesh

    entry = mix_entry("real-like", seed, MIX_KINDS["real-like"])
    assert entry.kind == kind
    obj = generate_object(entry.kind, entry.seed, "asset", variation=entry.variation, up=entry.up,
                          yaw_deg=entry.yaw_deg)
    frame = estimate_frame(load_mesh(write_object(obj, folder)).trimesh(), prior_up="+z")
    return frame, file_pose(entry.up, entry.yaw_deg)[:3, :3], entry


def test_a_wardrobes_front_is_a_broad_side_whatever_its_narrow_sides_show(tmp_path):
    """Real-like wardrobe 219, 2.5 times wider than deep, flush doors with two small knobs: each
    narrow side shows a step its whole height long (two metres of relief edges), far more relief
    than the knobs. A wardrobe faces along its thin side: the front is one of the broad sides
    (the format's, a tie there)."""
    frame, R, _ = _real_like_file_frame(219, "wardrobe", tmp_path)
    relief = frame.evidence["front_relief"]
    assert frame.evidence["flat"] >= 2.5 and relief["[1.0, 0.0, 0.0]"] > 1.5
    assert np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence


@pytest.mark.parametrize(("seed", "kind"), [(222, "microwave"), (303, "box")])
def test_a_small_objects_front_against_its_back_is_measured_at_its_own_scale(seed, kind, tmp_path):
    """Real-like microwave 222 (turned 270 degrees; its overlay door makes a step on one side)
    and box 303 (turned 180; a handle on its lid's edge, nothing else): the front shows less
    than half a metre of relief edges, which a wardrobe's seams would dwarf, but its back shows
    none. Measured against the object's size, the front's lead over its back decides."""
    frame, R, _ = _real_like_file_frame(seed, kind, tmp_path)
    assert frame.evidence["front"] == "relief against the opposite side"
    assert np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence


@pytest.mark.parametrize("kind, seed, mix", [("box", 22, None), ("open_laptop", 12, "real-like"),
                                             ("open_laptop", 38, "real-like")])
def test_a_scan_is_not_tipped_over_by_what_its_top_shows_as_much_as_its_underside(kind, seed, mix):
    """A scanned lidded box (generated box 22, +z up, front -y) and scanned open laptops turned
    90 degrees about their up (real-like 12 and 38): a scan shows the lid's parting line and the
    keyboard from above, and its underside about as much from below, while its level sides show
    little. Counting the top's relief alone made it the front and stood each on its back."""
    from rest2art.generate import generate_mix_object

    obj = generate_mix_object(mix, seed, "scan") if mix else generate_object(kind, seed, "scan")
    assert obj.spec.kind == kind
    generator = obj.asset.metadata["generator"]
    R = file_pose(generator.get("up", "z"), float(generator.get("yaw_deg", 0.0)))[:3, :3]
    frame = estimate_frame(obj.mesh, prior_up="+z")
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence


@pytest.mark.parametrize("seed", [233, 311])
def test_an_open_laptop_filed_y_up_is_not_laid_on_its_side_by_its_keyboard(seed):
    """Real-like open laptops 233 and 311, scanned, filed +y up in an OBJ file (read +z up) and
    turned about their up: the file's own floor (or its z bottom's failing to carry it) already
    says y-up, yet the keyboard seen from above (+y) outshone every level side and the rule for
    files in the other convention made that top the front, so the laptop lay on its side. Once
    the file reads y-up, no common convention puts its front on its top."""
    from rest2art.generate import generate_mix_object

    obj = generate_mix_object("real-like", seed, "scan")
    assert obj.spec.kind == "open_laptop"
    generator = obj.asset.metadata["generator"]
    assert generator.get("up") == "y"
    R = file_pose("y", float(generator.get("yaw_deg", 0.0)))[:3, :3]
    frame = estimate_frame(obj.mesh, prior_up="+z")
    assert "convention" in frame.evidence
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence


def test_a_scans_noise_on_its_back_and_side_does_not_turn_its_front():
    """A scanned microwave (generated 11, front -y) on a finer mesh, with one vertex in fifty of
    its back and of one side pushed 6 mm in or out: a scanner's pits and spikes. Each is a speck
    of relief a few pixels across, the door's outline and handle lines across the front. Counted
    speck by speck, the side's noise against the quiet opposite side outweighed the front's lead
    over its noisy back, and the microwave was read from its side."""
    import trimesh

    from rest2art.config import FrameConfig

    obj = generate_object("microwave", 11, "scan", scan_voxel=0.008, yaw_deg=0.0)
    vertices, faces = trimesh.remesh.subdivide_to_size(obj.mesh.vertices, obj.mesh.faces, max_edge=0.006)
    mesh = trimesh.Trimesh(vertices, faces)
    rng = np.random.default_rng(0)
    moved = mesh.vertices.copy()
    for axis in (0, 1):  # the +x side and the +y back
        near = np.flatnonzero(moved[:, axis] > moved[:, axis].max() - 0.004)
        pushed = rng.choice(near, size=len(near) // 50, replace=False)
        moved[pushed] += mesh.vertex_normals[pushed] * rng.choice([-0.006, 0.006], size=(len(pushed), 1))
    mesh.vertices = moved
    frame = estimate_frame(mesh, prior_up="+z")
    assert np.allclose(frame.front, [0, -1, 0]), frame.evidence
    # every speck counted, and the handle not looked for (it alone would keep the front)
    counted = estimate_frame(mesh, FrameConfig(relief_min_edge=0.0, fitting_proud=1.0), prior_up="+z")
    assert not np.allclose(counted.front, [0, -1, 0]), counted.evidence


def test_a_desks_knobs_outweigh_its_side_panel_framed_by_legs(tmp_path):
    """Furniture desk 72, scanned, filed +y up and turned 90 degrees: its side, a panel set
    between two legs under the apron, shows more relief edges than its front, whose drawer
    seams a scan blurs into shallow grooves, and it was read from the side (a "door" made of the
    side panel and the legs was published). Only the front shows knobs."""
    from rest2art.generate import MIX_KINDS, write_object
    from rest2art.generate.variation import mix_entry
    from rest2art.io.load import load_mesh

    entry = mix_entry("furniture", 72, MIX_KINDS["furniture"])
    assert entry.kind == "desk" and entry.up == "y" and entry.yaw_deg == 90.0
    obj = generate_object(entry.kind, entry.seed, "scan", variation=entry.variation, up=entry.up,
                          yaw_deg=entry.yaw_deg)
    frame = estimate_frame(load_mesh(write_object(obj, tmp_path)).trimesh(), prior_up="+z")
    R = file_pose(entry.up, entry.yaw_deg)[:3, :3]
    assert np.allclose(frame.up, R @ [0, 0, 1]) and np.allclose(frame.front, R @ [0, -1, 0]), frame.evidence
    fittings = {tuple(np.round(json.loads(k), 3) + 0.0): n for k, n in frame.evidence["front_fittings"].items()}
    front = tuple(np.round(R @ [0.0, -1.0, 0.0], 3) + 0.0)
    assert fittings[front] >= 3 and sum(fittings.values()) == fittings[front]  # the drawers' knobs, only there
