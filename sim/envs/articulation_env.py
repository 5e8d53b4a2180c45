"""Open or close one joint of a reconstructed asset with a floating two-finger gripper.

``OpenArticulationEnv`` starts with every joint closed and succeeds when the chosen joint is
past ``target_fraction`` of its range with the fingers released; ``CloseArticulationEnv`` starts
with it at ``close_start_fraction`` and succeeds below ``close_fraction``.

Action (7,) in [-1, 1]: gripper translation (x, y, z, world frame, times ``max_translation``
m), rotation vector (world frame, times ``max_rotation_deg``) and grip (> 0 closes the fingers
and makes their pads adhere, <= 0 opens them). Position and yaw alone cannot turn a knob or
follow a lid, so the gripper turns about every axis.

Observation (dict): ``gripper_pos`` (3,) m and ``gripper_quat`` (4,) w x y z of the point
between the fingertips, ``gripper_opening`` (1,) m between the fingers, ``joint_value`` (1,) rad
or m, ``joint_fraction`` (1,) of the range, ``handle_pos`` (3,) and ``handle_quat`` (4,) the
grasp frame (z into the part, y across the handle) at the current joint value; with
``image_obs``: ``rgb`` (H, W, 3) uint8 and ``depth`` (H, W, 1) float32 m from the fixed camera.
"""

from __future__ import annotations

import os
from pathlib import Path

if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
    os.environ["MUJOCO_GL"] = "egl"  # headless by default; set MUJOCO_GL=osmesa to use OSMesa

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces

from rest2art.config import EnvConfig
from rest2art.errors import InputError, SimulationError
from rest2art.sim.envs.scene import OBJECT_PREFIX, JointTask, Scene, catalog_assets, load_scene, model_copy

JOINT_TYPES = ("revolute", "prismatic")
RENDER_HINT = ("headless rendering needs MUJOCO_GL=egl (Debian: apt-get install libegl1 libgl1-mesa-dri) or "
               "MUJOCO_GL=osmesa (apt-get install libosmesa6), set before mujoco is imported")
MAX_DEPTH = 1000.0
"""Upper bound of the depth observation (m); the camera's far plane is much nearer."""
WORKSPACE_MARGIN = 0.4
"""The gripper target stays within a box around the object: two object radii and this much (m)."""


def quat_from_matrix(rotation: np.ndarray) -> np.ndarray:
    """(4,) w x y z quaternion of a (3, 3) rotation."""
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, float).reshape(9))
    return quat


