"""What real assets do and the default generator did not: sliding doors and sashes, buttons,
levers, knobs on a tilted panel, joints whose parent is a door, flush and sunk fronts, parts
built from primitives, the handle catalogue, +y up and turned files, and the real-like mix."""

import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from rest2art.asset import read_articulation
from rest2art.generate import (
    ALL_KINDS,
    MIX_KINDS,
    KINDS,
    REAL_LIKE_KINDS,
    VARIANTS,
    build_spec,
    file_pose,
    generate_object,
    write_object,
)
from rest2art.generate.check import motion_overlaps
from rest2art.generate.csg import Box, Cylinder, Transformed, box_pieces, union
from rest2art.generate.objects import HANDLE_STYLES, _Builder
from rest2art.generate.variation import FITS, Variation, mix_entry
from rest2art.geometry.basics import axis_angle_deg, rotation_about
from rest2art.io.load import connected_components

FRONT = np.array([0.0, -1.0, 0.0])


def movers(asset, semantic):
    return [(asset.part(j.child), j) for j in asset.movable_joints if asset.part(j.child).semantic == semantic]


def panel_normal(mesh) -> np.ndarray:
    """Axis of the thinnest extent of an axis-aligned panel."""
    return np.eye(3)[int(np.argmin(mesh.extents))]


def first_seed(kind, test, seeds=range(40), variation=Variation()):
    """The first seed whose object passes ``test`` (a case the kind draws at random)."""
    for seed in seeds:
        obj = generate_object(kind, seed, "asset", variation=variation)
        if test(obj):
            return obj
    raise AssertionError(f"no {kind} in seeds {seeds} has the case")


# ---- what each new kind is -----------------------------------------------------------------

def expect_sliding_cabinet(asset):
    doors = movers(asset, "door")
    assert len(doors) == 2
    for part, joint in doors:
        assert joint.type == "prismatic" and joint.parent == "base"
        assert abs(joint.axis @ panel_normal(part.mesh)) < 1e-9  # slides in the panel's plane
        assert abs(joint.axis @ FRONT) < 1e-9 and joint.limit[1] > 0.2
    (a, ja), (b, jb) = doors
    assert ja.axis @ jb.axis == pytest.approx(-1.0)  # towards each other
    ya, yb = a.mesh.bounds[:, 1], b.mesh.bounds[:, 1]
    assert ya[1] < yb[0] or yb[1] < ya[0]  # two tracks: they pass each other


def expect_window(asset):
    sashes = movers(asset, "sash")
    assert sashes
    for part, joint in sashes:
        assert joint.type == "prismatic"
        assert abs(joint.axis @ panel_normal(part.mesh)) < 1e-9
        assert max(abs(joint.axis[0]), abs(joint.axis[2])) == pytest.approx(1.0)  # up/down or sideways


def expect_button_panel(asset):
    buttons, levers = movers(asset, "button"), movers(asset, "lever")
    assert buttons or levers
    for part, joint in buttons:
        assert joint.type == "prismatic" and joint.axis @ FRONT == pytest.approx(-1.0)  # pushed inward
        assert 0.002 <= joint.limit[1] <= 0.006
    for part, joint in levers:
        assert joint.type == "revolute" and abs(joint.axis[2]) < 1e-9  # a horizontal pivot
        assert part.mesh.extents.max() < 0.1 and joint.limit[1] <= np.radians(75.0) + 1e-9


def expect_stove(asset):
    knobs = movers(asset, "knob")
    assert len(knobs) >= 2
    axes = np.array([j.axis for _, j in knobs])
    assert np.allclose(axes, axes[0])  # all on one panel
    tilt = axis_angle_deg(axes[0], FRONT)
    assert 15.0 - 1e-6 <= tilt <= 40.0 + 1e-6 and axes[0][2] > 0  # facing front and up
    top = asset.part("base").mesh.bounds[1, 2]
    for _, joint in knobs:
        assert joint.origin[2] > top - 0.2  # on the control panel above the cooktop


