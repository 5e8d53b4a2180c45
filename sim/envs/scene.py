"""The MuJoCo scene of an environment: an asset's own MJCF on a floor, a fixed camera and a
floating two-finger gripper driven by a mocap body.

The asset's ``NAME.xml`` is attached (``MjSpec`` attach) under a body ``object`` whose pose is
set at reset, turned so that the asset's up is +z and its front -y. The gripper is a free body
welded to the mocap body ``target``; its two fingers slide on position actuators and their pads
adhere (MuJoCo adhesion actuators) while the grip is closed, so that flat faces can be held as
well as handles. Compiled models are cached per asset folder and config in each process; every
environment works on its own copy.
"""

from __future__ import annotations

import copy
import functools
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rest2art.sim.envs.grasp import Grasp, find_back_grasp, find_grasp

from rest2art.asset import ArticulatedAsset, read_articulation
from rest2art.config import EnvConfig
from rest2art.errors import InputError
from rest2art.export.writers import link_origins

OBJECT_PREFIX = "obj/"
"""Prefix of the asset's bodies, joints and geoms in the scene."""
PART_COLOURS = np.array([[0.82, 0.78, 0.70, 1.0], [0.30, 0.55, 0.80, 1.0], [0.85, 0.45, 0.30, 1.0],
                         [0.40, 0.70, 0.45, 1.0], [0.70, 0.50, 0.75, 1.0], [0.85, 0.75, 0.35, 1.0]])
"""RGBA of the base (first row) and of the other parts in turn."""

SCENE_XML = """
<mujoco model="scene">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{timestep}" integrator="implicitfast"/>
  <visual>
    <global offwidth="{offwidth}" offheight="{offheight}"/>
    <headlight ambient="0.35 0.35 0.35" diffuse="0.5 0.5 0.5"/>
  </visual>
  <default>
    <default class="pad">
      <geom type="box" friction="1.5 0.05 0.001" condim="4" margin="0.002" rgba="0.95 0.55 0.15 1"/>
    </default>
  </default>
  <asset>
    <texture name="grid" type="2d" builtin="checker" rgb1="0.62 0.64 0.66" rgb2="0.52 0.54 0.56"
             width="256" height="256"/>
    <material name="floor" texture="grid" texrepeat="8 8"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 0.05" material="floor"/>
    <light name="sun" pos="{light}" dir="-0.1 0.4 -1" diffuse="0.6 0.6 0.6" castshadow="false"/>
    <camera name="fixed" pos="0 -3 1" fovy="{fovy}"/>
    <body name="object"/>
    <body name="target" mocap="true">
      <site name="target" size="0.006" rgba="0 1 0 0.3" group="4"/>
    </body>
    <body name="gripper" gravcomp="1">
      <freejoint name="gripper"/>
      <inertial pos="0 0 -0.07" mass="2.0" diaginertia="0.01 0.01 0.01"/>
      <geom name="palm" type="box" size="0.02 {palm} 0.012" pos="0 0 -0.075" rgba="0.25 0.25 0.28 1"/>
      <site name="tcp" size="0.005" rgba="1 0 0 1" group="4"/>
      <body name="finger_left" pos="0 {base} 0" gravcomp="1">
        <joint name="finger_left" type="slide" axis="0 1 0" range="0 {opening}" damping="20"/>
        <inertial pos="0 0 -0.03" mass="0.2" diaginertia="1e-4 1e-4 1e-4"/>
        <geom name="finger_left" class="pad" size="0.012 {base} 0.03" pos="0 0 -0.03"/>
      </body>
      <body name="finger_right" pos="0 -{base} 0" gravcomp="1">
        <joint name="finger_right" type="slide" axis="0 -1 0" range="0 {opening}" damping="20"/>
        <inertial pos="0 0 -0.03" mass="0.2" diaginertia="1e-4 1e-4 1e-4"/>
        <geom name="finger_right" class="pad" size="0.012 {base} 0.03" pos="0 0 -0.03"/>
      </body>
    </body>
  </worldbody>
  <contact>
    <exclude body1="gripper" body2="finger_left"/>
    <exclude body1="gripper" body2="finger_right"/>
    <exclude body1="finger_left" body2="finger_right"/>
  </contact>
  <equality>
    <weld name="grip_weld" body1="gripper" body2="target" solref="{weld} 1"/>
  </equality>
  <actuator>
    <position name="finger_left" joint="finger_left" kp="{kp}" kv="40" ctrlrange="0 {opening}"
              forcerange="-{force} {force}"/>
    <position name="finger_right" joint="finger_right" kp="{kp}" kv="40" ctrlrange="0 {opening}"
              forcerange="-{force} {force}"/>
    <adhesion name="adhesion_left" body="finger_left" ctrlrange="0 1" gain="{adhesion}"/>
    <adhesion name="adhesion_right" body="finger_right" ctrlrange="0 1" gain="{adhesion}"/>
  </actuator>
</mujoco>
"""
FINGER_HALF_THICKNESS = 0.005
"""Half thickness of a finger (m): the fingers' inner faces meet when both slides are at 0."""


