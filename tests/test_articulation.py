"""Articulation from motion evidence: models, classifier, truncation, consensus, grounding, and
the whole path on simulated videos of generated objects."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rest2art.config import ArticulationConfig
from rest2art.generate import generate_object
from rest2art.generate.videos import Degradation, render_motion, simulate_video
from rest2art.geometry.basics import axis_angle_deg, line_distance
from rest2art.joints.video.classify import classify_motion, motion_cues
from rest2art.joints.video.estimate import VideoEvidence, estimate_part_motions, evidence_from_frames
from rest2art.joints.video.fit import Observation, box_starts, fit_joint
from rest2art.joints.video.grounding import exposed_outward, ground_joint
from rest2art.joints.video.motion import prismatic_points, revolute_points
from rest2art.joints.video.tracks import LucasKanadeTracker, Tracks, grid_queries, truncate, truncation_frame
from rest2art.render.camera import Camera, project

CAMERA = Camera.looking_at(np.array([0.8, -2.5, 1.6]), np.array([0.0, 0.0, 0.5]), np.array([0.0, 0.0, 1.0]), 35.49, 800)


def door_anchors() -> np.ndarray:
    """(144, 3) points on a 0.4 x 0.6 m door front at y = -0.2."""
    g = np.stack(np.meshgrid(np.linspace(-0.19, 0.19, 12), np.linspace(0.2, 0.8, 12)), -1).reshape(-1, 2)
    return np.stack([g[:, 0], np.full(len(g), -0.2), g[:, 1]], axis=1)


def synthetic_tracks(points: np.ndarray, noise_px: float, seed: int = 0) -> Tracks:
    """Tracks of (T, N, 3) world points seen by CAMERA, frame 0 exact, the rest noisy."""
    rng = np.random.default_rng(seed)
    xy = project(CAMERA, points)
    xy[1:] += rng.normal(0.0, noise_px, xy[1:].shape)
    return Tracks(xy, np.ones(points.shape[:2], bool))


HINGE_AXIS, HINGE_POINT = np.array([0.0, 0.0, -1.0]), np.array([-0.2, -0.2, 0.5])
ANGLES = np.linspace(0.0, 1.4, 24)
SLIDE, OFFSETS = np.array([0.0, -1.0, 0.0]), np.linspace(0.0, 0.3, 24)


def test_revolute_fit_recovers_a_known_hinge_under_noise():
    anchors = door_anchors()
    tracks = synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, ANGLES), 1.0)
    fit = fit_joint("revolute", [Observation(CAMERA, anchors, tracks)], box_starts("revolute", anchors))
    assert axis_angle_deg(fit.axis, HINGE_AXIS) < 0.5
    assert line_distance(fit.origin, fit.axis, HINGE_POINT, HINGE_AXIS) < 0.005
    # positive values open: the fitted axis points the way the angles grew
    assert fit.axis @ HINGE_AXIS > 0 and abs(fit.amplitude - ANGLES[-1]) < 0.02
    assert fit.rmse_px < 2.0


def test_prismatic_fit_recovers_a_known_slide_and_its_offsets():
    anchors = door_anchors()
    tracks = synthetic_tracks(prismatic_points(anchors, SLIDE, OFFSETS), 1.0)
    fit = fit_joint("prismatic", [Observation(CAMERA, anchors, tracks)], box_starts("prismatic", anchors))
    assert axis_angle_deg(fit.axis, SLIDE) < 0.5 and fit.axis @ SLIDE > 0
    used = fit.frames[0]
    assert np.abs(fit.values[0] - OFFSETS[used]).max() < 0.01


def test_trimmed_refit_ignores_a_hallucinated_patch():
    anchors = door_anchors()
    points = revolute_points(anchors, HINGE_AXIS, HINGE_POINT, ANGLES)
    patch = np.argsort(np.linalg.norm(anchors - anchors[0], axis=1))[:30]  # 21 % of the door
    points[:, patch] = anchors[patch] + np.linspace(0, 1, 24)[:, None, None] * np.array([0.0, 0.0, 0.15])
    fit = fit_joint("revolute", [Observation(CAMERA, anchors, synthetic_tracks(points, 1.0))],
                    box_starts("revolute", anchors))
    assert axis_angle_deg(fit.axis, HINGE_AXIS) < 1.0
    assert fit.inlier_fraction < 0.85  # the patch was dropped


def test_joint_fit_over_two_videos_shares_the_axis():
    anchors = door_anchors()
    first = synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, ANGLES), 2.0, seed=1)
    second = synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, 0.5 * ANGLES), 2.0, seed=2)
    fit = fit_joint("revolute", [Observation(CAMERA, anchors, first), Observation(CAMERA, anchors, second)],
                    box_starts("revolute", anchors))
    assert len(fit.values) == 2
    assert abs(fit.values[1].max() - 0.5 * fit.values[0].max()) < 0.03
    assert axis_angle_deg(fit.axis, HINGE_AXIS) < 0.5


def test_classifier_tells_rotation_slide_and_stillness_apart():
    anchors = door_anchors()
    rotation = motion_cues(synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, ANGLES), 1.0))
    slide = motion_cues(synthetic_tracks(prismatic_points(anchors, SLIDE, OFFSETS), 1.0))
    still = motion_cues(synthetic_tracks(prismatic_points(anchors, SLIDE, 0 * OFFSETS), 2.0))
    assert classify_motion(rotation)[0] == "revolute" and rotation.cv > slide.cv
    assert classify_motion(slide) == ("prismatic", True) and slide.curvature < 0.01
    assert classify_motion(still)[0] == "static"
    assert abs(still.noise_px - 2.0) < 0.3  # the noise is read back from the tracks


def test_truncation_cuts_at_the_first_frame_below_half_the_visible_points():
    visible = np.ones((10, 100), bool)
    visible[4, :45] = False   # 55 % left: kept
    visible[6:, :60] = False  # 40 % left from frame 6 on
    assert truncation_frame(visible, 0.5) == 6
    tracks = truncate(Tracks(np.zeros((10, 100, 2)), visible), 0.5)
    assert tracks.n_frames == 6


def test_grid_stays_inside_the_eroded_mask():
    mask = np.zeros((200, 300), bool)
    mask[50:150, 20:220] = True  # short side 100 px: erosion 2 px
    queries = grid_queries(mask, 0.02, max_points=200)
    assert 100 <= len(queries) <= 260
    cols, rows = queries[:, 0] - 0.5, queries[:, 1] - 0.5
    assert cols.min() >= 22 and cols.max() <= 217 and rows.min() >= 52 and rows.max() <= 147


def _evidence_for(tracks: dict[str, Tracks], anchors: np.ndarray) -> VideoEvidence:
    """VideoEvidence whose depth map gives ``anchors`` at the frame-0 pixels."""
    depth = np.full((CAMERA.height, CAMERA.width), np.inf)
    for t in tracks.values():
        cols, rows = np.floor(t.xy[0, :, 0]).astype(int), np.floor(t.xy[0, :, 1]).astype(int)
        depth[rows, cols] = CAMERA.project(anchors)[1]
    return VideoEvidence(CAMERA, depth, tracks)


def _pixel_anchors() -> np.ndarray:
    """door_anchors moved onto the pixel centres they project to (so depth lookup is exact)."""
    from rest2art.render.camera import unproject

    anchors = door_anchors()
    xy, depth = CAMERA.project(anchors)
    return unproject(CAMERA, np.floor(xy) + 0.5, depth)


def test_consensus_fits_agreeing_videos_jointly_and_asks_for_more_when_all_is_still():
    anchors = _pixel_anchors()
    calls = []

    def moving(seed):
        calls.append(seed)
        return _evidence_for({"door": synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, ANGLES),
                                                         1.0, seed)}, anchors)

    result = estimate_part_motions(moving, ["door"], ArticulationConfig())["door"]
    assert calls == [0, 1] and result.combined and result.type == "revolute"
    assert axis_angle_deg(result.fit.axis, HINGE_AXIS) < 0.5

    calls.clear()

    def still(seed):
        calls.append(seed)
        return _evidence_for({"door": synthetic_tracks(np.repeat(anchors[None], 24, axis=0), 1.0, seed)}, anchors)

    result = estimate_part_motions(still, ["door"], ArticulationConfig())["door"]
    assert calls == [0, 1, 2, 3] and result.type == "static" and result.fit is None

    def one_of_two(seed):  # the first video forgot the door: the second one decides
        angles = ANGLES if seed == 1 else 0 * ANGLES
        return _evidence_for({"door": synthetic_tracks(revolute_points(anchors, HINGE_AXIS, HINGE_POINT, angles),
                                                         1.0, seed)}, anchors)

    result = estimate_part_motions(one_of_two, ["door"], ArticulationConfig())["door"]
    assert result.type == "revolute" and not result.combined
    assert [r["label"] for r in result.runs] == ["static", "revolute"]


@pytest.fixture(scope="module")
def microwave():
    return generate_object("microwave", 0, "asset").asset


def _front_camera(asset, size: int) -> Camera:
    vertices = np.concatenate([p.mesh.vertices for p in asset.parts])
    centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    return Camera.looking_at(centre + np.array([-0.6, -2.0, 1.0]), centre, np.array([0.0, 0.0, 1.0]), 35.49, size)


def test_simulated_video_of_a_generated_object_gives_its_hinge(microwave):
    camera = _front_camera(microwave, 400)
    rendered = render_motion(microwave, camera, 16)
    door = microwave.movable_joints[0]

    def make(seed):
        video = simulate_video(microwave, camera, 16, Degradation(noise_px=1.0), seed=seed, rendered=rendered)
        return VideoEvidence(video.camera, video.depth0, video.tracks)

    motion = estimate_part_motions(make, [door.child])[door.child]
    assert motion.type == "revolute"
    assert axis_angle_deg(motion.fit.axis, door.axis) < 1.0
    assert line_distance(motion.fit.origin, motion.fit.axis, door.origin, door.axis) < 0.01
    # the mesh keeps the fitted hinge on a carcass edge and bounds the opening
    part, base = microwave.part(door.child).mesh, microwave.part("base").mesh
    grounded = ground_joint(motion.fit, part, base, exposed_outward(part, base), np.radians(110))
    assert grounded.evidence["snapped"]
    assert line_distance(grounded.origin, grounded.axis, door.origin, door.axis) < 1e-3
    assert grounded.upper > np.radians(60)


def test_grounding_flips_a_hinge_whose_opening_drives_into_the_parent(microwave):
    door = microwave.movable_joints[0]
    part, base = microwave.part(door.child).mesh, microwave.part("base").mesh
    from rest2art.joints.video.fit import JointFit

    wrong = JointFit("revolute", -door.axis, door.origin, [np.array([0.0, 1.0])], [np.array([0, 1])], 1.0, 1.0)
    grounded = ground_joint(wrong, part, base, exposed_outward(part, base), np.radians(110))
    assert grounded.axis @ door.axis > 0.99
    assert grounded.evidence.get("flipped") or grounded.evidence["overruled"]


def test_lucas_kanade_follows_the_rendered_texture(microwave):
    camera = _front_camera(microwave, 320)
    rendered = render_motion(microwave, camera, 10, open_fraction=0.4, render_images=True)
    truth = simulate_video(microwave, camera, 10, rendered=rendered, max_points=120)
    name = microwave.movable_joints[0].child
    evidence = evidence_from_frames(rendered.images, camera, truth.depth0, {name: truth.masks0[name]},
                                    LucasKanadeTracker(), ArticulationConfig(max_track_points=120))
    tracked, gt = evidence.tracks[name], truth.tracks[name]
    assert tracked.n_points == gt.n_points
    both = tracked.visible & gt.visible
    error = np.linalg.norm(tracked.xy - gt.xy, axis=2)[both]
    assert both[-1].mean() > 0.5
    assert np.median(error) < 1.0


def test_reconstruct_takes_joints_from_motion_videos_made_from_its_conditioning_image(tmp_path, config_file):
    """The whole loop: --debug writes the video view's conditioning image and camera, videos
    are made from that camera (here: rendered openings of the ground truth, tracked by the
    offline Lucas-Kanade backend) and --motion-video turns them into the joint."""
    import cv2

    from rest2art.asset import read_articulation
    from rest2art.cli import main
    from rest2art.generate import write_object

    obj = generate_object("microwave", 0, "asset")
    mesh_path = write_object(obj, tmp_path / "gt")
    assert main(["reconstruct", str(mesh_path), "-o", str(tmp_path / "first"), "--debug", "--no-check", "--quiet",
                 "--config", str(config_file)]) == 0
    video_dir = tmp_path / "first" / "debug" / "video"
    assert (video_dir / "conditioning.png").exists() and "Camera locked." in (video_dir / "prompt.txt").read_text()
    cam = json.loads((video_dir / "camera.json").read_text())
    camera = Camera(np.array(cam["eye"]), np.array(cam["rotation"]), cam["focal_px"], cam["width"], cam["height"])
    folders = []
    for seed, fraction in enumerate([0.8, 0.6]):
        frames = render_motion(obj.asset, camera, 12, open_fraction=fraction, render_images=True).images
        folder = tmp_path / f"video{seed}"
        folder.mkdir()
        for t, image in enumerate(frames):
            cv2.imwrite(str(folder / f"{t:03d}.png"), image[..., ::-1])
        folders += ["--motion-video", str(folder)]
    assert main(["reconstruct", str(mesh_path), "-o", str(tmp_path / "second"), "--no-check", "--quiet",
                 "--config", str(config_file), *folders]) == 0
    asset = read_articulation(tmp_path / "second", load_meshes=False)
    truth = obj.asset.movable_joints[0]
    (joint,) = asset.movable_joints
    assert joint.type == "revolute" and axis_angle_deg(joint.axis, truth.axis) < 1.0
    assert line_distance(joint.origin, joint.axis, truth.origin, truth.axis) < 0.005
    evidence = json.loads((tmp_path / "second" / "articulation.json").read_text())["metadata"]["joints"][joint.child]
    assert evidence["rule"].startswith("motion video") and evidence["video"]["combined"]


def test_a_motion_video_folder_without_frames_is_refused_by_name(tmp_path, capsys):
    from rest2art.cli import DEMO_MESH, main

    (tmp_path / "empty").mkdir()
    code = main(["reconstruct", str(DEMO_MESH), "-o", str(tmp_path / "out"), "--no-check", "--quiet",
                 "--motion-video", str(tmp_path / "empty")])
    assert code != 0 and not (tmp_path / "out").exists()
    assert "empty" in capsys.readouterr().err


def test_a_nearly_right_hinge_snaps_to_its_own_edge_and_a_wrong_knob_axis_is_overruled():
    from rest2art.geometry.basics import rotation_about
    from rest2art.joints.video.fit import JointFit

    oven = generate_object("oven", 0, "asset").asset
    base = oven.part("base").mesh
    for joint in oven.movable_joints:
        if joint.child not in ("door_0", "knob_0"):
            continue
        part = oven.part(joint.child).mesh
        # tilted about the view direction: 1 degree for the door, 60 for the knob
        tilt = 1.0 if joint.child == "door_0" else 60.0
        axis = rotation_about(np.array([0.0, 0.0, 1.0]) if joint.child == "knob_0" else np.array([0.0, 1.0, 0.0]),
                              np.radians(tilt)) @ joint.axis
        fit = JointFit("revolute", axis, joint.origin, [np.array([0.0, 1.0])], [np.array([0, 1])], 1.0, 1.0)
        cap = np.radians(270.0 if joint.child == "knob_0" else 90.0)
        grounded = ground_joint(fit, part, base, exposed_outward(part, base), cap)
        assert axis_angle_deg(grounded.axis, joint.axis) < 1e-6, joint.child
        assert line_distance(grounded.origin, grounded.axis, joint.origin, joint.axis) < 1e-3, joint.child
        assert grounded.evidence["snapped" if joint.child == "door_0" else "overruled"]
