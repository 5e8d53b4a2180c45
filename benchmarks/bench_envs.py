"""Environment steps per second: one environment and a 2-worker vector environment, with and
without rendering.

    python benchmarks/bench_envs.py [--asset DIR] [--steps 300]

With no ``--asset`` a generated cabinet (seed 1: two doors, two drawers) is completed, exported
and used. Random actions; each setting is reset once and then stepped ``--steps`` times (per
environment). "rendering" adds the 128x96 rgb and depth images to every observation
(``image_obs=True``); it needs MUJOCO_GL=egl (libegl1) or osmesa (libosmesa6).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np


def make_cabinet(folder: Path) -> Path:
    from rest2art.config import Config
    from rest2art.export.writers import write_asset
    from rest2art.generate import generate_object
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import complete_asset

    asset = generate_object("cabinet", 1, "asset").asset
    config = Config()
    complete_asset(asset, config)
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "cabinet", config.export, np.array([0.0, 0.0, 1.0]))
    return folder


def steps_per_second(make, steps: int, vector: int) -> float:
    """Environment steps per second (summed over the vector's environments)."""
    import gymnasium as gym

    env = gym.vector.AsyncVectorEnv([make] * vector, context="spawn") if vector > 1 else make()
    env.reset(seed=0)
    env.action_space.seed(0)
    actions = [env.action_space.sample() for _ in range(steps)]
    start = time.perf_counter()
    for action in actions:
        env.step(action)
    elapsed = time.perf_counter() - start
    env.close()
    return steps * max(vector, 1) / elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--asset", help="asset folder (default: a generated cabinet)")
    parser.add_argument("--steps", type=int, default=300)
    args = parser.parse_args()

    import gymnasium as gym
    import rest2art.sim.envs  # noqa: F401

    with tempfile.TemporaryDirectory() as tmp:
        asset = Path(args.asset) if args.asset else make_cabinet(Path(tmp) / "cabinet")
        rows = {}
        for images in (False, True):
            def make(images=images):
                return gym.make("rest2art.sim.envs:rest2art/OpenArticulation-v0", asset=str(asset), image_obs=images)

            for vector in (1, 2):
                rows[(images, vector)] = steps_per_second(make, args.steps, vector)
    print(f"steps per second ({args.steps} random steps per environment, control step 0.04 s = 20 physics steps)")
    print("| setting | 1 env | AsyncVectorEnv, 2 workers |")
    print("|---|---|---|")
    for images, label in ((False, "no rendering"), (True, "rgb + depth 128x96 every step")):
        print(f"| {label} | {rows[(images, 1)]:.0f} | {rows[(images, 2)]:.0f} |")
    print(json.dumps({f"{'render' if i else 'state'}_{v}": round(s, 1) for (i, v), s in rows.items()}))


if __name__ == "__main__":
    main()
