"""PyBullet adapter: load the URDF with a fixed base in a DIRECT client and run it.

Self-collision is on with parent/child pairs excluded: the pairs MuJoCo checks (the MJCF
excludes each joint's parent and child) and SAPIEN checks (PhysX leaves out the two links of
each joint), so the engines judge an asset on the same contacts.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.sim import EngineRun, register_engine


def _load_fixed(client: int, asset_dir, name: str, gravity: np.ndarray, timestep: float) -> int:
    """Set gravity and the step in ``client`` and load NAME.urdf with a fixed base; its body id."""
    import pybullet as pb

    pb.setGravity(*gravity, physicsClientId=client)
    pb.setTimeStep(timestep, physicsClientId=client)
    flags = pb.URDF_USE_INERTIA_FROM_FILE | pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
    return pb.loadURDF(str(Path(asset_dir) / f"{name}.urdf"), useFixedBase=True, flags=flags, physicsClientId=client)


def touching(client: int, body: int, link: int) -> list[str]:
    """'a-b' link pairs in contact that involve ``link`` (self-contacts of ``body``), sorted.

    Only points at zero or negative distance count: PyBullet also returns points a few mm
    apart (within its contact threshold), which MuJoCo (geom margin 0) does not report."""
    import pybullet as pb

    names = {-1: pb.getBodyInfo(body, physicsClientId=client)[0].decode()}
    names.update({j: pb.getJointInfo(body, j, physicsClientId=client)[12].decode()
                  for j in range(pb.getNumJoints(body, physicsClientId=client))})
    pairs = set()
    for c in pb.getContactPoints(bodyA=body, bodyB=body, physicsClientId=client):
        if link in (c[3], c[4]) and c[3] != c[4] and c[8] <= 0.0:
            pairs.add("-".join(sorted((names[c[3]], names[c[4]]))))
    return sorted(pairs)


def run_gravity(asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    import pybullet as pb

    client = pb.connect(pb.DIRECT)
    try:
        body = _load_fixed(client, asset_dir, name, gravity, timestep)
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


def run_actuation(asset_dir, name: str, gravity: np.ndarray, pushes: dict[str, dict[str, float]], seconds: float,
                  timestep: float, contacts: dict[str, list[str]] | None = None) -> dict[str, np.ndarray]:
    """As ``mujoco_engine.run_actuation``: per pushed joint, +force then -force for ``seconds``
    each (torque control; the others held only by their dry friction), the joints pushed along
    with it pushed open first and held; ``contacts`` receives the pairs touching the pushed link
    at the end of the opening push."""
    import pybullet as pb

    client = pb.connect(pb.DIRECT)
    try:
        out = {}
        steps = int(round(seconds / timestep))
        for joint, forces in pushes.items():
            pb.resetSimulation(physicsClientId=client)
            body = _load_fixed(client, asset_dir, name, gravity, timestep)
            index = {pb.getJointInfo(body, j, physicsClientId=client)[1].decode(): j
                     for j in range(pb.getNumJoints(body, physicsClientId=client))}
            j = index[joint]
            # keep the body awake for the whole push
            pb.changeDynamics(body, -1, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=client)
            for pushed in forces:
                pb.setJointMotorControl2(body, index[pushed], pb.VELOCITY_CONTROL, force=0.0, physicsClientId=client)

            def push(pushed: str, force: float) -> None:
                pb.setJointMotorControl2(body, index[pushed], pb.TORQUE_CONTROL, force=force, physicsClientId=client)

            for _ in range(steps if len(forces) > 1 else 0):
                for carried, force in forces.items():
                    push(carried, 0.0 if carried == joint else force)
                pb.stepSimulation(physicsClientId=client)
            samples = []
            for sign in (1.0, -1.0):
                for k in range(steps):
                    for carried, force in forces.items():
                        push(carried, sign * force if carried == joint else force)
                    pb.stepSimulation(physicsClientId=client)
                    if k % 10 == 0:
                        samples.append(float(pb.getJointState(body, j, physicsClientId=client)[0]))
                if sign > 0 and contacts is not None:
                    contacts[joint] = touching(client, body, j)
            out[joint] = np.array(samples)
        return out
    finally:
        pb.disconnect(client)


register_engine("pybullet", run_gravity, run_actuation)
