import numpy as np
import pytest
import trimesh

from rest2art.completion.solids import mass_properties, solid_pieces, solidify_shell


def test_open_shell_is_thickened_into_a_volume():
    box = trimesh.creation.box([0.4, 0.3, 0.2])
    top = box.face_normals[:, 2] > 0.9
    shell = trimesh.Trimesh(box.vertices, box.faces[~top], process=False)  # open tray
    assert not shell.is_watertight
    solid = solidify_shell(shell, np.full(len(shell.vertices), 0.01))
    assert solid.is_watertight and solid.volume > 0
    # the volume of a thin wall is about area x thickness
    assert solid.volume == pytest.approx(shell.area * 0.01, rel=0.25)


def test_a_shell_pinched_where_holes_meet_or_sheets_share_an_edge_still_thickens_into_a_volume():
    # a 4 x 4 sheet of 5 cm cells with two holes touching at one corner (a culled scan's bow-tie)
    # and a fin standing on an inner edge (three faces on one edge)
    xs, ys = np.meshgrid(np.arange(5) * 0.05, np.arange(5) * 0.05, indexing="ij")
    vertices = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(25)])
    at = lambda i, j: 5 * i + j  # noqa: E731
    faces = [f for i in range(4) for j in range(4) if (i, j) not in ((1, 1), (2, 2))
             for f in ([at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)])]
    vertices = np.vstack([vertices, [[0.15, 0.0, 0.05], [0.15, 0.05, 0.05]]])
    faces += [[at(3, 0), 26, 25], [at(3, 0), at(3, 1), 26]]
    shell = trimesh.Trimesh(vertices, faces, process=False)
    solid = solidify_shell(shell, np.full(len(shell.vertices), 0.005))
    assert solid.is_watertight and solid.volume > 0
    assert solid.volume == pytest.approx(shell.area * 0.005, rel=0.25)


def test_closed_pieces_stay_as_they_are():
    a = trimesh.creation.box([0.1, 0.1, 0.1])
    b = trimesh.creation.box([0.1, 0.1, 0.1])
    b.apply_translation([0.5, 0, 0])
    solids, notes = solid_pieces(trimesh.util.concatenate([a, b]), None)
    assert len(solids) == 2 and not notes
    assert sum(s.volume for s in solids) == pytest.approx(0.002)



def test_closed_pieces_whose_corners_are_repeated_per_triangle_stay_closed():
    """An STL (or a flat-shaded export) repeats every corner for each triangle: by vertex index
    each triangle is a shell of its own, and each was thickened as an open sheet. By position
    the two boxes are two closed pieces, as when their corners are shared."""
    a = trimesh.creation.box([0.1, 0.1, 0.1])
    b = trimesh.creation.box([0.1, 0.1, 0.1])
    b.apply_translation([0.5, 0, 0])
    both = trimesh.util.concatenate([a, b])
    corners = both.vertices[both.faces].reshape(-1, 3)
    soup = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False)
    solids, notes = solid_pieces(soup, None)
    assert len(solids) == 2 and not notes
    assert sum(s.volume for s in solids) == pytest.approx(0.002)

def test_box_inertia_matches_closed_form():
    w, d, h, rho = 0.4, 0.3, 0.2, 500.0
    box = trimesh.creation.box([w, d, h])
    box.apply_translation([1.0, 2.0, 3.0])
    props = mass_properties([box], rho)
    m = w * d * h * rho
    assert props.mass == pytest.approx(m)
    assert np.allclose(props.com, [1, 2, 3])
    expected = m / 12 * np.array([d * d + h * h, w * w + h * h, w * w + d * d])
    assert np.allclose(np.diag(props.inertia), expected, rtol=1e-6)


def test_two_pieces_use_parallel_axis():
    a = trimesh.creation.box([0.1, 0.1, 0.1])
    b = a.copy()
    a.apply_translation([-0.5, 0, 0])
    b.apply_translation([0.5, 0, 0])
    props = mass_properties([a, b], 1000.0)
    m = 1.0  # each
    own = m / 12 * 0.02
    assert props.inertia[1, 1] == pytest.approx(2 * (own + m * 0.25))


