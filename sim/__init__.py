"""Simulator adapters: load an exported asset and run it in MuJoCo, PyBullet and SAPIEN.

Installed as ``rest2art.sim``. Each engine module imports its simulator lazily and exposes
``run_gravity(asset_dir, name, gravity, seconds, timestep) -> EngineRun``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

ENGINES = ("mujoco", "pybullet", "sapien")


@dataclass
class EngineRun:
    """What one engine did with the asset."""

    engine: str
    loaded: bool
    error: str | None = None
    joint_names: list[str] = field(default_factory=list)
    trajectory: np.ndarray | None = None
    """(T, J) joint values sampled during the run (rad or m)."""
    warnings: dict[str, int] = field(default_factory=dict)
    """Engine warning counters that were non-zero."""
    max_speed: float = 0.0
    """Largest joint speed seen (rad/s or m/s)."""


def run_engine(engine: str, asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    """Dispatch to the engine's adapter; an engine that cannot start reports loaded=False."""
    if engine == "mujoco":
        from rest2art.sim import mujoco_engine as mod
    elif engine == "pybullet":
        from rest2art.sim import pybullet_engine as mod
    elif engine == "sapien":
        from rest2art.sim import sapien_engine as mod
    else:
        raise ValueError(f"unknown engine '{engine}'. Valid engines: {', '.join(ENGINES)}")
    try:
        return mod.run_gravity(asset_dir, name, np.asarray(gravity, float), seconds, timestep)
    except Exception as exc:  # an asset the engine rejects is a finding, not a crash
        return EngineRun(engine, False, f"{type(exc).__name__}: {exc}")
