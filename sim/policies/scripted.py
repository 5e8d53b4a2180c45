"""A scripted policy: approach along the grasp normal, grasp, pull along the joint, release.

It reads only the observation and the joint's axis from ``info`` (known from the asset's
metadata): every step it predicts where the handle will be when the joint has moved a little
further (an arc about the axis for a revolute joint, a line for a prismatic one) and steers
the gripper there, so the commanded motion never runs more than ``lead`` of the range ahead of
the measured joint.
"""

from __future__ import annotations

import numpy as np

from rest2art.config import EnvConfig
from rest2art.geometry.basics import rotation_about

PHASES = ("approach", "reach", "grip", "pull", "release", "retreat", "done")
SLIP_DISTANCE = 0.04
"""The grasp has slipped when the fingertips are this far (m) from the handle while pulling."""
STALL_STEPS = 25
"""Pulling gives up after this many steps without the joint moving on."""
STALL_PROGRESS = 0.005
"""... by at least this share of its range."""
MAX_REGRASPS = 2
"""A slipped grasp is retried this many times."""
DOWNWARD = 0.5
"""A handle faces down when its outward normal's vertical component is below minus this."""
WAYPOINT_PROGRESS = 0.005
"""Getting this much closer (m) to an approach waypoint counts as progress."""
PRESS_TOL = 0.02
"""Pressing on a face: the fingertips are on it when they stop within this distance (m) of the
point past the surface they are driven to."""


