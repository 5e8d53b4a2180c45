"""Simulator adapters: load an exported asset and run it in MuJoCo, PyBullet and SAPIEN.

Installed as ``rest2art.sim``. An engine is one module that imports its simulator lazily and
registers itself::

    register_engine("mujoco", run_gravity, run_actuation)

``run_gravity(asset_dir, name, gravity, seconds, timestep) -> EngineRun`` loads the asset and
lets it hang under gravity; the optional ``run_actuation(asset_dir, name, gravity, pushes,
seconds, timestep, contacts) -> {joint: (T,) trajectory}`` pushes each joint open and shut
(``pushes``: per pushed joint, the force on it and on each joint pushed along with it).
``check.engines`` picks the engines validation runs; the actuation check runs in those that can
push.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from rest2art.errors import ConfigError


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


@dataclass(frozen=True)
class Engine:
    """One registered simulator."""

    name: str
    run_gravity: Callable[..., EngineRun]
    run_actuation: Callable[..., dict[str, np.ndarray]] | None = None
    """None for an engine validation does not push joints in."""


ENGINES: dict[str, Engine] = {}
"""Every registered engine by name, in registration order."""


def register_engine(name: str, run_gravity: Callable[..., EngineRun],
                    run_actuation: Callable[..., dict[str, np.ndarray]] | None = None) -> Engine:
    """Register an engine under ``name`` (registering a name again replaces it)."""
    ENGINES[name] = Engine(name, run_gravity, run_actuation)
    return ENGINES[name]


def engines(names: tuple[str, ...] | list[str]) -> list[Engine]:
    """The registered engines ``names``, in that order; a ConfigError naming the valid ones
    for a name that is not registered."""
    unknown = [n for n in names if n not in ENGINES]
    if unknown:
        raise ConfigError(f"check.engines: unknown engine '{unknown[0]}'. Engines: {', '.join(ENGINES)}")
    return [ENGINES[n] for n in names]


def run_engine(engine: str, asset_dir, name: str, gravity: np.ndarray, seconds: float, timestep: float) -> EngineRun:
    """Run the asset under gravity in a registered engine; one that cannot start reports loaded=False."""
    (adapter,) = engines([engine])
    try:
        return adapter.run_gravity(asset_dir, name, np.asarray(gravity, float), seconds, timestep)
    except Exception as exc:  # an asset the engine rejects is a finding, not a crash
        return EngineRun(engine, False, f"{type(exc).__name__}: {exc}")


from rest2art.sim import mujoco_engine, pybullet_engine, sapien_engine  # noqa: E402,F401  (they register themselves)
