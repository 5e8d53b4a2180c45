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
