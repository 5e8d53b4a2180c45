"""Policies for the articulation environments (``rest2art.sim.envs``).

``ScriptedPolicy`` approaches the handle along the part's outward normal, grasps it, pulls it
along the joint's motion and lets go; ``solve`` runs it on every movable joint of a catalog.
"""

from rest2art.sim.policies.scripted import ScriptedPolicy, run_episode

__all__ = ["ScriptedPolicy", "run_episode"]