def test_a_dense_open_shell_gets_a_small_watertight_collision_solid():
    from rest2art.completion.solids import collision_solids
    from rest2art.config import CompletionConfig

    sphere = trimesh.creation.icosphere(subdivisions=6, radius=0.3)  # 81,920 faces
    keep = sphere.triangles_center[:, 2] < 0.1  # an open bowl
    shell = trimesh.Trimesh(sphere.vertices, sphere.faces[keep], process=True)
    shell.remove_unreferenced_vertices()
    solids, _ = solid_pieces(shell, None, CompletionConfig())
    assert len(solids[0].faces) > 50_000
    small = collision_solids(shell, solids, None, CompletionConfig(), max_faces=4000)
    assert small and all(s.is_watertight and s.volume > 0 for s in small)
    assert sum(len(s.faces) for s in small) <= 4400
    assert abs(sum(s.volume for s in small) - solids[0].volume) < 0.1 * solids[0].volume


def test_a_flat_drawer_front_gets_a_tray_reaching_back_to_the_carcass():
    from rest2art.completion.solids import drawer_tray
    from rest2art.config import CompletionConfig

    config = CompletionConfig()
    front = trimesh.creation.box((0.40, 0.02, 0.20))  # width x, thin along y, height z
    front.apply_translation([0.0, -0.29, 0.5])  # slides out along -y; the carcass back is at y = +0.3
    tray = drawer_tray(front, np.array([0.0, -1.0, 0.0]), np.array([0.0, 0.0, 1.0]), -0.3, config)
    assert tray is not None and tray.is_watertight and tray.volume > 0
    lo, hi = tray.bounds
    assert np.allclose([hi[0] - lo[0], hi[2] - lo[2]], [0.75 * 0.40, 0.75 * 0.20], atol=1e-6)
    assert np.isclose(lo[1], -0.28, atol=1e-6)  # flush with the back of the front
    assert np.isclose(hi[1], 0.3 - config.thickness - config.tray_clearance, atol=1e-6)
    assert tray.volume < 0.5 * np.prod(hi - lo)  # hollow, open at the top
    deep = trimesh.creation.box((0.40, 0.30, 0.20))  # a modelled drawer box needs none
    assert drawer_tray(deep, np.array([0.0, -1.0, 0.0]), np.array([0.0, 0.0, 1.0]), -0.3, config) is None


def test_normals_along_a_ragged_cut_edge_come_from_the_interior():
    from rest2art.geometry.offsets import boundary_smoothed_normals

    n = 21
    xs, ys = np.meshgrid(np.linspace(0, 0.4, n), np.linspace(0, 0.4, n))
    vertices = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    quads = np.column_stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()])
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    edge = (xs.ravel() < 1e-9) | (xs.ravel() > 0.4 - 1e-9) | (ys.ravel() < 1e-9) | (ys.ravel() > 0.4 - 1e-9)
    rng = np.random.default_rng(0)
    vertices[edge, 2] += rng.uniform(-0.01, 0.01, edge.sum())  # a ragged cut
    grid = trimesh.Trimesh(vertices, faces, process=False)
    raw = np.array(grid.vertex_normals)
    smooth = boundary_smoothed_normals(grid, rings=3)
    up = np.array([0.0, 0.0, 1.0])
    assert np.degrees(np.arccos(np.clip(raw[edge] @ up, -1, 1))).max() > 20
    assert np.degrees(np.arccos(np.clip(smooth[edge] @ up, -1, 1))).max() < 5
    interior = ~edge & (xs.ravel() > 0.1) & (xs.ravel() < 0.3) & (ys.ravel() > 0.1) & (ys.ravel() < 0.3)
    assert np.allclose(smooth[interior], raw[interior])


def test_scan_parts_complete_into_valid_volumes_that_do_not_overlap():
    """Cut a fused scan along its true part labels: every completed part is a volume manifold3d
    accepts, and the parts' solids overlap by (almost) nothing at rest."""
    import manifold3d

    from rest2art.config import CompletionConfig
    from rest2art.generate import generate_object
    from rest2art.geometry.basics import is_closed_volume

    obj = generate_object("cabinet", 2, "scan")
    mesh = obj.mesh
    shells = []
    for k in range(len(obj.asset.parts)):
        shell = trimesh.Trimesh(mesh.vertices, mesh.faces[obj.face_part == k], process=True)
        shell.remove_unreferenced_vertices()
        shells.append(shell)
    solids = []
    for k, shell in enumerate(shells):
        others = np.concatenate([s.vertices for j, s in enumerate(shells) if j != k])
        pieces, _ = solid_pieces(shell, others, CompletionConfig())
        assert pieces and all(is_closed_volume(p) for p in pieces)
        solids.append(pieces)

    def manifold(pieces):
        out = manifold3d.Manifold()
        for p in pieces:
            out = out + manifold3d.Manifold(manifold3d.Mesh(np.asarray(p.vertices, np.float32),
                                                            np.asarray(p.faces, np.uint32)))
        return out

    base = manifold(solids[0])
    for pieces in solids[1:]:
        overlap = (base ^ manifold(pieces)).volume()
        assert overlap < 0.01 * sum(p.volume for p in pieces)