def quat_from_rotvec(rotvec: np.ndarray) -> np.ndarray:
    """(4,) w x y z quaternion of a rotation vector (3,) rad."""
    quat = np.zeros(4)
    mujoco.mju_axisAngle2Quat(quat, np.asarray(rotvec, float), 1.0)
    angle = float(np.linalg.norm(rotvec))
    if angle > 1e-12:
        mujoco.mju_axisAngle2Quat(quat, np.asarray(rotvec, float) / angle, angle)
    return quat


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(4,) the rotation ``a`` after ``b`` (w x y z)."""
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, a, b)
    return out


class ArticulationEnv(gym.Env):
    """Common base of the open and close environments (``mode`` says which).

    Args:
        asset: an asset folder (articulation.json + NAME.xml); or
        catalog: a folder of asset folders, of which the published ones are sampled at reset;
        category: keep catalog assets of this category only (e.g. cabinet);
        joint_type: keep joints of this type only (revolute or prismatic);
        joint: the joint to work on (default: one sampled at reset);
        seed: seeds the environment's random generator (as ``reset(seed=...)`` would);
        randomize: randomise object pose, joint friction and damping, and camera at each reset;
        image_obs: add ``rgb`` and ``depth`` images to the observation;
        render_mode: ``rgb_array`` or ``depth_array``;
        config: EnvConfig (defaults from rest2art.config).
    """

    metadata = {"render_modes": ["rgb_array", "depth_array"], "render_fps": 25}
    mode = "open"

    def __init__(self, asset: str | Path | None = None, catalog: str | Path | None = None,
                 category: str | None = None, joint_type: str | None = None, joint: str | None = None,
                 seed: int | None = None, randomize: bool = False, image_obs: bool = False,
                 render_mode: str | None = None, config: EnvConfig | None = None):
        self.config = config or EnvConfig()
        if (asset is None) == (catalog is None):
            raise InputError("give exactly one of asset=PATH (an asset folder) or catalog=PATH (a folder of assets)")
        if joint_type is not None and joint_type not in JOINT_TYPES:
            raise InputError(f"joint_type '{joint_type}' is not valid. Valid types: {', '.join(JOINT_TYPES)}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise InputError(f"render_mode '{render_mode}' is not valid. Valid modes: "
                             f"{', '.join(self.metadata['render_modes'])}")
        folders = [Path(asset)] if asset is not None else catalog_assets(catalog)
        self.choices = self._choices(folders, category, joint_type, joint)
        self.randomize, self.image_obs, self.render_mode = randomize, image_obs, render_mode
        self.substeps = max(1, int(round(self.config.control_dt / self.config.timestep)))
        self.action_space = spaces.Box(-1.0, 1.0, (7,), np.float32)
        self.observation_space = self._observation_space()
        self._renderers: dict[tuple[int, int, int], mujoco.Renderer] = {}
        self._models: dict[str, object] = {}
        self.scene: Scene | None = None
        self.task: JointTask | None = None
        if seed is not None:
            self.np_random, self._np_random_seed = gym.utils.seeding.np_random(seed)
        self._load(*self.choices[0])

    # ---- set-up --------------------------------------------------------------------------------

    def _choices(self, folders: list[Path], category, joint_type, joint) -> list[tuple[str, str]]:
        """(asset folder, joint name) pairs the environment samples from."""
        choices = []
        for folder in folders:
            scene = load_scene(str(folder.resolve()), self.config)
            if category is not None and scene.category != category:
                continue
            for name, task in scene.tasks.items():
                if (joint is None or name == joint) and (joint_type is None or task.type == joint_type):
                    choices.append((str(folder.resolve()), name))
            if joint is not None and joint not in scene.tasks:
                raise InputError(f"{folder}: joint '{joint}' does not exist or is fixed. Movable joints: "
                                 f"{', '.join(scene.tasks)}")
        if not choices:
            where = folders[0] if len(folders) == 1 else folders[0].parent
            raise InputError(f"{where}: no movable joint matches category={category} joint_type={joint_type}")
        return choices

    def _observation_space(self) -> spaces.Dict:
        box = lambda n, lo=-10.0, hi=10.0: spaces.Box(lo, hi, (n,), np.float64)  # noqa: E731
        entries = {"gripper_pos": box(3), "gripper_quat": box(4, -1.0, 1.0),
                   "gripper_opening": box(1, 0.0, 1.0), "joint_value": box(1, -10.0, 10.0),
                   "joint_fraction": box(1, -1.0, 2.0), "handle_pos": box(3), "handle_quat": box(4, -1.0, 1.0)}
        if self.image_obs:
            h, w = self.config.image_height, self.config.image_width
            entries["rgb"] = spaces.Box(0, 255, (h, w, 3), np.uint8)
            entries["depth"] = spaces.Box(0.0, MAX_DEPTH, (h, w, 1), np.float32)
        return spaces.Dict(entries)

    def _load(self, folder: str, joint: str) -> None:
        """Make the asset's scene current (its model copied once per environment)."""
        if self.scene is None or str(self.scene.asset_dir) != folder:
            self.scene = load_scene(folder, self.config)
            if folder not in self._models:
                self._models[folder] = model_copy(self.scene)
            self.model = self._models[folder]
            self.data = mujoco.MjData(self.model)
            ids = lambda kind, name: mujoco.mj_name2id(self.model, kind, name)  # noqa: E731
            self.object_body = ids(mujoco.mjtObj.mjOBJ_BODY, "object")
            self.mocap = int(self.model.body_mocapid[ids(mujoco.mjtObj.mjOBJ_BODY, "target")])
            self.gripper_qpos = int(self.model.jnt_qposadr[ids(mujoco.mjtObj.mjOBJ_JOINT, "gripper")])
            self.tcp = ids(mujoco.mjtObj.mjOBJ_SITE, "tcp")
            self.fingers = [int(self.model.jnt_qposadr[ids(mujoco.mjtObj.mjOBJ_JOINT, f)])
                            for f in ("finger_left", "finger_right")]
            self.camera = ids(mujoco.mjtObj.mjOBJ_CAMERA, "fixed")
            self.nominal = {"friction": self.model.dof_frictionloss.copy(), "damping": self.model.dof_damping.copy()}
        self.task = self.scene.tasks[joint]
        jid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, OBJECT_PREFIX + joint)
        self.joint_id, self.joint_qpos = jid, int(self.model.jnt_qposadr[jid])
        self.child_body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, OBJECT_PREFIX + self.task.child)
        self.grasp_frame = self.task.grasp.frame()

    # ---- gymnasium API -------------------------------------------------------------------------

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Sample an asset and joint (``options`` may name ``asset`` and ``joint``), place the
        object, set the joint's start value and the gripper in front of the object."""
        super().reset(seed=seed)
        options = options or {}
        folder, joint = self.choices[int(self.np_random.integers(len(self.choices)))]
        if "asset" in options:
            folder = str(Path(options["asset"]).resolve())
            joint = options.get("joint") or next(iter(load_scene(folder, self.config).tasks))
        elif "joint" in options:
            joint = options["joint"]
        self._load(folder, joint)
        self._place()
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[self.joint_qpos] = self.start_fraction() * self.task.upper
        self._place_gripper()
        mujoco.mj_forward(self.model, self.data)
        self.steps, self.grip = 0, -1.0
        self.start_value = float(self.data.qpos[self.joint_qpos])
        return self._observation(), self._info()

    def step(self, action: np.ndarray):
        """Move the mocap target by the scaled action, set the fingers, simulate control_dt."""
        action = np.clip(np.asarray(action, float), -1.0, 1.0)
        c = self.config
        pos = self.data.mocap_pos[self.mocap] + action[:3] * c.max_translation
        self.data.mocap_pos[self.mocap] = np.clip(pos, self.work_lo, self.work_hi)
        turn = quat_from_rotvec(action[3:6] * np.radians(c.max_rotation_deg))
        quat = quat_multiply(turn, self.data.mocap_quat[self.mocap])
        self.data.mocap_quat[self.mocap] = quat / np.linalg.norm(quat)
        self.grip = float(action[6])
        closed = self.grip > 0
        self.data.ctrl[:2] = 0.0 if closed else c.finger_opening
        self.data.ctrl[2:4] = 1.0 if closed else 0.0
        mujoco.mj_step(self.model, self.data, nstep=self.substeps)
        self.steps += 1
        observation, info = self._observation(), self._info()
        reward = self.reward(observation, info["success"])
        truncated = self.steps >= c.max_steps
        return observation, reward, bool(info["success"]), truncated, info

    def render(self):
        """The fixed camera's view: (H, W, 3) uint8 for rgb_array, (H, W) float32 m for depth_array."""
        if self.render_mode is None:
            return None
        size = (self.config.render_height, self.config.render_width)
        return self._camera_image(size, depth=self.render_mode == "depth_array")

    def close(self):
        for renderer in self._renderers.values():
            renderer.close()
        self._renderers.clear()

    # ---- what the task is ----------------------------------------------------------------------

    def start_fraction(self) -> float:
        """Share of the range the joint starts at."""
        return 0.0

    def succeeded(self, fraction: float) -> bool:
        """Success on the joint's share of its range (the fingers must be released too)."""
        return fraction >= self.config.target_fraction

    def progress(self, fraction: float) -> float:
        """0 at the start, 1 at the target."""
        return float(np.clip(fraction / self.config.target_fraction, 0.0, 1.0))

    def reward(self, observation: dict, success: bool) -> float:
        """Dense: minus the fingertip-handle distance, plus the joint's progress; sparse success."""
        c = self.config
        distance = float(np.linalg.norm(observation["gripper_pos"] - observation["handle_pos"]))
        dense = -c.reach_weight * distance + c.progress_weight * self.progress(float(observation["joint_fraction"][0]))
        return dense + (c.success_reward if success else 0.0)

    # ---- internals -----------------------------------------------------------------------------

    def _place(self) -> None:
        """Object pose on the floor, joint dynamics and camera (randomised if asked)."""
        scene, c, rng = self.scene, self.config, self.np_random
        shift, yaw = np.zeros(2), 0.0
        self.model.dof_frictionloss[:] = self.nominal["friction"]
        self.model.dof_damping[:] = self.nominal["damping"]
        if self.randomize:
            shift = rng.uniform(-c.pose_jitter, c.pose_jitter, 2)
            yaw = float(np.radians(rng.uniform(-c.yaw_jitter_deg, c.yaw_jitter_deg)))
            lo, hi = np.log(c.dynamics_scale)
            dofs = self.model.jnt_dofadr[[j for j in range(self.model.njnt)
                                          if mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_JOINT, j)
                                          .startswith(OBJECT_PREFIX)]]
            self.model.dof_frictionloss[dofs] *= np.exp(rng.uniform(lo, hi))
            self.model.dof_damping[dofs] *= np.exp(rng.uniform(lo, hi))
        centre = (scene.lower + scene.upper) / 2
        cz, sz = np.cos(yaw), np.sin(yaw)
        turn = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
        offset = np.array([shift[0], shift[1], 0.0]) - turn @ np.array([centre[0], centre[1], scene.lower[2]])
        self.model.body_pos[self.object_body] = offset
        self.model.body_quat[self.object_body] = quat_from_matrix(turn)
        self.object_rotation = turn @ scene.rotation
        half = (scene.upper - scene.lower) / 2
        radius = float(np.linalg.norm(half))
        reach = 2 * radius + WORKSPACE_MARGIN  # open doors and lids stick out by up to a radius
        self.work_lo = np.array([-reach, -reach, 0.0]) + np.append(shift, 0.0)
        self.work_hi = np.array([reach, reach, 2 * half[2] + reach]) + np.append(shift, 0.0)
        self.safe_height = float(2 * half[2] + 0.1)
        self._place_camera(np.array([shift[0], shift[1], half[2]]), radius)

    def _place_camera(self, centre: np.ndarray, radius: float) -> None:
        c, rng = self.config, self.np_random
        azimuth, elevation = np.radians(c.camera_azimuth_deg), np.radians(c.camera_elevation_deg)
        distance = c.camera_distance * radius / np.sin(np.radians(c.camera_fovy_deg) / 2)
        direction = np.array([np.sin(azimuth) * np.cos(elevation), -np.cos(azimuth) * np.cos(elevation),
                              np.sin(elevation)])
        position = centre + distance * direction
        look = -direction
        if self.randomize:
            position = position + rng.uniform(-c.camera_jitter, c.camera_jitter, 3)
            look = look + rng.uniform(-1, 1, 3) * np.radians(c.camera_jitter_deg)
            look = look / np.linalg.norm(look)
        right = np.cross(look, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, look)
        self.model.cam_pos[self.camera] = position
        self.model.cam_quat[self.camera] = quat_from_matrix(np.column_stack([right, up, -look]))

    def _place_gripper(self) -> None:
        """Gripper open, in front of and above the object, pointing at it (+y)."""
        centre = (self.work_lo + self.work_hi) / 2
        radius = float(np.linalg.norm(self.scene.upper - self.scene.lower) / 2)
        position = np.array([centre[0], centre[1] - radius - 0.25, self.safe_height])
        quat = quat_from_matrix(np.array([[-1.0, 0, 0], [0, 0, 1.0], [0, 1.0, 0]]))  # columns: x, y, z of the tool
        self.data.mocap_pos[self.mocap] = position
        self.data.mocap_quat[self.mocap] = quat
        self.data.qpos[self.gripper_qpos:self.gripper_qpos + 3] = position
        self.data.qpos[self.gripper_qpos + 3:self.gripper_qpos + 7] = quat
        self.data.qpos[self.fingers] = self.config.finger_opening
        self.data.ctrl[:2] = self.config.finger_opening
        self.data.ctrl[2:4] = 0.0

    def handle_pose(self, back: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """World position (3,) and rotation (3, 3) of the grasp frame at the current state (with
        ``back``: of the grasp on the panel's inner face)."""
        xmat = self.data.xmat[self.child_body].reshape(3, 3)
        local, frame = ((self.task.back_local_point, self.task.back.frame()) if back
                        else (self.task.local_point, self.grasp_frame))
        return self.data.xpos[self.child_body] + xmat @ local, xmat @ frame

    def joint_axis(self) -> tuple[np.ndarray, np.ndarray]:
        """World direction (3,) and a point (3,) of the target joint's axis, now."""
        return self.data.xaxis[self.joint_id].copy(), self.data.xanchor[self.joint_id].copy()

    def joint_fraction(self) -> float:
        return float(self.data.qpos[self.joint_qpos]) / self.task.upper

    def _observation(self) -> dict:
        tcp = self.data.site_xpos[self.tcp].copy()
        tcp_quat = quat_from_matrix(self.data.site_xmat[self.tcp].reshape(3, 3))
        handle, frame = self.handle_pose()
        value = float(self.data.qpos[self.joint_qpos])
        opening = max(0.0, float(self.data.qpos[self.fingers].sum()))  # the soft finger limits give a little
        obs = {"gripper_pos": tcp, "gripper_quat": tcp_quat, "gripper_opening": np.array([opening]),
               "joint_value": np.array([value]), "joint_fraction": np.array([value / self.task.upper]),
               "handle_pos": handle, "handle_quat": quat_from_matrix(frame)}
        if self.image_obs:
            size = (self.config.image_height, self.config.image_width)
            obs["rgb"] = self._camera_image(size, depth=False)
            obs["depth"] = self._camera_image(size, depth=True)[..., None]
        return obs

    def _info(self) -> dict:
        fraction = self.joint_fraction()
        axis, anchor = self.joint_axis()
        return {"success": bool(self.succeeded(fraction) and self.grip <= 0), "joint_fraction": fraction,
                "asset": self.scene.asset_dir.name, "joint": self.task.name, "joint_type": self.task.type,
                "joint_axis": axis, "joint_anchor": anchor, "joint_range": self.task.upper,
                "grasp_mode": self.task.grasp.mode, "safe_height": self.safe_height, **self._back_info()}

    def _back_info(self) -> dict:
        """The inner-face grasp's pose, where the part has one (NaN otherwise)."""
        if self.task.back is None:
            return {"back_pos": np.full(3, np.nan), "back_quat": np.full(4, np.nan)}
        position, frame = self.handle_pose(back=True)
        return {"back_pos": position, "back_quat": quat_from_matrix(frame)}

    def _camera_image(self, size: tuple[int, int], depth: bool) -> np.ndarray:
        key = (id(self.model), *size)
        renderer = self._renderers.get(key)
        if renderer is None:
            try:
                renderer = mujoco.Renderer(self.model, *size)
            except Exception as exc:  # no GL library: say which package to install
                raise SimulationError(f"{RENDER_HINT} ({type(exc).__name__}: {exc})") from None
            self._renderers[key] = renderer
        if depth:
            renderer.enable_depth_rendering()
        else:
            renderer.disable_depth_rendering()
        renderer.update_scene(self.data, self.camera)
        image = renderer.render()
        return image.astype(np.float32) if depth else image


class OpenArticulationEnv(ArticulationEnv):
    """Open the chosen joint past ``target_fraction`` of its range and let go."""

    mode = "open"


class CloseArticulationEnv(ArticulationEnv):
    """Close the chosen joint (from ``close_start_fraction``) below ``close_fraction`` and let go."""

    mode = "close"

    def start_fraction(self) -> float:
        return self.config.close_start_fraction

    def succeeded(self, fraction: float) -> bool:
        return fraction <= self.config.close_fraction

    def progress(self, fraction: float) -> float:
        start = self.config.close_start_fraction
        return float(np.clip((start - fraction) / (start - self.config.close_fraction), 0.0, 1.0))
