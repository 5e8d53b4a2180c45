"""Gymnasium environments on generated cabinets: the env checker, make with asset= and catalog=,
vector envs, rendering, grasp points from geometry and the scripted policy."""

import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import rest2art.sim.envs  # noqa: F401  (registers the environments)
from gymnasium.utils.env_checker import check_env
from rest2art.sim.envs import ENV_IDS, CloseArticulationEnv, OpenArticulationEnv
from rest2art.sim.envs.grasp import find_grasp
from rest2art.sim.policies import ScriptedPolicy, run_episode
from rest2art.validators.validate import validate_folder

from rest2art.errors import InputError
from rest2art.export.writers import write_asset
from rest2art.generate import generate_object
from rest2art.io.atomic import atomic_folder
from rest2art.pipeline import complete_asset

REPO = Path(__file__).resolve().parents[1]


def make_asset(kind: str, seed: int, folder: Path, config) -> Path:
    """A generated object's ground truth, completed, exported and validated (published)."""
    asset = generate_object(kind, seed, "asset").asset
    complete_asset(asset, config)
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, kind, config.export, np.array([0.0, 0.0, 1.0]))
    report = validate_folder(folder, kind, config, refine=True)
    assert report.decision.status == "publish", report.decision.reasons
    return folder


@pytest.fixture(scope="module")
def catalog(tmp_path_factory, config) -> Path:
    """A catalog of two published cabinets: doors and drawers (seed 1), drawers only (seed 2)."""
    root = tmp_path_factory.mktemp("catalog")
    make_asset("cabinet", 1, root / "cabinet_1", config)
    make_asset("cabinet", 2, root / "cabinet_2", config)
    return root


@pytest.fixture(scope="module")
def cabinet(catalog) -> Path:
    return catalog / "cabinet_1"


def gl_available() -> bool:
    """True when MuJoCo can open an offscreen context (EGL or OSMesa)."""
    probe = "import rest2art.sim.envs, mujoco; mujoco.Renderer(mujoco.MjModel.from_xml_string('<mujoco/>'), 8, 8)"
    return subprocess.run([sys.executable, "-c", probe], capture_output=True).returncode == 0


needs_gl = pytest.mark.skipif(not gl_available(), reason="headless rendering needs libEGL (apt-get install libegl1 "
                              "libgl1-mesa-dri, MUJOCO_GL=egl) or OSMesa (apt-get install libosmesa6, MUJOCO_GL=osmesa)")