def test_a_knob_cut_from_a_surface_is_capped_not_thickened_into_it():
    from rest2art.config import CompletionConfig

    dome = trimesh.creation.icosphere(subdivisions=3, radius=0.02)
    shell = trimesh.Trimesh(dome.vertices, dome.faces[dome.triangles_center[:, 1] < -0.005], process=True)
    shell.remove_unreferenced_vertices()  # the front of a knob; its rim lies in the plane y = -0.005
    solids, notes = solid_pieces(shell, None, CompletionConfig(), cap=True)
    assert "capped" in notes[0] and solids[0].is_watertight
    assert solids[0].bounds[1, 1] <= -0.005 + 1e-3  # nothing behind the rim, nothing into the panel
    thick, _ = solid_pieces(shell, None, CompletionConfig())
    assert thick[0].bounds[1, 1] > solids[0].bounds[1, 1] + 0.005  # thickening reaches behind it


def test_a_decomposition_worker_stops_when_its_parent_dies(tmp_path):
    """CoACD runs in a child process; killing the parent must not leave it running."""
    import os
    import signal
    import subprocess
    import sys
    import time

    mesh = trimesh.creation.icosphere(subdivisions=5)
    src = tmp_path / "in.npz"
    np.savez(src, vertices=mesh.vertices, faces=mesh.faces)
    # the parent starts a worker that would run for minutes, prints its pid, then waits
    code = ("import subprocess, sys, time; p = subprocess.Popen([sys.executable, '-m', 'rest2art.collision.hulls', "
            f"'{src}', '{tmp_path / 'out.npz'}', '{{\"threshold\": 0.001, \"mcts_iterations\": 2000}}', '600']); "
            "print(p.pid, flush=True); time.sleep(600)")
    parent = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    child = int(parent.stdout.readline())
    time.sleep(2.0)
    os.kill(parent.pid, signal.SIGKILL)
    parent.wait()
    for _ in range(50):
        time.sleep(0.2)
        try:
            os.kill(child, 0)
        except ProcessLookupError:
            break
    else:
        os.kill(child, signal.SIGKILL)
        raise AssertionError("the worker outlived its parent")


def _slab(lo, hi):
    box = trimesh.creation.box(np.subtract(hi, lo))
    box.apply_translation(np.add(lo, hi) / 2)
    return box


def test_clipping_a_hull_keeps_the_side_below_the_plane():
    from rest2art.collision.clearance import clip_hull

    box = trimesh.creation.box((1.0, 1.0, 1.0))
    kept, removed = clip_hull(box, np.array([1.0, 0.0, 0.0]), 0.2)
    assert kept.volume == pytest.approx(0.7)
    assert kept.vertices[:, 0].max() == pytest.approx(0.2) and removed[:, 0].min() == pytest.approx(0.2)
    assert clip_hull(box, np.array([1.0, 0.0, 0.0]), -0.6)[0] is None  # nothing left
    assert clip_hull(box, np.array([1.0, 0.0, 0.0]), 0.6)[0] is box  # nothing cut


