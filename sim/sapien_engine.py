"""SAPIEN adapter: a physics-only scene (CPU PhysX, no renderer), URDF with a fixed root."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from rest2art.sim import EngineRun, register_engine


def run_gravity(asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # SAPIEN warns about Vulkan on import; no renderer is used
        import sapien

    config = sapien.physx.PhysxSceneConfig()
    config.gravity = np.asarray(gravity, dtype=np.float32)
    sapien.physx.set_scene_config(config)
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(timestep)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    builders, actors, _ = loader.parse(str(Path(asset_dir) / f"{name}.urdf"))
    if not builders and actors:  # a single link: SAPIEN makes it an actor, fixed in place
        actors[0].visual_records = []
        actors[0].build_kinematic()
        for _ in range(int(round(seconds / timestep))):
            scene.step()
        return EngineRun("sapien", True, None, [], np.zeros((0, 0)), {}, 0.0)
    if not builders:
        return EngineRun("sapien", False, "the URDF holds no link")
    for link in builders[0].link_builders:
        link.visual_records = []  # visual shapes need a render device; physics does not
    articulation = builders[0].build()
    names = [j.name for j in articulation.get_active_joints()]
    for joint in articulation.get_active_joints():
        joint.set_friction(0.2)
        joint.set_drive_properties(0.0, 0.5)
    samples, max_speed = [], 0.0
    for k in range(int(round(seconds / timestep))):
        scene.step()
        if k % 10 == 0:
            samples.append(np.asarray(articulation.get_qpos(), dtype=float).copy())
            max_speed = max(max_speed, float(np.abs(articulation.get_qvel()).max(initial=0.0)))
    return EngineRun("sapien", True, None, names, np.array(samples).reshape(len(samples), len(names)), {}, max_speed)


register_engine("sapien", run_gravity)
