"""The layout's promises: stages import only earlier stages, and the extension points that
docs/architecture.md shows work as shown (its examples are read from the page and run)."""

import ast
import json
import re
from pathlib import Path

import numpy as np
import pytest
from rest2art.validators.registry import CHECKS
from rest2art.validators.validate import run_checks, validate_folder

from rest2art.errors import ConfigError
from rest2art.export.formats import FORMATS
from rest2art.export.writers import write_asset
from rest2art.generate import generate_object
from rest2art.io.atomic import atomic_folder
from rest2art.pipeline import complete_asset

ROOT = Path(__file__).resolve().parents[1]
STAGES = ["io", "frame", "parts", "joints", "gate", "completion", "collision", "export"]
"""The stage packages in data-flow order."""
AROUND = {"generate", "bench", "catalog"}
"""Packages around the core that no stage may import."""


def doc_examples() -> list[str]:
    """The python code blocks of docs/architecture.md, in order."""
    return re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "architecture.md").read_text(), re.S)


def imported_packages(path: Path) -> set[str]:
    """The rest2art sub-packages a module imports (the name after ``rest2art.``)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("rest2art."):
            names.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            names |= {a.name.split(".")[1] for a in node.names if a.name.startswith("rest2art.")}
    return names


@pytest.mark.parametrize("stage", STAGES)
def test_a_stage_imports_no_later_stage_and_nothing_around_the_core(stage):
    later = set(STAGES[STAGES.index(stage) + 1:])
    for path in (ROOT / "rest2art" / stage).rglob("*.py"):
        wrong = imported_packages(path) & (later | AROUND)
        assert not wrong, f"{path.relative_to(ROOT)} imports {sorted(wrong)}"


@pytest.fixture()
def microwave(config):
    asset = generate_object("microwave", 5, "asset").asset
    complete_asset(asset, config)
    return asset


def export(asset, folder, config):
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "microwave", config.export, np.array([0.0, 0.0, 1.0]))
    return folder


def test_the_documented_check_runs_in_validation_and_its_failure_rejects(microwave, config, tmp_path):
    before = dict(CHECKS)
    try:
        exec(doc_examples()[0], {})
        findings = [f for f in run_checks(export(microwave, tmp_path / "light", config), "microwave", config)
                    if f.check == "part_mass"]
        assert {f.subject for f in findings} == {p.name for p in microwave.parts}
        assert all(f.ok for f in findings)
        door = next(p for p in microwave.parts if p.parent is not None)
        door.inertial.mass = 80.0
        report = validate_folder(export(microwave, tmp_path / "heavy", config), "microwave", config)
        assert report.decision.status == "reject"
        assert any(r.check == "part_mass" and r.subject == door.name for r in report.decision.reasons)
    finally:
        CHECKS.clear()
        CHECKS.update(before)


def test_the_documented_format_is_written_when_listed(microwave, config, tmp_path):
    import dataclasses

    before = dict(FORMATS)
    try:
        exec(doc_examples()[1], {})
        export_config = dataclasses.replace(config.export, formats=("urdf", "mjcf", "joints-json"))
        folder = export(microwave, tmp_path / "out", dataclasses.replace(config, export=export_config))
        written = json.loads((folder / "microwave.joints.json").read_text())
        assert set(written) == {j.name for j in microwave.movable_joints}
        joint = microwave.movable_joints[0]
        assert written[joint.name]["type"] == joint.type
        assert np.allclose(written[joint.name]["axis"], joint.axis)
        unknown = dataclasses.replace(config, export=dataclasses.replace(config.export, formats=("usd",)))
        with pytest.raises(ConfigError, match="joints-json"):
            export(microwave, tmp_path / "usd", unknown)
        assert not (tmp_path / "usd").exists()
    finally:
        FORMATS.clear()
        FORMATS.update(before)
