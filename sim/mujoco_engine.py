"""MuJoCo adapter: compile the MJCF, run it under gravity, read the warning counters."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.sim import EngineRun


def load_model(asset_dir: str | Path, name: str):
    import mujoco

    return mujoco.MjModel.from_xml_path(str(Path(asset_dir) / f"{name}.xml"))


def run_gravity(asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    import mujoco

    model = load_model(asset_dir, name)
    model.opt.gravity[:] = gravity
    model.opt.timestep = timestep
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