@pytest.mark.parametrize("share", [1.0, 0.5])
def test_overlapping_hulls_are_clipped_apart_with_a_gap(share):
    from rest2art.collision.clearance import ClearanceLog, separate_hulls
    from rest2art.geometry.basics import convex_overlap

    wall, panel = _slab((-0.3, 0.0, 0.0), (0.3, 0.02, 0.4)), _slab((-0.1, 0.016, 0.1), (0.1, 0.036, 0.3))
    log_a, log_b = ClearanceLog(), ClearanceLog()
    (a,), (b,) = separate_hulls([wall], [panel], share, clearance=0.0005, max_depth=0.03, log_a=log_a, log_b=log_b)
    assert convex_overlap(a.vertices, a.face_normals, b.vertices, b.face_normals)[0] == 0.0
    gap = b.vertices[:, 1].min() - a.vertices[:, 1].max()
    assert gap == pytest.approx(0.0005)
    assert a.vertices[:, 1].max() == pytest.approx(0.02 - share * 0.0045)  # 4 mm overlap + the gap, shared
    assert log_a.clipped == 1 and log_a.deepest_mm == pytest.approx(4.0)
    assert (b is panel) == (share == 1.0)
    deep = _slab((-0.1, -0.02, 0.1), (0.1, 0.036, 0.3))  # 40 mm into the wall: not an approximation error
    (a2,), _ = separate_hulls([wall], [deep], 1.0, clearance=0.0005, max_depth=0.03, log_a=log_a)
    assert a2 is wall and log_a.left == 1


def test_siblings_are_cut_apart_by_a_plane_that_holds_while_they_swing():
    """Two stacked doors on vertical hinges: the lower one's hull pokes 15 mm up into the upper
    one at a corner. Cutting that corner off along its slanted face keeps the most volume, but
    the upper door turns the cut away within degrees; the cut must be level (normal to the
    hinges), which no rotation about them undoes."""
    from rest2art.collision.clearance import ClearanceLog, separate_hulls
    from rest2art.collision.hulls import closed_hull

    box = np.array([[x, y, z] for x in (0, 0.3) for y in (0, 0.04) for z in (0, 1)], float)
    lower = closed_hull(np.vstack([box * [1, 1, 0.5], [[0.29, 0.02, 0.52]]]))
    upper = closed_hull(box * [1, 1, 0.495] + [0, 0, 0.505])
    hinges = (("revolute", np.array([0.0, 0.0, 1.0])),) * 2
    for motions, level in (((), False), (hinges, True)):
        (a,), (b,) = separate_hulls([lower], [upper], 0.5, clearance=0.0005, max_depth=0.03,
                                    log_a=ClearanceLog(), log_b=ClearanceLog(), motions=motions)
        bottom = b.vertices[b.vertices[:, 2] < 0.53, 2]
        assert (np.ptp(bottom) < 1e-9) == level
    assert bottom.min() == pytest.approx(a.vertices[:, 2].max() + 0.0005)


def test_stacked_drawers_that_only_meet_when_one_slides_are_cut_level():
    """Two drawers' hulls part along a slanted plane at rest, 0.2 mm apart: sliding the lower
    one out drives its top into the upper one. The sweep finds it and both are cut by a level
    plane, which the slide cannot undo."""
    from rest2art.asset import Joint
    from rest2art.collision.clearance import ClearanceLog, separate_hulls, swept_hull
    from rest2art.collision.hulls import closed_hull
    from rest2art.geometry.basics import convex_overlap

    box = np.array([[x, y, z] for x in (0, 0.3) for y in (-0.3, 0) for z in (0, 1)], float)
    slope = 0.01 * (box[:, 1] + 0.3) / 0.3  # 1 cm higher at the back
    lower = closed_hull(np.column_stack([box[:, :2], np.where(box[:, 2] > 0, 0.2 + slope, 0.0)]))
    upper = closed_hull(np.column_stack([box[:, :2], np.where(box[:, 2] > 0, 0.4, 0.2002 + slope)]))
    assert convex_overlap(lower.vertices, lower.face_normals, upper.vertices, upper.face_normals)[0] == 0.0
    slide = Joint("lower_joint", "prismatic", "base", "lower", [0.0, -1.0, 0.0], [0.0, 0.0, 0.0], (0.0, 0.25))
    log_a, log_b = ClearanceLog(), ClearanceLog()
    (a,), (b,) = separate_hulls([lower], [upper], 0.5, clearance=0.0005, max_depth=0.03, log_a=log_a, log_b=log_b,
                                motions=(("prismatic", slide.axis),), sweep_a=lambda h: swept_hull(h, slide, 8))
    assert log_a.clipped == 1 and log_b.clipped == 1
    out = a.copy().apply_transform(slide.transform(0.25))
    assert convex_overlap(out.vertices, out.face_normals, b.vertices, b.face_normals)[0] == 0.0
    assert b.vertices[:, 2].min() == pytest.approx(a.vertices[:, 2].max() + 0.0005)


