"""Motion videos as a joint hypothesis source in the pipeline.

The video view is the rig camera (``segment.views``) that sees the most of the movable parts; its
conditioning image is the shaded view with the parts' masks blended in (alpha 0.35), with a
prompt naming the parts (or written by a VLM, ``articulation.prompt_backend``). Videos are made
from it by the ``articulation.video_backend`` model, or by any tool from the written
conditioning image and come back as folders of frames; the ``tracks`` backend
follows a grid inside each part's mask, the estimator fits a joint per part over the videos, and
the mesh grounds each fit (``grounding.ground_joint``). A part the videos show as static keeps
its geometric joint.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from rest2art.config import Config
from rest2art.errors import InputError
from rest2art.joints.video.estimate import conditioning_image, estimate_part_motions, evidence_from_frames
from rest2art.joints.video.grounding import ground_joint
from rest2art.joints.video.tracks import TracksBackend
from rest2art.parts.segment.views import camera_rig
from rest2art.render.camera import Camera
from rest2art.render.raster import ViewMaps, render_views

PROMPT_SUFFIX = "No camera movement. Camera locked."


@dataclass
class VideoView:
    camera: Camera
    view: ViewMaps
    masks: dict[str, np.ndarray]
    """Per movable part, its (H, W) bool mask in the view."""


def video_view(canonical: np.ndarray, faces: np.ndarray, face_part: np.ndarray, names: list[str],
               movable: list[str], config: Config = Config()) -> VideoView:
    """The rig view with the most movable-part pixels, and each movable part's mask there.
    ``face_part`` (F,) indexes ``names``."""
    views = render_views(canonical, faces, camera_rig(canonical, config.segment), cull_backfaces=False)
    index = {n: k for k, n in enumerate(names)}
    wanted = np.array([index[n] for n in movable])

    def part_map(v: ViewMaps) -> np.ndarray:
        return np.where(v.face >= 0, face_part[np.maximum(v.face, 0)], -1)

    best = max(views, key=lambda v: int(np.isin(part_map(v), wanted).sum()))
    pm = part_map(best)
    return VideoView(best.camera, best, {n: pm == index[n] for n in movable})


def motion_prompt(semantics: dict[str, str]) -> str:
    """Text prompt for the motion video: what opens and how (the offline stand-in of the VLM)."""
    verbs = {"door": "swings open on its hinge", "drawer": "slides straight out", "lid": "lifts open on its hinge",
             "knob": "turns about its own axis"}
    sentences = [f"The highlighted {s} ({name}) {verbs.get(s, 'opens')}." for name, s in semantics.items()]
    return " ".join(sentences + ["Everything else stays still.", PROMPT_SUFFIX])


def write_conditioning(vv: VideoView, semantics: dict[str, str], folder: str | Path, alpha: float = 0.35,
                       prompt: str | None = None, videos: dict[int, np.ndarray] | None = None) -> None:
    """conditioning.png, prompt.txt (``prompt``, or the template's) and camera.json (canonical
    frame) into ``folder``; with ``videos`` ({seed: (T, H, W, 3) uint8}), the frames of each as
    ``seed_K/frame_NNNN.png``, the layout ``--motion-video`` reads."""
    import cv2

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    image = conditioning_image(vv.view.shaded(), list(vv.masks.values()), alpha)
    cv2.imwrite(str(folder / "conditioning.png"), image[..., ::-1])
    (folder / "prompt.txt").write_text((prompt or motion_prompt(semantics)) + "\n")
    for seed, frames in (videos or {}).items():
        (folder / f"seed_{seed}").mkdir(exist_ok=True)
        for t, frame in enumerate(frames):
            cv2.imwrite(str(folder / f"seed_{seed}" / f"frame_{t:04d}.png"), frame[..., ::-1])
    cam = vv.camera
    (folder / "camera.json").write_text(json.dumps({
        "frame": "canonical (+z up, -y front)", "eye": cam.eye.tolist(), "rotation": cam.rotation.tolist(),
        "focal_px": cam.focal, "width": cam.width, "height": cam.height, "parts": list(vv.masks)}, indent=1))


def read_frames(folder: str | Path, width: int, height: int) -> np.ndarray:
    """(T, H, W, 3) uint8 RGB frames from the PNG/JPG files of ``folder`` in name order,
    resized to the view's size."""
    import cv2

    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{folder}: motion video folder not found (expected a folder of PNG/JPG frames)")
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in (".png", ".jpg", ".jpeg"))
    if len(files) < 3:
        raise InputError(f"{folder}: a motion video needs at least 3 frames (PNG/JPG), found {len(files)}")
    frames = []
    for path in files:
        image = cv2.imread(str(path), cv2.IMREAD_COLOR)
        if image is None:
            raise InputError(f"{path}: not a readable image")
        if image.shape[:2] != (height, width):
            image = cv2.resize(image, (width, height), interpolation=cv2.INTER_AREA)
        frames.append(image[..., ::-1])
    return np.stack(frames)