def expect_safe(asset):
    (door, door_joint), = movers(asset, "door")
    assert door_joint.parent == "base"
    for semantic in ("dial", "handle"):
        (part, joint), = movers(asset, semantic)
        assert part.parent == door.name and joint.parent == door.name  # nested on the door
        assert joint.type == "revolute" and joint.axis @ FRONT == pytest.approx(1.0)


def expect_wardrobe(asset):
    doors = movers(asset, "door")
    assert len(doors) == 2
    (_, a), (_, b) = doors
    assert a.axis @ b.axis == pytest.approx(-1.0) and abs(a.axis[2]) == pytest.approx(1.0)
    assert a.origin[0] < 0 < b.origin[0]  # hinged on opposite sides
    for part, joint in movers(asset, "handle"):
        assert part.parent in (asset.part(j.child).name for _, j in doors) and joint.parent == part.parent


def expect_open_laptop(asset):
    (screen, joint), = movers(asset, "lid")
    assert joint.type == "revolute" and joint.axis @ [1.0, 0.0, 0.0] == pytest.approx(1.0)  # closes forward
    base = asset.part("base").mesh.bounds
    assert screen.mesh.bounds[1, 2] > base[1, 2] + 0.15  # standing open above the keyboard
    assert joint.limit[1] >= np.radians(89.0)
    closed = screen.mesh.copy()
    closed.apply_transform(joint.transform(joint.limit[1]))
    assert closed.bounds[1, 2] < base[1, 2] + 0.03  # closed, it lies on the keyboard


EXPECT = {"sliding_cabinet": expect_sliding_cabinet, "window": expect_window, "button_panel": expect_button_panel,
          "stove": expect_stove, "safe": expect_safe, "wardrobe": expect_wardrobe, "open_laptop": expect_open_laptop}


def test_every_new_kind_has_its_expectations():
    assert set(EXPECT) == set(REAL_LIKE_KINDS) and ALL_KINDS[:len(KINDS)] == KINDS


@pytest.mark.parametrize("kind", REAL_LIKE_KINDS)
@pytest.mark.parametrize("variant", VARIANTS)
def test_new_kind_in_both_variants(kind, variant):
    obj = generate_object(kind, 0, variant, scan_voxel=0.01)
    asset = obj.asset
    asset.validate()
    assert len(obj.face_part) == len(obj.mesh.faces)
    assert set(np.unique(obj.face_part)) == set(range(len(asset.parts)))  # every part has faces
    assert all(p.mesh.is_watertight for p in asset.parts)
    assert asset.movable_joints and all(j.limit[0] == 0.0 < j.limit[1] for j in asset.movable_joints)
    if variant == "scan":
        assert connected_components(obj.mesh.faces, len(obj.mesh.vertices)).max() == 0
    EXPECT[kind](asset)


@pytest.mark.parametrize("kind", REAL_LIKE_KINDS)
def test_new_kind_over_seeds_and_options(kind):
    for seed in range(1, 6):
        variation = Variation(FITS[seed % 3], primitives=seed % 2 == 0)
        obj = generate_object(kind, seed, "asset", variation=variation)
        obj.asset.validate()
        assert set(np.unique(obj.face_part)) == set(range(len(obj.asset.parts)))
        EXPECT[kind](obj.asset)


@pytest.mark.parametrize("kind", ["sliding_cabinet", "window"])
def test_a_sliding_panel_runs_in_its_track(kind):
    """Every sliding door and sash runs in grooves that hold it: rays out of its edges meet a lip
    of the frame or carcass in front, as the joints stage judges a track, whatever the fit's gap
    (up to 6 mm, as deep as the groove: the panel sat 0.4 mm in it) and the bar's shape (a round
    bar's surface falls back off its crest: the sash's edges stood clear of it)."""
    from rest2art.config import JointsConfig
    from rest2art.joints.rules import held_edges, in_track

    for seed in range(8):
        for fit in FITS:
            obj = generate_object(kind, seed, "asset", variation=Variation(fit, primitives=seed % 2 == 0))
            base = obj.asset.part("base").mesh
            for part, joint in movers(obj.asset, "door") + movers(obj.asset, "sash"):
                held = held_edges(part.mesh, FRONT, base, JointsConfig())
                assert in_track(held), (obj.name, part.name, held, obj.spec.params)


