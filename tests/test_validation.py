"""The validation layer on sound generated assets and on assets with planted faults.

The sound assets are the generator's ground truth, completed and exported by the project; each
fault is planted in a copy, and the layer must reject it (or refine it) for the right reason.
"""

import copy
import dataclasses
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import trimesh
from rest2art.validators.policy import Redecompose, ShrinkLimit, Thin, decide
from rest2art.validators.validate import validate_folder

from rest2art.export.writers import write_asset
from rest2art.generate import generate_object
from rest2art.io.atomic import atomic_folder
from rest2art.pipeline import complete_asset


@pytest.fixture(scope="module")
def completed(config):
    """Completed ground-truth assets: a microwave (one door) and a cabinet with three drawers."""
    out = {}
    for kind, seed in (("microwave", 5), ("cabinet", 2)):
        asset = generate_object(kind, seed, "asset").asset
        complete_asset(asset, config)
        out[kind] = asset
    return out


def export(asset, folder, name, config):
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, name, config.export, np.array([0.0, 0.0, 1.0]))
    return folder


def failed(report):
    return {(f.check, f.subject) for f in report.rounds[0].findings if not f.ok}


@pytest.mark.parametrize("kind", ["microwave", "cabinet"])
def test_sound_assets_are_published_without_refinement(completed, kind, config, tmp_path):
    folder = export(completed[kind], tmp_path / kind, kind, config)
    report = validate_folder(folder, kind, config)
    assert report.decision.status == "publish", report.decision.reasons
    checks = {f.check for f in report.findings}
    assert {"files", "inertia", "load", "gravity", "rest", "collision", "sweep", "actuation"} <= checks
    sweeps = [f for f in report.findings if f.check == "sweep"]
    assert all(s["depth_mm"] <= 1.0 for f in sweeps for s in f.data["samples"])
    written = (folder / "validation.json").read_text()
    assert '"status": "publish"' in written


def test_validation_runs_the_registered_engines_the_config_names(completed, config, tmp_path):
    from rest2art.errors import ConfigError
    from rest2art.sim import ENGINES

    assert list(ENGINES) == ["mujoco", "pybullet", "sapien"]
    assert ENGINES["sapien"].run_actuation is None  # it loads and hangs the asset; it does not push
    folder = export(completed["microwave"], tmp_path / "m", "m", config)
    only_mujoco = dataclasses.replace(config, check=dataclasses.replace(config.check, engines=("mujoco",)))
    report = validate_folder(folder, "m", only_mujoco)
    assert report.decision.status == "publish", report.decision.reasons
    assert {f.subject for f in report.findings if f.check == "load"} == {"mujoco", "yourdfpy"}
    pushed = [f for f in report.findings if f.check == "actuation"]
    assert pushed and all(set(f.data) & {"mujoco_ok", "pybullet_ok"} == {"mujoco_ok"} for f in pushed)
    unknown = dataclasses.replace(config, check=dataclasses.replace(config.check, engines=("mujoco", "gazebo")))
    with pytest.raises(ConfigError, match="unknown engine 'gazebo'. Engines: mujoco, pybullet, sapien"):
        validate_folder(folder, "m", unknown)


def test_door_hinged_on_the_wrong_edge_is_rejected(completed, config, tmp_path):
    asset = copy.deepcopy(completed["microwave"])
    joint = asset.joints[0]
    door = asset.part(joint.child).mesh
    centre = door.bounds.mean(axis=0)
    across = np.cross(joint.axis, [0.0, -1.0, 0.0])  # horizontal, along the door's width
    joint.origin = joint.origin + 2.0 * ((centre - joint.origin) @ across) * across  # the other vertical edge
    report = validate_folder(export(asset, tmp_path / "a", "m", config), "m", config, refine=True)
    assert ("sweep", joint.name) in failed(report)
    assert report.decision.status == "reject"
    assert any(r.subject == joint.name for r in report.decision.reasons)


