"""PyBullet adapter: load the URDF with a fixed base in a DIRECT client and run it."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.sim import EngineRun


def run_gravity(asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    import pybullet as pb

    client = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(*gravity, physicsClientId=client)
        pb.setTimeStep(timestep, physicsClientId=client)
        body = pb.loadURDF(str(Path(asset_dir) / f"{name}.urdf"), useFixedBase=True,
                           flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        joints = [j for j in range(pb.getNumJoints(body, physicsClientId=client))
                  if pb.getJointInfo(body, j, physicsClientId=client)[2] in (pb.JOINT_REVOLUTE, pb.JOINT_PRISMATIC)]
        names = [pb.getJointInfo(body, j, physicsClientId=client)[1].decode() for j in joints]
        samples, max_speed = [], 0.0
        for k in range(int(round(seconds / timestep))):
            pb.stepSimulation(physicsClientId=client)
            if k % 10 == 0:
                states = pb.getJointStates(body, joints, physicsClientId=client) if joints else []
                samples.append([s[0] for s in states])
                max_speed = max([max_speed, *[abs(s[1]) for s in states]])
        return EngineRun("pybullet", True, None, names, np.array(samples, dtype=float).reshape(len(samples), len(joints)),
                         {}, max_speed)
    finally:
        pb.disconnect(client)


def run_actuation(asset_dir, name: str, gravity: np.ndarray, forces: dict[str, float], seconds: float,
                  timestep: float) -> dict[str, np.ndarray]:
    """As ``mujoco_engine.run_actuation``: per joint, +force then -force for ``seconds`` each
    (torque control on the pushed joint; the others held only by their dry friction)."""
    import pybullet as pb

    client = pb.connect(pb.DIRECT)
    try:
        out = {}
        steps = int(round(seconds / timestep))
        for joint, force in forces.items():
            pb.resetSimulation(physicsClientId=client)
            pb.setGravity(*gravity, physicsClientId=client)
            pb.setTimeStep(timestep, physicsClientId=client)
            body = pb.loadURDF(str(Path(asset_dir) / f"{name}.urdf"), useFixedBase=True,
                               flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
            index = {pb.getJointInfo(body, j, physicsClientId=client)[1].decode(): j
                     for j in range(pb.getNumJoints(body, physicsClientId=client))}
            j = index[joint]
            # a body at rest falls asleep, and a sleeping body ignores the torque applied to it
            pb.changeDynamics(body, -1, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=client)
            pb.setJointMotorControl2(body, j, pb.VELOCITY_CONTROL, force=0.0, physicsClientId=client)
            samples = []
            for sign in (1.0, -1.0):
                for k in range(steps):
                    pb.setJointMotorControl2(body, j, pb.TORQUE_CONTROL, force=sign * force, physicsClientId=client)
                    pb.stepSimulation(physicsClientId=client)
                    if k % 10 == 0:
                        samples.append(float(pb.getJointState(body, j, physicsClientId=client)[0]))
            out[joint] = np.array(samples)
        return out
    finally:
        pb.disconnect(client)