def test_cases_each_kind_draws():
    assert first_seed("window", lambda o: o.spec.params["slide"] == "vertical" and o.spec.params["frame"] == "cylinders")
    assert first_seed("window", lambda o: o.spec.params["slide"] == "horizontal" and o.spec.params["frame"] == "boxes")
    assert first_seed("window", lambda o: len(movers(o.asset, "sash")) == 1)  # the back sash fixed
    assert first_seed("button_panel", lambda o: movers(o.asset, "button") and movers(o.asset, "lever"))
    assert first_seed("sliding_cabinet", lambda o: movers(o.asset, "drawer"))
    lever = first_seed("wardrobe", lambda o: movers(o.asset, "handle"))
    assert all(j.type == "revolute" for _, j in movers(lever.asset, "handle"))
    plain = first_seed("wardrobe", lambda o: all(len(p.pieces) == 1 for p in o.spec.parts if p.semantic == "door")
                       and not movers(o.asset, "handle"))
    assert all(isinstance(p.pieces[0], Box) for p in plain.spec.parts if p.semantic == "door")  # no handle at all


def test_a_nested_part_moves_with_its_parent():
    asset = generate_object("safe", 3, "asset").asset
    door = asset.joint_for("door_0")
    dial = asset.joint_for("dial_0")
    poses = asset.part_poses({door.name: np.pi / 2})
    assert np.allclose(poses["dial_0"], poses["door_0"]) and not np.allclose(poses["door_0"], np.eye(4))
    turned = asset.part_poses({door.name: np.pi / 2, dial.name: 1.0})
    assert np.allclose(turned["dial_0"], poses["door_0"] @ dial.transform(1.0))


def test_nested_parents_survive_the_contract(tmp_path):
    write_object(generate_object("safe", 1, "asset"), tmp_path)
    back = read_articulation(tmp_path)
    assert back.part("dial_0").parent == "door_0" and back.joint_for("handle_0").parent == "door_0"


# ---- physically valid: nothing passes through anything -------------------------------------

@pytest.mark.parametrize("kind", REAL_LIKE_KINDS)
@pytest.mark.parametrize("fit", FITS)
def test_new_kinds_move_free(kind, fit):
    """Over every joint's range, alone and all together, parts share no volume; only sunk fronts
    sit in the carcass at rest, and come out of it as they open."""
    for seed in range(2):
        obj = generate_object(kind, seed, "asset", variation=Variation(fit, varied_handles=True))
        report = motion_overlaps(obj.asset, samples=6)
        check_overlaps(report, obj.spec.params.get("sink", 0.0))


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("fit", ["flush", "sunk"])
def test_flush_and_sunk_fronts_of_the_default_kinds_move_free(kind, fit):
    """Each joint alone (the default layouts can make two open fronts meet: a door swung across
    an open drawer)."""
    for seed in range(3):
        obj = generate_object(kind, seed, "asset", variation=Variation(fit))
        report = motion_overlaps(obj.asset, samples=6)
        report.pop("all")
        check_overlaps(report, obj.spec.params.get("sink", 0.0))


def check_overlaps(report, sink):
    for run, overlaps in report.items():
        for overlap in overlaps:
            assert sink and "base" in overlap.pair, (run, overlap)
            assert overlap.depth <= sink + 1e-4, (run, overlap)
    if sink and report["rest"]:
        assert 0.001 <= sink <= 0.003 and max(o.depth for o in report["rest"]) > 0.5 * sink