@dataclass(frozen=True)
class JointTask:
    """One movable joint of the asset, as the environment needs it."""

    name: str
    """Joint name in articulation.json (in the scene: OBJECT_PREFIX + name)."""
    type: str
    """revolute or prismatic."""
    child: str
    """The part it moves."""
    upper: float
    """Upper limit (rad or m); the lower one is 0 (closed)."""
    grasp: Grasp
    """Where the gripper holds the part at the closed state, in the asset frame."""
    local_point: np.ndarray
    """(3,) the grasp point in the child body's frame (m)."""
    back: Grasp | None = None
    """For a swinging panel: fingertips on its inner face (to lift an opened flap)."""
    back_local_point: np.ndarray | None = None
    """(3,) that grasp's point in the child body's frame (m)."""


@dataclass
class Scene:
    """A compiled scene and the indices the environment reads; ``model`` is shared, copy it."""

    model: object
    """mujoco.MjModel (shared by every environment of the process: copy before changing it)."""
    asset_dir: Path
    name: str
    category: str
    tasks: dict[str, JointTask]
    """Movable joints by name."""
    rotation: np.ndarray
    """(3, 3) asset frame -> object body frame (up to +z, front to -y)."""
    lower: np.ndarray
    upper: np.ndarray
    """(3,) bounds of the closed asset in the object body frame, before placement (m)."""


def canonical_rotation(up: np.ndarray, front: np.ndarray) -> np.ndarray:
    """(3, 3) rotation taking the asset's ``up`` to +z and ``front`` to -y."""
    z = np.asarray(up, float) / np.linalg.norm(up)
    f = np.asarray(front, float) - (np.asarray(front, float) @ z) * z
    y = -f / np.linalg.norm(f)
    x = np.cross(y, z)
    return np.stack([x, y, z])


def mjcf_name(asset_dir: Path) -> str:
    """Stem of the asset's single MJCF file (NAME.xml beside NAME.urdf, or the only .xml)."""
    urdfs = sorted(asset_dir.glob("*.urdf"))
    candidates = [asset_dir / f"{u.stem}.xml" for u in urdfs if (asset_dir / f"{u.stem}.xml").is_file()]
    if not candidates:
        candidates = sorted(asset_dir.glob("*.xml"))
    if len(candidates) != 1:
        raise InputError(f"{asset_dir}: expected one MJCF file NAME.xml, found {len(candidates)}; export the asset "
                         "with 'rest2art reconstruct' or 'rest2art publish' first")
    return candidates[0].stem


def asset_category(asset: ArticulatedAsset, asset_dir: Path) -> str:
    """The asset's category from its metadata, else its folder name up to the first '_'."""
    return str(asset.metadata.get("category") or asset_dir.name.split("_")[0])


def joint_tasks(asset: ArticulatedAsset, config: EnvConfig) -> dict[str, JointTask]:
    """A JointTask per movable joint of ``asset`` (part meshes loaded)."""
    up = asset.up
    origins = link_origins(asset)
    tasks = {}
    for joint in asset.movable_joints:
        part = asset.part(joint.child)
        parent = asset.part(joint.parent).mesh
        grasp = find_grasp(np.asarray(part.mesh.vertices), joint.type, joint.axis, joint.origin,
                           np.asarray(parent.bounds).mean(axis=0), up, config)
        back = None
        if joint.type == "revolute":
            back = find_back_grasp(np.asarray(part.mesh.vertices), joint.axis, joint.origin,
                                   np.asarray(parent.bounds).mean(axis=0), up, config)
        tasks[joint.name] = JointTask(joint.name, joint.type, joint.child, float(joint.limit[1]), grasp,
                                      grasp.point - origins[joint.child], back,
                                      None if back is None else back.point - origins[joint.child])
    return tasks


def scene_xml(config: EnvConfig, radius: float) -> str:
    """The scene's MJCF without the asset: floor, light, camera, body ``object``, the gripper
    (finger travel, forces and weld from ``config``); ``radius`` (m) scales the light."""
    return SCENE_XML.format(
        timestep=f"{config.timestep:g}", offwidth=max(config.render_width, config.image_width),
        offheight=max(config.render_height, config.image_height), light=_fmt([0.5 * radius, -2 * radius, 4 * radius]),
        fovy=f"{config.camera_fovy_deg:g}", palm=f"{FINGER_HALF_THICKNESS * 2 + config.finger_opening + 0.01:.4f}",
        base=f"{FINGER_HALF_THICKNESS:g}", opening=f"{config.finger_opening:g}", kp=f"{config.finger_force / 0.01:g}",
        force=f"{config.finger_force:g}", adhesion=f"{config.adhesion_force:g}", weld=f"{config.weld_time:g}")


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in values)