def test_drawer_with_a_reversed_axis_is_rejected(completed, config, tmp_path):
    asset = copy.deepcopy(completed["cabinet"])
    joint = asset.movable_joints[1]
    joint.axis = -joint.axis  # pushes into the carcass
    report = validate_folder(export(asset, tmp_path / "a", "c", config), "c", config, refine=True)
    assert ("sweep", joint.name) in failed(report)
    assert report.decision.status == "reject"
    sweep = next(f for f in report.rounds[0].findings if f.subject == joint.name and f.check == "sweep")
    assert sweep.data["last_free_fraction"] == 0.0 and sweep.data["max_depth_mm"] > 5.0


def test_joint_with_an_empty_range_is_rejected_as_not_opening(completed, config, tmp_path):
    """A drawer whose travel came out as nothing is named as not opening, not judged by a share
    of a zero range."""
    asset = copy.deepcopy(completed["cabinet"])
    joint = asset.movable_joints[0]
    joint.limit = (0.0, 1e-9)
    report = validate_folder(export(asset, tmp_path / "a", "c", config), "c", config, refine=True)
    assert report.decision.status == "reject"
    reason = next(r for r in report.decision.reasons if r.subject == joint.name and r.check == "actuation")
    assert "does not open" in reason.message
    others = [f for f in report.rounds[-1].findings if f.check == "actuation" and f.subject != joint.name]
    assert others and all(f.ok for f in others)


def test_collision_part_with_a_hole_is_rejected(completed, config, tmp_path):
    folder = export(completed["microwave"], tmp_path / "a", "m", config)
    hull_file = next((folder / "collision").glob("door_0_*.obj"))
    hull = trimesh.load(hull_file, force="mesh", process=False)
    trimesh.Trimesh(hull.vertices, hull.faces[2:], process=False).export(hull_file)
    report = validate_folder(folder, "m", config, refine=True)
    assert ("collision", "files") in failed(report)
    assert report.decision.status == "reject"
    assert "not a closed volume" in " ".join(r.message for r in report.decision.reasons)


def test_zero_mass_part_is_rejected(completed, config, tmp_path):
    folder = export(completed["microwave"], tmp_path / "a", "m", config)
    urdf = folder / "m.urdf"
    tree = ET.parse(urdf)
    next(link for link in tree.getroot().iter("link") if link.get("name") == "door_0").find("inertial/mass").set("value", "0")
    tree.write(urdf)
    report = validate_folder(folder, "m", config, refine=True)
    assert ("inertia", "links") in failed(report) and report.decision.status == "reject"


def test_carcass_wrapped_in_one_hull_is_caught_and_decomposed_again(completed, config, tmp_path):
    asset = copy.deepcopy(completed["cabinet"])
    base = asset.part("base")
    base.collision = [base.mesh.convex_hull]  # the drawers sit inside one solid block
    report = validate_folder(export(asset, tmp_path / "a", "c", config), "c", config, refine=True)
    assert ("sweep", "rest") in failed(report)
    first = report.rounds[0].decision
    assert first.status == "refine" and isinstance(first.actions[0], Redecompose) and first.actions[0].part == "base"
    assert first.actions[0].done.startswith("base: decomposed again finer")
    assert report.decision.status == "publish", report.decision.reasons
    final_hulls = next(f for f in report.findings if f.check == "collision" and f.subject == "hulls")
    assert final_hulls.data["hulls"]["base"] > 1


def test_mjcf_with_a_bad_mesh_path_is_rejected(completed, config, tmp_path):
    folder = export(completed["microwave"], tmp_path / "a", "m", config)
    mjcf = folder / "m.xml"
    mjcf.write_text(mjcf.read_text().replace('file="parts/door_0.obj"', 'file="parts/missing.obj"', 1))
    report = validate_folder(folder, "m", config, refine=True)
    assert failed(report) == {("files", "asset folder")}  # no simulator sees a folder that failed it
    assert report.decision.status == "reject"