def test_flush_fronts_touch_at_rest():
    gap = generate_object("cabinet", 2, "asset")  # overlay drawers
    flush = generate_object("cabinet", 2, "asset", variation=Variation("flush"))
    for asset, expected in ((gap.asset, gap.spec.params["gap"]), (flush.asset, 0.0)):
        base_front = asset.part("base").mesh.bounds[0, 1]
        backs = [asset.part(j.child).mesh.bounds[:, 1] for j in asset.movable_joints]
        assert min(base_front - b[0] for b in backs) > 0  # fronts in front of the carcass
        gaps = [base_front - mesh_back(asset.part(j.child).mesh, base_front) for j in asset.movable_joints]
        assert min(gaps) == pytest.approx(expected, abs=1e-6)  # part meshes hold float32 vertices


def mesh_back(mesh, limit):
    """y of a front's back face: its highest y not behind ``limit`` (its box reaches further)."""
    y = np.asarray(mesh.vertices)[:, 1]
    return y[y <= limit + 1e-9].max()


def test_a_variation_keeps_the_layout():
    for kind in KINDS:
        base = build_spec(kind, 5)
        for variation in (Variation("sunk"), Variation(primitives=True), Variation(varied_handles=True)):
            varied = build_spec(kind, 5, variation)
            assert [p.name for p in varied.parts] == [p.name for p in base.parts]
            assert [p.joint["type"] if p.joint else None for p in varied.parts] == \
                [p.joint["type"] if p.joint else None for p in base.parts]


# ---- primitives and handles ----------------------------------------------------------------

@pytest.mark.parametrize("kind", ALL_KINDS)
def test_primitives_are_the_same_solids_in_more_pieces(kind):
    whole = generate_object(kind, 2, "asset")
    split = generate_object(kind, 2, "asset", variation=Variation(primitives=True))
    assert len(split.piece_faces) > len(whole.piece_faces)
    for a, b in zip(whole.asset.parts, split.asset.parts):
        assert b.mesh.volume == pytest.approx(a.mesh.volume, rel=1e-6)
    for part in split.spec.parts:
        assert all(piece.mesh().is_watertight for piece in part.pieces)
    assert len(split.spec.parts[0].pieces) >= 2  # the base too: wall panels, a frame's bars


def test_a_primitive_drawer_is_five_boards_and_a_handle():
    obj = first_seed("cabinet", lambda o: movers(o.asset, "drawer"), variation=Variation(primitives=True))
    drawer = next(p for p in obj.spec.parts if p.semantic == "drawer")
    assert len(drawer.pieces) >= 5 and sum(isinstance(p, Box) for p in drawer.pieces) >= 4


def test_box_pieces_rebuild_the_carved_box():
    cuts = [((0.02, -0.1, 0.02), (0.48, 0.48, 0.5)), ((0.52, -0.1, 0.02), (0.98, 0.48, 0.98)),
            ((0.02, 0.2, 0.52), (0.48, 0.48, 0.98))]
    pieces = box_pieces((0, 0, 0), (1, 0.5, 1), cuts)
    carved = Box((0, 0, 0), (1, 0.5, 1))
    for lo, hi in cuts:
        carved = carved - Box(lo, hi)
    assert union(pieces).mesh().volume == pytest.approx(carved.mesh().volume, rel=1e-9)
    assert sum(p.mesh().volume for p in pieces) == pytest.approx(carved.mesh().volume, rel=1e-9)  # disjoint


def test_a_turned_solid_has_the_distance_of_its_mesh():
    T = np.eye(4)
    T[:3, :3] = rotation_about(np.array([1.0, 0.2, 0.0]), 0.7)
    T[:3, 3] = [0.1, -0.2, 0.3]
    solid = Transformed.of(Cylinder((0, 0, 0), (0, -0.1, 0), 0.05, segments=96), T)
    mesh = solid.mesh()
    points = np.random.default_rng(0).uniform(*solid.bounds(), size=(2000, 3))
    inside = mesh.contains(points)
    distance = solid.sdf(points)
    clear = np.abs(distance) > 0.002  # away from the facets of the 96-gon
    assert np.array_equal(inside[clear], distance[clear] < 0)