def _scanned_slab(lo, hi, rng):
    """A thin slab's hull as a scan gives it: its broad faces (normal y) sampled on a grid with
    0.3 mm of noise, so that many of its faces lean a little off the axes."""
    from rest2art.collision.hulls import closed_hull

    grid = np.array([[x, z] for x in np.linspace(lo[0], hi[0], 6) for z in np.linspace(lo[2], hi[2], 6)])
    sides = [np.column_stack([grid[:, 0], np.full(len(grid), y), grid[:, 1]]) for y in (lo[1], hi[1])]
    points = np.vstack(sides)
    points[:, 1] += rng.uniform(-0.0003, 0.0003, len(points))
    return closed_hull(points)


def _overlap(hulls_a, hulls_b) -> float:
    from rest2art.geometry.basics import convex_overlap

    return max(convex_overlap(a.vertices, a.face_normals, b.vertices, b.face_normals)[0]
               for a in hulls_a for b in hulls_b)


def test_a_door_beside_a_drawer_is_parted_across_the_plane_their_motions_span():
    """Scanned real-like cabinet 416: a door (hinged about z) over the corner of a drawer
    (sliding along -y), both thin front slabs that overlap 2 mm in depth and 7 mm sideways. No
    face plane of either hull holds for both motions and their leaning faces crowd out the
    sideways one; the plane normal to x, which the two motion axes span, parts them."""
    from rest2art.asset import ArticulatedAsset, Joint, Part
    from rest2art.collision.clearance import clear_asset_hulls

    rng = np.random.default_rng(0)
    door = _scanned_slab((0.124, -0.2253, 0.42), (0.393, -0.2228, 0.88), rng)
    drawer = _scanned_slab((-0.144, -0.2258, 0.345), (0.1306, -0.2234, 0.484), rng)
    assert _overlap([door], [drawer]) > 0.001
    asset = ArticulatedAsset(
        [Part("base", "base", None, collision=[_slab((-0.4, -0.22, 0.0), (0.4, 0.2, 0.9))]),
         Part("door_0", "door", "base", collision=[door]), Part("drawer_0", "drawer", "base", collision=[drawer])],
        [Joint("door_0_joint", "revolute", "base", "door_0", [0.0, 0.0, 1.0], [0.4, -0.2187, 0.65], (0.0, 1.57)),
         Joint("drawer_0_joint", "prismatic", "base", "drawer_0", [0.0, -1.0, 0.0], [0.0, -0.23, 0.25], (0.0, 0.4))])
    log = clear_asset_hulls(asset)
    assert log["door_0"]["left"] == 0
    assert _overlap(asset.part("door_0").collision, asset.part("drawer_0").collision) == 0.0
    door_x = min(h.bounds[0][0] for h in asset.part("door_0").collision)
    drawer_x = max(h.bounds[1][0] for h in asset.part("drawer_0").collision)
    assert door_x - drawer_x >= 0.0025 - 1e-6  # parted sideways, by the siblings' gap


def test_a_speck_of_one_door_in_the_groove_beside_the_next_is_dropped():
    """Two doors meeting in the middle; the scan left a 3 x 3 x 8 mm speck of the right door in
    the groove, 0.2 mm from the left door. The speck goes; each door's panel stays whole."""
    from rest2art.asset import ArticulatedAsset, Joint, Part
    from rest2art.collision.clearance import clear_asset_hulls

    right = _slab((0.002, -0.02, 0.0), (0.5, 0.0, 1.5))
    speck = _slab((-0.0012, -0.012, 0.8), (0.0018, -0.009, 0.808))
    left = _slab((-0.5, -0.02, 0.0), (-0.0014, 0.0, 1.5))
    asset = ArticulatedAsset(
        [Part("base", "base", None, collision=[_slab((-0.5, 0.0, 0.0), (0.5, 0.4, 1.5))]),
         Part("door_0", "door", "base", collision=[right, speck]), Part("door_1", "door", "base", collision=[left])],
        [Joint("door_0_joint", "revolute", "base", "door_0", [0.0, 0.0, 1.0], [0.5, -0.02, 0.75], (0.0, 1.57)),
         Joint("door_1_joint", "revolute", "base", "door_1", [0.0, 0.0, -1.0], [-0.5, -0.02, 0.75], (0.0, 1.57))])
    log = clear_asset_hulls(asset)
    assert log["door_0"]["dropped"] == 1 and log["door_1"]["dropped"] == 0
    assert len(asset.part("door_0").collision) == 1
    assert asset.part("door_0").collision[0].volume == pytest.approx(right.volume)
    assert asset.part("door_1").collision[0].volume == pytest.approx(left.volume)