def make_tracker(config: Config = Config()) -> TracksBackend:
    """The ``tracks`` backend named by ``articulation.tracks_backend``."""
    from rest2art.backends import create

    return create("tracks", config.articulation.tracks_backend, config.models)


def video_maker(vv: VideoView, semantics: dict[str, str], config: Config = Config(),
                debug: dict | None = None) -> Callable[[int], np.ndarray] | None:
    """``seed -> (T, H, W, 3) uint8 frames`` from the ``articulation.video_backend`` model,
    conditioned on the view's mask overlay and the prompt of ``articulation.prompt_backend``;
    None when no video model is configured. A ``debug`` dict receives the prompt
    (``"video_prompt"``) and the frames per seed (``"motion_videos"``)."""
    from rest2art.backends import create

    model = create("video", config.articulation.video_backend, config.models)
    if model is None:
        return None
    image = conditioning_image(vv.view.shaded(), list(vv.masks.values()), config.articulation.overlay_alpha)
    prompt = create("prompt", config.articulation.prompt_backend, config.models)(image, semantics)
    made: dict[int, np.ndarray] = {}
    if debug is not None:
        debug["video_prompt"] = prompt
        debug["motion_videos"] = made

    def make(seed: int) -> np.ndarray:
        made[seed] = model.generate(image, prompt, seed, config.articulation.video_frames)
        return made[seed]

    return make


def joints_from_videos(vv: VideoView, videos: list[np.ndarray] | Callable[[int], np.ndarray], part_meshes: dict,
                       parent, outward: dict, caps: dict[str, dict[str, float]],
                       config: Config = Config()) -> tuple[dict, dict]:
    """Grounded joints of the parts the videos show moving, and a per-part report.

    ``videos``: (T, H, W, 3) frames, one array per seed, or a video model's ``seed -> frames``
    (R seeds, and the extra ones when every part comes out static); ``part_meshes``/``outward``
    /``caps`` per movable part name (canonical trimesh, (3,) direction, limit cap per joint type
    in rad or m)."""
    tracker = make_tracker(config)
    depth0 = vv.view.depth
    if callable(videos):
        make = videos
        art = config.articulation
        motions = estimate_part_motions(
            lambda seed: evidence_from_frames(make(seed), vv.camera, depth0, vv.masks, tracker, art),
            list(vv.masks), art)
    else:
        evidence = [evidence_from_frames(frames, vv.camera, depth0, vv.masks, tracker, config.articulation)
                    for frames in videos]
        motions = estimate_part_motions(lambda seed: evidence[seed], list(vv.masks),
                                        _given_videos(config, len(evidence)))
    joints, report = {}, {}
    for name, motion in motions.items():
        report[name] = {"type": motion.type, "combined": motion.combined,
                        "runs": [{k: v for k, v in r.items() if k != "cues"} for r in motion.runs]}
        if motion.fit is None:
            continue
        grounded = ground_joint(motion.fit, part_meshes[name], parent, outward[name], caps[name][motion.type],
                                config.articulation, config.joints)
        joints[name] = grounded
        report[name]["grounding"] = grounded.evidence
    return joints, report


def _given_videos(config: Config, n_videos: int):
    """The articulation config with R = the number of videos given and no extra seeds (videos
    given from outside cannot be asked for more)."""
    import dataclasses

    return dataclasses.replace(config.articulation, seeds=n_videos, extra_seeds=0)