@pytest.mark.parametrize("style", [*HANDLE_STYLES, "none"])
@pytest.mark.parametrize("orient", ["h", "v"])
def test_every_handle_sits_on_its_panel(style, orient):
    """Placed as doors and drawers place them (a door's by its latch edge, as near it as a
    narrow door's 12 % of its width), every handle stays inside its panel's outline: a cup
    pull reaching over the edge fused a pair of doors' pulls into one."""
    lo, hi = np.array([-0.2, -0.2, 0.3]), np.array([0.2, -0.18, 0.6])
    where = np.array([hi[0] - 0.12 * (hi[0] - lo[0]), 0.45]) if orient == "v" else np.array([0.0, 0.5])
    for seed in range(6):
        b = _Builder(np.random.default_rng(seed), "test")
        pieces, cut = b.handle(lo, hi, where, orient, style)
        if style in ("none", "recessed"):
            assert not pieces and (cut is None) == (style == "none")
            continue
        for piece in pieces:
            (x0, y0, z0), (x1, y1, z1) = piece.mesh().bounds
            tol = 1e-6  # solids mesh with float32 vertices
            assert lo[0] - tol <= x0 and x1 <= hi[0] + tol and lo[2] - tol <= z0 and z1 <= hi[2] + tol
            assert y1 == pytest.approx(lo[1], abs=tol) and y0 < lo[1] - 0.005  # on the face, proud of it


def test_varied_handles_leave_some_pairs_of_doors_bare():
    bare = 0
    for seed in range(40):
        spec = build_spec("cabinet", seed, Variation(varied_handles=True))
        doors = [p for p in spec.parts if p.semantic == "door"]
        bare += sum(len(p.pieces) == 1 and isinstance(p.pieces[0], Box) for p in doors)
    assert bare >= 2


# ---- file frames ---------------------------------------------------------------------------

def test_a_y_up_file_has_its_ground_truth_in_its_frame():
    obj = generate_object("window", 1, "asset", up="y")  # two sashes sliding up and down
    asset = obj.asset
    assert asset.metadata["frame"]["up"] == [0.0, 1.0, 0.0]
    assert obj.mesh.bounds[0, 1] == pytest.approx(0.0, abs=1e-9)  # stands on y = 0
    for part, joint in movers(asset, "sash"):
        assert abs(joint.axis[1]) == pytest.approx(1.0)
    for index, part in enumerate(asset.parts):
        assert np.allclose(obj.mesh.vertices[np.unique(obj.mesh.faces[obj.face_part == index])].min(axis=0),
                           part.mesh.bounds[0], atol=1e-9)


def test_a_turned_file_turns_its_ground_truth():
    plain = generate_object("button_panel", 1, "asset").asset
    turned = generate_object("button_panel", 1, "asset", yaw_deg=90.0).asset
    R = file_pose("z", 90.0)[:3, :3]
    assert np.allclose(turned.metadata["frame"]["front"], R @ FRONT)
    for a, b in zip(plain.joints, turned.joints):
        assert np.allclose(b.axis, R @ a.axis) and np.allclose(b.origin, R @ a.origin)
    for _, joint in movers(turned, "button"):
        assert joint.axis @ np.asarray(turned.metadata["frame"]["front"]) == pytest.approx(-1.0)


# ---- the real-like mix, the bench set and the command line ----------------------------------

