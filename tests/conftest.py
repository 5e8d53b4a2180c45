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


@pytest.fixture
def tile_grid():
    """A maker of (nx * ny) touching square tiles (boxes ``size`` wide, ``thickness`` thick) in a
    slab on the xy plane: the many small pieces of an artist carcass."""
    import trimesh

    def make(nx: int, ny: int, size: float, thickness: float) -> list:
        tiles = []
        for x in range(nx):
            for y in range(ny):
                tile = trimesh.creation.box((size, size, thickness))
                tile.apply_translation([size * x, size * y, 0.0])
                tiles.append(tile)
        return tiles

    return make
