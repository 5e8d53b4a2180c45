"""Shared fixtures: a session CoACD cache and a few generated objects."""

from __future__ import annotations

import dataclasses

import pytest

from rest2art.config import Config


@pytest.fixture(scope="session")
def config(tmp_path_factory) -> Config:
    """Default config with the CoACD cache in a session temp folder."""
    base = Config()
    cache = tmp_path_factory.mktemp("coacd-cache")
    return dataclasses.replace(base, collision=dataclasses.replace(base.collision, cache_dir=str(cache)))


@pytest.fixture(scope="session")
def config_file(config, tmp_path_factory):
    """The same config as a YAML file for CLI tests."""
    import yaml

    path = tmp_path_factory.mktemp("cfg") / "config.yaml"
    path.write_text(yaml.safe_dump({"collision": {"cache_dir": config.collision.cache_dir}}))
    return path