def test_the_real_like_mix_draws_every_case():
    entries = [mix_entry("real-like", seed, MIX_KINDS["real-like"]) for seed in range(48)]
    assert {e.kind for e in entries} == set(MIX_KINDS["real-like"])
    assert {e.variation.fit for e in entries} == set(FITS)
    assert {e.variation.primitives for e in entries} == {True, False}
    assert {e.variation.varied_handles for e in entries} == {True, False}
    assert {e.up for e in entries} == {"y", "z"} and {e.yaw_deg for e in entries} == {0.0, 90.0, 180.0, 270.0}
    assert len({e.name for e in entries}) == 48


def test_the_real_like_bench_set_materializes(tmp_path):
    from rest2art.bench import mix_items

    items = mix_items("real-like", 3, "asset", seed=10)
    assert [i.seed for i in items] == [10, 11, 12] and all(i.mix == "real-like" for i in items)
    items[0].materialize(tmp_path / items[0].name, 0.01)
    truth = read_articulation(tmp_path / items[0].name)
    assert truth.metadata["generator"]["mix"] == "real-like" and truth.metadata["generator"]["kind"] == items[0].kind


def rest2art(*args):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, "-m", "rest2art.cli", *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=600)


def test_generate_command_options(tmp_path):
    run = rest2art("generate", "window", "--fit", "sunk", "--primitives", "--varied-handles", "--up", "y",
                   "--rotate-z", "90", "-o", tmp_path)
    assert run.returncode == 0, run.stderr
    folder = tmp_path / "window_0000_sunk_prim_handles_yup_rz90"
    truth = read_articulation(folder)
    assert truth.metadata["generator"]["fit"] == "sunk" and truth.metadata["generator"]["up"] == "y"
    assert np.allclose(truth.metadata["frame"]["up"], file_pose("y", 90.0)[:3, 2])
    mesh = trimesh.load(folder / "mesh.obj", force="mesh", process=False)
    assert len(np.load(folder / "face_part.npy")) == len(mesh.faces)


def test_generate_command_mix(tmp_path):
    run = rest2art("generate", "--mix", "real-like", "--count", "2", "--seed", "4", "--variant", "both",
                   "--scan-voxel", "0.012", "-o", tmp_path)
    assert run.returncode == 0, run.stderr
    names = sorted(p.name for p in tmp_path.iterdir())
    expected = sorted(f"{mix_entry('real-like', s, MIX_KINDS['real-like']).name}_{v}" for s in (4, 5) for v in VARIANTS)
    assert names == expected
    both = rest2art("generate", "safe", "--mix", "real-like", "-o", tmp_path / "x")
    assert both.returncode == 2 and both.stderr.count("\n") == 1 and "not both" in both.stderr
    unknown = rest2art("generate", "sofa", "-o", tmp_path / "y")
    assert unknown.returncode == 2 and "sliding_cabinet" in unknown.stderr


# ---- furniture -------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(4))
def test_furnished_furniture_stands_on_legs_or_under_a_top_and_moves_free(seed):
    """A furnished object keeps its layout, lifted onto its legs (its joints with it), and
    gains a top board reaching past its sides and front; nothing it adds stands in a part's way."""
    from rest2art.generate.furniture import FURNITURE_KINDS

    for kind in FURNITURE_KINDS:
        plain_obj = generate_object(kind, seed, "asset", variation=Variation("flush", varied_handles=True))
        plain = plain_obj.spec
        obj = generate_object(kind, seed, "asset", variation=Variation("flush", varied_handles=True, furnished=True))
        params = obj.spec.params
        assert "legs" in params or "top_thickness" in params
        lift = params.get("legs", 0.0)
        assert [p.name for p in obj.spec.parts] == [p.name for p in plain.parts]
        for p, q in zip(obj.spec.parts[1:], plain.parts[1:]):
            assert np.allclose(np.asarray(p.joint["origin"]) - q.joint["origin"], [0.0, 0.0, lift])
        base = obj.asset.part("base").mesh
        carcass_lo = np.min([s.bounds()[0] for s in plain.parts[0].pieces], axis=0)
        if lift:  # four legs hold the floor: what lies within 1 mm of it is a small share of the footprint
            floor = base.triangles_center[:, 2] < 1e-3
            foot = base.area_faces[floor & (base.face_normals[:, 2] < -0.9)].sum()
            assert base.bounds[0, 2] == pytest.approx(0.0) and foot < 0.1 * np.prod(np.ptp(base.bounds, axis=0)[:2])
        if "top_thickness" in params:  # the top reaches past the carcass's front
            assert base.bounds[0, 1] < carcass_lo[1] - 0.009
        pairs = lambda a: {(run, o.pair) for run, found in motion_overlaps(a, samples=4).items() for o in found}  # noqa: E731
        assert pairs(obj.asset) <= pairs(plain_obj.asset)


