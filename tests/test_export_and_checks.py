"""Export writes a self-contained folder; all three engines load it and hold it under gravity."""

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from rest2art.validators.load_checks import run_load_checks

from rest2art.export.writers import write_asset
from rest2art.generate import generate_object, write_object
from rest2art.io.atomic import atomic_folder
from rest2art.pipeline import reconstruct_file


@pytest.fixture(scope="module")
def exported(tmp_path_factory, config):
    """The oven has a flip-down door (gravity pulls it open) and knobs; the cabinet drawers."""
    out = {}
    for kind, seed in (("oven", 3), ("cabinet", 3)):
        src = tmp_path_factory.mktemp(f"{kind}-src")
        obj = generate_object(kind, seed, "asset")
        asset, _ = reconstruct_file(write_object(obj, src), config)
        folder = tmp_path_factory.mktemp(kind) / "asset"
        with atomic_folder(folder) as tmp:
            write_asset(asset, tmp, kind, config.export, np.array([0.0, 0.0, 1.0]))
        out[kind] = (folder, asset)
    return out


@pytest.mark.parametrize("kind", ["oven", "cabinet"])
def test_three_engines_load_and_hold(exported, kind, config):
    folder, _ = exported[kind]
    findings = run_load_checks(folder, kind, config.check)
    failed = [f.message for f in findings if not f.ok]
    assert not failed
    assert {f.subject for f in findings if f.check == "gravity"} == {"mujoco", "pybullet", "sapien"}


def test_paths_are_relative_and_inside(exported):
    folder, asset = exported["cabinet"]
    urdf = ET.parse(folder / "cabinet.urdf").getroot()
    files = [m.get("filename") for m in urdf.iter("mesh")]
    mjcf = ET.parse(folder / "cabinet.xml").getroot()
    files += [m.get("file") for m in mjcf.iter("mesh")]
    for f in files:
        assert not Path(f).is_absolute() and ".." not in Path(f).parts
        assert (folder / f).is_file()
    excluded = {(e.get("body1"), e.get("body2")) for e in mjcf.iter("exclude")}
    assert excluded == {(j.parent, j.child) for j in asset.joints}


def test_every_part_has_collision_and_mass(exported):
    _, asset = exported["cabinet"]
    for part in asset.parts:
        assert part.collision, part.name
        assert part.inertial.mass > 0
        assert np.all(np.linalg.eigvalsh(part.inertial.inertia) > 0)
    # the carcass is hollow where the drawers go: it needed more than one convex piece
    assert len(asset.part("base").collision) > 1


def planted(exported, tmp_path, file: str, edit) -> Path:
    """A copy of the exported cabinet whose ``file`` was changed by ``edit(text) -> text``."""
    import shutil

    folder, _ = exported["cabinet"]
    broken = tmp_path / "planted"
    shutil.copytree(folder, broken)
    (broken / file).write_text(edit((broken / file).read_text()))
    return broken


def test_broken_mjcf_is_a_finding_not_a_crash(exported, tmp_path, config):
    broken = planted(exported, tmp_path, "cabinet.xml", lambda t: t.replace("parts/base.obj", "parts/missing.obj"))
    findings = run_load_checks(broken, "cabinet", config.check)
    # the files check names the missing mesh, and no simulator is handed a folder that failed it
    assert [f.check for f in findings] == ["files"]
    assert not findings[0].ok and "missing.obj" in findings[0].message


def test_atomic_folder_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "asset"
    with pytest.raises(RuntimeError):
        with atomic_folder(target) as tmp:
            (tmp / "half.txt").write_text("x")
            raise RuntimeError("boom")
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_single_body_asset_loads_everywhere(tmp_path, config):
    """A fused scan mesh without segmentation gives a base without joints; SAPIEN parses a
    one-link URDF as an actor, which must still load."""
    import dataclasses

    obj = generate_object("laptop", 4, "scan", scan_voxel=0.008)
    no_segmentation = dataclasses.replace(config, segment=dataclasses.replace(config.segment, enabled=False))
    asset, _ = reconstruct_file(write_object(obj, tmp_path / "src"), no_segmentation)
    assert [p.name for p in asset.parts] == ["base"] and not asset.joints
    folder = tmp_path / "asset"
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "laptop", config.export)
    findings = run_load_checks(folder, "laptop", config.check)
    assert all(f.ok for f in findings), [f.message for f in findings if not f.ok]


def test_planted_fault_mesh_path_outside_folder(exported, tmp_path, config):
    broken = planted(exported, tmp_path, "cabinet.urdf",
                     lambda t: t.replace('filename="parts/door_0.obj"', 'filename="../door_0.obj"'))
    findings = run_load_checks(broken, "cabinet", config.check)
    files = next(f for f in findings if f.check == "files")
    assert not files.ok and "'../door_0.obj' points outside the asset folder" in files.message


def test_planted_fault_zero_mass_part(exported, tmp_path, config):
    import re

    pattern = r'(<link name="drawer_0">\s*<inertial>\s*<origin[^>]*/>\s*)<mass value="[^"]*"'
    broken = planted(exported, tmp_path, "cabinet.urdf", lambda t: re.sub(pattern, r'\1<mass value="0"', t))
    findings = run_load_checks(broken, "cabinet", config.check)
    inertia = next(f for f in findings if f.check == "inertia")
    assert not inertia.ok and "link 'drawer_0': mass 0 kg" in inertia.message