def checked(env) -> list[str]:
    """Run gymnasium's env checker; returns the warnings it gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env)
    return [str(w.message) for w in caught]


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_env_checker_passes(cabinet, env_id):
    env = gym.make(env_id, asset=str(cabinet)).unwrapped
    assert checked(env) == []
    env.close()


@needs_gl
def test_env_checker_passes_with_images_and_render(cabinet):
    env = gym.make(ENV_IDS[0], asset=str(cabinet), image_obs=True, render_mode="rgb_array").unwrapped
    assert checked(env) == []
    obs, _ = env.reset(seed=0)
    assert obs["rgb"].shape == (96, 128, 3) and obs["depth"].shape == (96, 128, 1)
    env.close()


def test_make_with_asset_and_with_catalog(cabinet, catalog):
    env = gym.make(ENV_IDS[0], asset=str(cabinet), joint="drawer_0_joint")
    obs, info = env.reset(seed=0)
    assert info["joint"] == "drawer_0_joint" and info["joint_type"] == "prismatic"
    assert obs["joint_fraction"][0] == pytest.approx(0.0)
    env.close()
    env = gym.make(ENV_IDS[1], catalog=str(catalog), joint_type="revolute", seed=3)
    seen = set()
    for k in range(8):
        obs, info = env.reset(seed=k)
        seen.add((info["asset"], info["joint"]))
        assert info["joint_type"] == "revolute"
        assert obs["joint_fraction"][0] == pytest.approx(0.9)  # the close task starts open
    assert seen <= {("cabinet_1", "door_0_joint"), ("cabinet_1", "door_1_joint")} and len(seen) == 2
    env.close()
    env = gym.make(ENV_IDS[0], catalog=str(catalog), joint_type="prismatic")
    assets = {env.reset(seed=k)[1]["asset"] for k in range(12)}
    assert assets == {"cabinet_1", "cabinet_2"}
    env.close()


def test_an_asset_lying_on_its_side_gets_the_scene_gravity_without_a_log(cabinet, tmp_path, monkeypatch):
    """An asset's MJCF points gravity down its file frame; attaching it upright used to make
    MuJoCo warn of the conflict into MUJOCO_LOG.TXT in the working directory."""
    import shutil

    from rest2art.config import EnvConfig
    from rest2art.sim.envs.scene import load_scene

    folder = tmp_path / "side"
    shutil.copytree(cabinet, folder)
    xml = folder / "cabinet.xml"
    text, count = re.subn(r'gravity="[^"]*"', 'gravity="9.81 0 0"', xml.read_text())
    assert count == 1
    xml.write_text(text)
    monkeypatch.chdir(tmp_path)
    scene = load_scene(str(folder), EnvConfig())
    assert np.allclose(scene.model.opt.gravity, [0.0, 0.0, -9.81])
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_bad_arguments_name_the_problem(cabinet, tmp_path):
    with pytest.raises(InputError, match="exactly one of asset"):
        OpenArticulationEnv()
    with pytest.raises(InputError, match="joint 'nope' does not exist.*door_0_joint"):
        OpenArticulationEnv(asset=cabinet, joint="nope")
    with pytest.raises(InputError, match="no published asset"):
        OpenArticulationEnv(catalog=tmp_path)
    (tmp_path / "articulation.json").write_text("{}")
    with pytest.raises(InputError, match="articulation.json"):
        OpenArticulationEnv(asset=tmp_path)


def test_same_seed_same_episode_and_randomisation_changes_the_scene(cabinet):
    env = OpenArticulationEnv(asset=cabinet, randomize=True)
    first, _ = env.reset(seed=5)
    friction = env.model.dof_frictionloss.copy()
    again, _ = env.reset(seed=5)
    assert all(np.array_equal(first[k], again[k]) for k in first)
    other, _ = env.reset(seed=6)
    assert not np.allclose(first["handle_pos"], other["handle_pos"])  # object moved on the floor
    assert not np.allclose(friction, env.model.dof_frictionloss)
    env.close()


def test_vector_envs_step(cabinet):
    kwargs = {"asset": str(cabinet), "joint": "door_0_joint"}
    spawned = f"rest2art.sim.envs:{ENV_IDS[0]}"  # the module is imported in each spawned worker
    for envs in (gym.vector.SyncVectorEnv([lambda: gym.make(ENV_IDS[0], **kwargs)] * 2),
                 gym.vector.AsyncVectorEnv([lambda: gym.make(spawned, **kwargs)] * 2, context="spawn")):
        obs, _ = envs.reset(seed=0)
        assert obs["handle_pos"].shape == (2, 3)
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
        assert reward.shape == (2,) and np.all(np.isfinite(reward))
        envs.close()


def test_grasp_of_a_bar_handle_is_on_the_bar_and_across_it():
    obj = generate_object("fridge", 0, "asset")
    asset = obj.asset
    joint = asset.movable_joints[0]
    part = asset.part(joint.child)
    grasp = find_grasp(part.mesh.vertices, joint.type, joint.axis, joint.origin,
                       asset.part("base").mesh.bounds.mean(axis=0), np.array([0.0, 0.0, 1.0]))
    assert grasp.mode == "pinch"
    assert np.allclose(grasp.normal, [0.0, -1.0, 0.0])  # the fridge's front
    assert abs(grasp.pinch[2]) < 1e-9  # a vertical bar: the fingers close horizontally
    front = part.mesh.vertices[:, 1].min()
    assert front < grasp.point[1] < front + 0.015  # within the bar, standing proud of the door
    hinge_distance = np.linalg.norm(np.cross(grasp.point - joint.origin, joint.axis))
    assert hinge_distance > 0.7 * np.ptp(part.mesh.vertices[:, 0])  # on the side far from the hinge


def test_grasp_of_a_laptop_lid_presses_its_top_near_the_front():
    asset = generate_object("laptop", 0, "asset").asset
    joint = asset.movable_joints[0]
    lid = asset.part(joint.child).mesh
    grasp = find_grasp(lid.vertices, joint.type, joint.axis, joint.origin, asset.part("base").mesh.bounds.mean(axis=0),
                       np.array([0.0, 0.0, 1.0]))
    assert grasp.mode == "press" and np.allclose(grasp.normal, [0.0, 0.0, 1.0])
    assert grasp.point[2] == pytest.approx(lid.bounds[1, 2])
    assert grasp.point[1] == pytest.approx(lid.bounds[0, 1] + 0.03)


@pytest.mark.parametrize("joint", ["door_0_joint", "drawer_1_joint"])
def test_scripted_policy_opens_and_closes(cabinet, joint):
    for mode, env_class in (("open", OpenArticulationEnv), ("close", CloseArticulationEnv)):
        env = env_class(asset=cabinet, joint=joint)
        result = run_episode(env, ScriptedPolicy(mode), seed=0)
        assert result["success"], result
        if mode == "open":
            assert result["final_fraction"] >= 0.8
        else:
            assert result["final_fraction"] <= 0.05


@needs_gl
def test_rendered_frame_shows_the_object(cabinet):
    env = OpenArticulationEnv(asset=cabinet, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (360, 480, 3) and frame.dtype == np.uint8
    assert frame.std() > 20  # not blank
    # the object's parts are coloured: a door's blue covers a good share of the middle of the picture
    middle = frame[90:270, 120:360].reshape(-1, 3).astype(int)
    blue = (middle[:, 2] > middle[:, 0] + 40) & (middle[:, 2] > 120)
    assert blue.mean() > 0.05
    env.render_mode = "depth_array"
    depth = env.render()
    assert depth.shape == (360, 480) and np.isfinite(depth).all()
    assert depth[180, 240] < depth[5, 240]  # the object is nearer than the floor behind it
    env.close()


def test_render_without_gl_says_what_to_install(cabinet):
    probe = ("import os; os.environ['MUJOCO_GL'] = 'osmesa'; "
             "import rest2art.sim.envs as e; from rest2art.errors import SimulationError\n"
             f"env = e.OpenArticulationEnv(asset={str(cabinet)!r}, render_mode='rgb_array'); env.reset(seed=0)\n"
             "try:\n    env.render(); print('rendered')\n"
             "except SimulationError as exc:\n    print(exc)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True).stdout
    assert out.startswith("rendered") or "apt-get install libosmesa6" in out


def test_cli_solve_prints_the_table_and_writes_json(cabinet, tmp_path):
    out = tmp_path / "solve.json"
    run = subprocess.run([sys.executable, "-m", "rest2art.cli", "envs", "solve", str(cabinet), "-o", str(out)],
                         capture_output=True, text=True, cwd=REPO, timeout=600)
    assert run.returncode == 0, run.stderr
    last = run.stdout.strip().splitlines()[-1]
    assert last.startswith("overall success:") and "of 4 joints" in last
    report = json.loads(out.read_text())
    assert report["summary"]["joints"] == 4
    assert {r["joint"] for r in report["joints"]} == {"door_0_joint", "door_1_joint", "drawer_0_joint", "drawer_1_joint"}
    assert report["summary"]["success_pct"] == pytest.approx(
        100.0 * sum(r["success"] for r in report["joints"]) / 4)


def test_cli_solve_bad_path_is_one_line(tmp_path):
    run = subprocess.run([sys.executable, "-m", "rest2art.cli", "envs", "solve", str(tmp_path / "none")],
                         capture_output=True, text=True, cwd=REPO)
    assert run.returncode == 2
    assert run.stderr.strip().count("\n") == 0 and "catalog folder not found" in run.stderr


@pytest.mark.slow
def test_catalog_built_by_rest2art_catalog_is_sampled(tmp_path, config_file):
    from rest2art.generate import write_object

    mesh = write_object(generate_object("cabinet", 5, "asset"), tmp_path / "src")  # one door
    build = subprocess.run([sys.executable, "-m", "rest2art.cli", "catalog", "build", str(mesh), "--catalog",
                            str(tmp_path / "cat"), "--workers", "1", "--quiet", "--config", str(config_file)],
                           capture_output=True, text=True, cwd=REPO, timeout=600)
    assert build.returncode == 0, build.stderr
    env = gym.make(ENV_IDS[0], catalog=str(tmp_path / "cat"), seed=0)
    obs, info = env.reset(seed=0)
    assert info["joint"] == "door_0_joint" and info["joint_fraction"] == 0.0
    result = run_episode(env.unwrapped, ScriptedPolicy("open"), seed=0)
    assert result["success"], result
    env.close()