def test_the_furniture_mix_draws_furniture_furnished(tmp_path):
    from rest2art.bench import mix_items
    from rest2art.generate import MIX_KINDS
    from rest2art.generate.furniture import FURNITURE_KINDS

    entries = [mix_entry("furniture", seed, MIX_KINDS["furniture"]) for seed in range(12)]
    assert {e.kind for e in entries} == {*FURNITURE_KINDS, "desk"}
    furnished = [e for e in entries if e.kind != "desk"]  # a desk stands on its own legs
    assert all(e.variation.furnished and e.name.split("_furnished")[0] != e.name for e in furnished)
    items = mix_items("furniture", 2, "asset", seed=3)
    items[0].materialize(tmp_path / items[0].name, 0.01)
    truth = read_articulation(tmp_path / items[0].name)
    assert truth.metadata["generator"]["mix"] == "furniture" and truth.metadata["generator"]["furnished"]


@pytest.mark.parametrize("seed", range(6))
def test_a_furnished_box_stands_on_legs_under_its_own_lid(seed):
    """A lid opens where a top board would lie: a furnished box always gets legs, never a top."""
    obj = generate_object("box", seed, "asset", variation=Variation(furnished=True))
    assert obj.spec.params["legs"] > 0.0 and "top_thickness" not in obj.spec.params
    assert obj.asset.part("lid_0").mesh.bounds[1, 2] == pytest.approx(obj.mesh.bounds[1, 2])


@pytest.mark.parametrize("seed", [45, 81, 87])
def test_open_shelves_leave_door_cells_open_and_keep_the_rest(seed):
    """A furniture cabinet with open shelves is its closed self with some door cells left
    without a front: every front it keeps is one of the closed cabinet's, at least one stays,
    and where a door was the carcass is open to at least half its depth."""
    from rest2art.generate import MIX_KINDS

    entry = mix_entry("furniture", seed, MIX_KINDS["furniture"])
    assert entry.kind == "cabinet" and entry.variation.open_shelves
    obj = generate_object("cabinet", seed, "asset", variation=entry.variation)
    closed = generate_object("cabinet", seed, "asset", variation=Variation(
        entry.variation.fit, entry.variation.primitives, entry.variation.varied_handles, furnished=True))
    origins = lambda o: {tuple(np.round(j.origin, 6)) for j in o.asset.movable_joints}  # noqa: E731
    assert 0 < len(origins(obj)) < len(origins(closed)) and origins(obj) <= origins(closed)
    base = obj.asset.part("base").mesh
    depth = float(np.ptp(base.bounds[:, 1]))
    for joint in closed.asset.movable_joints:
        if tuple(np.round(joint.origin, 6)) in origins(obj):
            continue
        lo, hi = closed.asset.part(joint.child).mesh.bounds
        centre = (lo + hi) / 2 + [0.0, 0.0, (hi[2] - lo[2]) / 4]  # above a shelf halfway up
        start = centre - [0.0, 0.1, 0.0]
        hits, _, _ = base.ray.intersects_location([start], [[0.0, 1.0, 0.0]], multiple_hits=False)
        assert len(hits) == 1 and hits[0, 1] - centre[1] > depth / 2, joint.child