def quat_to_matrix(quat: np.ndarray) -> np.ndarray:
    """(3, 3) rotation of a w x y z quaternion (4,)."""
    w, x, y, z = np.asarray(quat, float) / np.linalg.norm(quat)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rotation_error(target: np.ndarray, current: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) rad, world frame, that turns ``current`` (3, 3) into ``target``."""
    delta = target @ current.T
    angle = float(np.arccos(np.clip((np.trace(delta) - 1) / 2, -1.0, 1.0)))
    if angle < 1e-9:
        return np.zeros(3)
    axis = np.array([delta[2, 1] - delta[1, 2], delta[0, 2] - delta[2, 0], delta[1, 0] - delta[0, 1]])
    if np.linalg.norm(axis) < 1e-9:  # a half turn: axis from the symmetric part
        axis = np.linalg.eigh(delta + delta.T)[1][:, -1]
    return angle * axis / np.linalg.norm(axis)


class ScriptedPolicy:
    """Open (``mode='open'``) or close (``'close'``) the environment's joint; call ``reset(obs, info)``
    after ``env.reset`` and ``act(obs, info)`` every step. ``failure`` says why an attempt
    gave up (None while it goes on or after success)."""

    def __init__(self, mode: str = "open", config: EnvConfig = EnvConfig()):
        if mode not in ("open", "close"):
            raise ValueError(f"mode '{mode}' is not valid. Valid modes: open, close")
        self.mode, self.config, self.policy = mode, config, config.policy

    def reset(self, obs: dict, info: dict) -> None:
        """Start a new attempt on the joint described by ``obs`` and ``info`` (from ``env.reset``)."""
        self._go("approach")
        self.regrasps = 0
        self.safe_height = float(info["safe_height"])
        self.failure: str | None = None
        self.best, self.best_step = None, 0
        outward_z = -quat_to_matrix(obs["handle_quat"])[2, 2]
        self.back = bool(self.mode == "close" and info["grasp_mode"] == "pinch" and outward_z < -DOWNWARD
                         and np.isfinite(info["back_pos"]).all())
        self.press = info["grasp_mode"] == "press" or self.back

    # ---- targets ---------------------------------------------------------------------------

    def goal_fraction(self) -> float:
        c, p = self.config, self.policy
        return c.target_fraction + p.overshoot if self.mode == "open" else c.close_fraction - p.overshoot

    def reached_goal(self, fraction: float) -> bool:
        c, p = self.config, self.policy
        if self.mode == "open":
            return fraction >= min(c.target_fraction + 0.5 * p.overshoot, 1.0)
        return fraction <= c.close_fraction * 0.5

    def moved_handle(self, obs: dict, info: dict, delta: float) -> tuple[np.ndarray, np.ndarray]:
        """Handle position (3,) and rotation (3, 3) once the joint has moved by ``delta``."""
        position, rotation = self.holding(obs, info)
        axis, anchor = np.asarray(info["joint_axis"], float), np.asarray(info["joint_anchor"], float)
        if info["joint_type"] == "prismatic":
            return position + delta * axis, rotation
        turn = rotation_about(axis, delta)
        return anchor + turn @ (position - anchor), turn @ rotation

    def holding(self, obs: dict, info: dict) -> tuple[np.ndarray, np.ndarray]:
        """Where the gripper holds the part now: the handle's position (3,) and rotation (3, 3),
        or, for an opened flap whose handle faces the floor, the grasp on its inner face."""
        if self.back:
            return np.asarray(info["back_pos"], float), quat_to_matrix(info["back_quat"])
        return obs["handle_pos"], quat_to_matrix(obs["handle_quat"])

    def target(self, obs: dict, info: dict) -> tuple[np.ndarray, np.ndarray, float]:
        """The gripper's target position (3,), rotation (3, 3) and grip for the current phase."""
        p = self.policy
        position, rotation = self.holding(obs, info)
        inward = rotation[:, 2]
        press = p.press_depth * inward if self.press else 0.0
        if self.phase == "approach":
            far = position - p.clearance_distance * inward
            above = np.array([far[0], far[1], max(self.safe_height, far[2], position[2] + p.clearance_distance)])
            waypoints = (above, far, position - p.pregrasp_distance * inward)
            return waypoints[self.waypoint], rotation, -1.0
        if self.phase == "reach":
            return position + press, rotation, -1.0
        if self.phase == "grip":
            return position + press, rotation, 1.0
        if self.phase == "pull":
            span = info["joint_range"]
            fraction = float(obs["joint_fraction"][0])
            goal = self.goal_fraction()
            step = np.clip(goal - fraction, -p.lead, p.lead)
            moved, turned = self.moved_handle(obs, info, step * span)
            return moved + press, turned, 1.0
        if self.phase == "release":  # hold still while the fingers open
            return obs["gripper_pos"], quat_to_matrix(obs["gripper_quat"]), -1.0
        return position - p.pregrasp_distance * inward, rotation, -1.0

    # ---- control ---------------------------------------------------------------------------

    def act(self, obs: dict, info: dict) -> np.ndarray:
        """The action (7,) for this step."""
        self._advance(obs, info)
        position, rotation, grip = self.target(obs, info)
        return self.action_towards(obs, position, rotation, grip)

    def action_towards(self, obs: dict, position: np.ndarray, rotation: np.ndarray, grip: float) -> np.ndarray:
        """Action (7,) that moves the gripper towards a pose, at most the full step per axis."""
        c = self.config
        move = (position - obs["gripper_pos"]) / c.max_translation
        turn = rotation_error(rotation, quat_to_matrix(obs["gripper_quat"])) / np.radians(c.max_rotation_deg)
        move /= max(1.0, float(np.abs(move).max()))
        turn /= max(1.0, float(np.abs(turn).max()))
        return np.concatenate([move, turn, [grip]]).astype(np.float32)

    def _at(self, obs: dict, position: np.ndarray, rotation: np.ndarray) -> bool:
        p = self.policy
        angle = np.degrees(np.linalg.norm(rotation_error(rotation, quat_to_matrix(obs["gripper_quat"]))))
        return np.linalg.norm(position - obs["gripper_pos"]) < p.reach_tol and angle < p.reach_angle_deg

    def _go(self, phase: str) -> None:
        self.phase, self.phase_steps, self.waypoint = phase, 0, 0
        self.closest, self.closest_step = np.inf, 0

    def _advance(self, obs: dict, info: dict) -> None:
        """Move on to the next phase when the current one is done."""
        p = self.policy
        self.phase_steps += 1
        fraction = float(obs["joint_fraction"][0])
        if self.phase in ("approach", "reach"):
            position, rotation, _ = self.target(obs, info)
            distance = float(np.linalg.norm(position - obs["gripper_pos"]))
            if distance < self.closest - WAYPOINT_PROGRESS:
                self.closest, self.closest_step = distance, self.phase_steps
            passing = self.phase == "approach" and self.waypoint < 2 and distance < p.clearance_tol
            if passing:
                self.waypoint += 1
                self.closest, self.closest_step = np.inf, self.phase_steps
            elif self._at(obs, position, rotation) or (self.phase == "reach" and self.press and distance < PRESS_TOL
                                                        and self.phase_steps - self.closest_step > 3):
                self._go("reach" if self.phase == "approach" else "grip")
            elif self.phase_steps - self.closest_step > p.waypoint_steps:
                self.failure = f"{self.phase}: the gripper got stuck {100 * distance:.0f} cm from the handle"
                self._go("done")
        elif self.phase == "grip" and self.phase_steps >= p.grip_steps:
            self._go("pull")
            self.best, self.best_step = fraction, 0
        elif self.phase == "pull":
            towards = fraction - self.best if self.mode == "open" else self.best - fraction
            if towards > STALL_PROGRESS:
                self.best, self.best_step = fraction, self.phase_steps
            if self.reached_goal(fraction):
                self._go("release")
            elif np.linalg.norm(self.holding(obs, info)[0] - obs["gripper_pos"]) > SLIP_DISTANCE:
                if self.regrasps < MAX_REGRASPS:
                    self.regrasps += 1
                    self._go("approach")
                else:
                    self.failure = f"pull: the grasp slipped at {100 * fraction:.0f} % of the range"
                    self._go("release")
            elif self.phase_steps - self.best_step > STALL_STEPS:
                self.failure = f"pull: the joint stalled at {100 * fraction:.0f} % of the range"
                self._go("release")
        elif self.phase == "release" and self.phase_steps >= p.release_steps:
            self._go("retreat")
        elif self.phase == "retreat":
            position, rotation, _ = self.target(obs, info)
            if self._at(obs, position, rotation) or self.phase_steps > p.waypoint_steps:
                self._go("done")


def run_episode(env, policy: ScriptedPolicy, seed: int | None = None, options: dict | None = None) -> dict:
    """One episode of ``policy`` in ``env``: success, the final joint fraction, steps, and the
    reason of a failure."""
    obs, info = env.reset(seed=seed, options=options)
    policy.reset(obs, info)
    start = info["joint_fraction"]
    steps, success, reward = 0, False, 0.0
    while True:
        obs, r, terminated, truncated, info = env.step(policy.act(obs, info))
        steps, reward = steps + 1, reward + float(r)
        if terminated:
            success = bool(info["success"])
            break
        if truncated or policy.phase == "done":
            break
    reason = None
    if not success:
        reason = policy.failure or (f"released at {100 * info['joint_fraction']:.0f} % of the range"
                                    if policy.phase == "done" else f"time out in phase {policy.phase}")
    return {"success": success, "start_fraction": float(start), "final_fraction": float(info["joint_fraction"]),
            "steps": steps, "return": reward, "reason": reason, "grasp_mode": info["grasp_mode"]}
