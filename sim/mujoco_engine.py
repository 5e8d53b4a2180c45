"""MuJoCo adapter: compile the MJCF, run it under gravity, read the warning counters."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.sim import EngineRun, register_engine


def load_model(asset_dir: str | Path, name: str, gravity: np.ndarray | None = None, timestep: float | None = None):
    """Compile NAME.xml; ``gravity`` (3,) m/s^2 and ``timestep`` s replace the file's values."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(Path(asset_dir) / f"{name}.xml"))
    if gravity is not None:
        model.opt.gravity[:] = gravity
    if timestep is not None:
        model.opt.timestep = timestep
    return model


def steps_per_second(asset_dir: str | Path, name: str, steps: int = 2000) -> float:
    """Simulation speed of NAME.xml as written (its own timestep, no robot): ``steps`` calls of
    ``mj_step`` from the rest pose, per second of wall time on this machine."""
    import time

    import mujoco

    model = load_model(asset_dir, name)
    data = mujoco.MjData(model)
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, data)
    return steps / (time.perf_counter() - start)


def run_gravity(asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    import mujoco

    model = load_model(asset_dir, name, gravity, timestep)
    data = mujoco.MjData(model)
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(model.njnt)]
    steps = int(round(seconds / timestep))
    samples = []
    max_speed = 0.0
    for k in range(steps):
        mujoco.mj_step(model, data)
        if k % 10 == 0:
            samples.append(data.qpos.copy())
            max_speed = max(max_speed, float(np.abs(data.qvel).max(initial=0.0)))
    warnings = {mujoco.mjtWarning(i).name: int(w.number) for i, w in enumerate(data.warning) if w.number}
    return EngineRun("mujoco", True, None, names, np.array(samples), warnings, max_speed)


def joint_loads(asset_dir, name: str, gravity: np.ndarray) -> dict[str, dict[str, float]]:
    """Per movable joint: effective inertia at rest (kg or kg m^2, armature included), dry
    friction, damping, range, the largest gravity load over the range (N or N m), and the
    movable joints it carries (``carries``: those of the bodies below its own)."""
    import mujoco

    model = load_model(asset_dir, name, gravity)
    data = mujoco.MjData(model)
    mass_matrix = np.zeros((model.nv, model.nv))
    mujoco.mj_forward(model, data)
    if hasattr(data, "qM"):  # MuJoCo 3
        mujoco.mj_fullM(model, mass_matrix, data.qM)
    else:  # MuJoCo 4 takes the data itself
        mujoco.mj_fullM(model, data, mass_matrix)
    out = {}
    for j in range(model.njnt):
        if int(model.jnt_type[j]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            continue
        dof, adr = model.jnt_dofadr[j], model.jnt_qposadr[j]
        lo, hi = model.jnt_range[j]
        loads = []
        for q in np.linspace(lo, hi, 5):
            data.qpos[:] = model.qpos0
            data.qpos[adr] = q
            mujoco.mj_forward(model, data)
            loads.append(abs(float(data.qfrc_bias[dof])))
        out[mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j)] = {
            "inertia": float(mass_matrix[dof, dof]), "friction": float(model.dof_frictionloss[dof]),
            "damping": float(model.dof_damping[dof]), "range": (float(lo), float(hi)), "gravity": max(loads),
            "carries": [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, k) for k in range(model.njnt)
                        if k != j and _below(model, int(model.jnt_bodyid[k]), int(model.jnt_bodyid[j]))]}
    return {joint: {**load, "carries": [k for k in load["carries"] if k in out]} for joint, load in out.items()}


def _below(model, body: int, ancestor: int) -> bool:
    """Whether ``body`` is ``ancestor`` or hangs below it in the model's body tree."""
    while body > 0 and body != ancestor:
        body = int(model.body_parentid[body])
    return body == ancestor


def rest_contacts(asset_dir, name: str) -> tuple[float, list[tuple[str, str, float]]]:
    """At the closed pose without gravity: the norm of all constraint forces (N) and the
    penetrating contacts (body, body, depth m)."""
    import mujoco

    model = load_model(asset_dir, name, np.zeros(3))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    contacts = []
    for c in data.contact[: data.ncon]:
        b1 = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[c.geom1])
        b2 = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[c.geom2])
        contacts.append((b1, b2, float(-c.dist)))
    return float(np.linalg.norm(data.efc_force)), contacts


def touching(model, data, body: int) -> list[str]:
    """'a-b' body pairs in contact that involve ``body``, sorted."""
    import mujoco

    pairs = set()
    for c in data.contact[: data.ncon]:
        b1, b2 = int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2])
        if body in (b1, b2) and b1 != b2:
            pairs.add("-".join(sorted(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in (b1, b2))))
    return sorted(pairs)


def run_actuation(asset_dir, name: str, gravity: np.ndarray, pushes: dict[str, dict[str, float]], seconds: float,
                  timestep: float, contacts: dict[str, list[str]] | None = None) -> dict[str, np.ndarray]:
    """Per pushed joint, from rest: push with +force for ``seconds`` then with -force for
    ``seconds`` (the other joints free); returns its (T,) trajectory sampled every 10 steps.
    ``pushes[joint]``: the generalized force on that joint and on each joint it carries that is
    pushed along with it; those are pushed open first, for ``seconds``, and held open (a hand
    turns a door's latch, then pulls the door). ``contacts`` receives the body pairs touching
    the pushed body at the end of the opening push."""
    import mujoco

    model = load_model(asset_dir, name, gravity, timestep)
    out = {}
    steps = int(round(seconds / timestep))
    for joint, forces in pushes.items():
        j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        dof, adr = model.jnt_dofadr[j], model.jnt_qposadr[j]
        data = mujoco.MjData(model)
        for carried, force in forces.items():
            if carried != joint:
                data.qfrc_applied[model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, carried)]] = force
        for _ in range(steps if len(forces) > 1 else 0):
            mujoco.mj_step(model, data)
        samples = []
        for sign in (1.0, -1.0):
            data.qfrc_applied[dof] = sign * forces[joint]
            for k in range(steps):
                mujoco.mj_step(model, data)
                if k % 10 == 0:
                    samples.append(float(data.qpos[adr]))
            if sign > 0 and contacts is not None:
                contacts[joint] = touching(model, data, int(model.jnt_bodyid[j]))
        out[joint] = np.array(samples)
    return out


register_engine("mujoco", run_gravity, run_actuation)