def test_hulls_are_cut_back_to_the_box_of_the_solids_they_stand_for():
    """A decimated scan shell folds out: a hull reaching 3 cm in front of the door slab it
    approximates is cut back to the slab's box (plus the margin), one lying wholly outside it
    goes, one inside stays as it is. The box is along the object's axes, here turned 30 degrees
    about z."""
    from rest2art.collision.clearance import clip_to_solids

    turn = trimesh.transformations.rotation_matrix(np.radians(30.0), [0, 0, 1])
    axes = turn[:3, :3].T  # rows: the object's side, front and up in the input frame
    slab = _slab((-0.2, 0.0, 0.0), (0.2, 0.02, 0.5)).apply_transform(turn)
    inside = _slab((-0.1, 0.005, 0.1), (0.1, 0.015, 0.4)).apply_transform(turn)
    bulging = _slab((0.1, -0.03, 0.2), (0.15, 0.01, 0.3)).apply_transform(turn)
    outside = _slab((0.1, -0.05, 0.2), (0.15, -0.01, 0.3)).apply_transform(turn)
    hulls, cut = clip_to_solids([inside, bulging, outside], [slab], axes, margin=0.002)
    assert cut == 2 and len(hulls) == 2
    assert hulls[0] is inside
    front = (hulls[1].vertices @ axes[1]).min()
    assert front == pytest.approx(-0.002)  # the slab's front face, less the margin
    assert hulls[1].volume == pytest.approx(0.05 * 0.012 * 0.1)


def _door_asset(hinge_x: float, axis_z: float):
    """A door 0.3 m wide and 2 cm thick in a frame: a side wall flush with its left edge, a top
    rail that overlaps it by 2 mm, and a back wall; the hinge on its left back edge."""
    from rest2art.asset import ArticulatedAsset, Joint, Part

    base = Part("base", "base", None, collision=[_slab((-0.03, -0.02, 0.0), (0.0, 0.3, 0.4)),
                                                 _slab((0.0, -0.02, 0.398), (0.3, 0.3, 0.42)),
                                                 _slab((0.0, 0.28, 0.0), (0.3, 0.3, 0.398))])
    door = Part("door_0", "door", "base", collision=[_slab((0.0, -0.02, 0.0), (0.3, 0.0, 0.4))])
    joint = Joint("door_0_joint", "revolute", "base", "door_0", [0.0, 0.0, axis_z], [hinge_x, 0.0, 0.2], (0.0, 1.6))
    return ArticulatedAsset([base, door], [joint])


def _deepest_over_range(asset, samples: int = 64) -> float:
    from rest2art.geometry.basics import convex_overlap

    joint, base, door = asset.joints[0], asset.part("base").collision, asset.part("door_0").collision
    deepest = 0.0
    for value in np.linspace(0.0, joint.limit[1], samples + 1):
        posed = [h.copy().apply_transform(joint.transform(value)) for h in door]
        deepest = max(deepest, max(convex_overlap(a.vertices, a.face_normals, b.vertices, b.face_normals)[0]
                                   for a in base for b in posed))
    return deepest