def build_spec(asset_dir: Path, name: str, rotation: np.ndarray, radius: float, config: EnvConfig):
    """The scene's MjSpec: ``scene_xml`` with the asset's NAME.xml attached under ``object``,
    turned by ``rotation`` (3, 3)."""
    import mujoco

    spec = mujoco.MjSpec.from_string(scene_xml(config, radius))
    child = mujoco.MjSpec.from_file(str(asset_dir / f"{name}.xml"))
    # the asset's gravity points down its file frame; the scene turns it upright and keeps its
    # own (otherwise MuJoCo warns of the conflict into MUJOCO_LOG.TXT in the working directory)
    child.option.gravity = spec.option.gravity
    frame = spec.body("object").add_frame(quat=rotation_quat(rotation))
    frame.attach_body(child.worldbody.first_body(), OBJECT_PREFIX, "")
    return spec


def rotation_quat(rotation: np.ndarray) -> np.ndarray:
    """(4,) w, x, y, z quaternion of a (3, 3) rotation."""
    import mujoco

    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, float).reshape(9))
    return quat


@functools.lru_cache(maxsize=64)
def load_scene(asset_dir: str, config: EnvConfig) -> Scene:
    """The compiled scene of the asset in ``asset_dir`` (cached per process; copy its model).

    Raises InputError naming the folder when the asset cannot be read or compiled."""
    folder = Path(asset_dir)
    asset = read_articulation(folder)
    if not asset.movable_joints:
        raise InputError(f"{folder}: the asset has no movable joint")
    name = mjcf_name(folder)
    up, front = asset.up, asset.front
    rotation = canonical_rotation(up, front)
    points = np.concatenate([np.asarray(p.mesh.vertices) for p in asset.parts]) @ rotation.T
    lower, upper = points.min(axis=0), points.max(axis=0)
    radius = float(np.linalg.norm(upper - lower) / 2)
    spec = build_spec(folder, name, rotation, radius, config)
    try:
        model = spec.compile()
    except Exception as exc:  # a broken MJCF is bad input, not a crash
        raise InputError(f"{folder / (name + '.xml')}: MuJoCo cannot compile the scene ({exc})") from None
    colour_parts(model, asset)
    return Scene(model, folder, name, asset_category(asset, folder), joint_tasks(asset, config), rotation,
                 lower, upper)


def colour_parts(model, asset: ArticulatedAsset) -> None:
    """Give each part's visual geoms its own colour (base first), in place."""
    import mujoco

    for k, part in enumerate(asset.parts):
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, OBJECT_PREFIX + part.name)
        colour = PART_COLOURS[0] if part.parent is None else PART_COLOURS[1 + (k - 1) % (len(PART_COLOURS) - 1)]
        for g in np.flatnonzero(model.geom_bodyid == body):
            if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
                model.geom_rgba[g] = colour


def model_copy(scene: Scene):
    """A private copy of the scene's model, for one environment to change."""
    return copy.copy(scene.model)


def is_published(asset_dir: Path) -> bool:
    """True when ``asset_dir`` holds articulation.json and a validation.json whose decision is
    publish."""
    report = asset_dir / "validation.json"
    if not (asset_dir / "articulation.json").is_file() or not report.is_file():
        return False
    try:
        return json.loads(report.read_text()).get("decision", {}).get("status") == "publish"
    except json.JSONDecodeError:
        return False


def catalog_assets(catalog: str | Path) -> list[Path]:
    """Published asset folders of a catalog: the published entries of ``rest2art catalog build``'s
    index.jsonl (``rest2art.catalog.open``); in a folder without an index, the sub-folders
    (searched two levels deep) with articulation.json and a validation.json deciding publish,
    sorted by path.

    Raises InputError when ``catalog`` is not a folder or holds no published asset."""
    root = Path(catalog)
    if not root.is_dir():
        raise InputError(f"{root}: catalog folder not found")
    from rest2art.catalog import INDEX
    from rest2art.catalog import open as open_catalog

    if (root / INDEX).is_file():
        entries = open_catalog(root)
        if not len(entries):
            raise InputError(f"{root}: the catalog has no published entry")
        return [entry.folder for entry in entries]
    found = sorted({p.parent for pattern in ("*/articulation.json", "*/*/articulation.json")
                    for p in root.glob(pattern) if is_published(p.parent)})
    if not found:
        raise InputError(f"{root}: no published asset (sub-folders with articulation.json and a validation.json "
                         "deciding publish)")
    return found
