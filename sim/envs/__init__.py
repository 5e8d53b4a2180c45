"""Gymnasium environments on MuJoCo built from reconstructed assets.

Importing this package registers ``rest2art/OpenArticulation-v0`` and
``rest2art/CloseArticulation-v0``::

    import gymnasium as gym
    import rest2art.sim.envs  # noqa: F401  (registers the environments)

    env = gym.make("rest2art/OpenArticulation-v0", asset="assets_out/demo", render_mode="rgb_array")
    env = gym.make("rest2art/CloseArticulation-v0", catalog="assets_out", category="cabinet",
                   joint_type="prismatic", seed=0)

In worker processes started with ``spawn`` (``AsyncVectorEnv(..., context="spawn")``) name the
module in the id so that it is imported there: ``"rest2art.sim.envs:rest2art/OpenArticulation-v0"``.
"""

from __future__ import annotations

import gymnasium

from rest2art.sim.envs.articulation_env import ArticulationEnv, CloseArticulationEnv, OpenArticulationEnv

ENV_IDS = ("rest2art/OpenArticulation-v0", "rest2art/CloseArticulation-v0")

for _id, _cls in zip(ENV_IDS, ("OpenArticulationEnv", "CloseArticulationEnv")):
    if _id not in gymnasium.registry:
        gymnasium.register(id=_id, entry_point=f"rest2art.sim.envs.articulation_env:{_cls}")

__all__ = ["ENV_IDS", "ArticulationEnv", "CloseArticulationEnv", "OpenArticulationEnv"]