def test_urdf_mesh_path_outside_the_folder_is_rejected(completed, config, tmp_path):
    folder = export(completed["microwave"], tmp_path / "a", "m", config)
    (tmp_path / "outside.obj").write_text((folder / "parts" / "base.obj").read_text())
    urdf = folder / "m.urdf"
    urdf.write_text(urdf.read_text().replace('filename="parts/base.obj"', 'filename="../outside.obj"', 1))
    report = validate_folder(folder, "m", config, refine=True)
    assert ("files", "asset folder") in failed(report)
    assert report.decision.status == "reject"
    assert "outside the asset folder" in " ".join(r.message for r in report.decision.reasons)


def test_policy_shrinks_a_limit_to_the_last_free_sample_and_rejects_a_joint_that_collides_at_once(config):
    from rest2art.validators import Finding

    def sweep(free, depth):
        return Finding("sweep", "door_0_joint", False, "", {
            "last_free_fraction": free, "limit": [0.0, 2.0], "child": "door_0", "max_depth_mm": depth,
            "samples": [{"fraction": 1.0, "depth_mm": depth, "pair": ["base", "door_0"]}]})

    parents = {"base": None, "door_0": "base"}
    shrink = decide([sweep(0.75, 20.0)], parents, config.validate)
    assert shrink.status == "refine" and shrink.actions[0] == ShrinkLimit(joint="door_0_joint", upper=1.5, why="")
    assert decide([sweep(0.0, 20.0)], parents, config.validate).status == "reject"
    thin = decide([sweep(0.0, 2.0)], parents, config.validate)  # a hull bulging by 2 mm
    assert thin.status == "refine" and isinstance(thin.actions[0], Thin) and thin.actions[0].part == "door_0"
    assert decide([Finding("load", "mujoco", True, "")], parents, config.validate).status == "publish"


def test_publish_adds_a_sound_asset_to_the_catalog_and_refuses_a_broken_one(completed, config, config_file, tmp_path):
    import os
    import subprocess
    import sys

    def rest2art(*args):
        env = {**os.environ, "PYTHONWARNINGS": "ignore"}
        return subprocess.run([sys.executable, "-m", "rest2art.cli", *map(str, args)], capture_output=True, text=True,
                              env=env, timeout=600)

    sound = export(completed["microwave"], tmp_path / "sound", "m", config)
    catalog = tmp_path / "catalog"
    run = rest2art("publish", sound, "--catalog", catalog, "--config", config_file)
    assert run.returncode == 0, run.stderr
    entry = catalog / "sound"
    assert (entry / "thumbnail.png").is_file() and (entry / "m.urdf").is_file()
    assert '"status": "publish"' in (entry / "validation.json").read_text()
    again = rest2art("publish", sound, "--catalog", catalog, "--config", config_file)
    assert again.returncode == 2 and "already in the catalog" in again.stderr

    broken = export(completed["microwave"], tmp_path / "broken", "m", config)
    mjcf = broken / "m.xml"
    mjcf.write_text(mjcf.read_text().replace('file="parts/door_0.obj"', 'file="parts/missing.obj"', 1))
    before = sorted(p.name for p in broken.rglob("*"))
    run = rest2art("publish", broken, "--catalog", catalog, "--config", config_file)
    assert run.returncode == 3 and "rejected" in run.stderr
    assert not (catalog / "broken").exists() and sorted(p.name for p in catalog.iterdir()) == ["rejected", "sound"]
    assert '"status": "reject"' in (catalog / "rejected" / "broken" / "validation.json").read_text()
    assert sorted(p.name for p in broken.rglob("*")) == before  # the source is left as it is


def test_separating_depth_is_the_overlap_of_two_slabs():
    from rest2art.validators.sweep import separating_depth

    a = trimesh.creation.box((0.30, 0.009, 0.015))
    b = trimesh.creation.box((0.04, 0.004, 0.010))
    b.apply_translation([0.1, 0.0045, 0.0])  # y from 2.5 to 6.5 mm: 2 mm into a, inside it along x and z
    depth = separating_depth(a.vertices, a.face_normals, b.vertices, b.face_normals)
    assert depth == pytest.approx(0.002, abs=1e-9)
    b.apply_translation([0.0, 0.01, 0.0])
    assert separating_depth(a.vertices, a.face_normals, b.vertices, b.face_normals) == 0.0
