"""rest2art: a closed-state mesh of an articulated object in, a simulation-ready asset out.

The public API (imported on first use, so that ``import rest2art.sim.envs`` stays light)::

    from rest2art import reconstruct_file, write_asset, validate_folder, load_config

    config = load_config()                                  # or load_config("my.yaml")
    asset, _ = reconstruct_file("cabinet.obj", config)      # ArticulatedAsset, input frame
    with atomic_folder("assets_out/cabinet") as tmp:
        write_asset(asset, tmp, "cabinet", config.export, asset.up)
    report = validate_folder("assets_out/cabinet", "cabinet", config)

The stages, in the order the data flows, are the packages ``io``, ``frame``, ``parts``,
``joints``, ``gate``, ``completion``, ``collision`` and ``export`` (docs/architecture.md).
"""

from __future__ import annotations

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rest2art")
except PackageNotFoundError:  # a source tree that is not installed
    __version__ = "unknown"

_PUBLIC = {
    "ArticulatedAsset": "rest2art.asset",
    "Part": "rest2art.asset",
    "Joint": "rest2art.asset",
    "MassProperties": "rest2art.asset",
    "read_articulation": "rest2art.asset",
    "Config": "rest2art.config",
    "load_config": "rest2art.config",
    "load_mesh": "rest2art.io.load",
    "atomic_folder": "rest2art.io.atomic",
    "reconstruct_file": "rest2art.pipeline",
    "reconstruct_mesh": "rest2art.pipeline",
    "complete_asset": "rest2art.pipeline",
    "write_asset": "rest2art.export.writers",
    "validate_folder": "rest2art.validators.validate",
}
__all__ = ["__version__", *_PUBLIC]


def __getattr__(name: str):
    if name in _PUBLIC:
        return getattr(import_module(_PUBLIC[name]), name)
    raise AttributeError(f"module 'rest2art' has no attribute '{name}'")