def test_a_carcass_gives_way_to_its_door_at_rest_and_next_to_the_hinge_only():
    from rest2art.collision.clearance import clear_asset_hulls

    sound = _door_asset(hinge_x=0.0, axis_z=-1.0)  # swings out of the front
    before = sum(h.volume for h in sound.part("base").collision)
    assert _deepest_over_range(sound) > 0.01  # the front edge sweeps 2 cm into the side wall
    log = clear_asset_hulls(sound)
    assert _deepest_over_range(sound) < 0.001  # validator samples fall between the 24 used here
    assert log["base"]["clipped"] >= 2 and log["base"]["left"] == 0 and log["door_0"]["clipped"] == 0
    assert log["base"]["split"] >= 1  # the side wall is cut around the hinge; only the piece next to it gives way
    hulls = sound.part("base").collision
    back = sum(h.volume for h in hulls if h.bounds[0][1] >= 0.28 - 1e-9)
    assert back == pytest.approx(0.3 * 0.02 * 0.398)  # far from the door: untouched
    lost = before - sum(h.volume for h in hulls)
    assert 0 < lost < 0.08 ** 2 * 0.42  # no more than the hinge prism's share of the walls

    wrong = _door_asset(hinge_x=0.0, axis_z=1.0)  # swings into the carcass
    log = clear_asset_hulls(wrong)
    assert log["base"]["left"] > 0  # the back wall is 0.28 m from the hinge: left for the validator
    assert _deepest_over_range(wrong) > 0.005


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_the_farthest_a_motion_carries_points_is_exact(kind):
    from rest2art.asset import Joint
    from rest2art.joints.sweep import farthest_along, swept_points

    rng = np.random.default_rng(3)
    for _ in range(20):
        axis, direction = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        limit = tuple(np.sort(rng.uniform(-3.0, 3.0, 2) if kind == "revolute" else rng.uniform(-0.5, 0.5, 2)))
        joint = Joint("j", kind, "base", "part", axis, rng.normal(size=3), limit)
        points = rng.normal(size=(30, 3))
        sampled = float((swept_points(points, joint.transform, np.linspace(*limit, 20001)) @ direction).max())
        assert sampled - 1e-9 <= farthest_along(points, joint, direction) <= sampled + 1e-4


def test_two_doors_meeting_in_the_middle_keep_a_gap_while_either_swings():
    """Two 0.4 m doors 3 cm thick, hinged on their outer front edges, 0.5 mm apart at rest (a
    scan's fused gap, split by segmentation). Opening, a door's back inner corner first swings
    about t^2 / 2w = 1.1 mm towards its neighbour; PyBullet pads each hull by 1 mm and friction
    then holds the door. Both keep the sibling clearance at rest and at every angle."""
    from rest2art.asset import ArticulatedAsset, Joint, Part
    from rest2art.collision.clearance import clear_asset_hulls
    from rest2art.config import CollisionConfig
    from rest2art.geometry.fcl import bvh_object, distance

    config = CollisionConfig()
    base = Part("base", "base", None, collision=[_slab((-0.4, 0.03, 0.0), (0.4, 0.3, 0.6))])
    left = Part("door_0", "door", "base", collision=[_slab((-0.4, 0.0, 0.0), (-0.00025, 0.03, 0.6))])
    right = Part("door_1", "door", "base", collision=[_slab((0.00025, 0.0, 0.0), (0.4, 0.03, 0.6))])
    joints = [Joint("door_0_joint", "revolute", "base", "door_0", [0.0, 0.0, -1.0], [-0.4, 0.0, 0.3], (0.0, 1.6)),
              Joint("door_1_joint", "revolute", "base", "door_1", [0.0, 0.0, 1.0], [0.4, 0.0, 0.3], (0.0, 1.6))]
    asset = ArticulatedAsset([base, left, right], joints)
    clear_asset_hulls(asset, config)
    (a,), (b,) = asset.part("door_0").collision, asset.part("door_1").collision
    for moving, still, joint in ((a, b, joints[0]), (b, a, joints[1])):
        gaps = []
        for value in np.linspace(0.0, 0.2, 81):
            posed = moving.copy().apply_transform(joint.transform(value))
            gaps.append(distance(bvh_object(posed.vertices, posed.faces), bvh_object(still.vertices, still.faces)))
        assert min(gaps) >= config.sibling_clearance - 1e-6
    assert sum(h.volume for h in (a, b)) > 0.99 * 2 * 0.4 * 0.03 * 0.6  # a strip at the meeting edge, no more