def test_the_furniture_mix_opens_shelves_only_in_cabinets_and_draws_desks_for_some():
    from rest2art.generate import MIX_KINDS

    entries = [mix_entry("furniture", seed, MIX_KINDS["furniture"]) for seed in range(300)]
    opened = [e for e in entries if e.variation.open_shelves]
    cabinets = [e for e in entries if e.kind == "cabinet"]
    assert {e.kind for e in opened} == {"cabinet"} and 0.35 < len(opened) / len(cabinets) < 0.65
    assert 0.2 < sum(e.kind == "desk" for e in entries) / (len(cabinets) + sum(e.kind == "desk" for e in entries)) < 0.45
    assert all(e.name.endswith(("_open", "_open_yup")) or "_open_" in e.name for e in opened)


@pytest.mark.parametrize("fit", FITS)
def test_desks_move_free_over_open_knee_room(fit):
    """A desk's drawers, in its frame or its pedestal, slide out free of everything; under the
    frame there is knee room: a ray straight down from under the top, between the frame's
    drawers and the legs or the pedestal, meets nothing but the floor."""
    kinds = set()
    for seed in range(4):
        obj = generate_object("desk", seed, "asset", variation=Variation(fit, varied_handles=True))
        check_overlaps(motion_overlaps(obj.asset, samples=6), obj.spec.params.get("sink", 0.0))
        params, base = obj.spec.params, obj.asset.part("base").mesh
        kinds.add(bool(params["pedestal"]))
        assert len(obj.asset.movable_joints) >= 1 and all(j.type == "prismatic" for j in obj.asset.movable_joints)
        assert base.bounds[1, 2] == pytest.approx(params["height"])
        # under the frame's middle (beside the pedestal, if any), just below it
        x = -params["pedestal_side"] * params["pedestal"] / 2
        start = [x, 0.0, params["height"] - params["top_thickness"] - params["apron"] - 0.01]
        assert not base.ray.intersects_any([start], [[0.0, 0.0, -1.0]])[0]
    assert kinds == {True, False}


@pytest.mark.parametrize("seed", [60, 90])  # a cabinet with varied handles, a desk; both unturned, +z up
def test_the_framed_mix_is_the_furniture_mix_with_shaker_fronts(seed):
    """``framed`` draws the furniture mix's object for each seed with framed fronts: the same
    parts and joints, every door and drawer front a frame around a field sunk a few millimetres,
    and every handle standing on the face it is fixed to (a pull in the field does not float
    over it)."""
    from rest2art.generate import MIX_KINDS, generate_mix_object
    from rest2art.generate.objects import FIELD_DEPTH

    plain, framed = mix_entry("furniture", seed, MIX_KINDS["furniture"]), mix_entry("framed", seed, MIX_KINDS["framed"])
    assert framed.variation.framed_fronts and framed.name == plain.name.replace(
        plain.variation.tag(), plain.variation.tag() + "_framed")
    a, b = generate_mix_object("furniture", seed, "asset"), generate_mix_object("framed", seed, "asset")
    assert [(j.child, j.type) for j in a.asset.joints] == [(j.child, j.type) for j in b.asset.joints]
    fronts = [p for p in b.asset.parts if p.semantic in ("door", "drawer")]
    assert fronts
    def field_step(mesh) -> bool:  # two faces turned to the front FIELD_DEPTH apart: frame and field
        levels = np.unique(np.round(mesh.triangles_center[mesh.face_normals @ FRONT > 0.99] @ FRONT, 4))
        return bool(np.isclose(levels[:, None] - levels[None, :], FIELD_DEPTH, atol=2e-4).any())

    for part in fronts:
        mesh = part.mesh
        assert field_step(mesh) and not field_step(a.asset.part(part.name).mesh), part.name
        pieces = lambda m: len(np.unique(connected_components(m.faces, len(m.vertices))))  # noqa: E731
        assert pieces(mesh) == pieces(a.asset.part(part.name).mesh), part.name
