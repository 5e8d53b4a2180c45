import dataclasses

import pytest
import yaml

from rest2art.config import Config, load_config
from rest2art.errors import ConfigError
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_default_yaml_mirrors_dataclass_defaults():
    data = yaml.safe_load((REPO / "configs" / "default.yaml").read_text())
    assert data == Config().to_dict()


def test_override_file_changes_one_field(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("joints:\n  door_limit_deg: 100\n")
    config = load_config(path)
    assert config.joints.door_limit_deg == 100.0
    assert config.joints.knob_limit_deg == Config().joints.knob_limit_deg


def test_unknown_key_names_valid_keys(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text("joints:\n  door_limit: 100\n")
    with pytest.raises(ConfigError, match="unknown key 'door_limit'.*door_limit_deg"):
        load_config(path)


def test_configs_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        Config().joints.door_limit_deg = 5.0


def test_every_field_is_a_documented_command_line_option(tmp_path):
    from rest2art.cli import build_parser, config_from_args
    from rest2art.config import config_fields

    fields = config_fields()
    assert len(fields) == len({key for key, _, _ in fields}) > 250
    assert all(doc for _, _, doc in fields), [key for key, _, doc in fields if not doc]
    path = tmp_path / "c.yaml"
    path.write_text("gate:\n  min_opening_depth: 0.05\n  open_grid: 9\n")
    args = build_parser().parse_args(["reconstruct", "mesh.obj", "-o", str(tmp_path / "out"), "--config", str(path),
                                      "--gate.min_opening_depth", "0.03", "--export.formats", "[urdf, mjcf]",
                                      "--load.decimate_large", "true"])
    config = config_from_args(args)
    assert config.gate.min_opening_depth == 0.03  # the option wins over the file
    assert config.gate.open_grid == 9  # the file wins over the default
    assert config.export.formats == ("urdf", "mjcf") and config.load.decimate_large is True
    bad = build_parser().parse_args(["reconstruct", "mesh.obj", "-o", "out", "--gate.open_grid", "many"])
    with pytest.raises(ConfigError, match="^gate.open_grid: expected a number, got 'many'"):
        config_from_args(bad)