def test_a_board_beside_a_drawer_gives_way_along_its_run_by_millimetres_only():
    """Scanned desk 165: a drawer's front sits 2 cm behind the face of the board beside it and
    the part boundary fell 6 mm into the drawer, so the board's hull reaches 6 mm across the
    drawer's side. At rest they only touch; drawn out, the drawer runs through that strip. The
    board gives way by a plane parallel to the run (its volume less the strip); a board reaching
    2 cm across is a wrong part, left for the validator."""
    from rest2art.asset import ArticulatedAsset, Joint, Part
    from rest2art.collision.clearance import clear_asset_hulls
    from rest2art.config import CollisionConfig

    def asset(reach: float):
        base = Part("base", "base", None, collision=[_slab((-0.2, -0.04, 0.45), (reach, -0.02, 0.75)),
                                                     _slab((-0.2, 0.3, 0.0), (0.6, 0.32, 0.75))])
        drawer = Part("drawer_0", "drawer", "base", collision=[_slab((0.0, -0.02, 0.5), (0.4, 0.0, 0.65)),
                                                               _slab((0.02, 0.0, 0.52), (0.38, 0.28, 0.54))])
        joint = Joint("drawer_0_joint", "prismatic", "base", "drawer_0", [0.0, -1.0, 0.0], [0.2, -0.02, 0.57], (0.0, 0.25))
        return ArticulatedAsset([base, drawer], [joint])

    def deepest(a) -> float:
        joint = a.joints[0]
        posed = [[h.copy().apply_transform(joint.transform(v)) for h in a.part("drawer_0").collision]
                 for v in np.linspace(0.0, joint.limit[1], 9)]
        return max(_overlap(a.part("base").collision, hulls) for hulls in posed)

    near = asset(0.006)
    assert _overlap(near.part("base").collision, near.part("drawer_0").collision) < 1e-9  # touching at rest
    assert deepest(near) > 0.005
    log = clear_asset_hulls(near)
    assert log["base"]["deepest_mm"] == pytest.approx(6.0) and log["drawer_0"]["clipped"] == 0
    assert deepest(near) < 1e-9
    board = min(near.part("base").collision, key=lambda h: h.bounds[0][1])
    assert board.bounds[1][0] == pytest.approx(-CollisionConfig().clearance)  # cut along the run, not across it
    assert board.bounds[0][1] == pytest.approx(-0.04) and board.bounds[1][2] == pytest.approx(0.75)

    far = asset(0.02)
    log = clear_asset_hulls(far)
    assert log["base"]["deepest_mm"] < 1.0 and deepest(far) > 0.008


def test_a_button_pushed_into_its_box_gets_its_bore_carved_out_of_the_box_hull():
    """A button 4 cm across standing 1 cm proud of a box whose collision is one solid hull (the
    decomposition filled the bore): pushing it 2 cm in drives it into that hull. Clearance carves
    the bore, the box keeps the rest of its volume, and a drawer of the same size sliding out of
    the same face (or a 'drawer' wrongly slid inwards) leaves the box alone."""
    from rest2art.asset import ArticulatedAsset, Joint, Part
    from rest2art.collision.clearance import clear_asset_hulls
    from rest2art.config import CollisionConfig
    from rest2art.geometry.basics import convex_overlap

    def asset(semantic: str, axis_y: float):
        box = Part("base", "base", None, collision=[_slab((-0.1, 0.0, 0.0), (0.1, 0.2, 0.2))])
        child = Part("part_0", semantic, "base", collision=[_slab((-0.02, -0.01, 0.08), (0.02, 0.0, 0.12))])
        joint = Joint("part_0_joint", "prismatic", "base", "part_0", [0.0, axis_y, 0.0], [0.0, -0.005, 0.1], (0.0, 0.02))
        return ArticulatedAsset([box, child], [joint])

    def deepest(a) -> float:
        joint = a.joints[0]
        return max(convex_overlap(b.vertices, b.face_normals, p.vertices, p.face_normals)[0]
                   for value in np.linspace(0.0, joint.limit[1], 9)
                   for p in [h.copy().apply_transform(joint.transform(value)) for h in a.part("part_0").collision]
                   for b in a.part("base").collision)

    pushed = asset("button", 1.0)
    assert deepest(pushed) > 0.019
    log = clear_asset_hulls(pushed)
    assert log["base"]["carved"] == 1 and deepest(pushed) == 0.0
    volume = sum(h.volume for h in pushed.part("base").collision)
    bore = (0.04 + 2 * CollisionConfig().clearance) ** 2 * (0.02 + CollisionConfig().clearance)
    assert volume == pytest.approx(0.2 * 0.2 * 0.2 - bore, rel=1e-6)
    assert all(h.is_convex for h in pushed.part("base").collision)

    for semantic, axis_y in (("drawer", -1.0), ("drawer", 1.0), ("button", -1.0)):
        other = asset(semantic, axis_y)
        log = clear_asset_hulls(other)
        assert log["base"]["carved"] == 0 and len(other.part("base").collision) == 1
