"""The registries: one per role, filled by the backend modules of this package on first use."""

from __future__ import annotations

import importlib
import importlib.util
from dataclasses import dataclass, field
from typing import Any, Callable

from rest2art.errors import ConfigError

ROLES = ("hierarchy", "masks", "video", "tracks", "prompt")
"""The roles, in data-flow order (``prompt`` writes the motion video's text prompt)."""

CONFIG_KEYS = {"hierarchy": "segment.hierarchy_backend", "masks": "segment.masks_backend",
               "video": "articulation.video_backend", "tracks": "articulation.tracks_backend",
               "prompt": "articulation.prompt_backend"}
"""Where each role's backend is chosen in the config."""

_MODULES = ("geometric", "openai_chat", "qwen3vl", "sam3", "wan", "cotracker")
"""Backend modules of this package (each registers its backends when imported)."""


@dataclass(frozen=True)
class Backend:
    """One registered backend of one role."""

    role: str
    name: str
    factory: Callable[..., Any]
    """Builds the backend; its arguments depend on the role (see the ``make_*`` callers)."""
    summary: str
    """One line: what it is."""
    packages: tuple[str, ...] = ()
    """Import names it needs (empty: the core install)."""
    extra: str = ""
    """The optional extra that installs ``packages``."""
    weights: Callable[[Any], dict[str, str]] | None = None
    """``ModelsConfig -> {what: local path}`` of the files it loads; None: no weights."""
    hints: dict[str, str] = field(default_factory=dict)
    """Per entry of ``weights``: a one-line hint on where to get it and which key to set."""

    def missing_packages(self) -> list[str]:
        """The import names of ``packages`` that cannot be found."""
        return [p for p in self.packages if importlib.util.find_spec(p) is None]


_REGISTRY: dict[str, dict[str, Backend]] = {role: {} for role in ROLES}
_loaded = False


def register(role: str, name: str, summary: str, packages: tuple[str, ...] = (), extra: str = "",
             weights: Callable[[Any], dict[str, str]] | None = None, hints: dict[str, str] | None = None):
    """Decorator: register ``factory`` as backend ``name`` of ``role``."""
    if role not in _REGISTRY:
        raise ConfigError(f"unknown role '{role}'. Roles: {', '.join(ROLES)}")

    def wrap(factory: Callable[..., Any]) -> Callable[..., Any]:
        _REGISTRY[role][name] = Backend(role, name, factory, summary, packages, extra, weights, hints or {})
        return factory

    return wrap


def _load() -> None:
    global _loaded
    if not _loaded:
        _loaded = True
        for module in _MODULES:
            importlib.import_module(f"rest2art.backends.{module}")


def available(role: str) -> list[str]:
    """Names of the registered backends of ``role``."""
    _load()
    if role not in _REGISTRY:
        raise ConfigError(f"unknown role '{role}'. Roles: {', '.join(ROLES)}")
    return sorted(_REGISTRY[role])


def get(role: str, name: str) -> Backend:
    """The backend ``name`` of ``role``; a ConfigError lists the valid names."""
    names = available(role)
    if name not in names:
        raise ConfigError(f"{CONFIG_KEYS[role]}: unknown backend '{name}'. Valid: {', '.join(names)}")
    return _REGISTRY[role][name]


def create(role: str, name: str, *args, **kwargs) -> Any:
    """Build backend ``name`` of ``role``; a missing package is a ConfigError naming the extra."""
    backend = get(role, name)
    missing = backend.missing_packages()
    if missing:
        raise ConfigError(f"{CONFIG_KEYS[role]}={name}: missing {', '.join(missing)}; "
                          f"install it with: pip install -e \".[{backend.extra}]\"")
    return backend.factory(*args, **kwargs)


def resolve_device(device: str) -> str:
    """``auto`` -> ``cuda`` when torch sees a GPU, else ``cpu``; other names unchanged."""
    if device != "auto":
        return device
    import torch

    return "cuda" if torch.cuda.is_available() else "cpu"


def torch_dtype(dtype: str, device: str):
    """The torch dtype named ``dtype``; ``auto``: bfloat16 on CUDA, float32 elsewhere."""
    import torch

    if dtype == "auto":
        return torch.bfloat16 if device.startswith("cuda") else torch.float32
    names = {"float32": torch.float32, "bfloat16": torch.bfloat16, "float16": torch.float16}
    if dtype not in names:
        raise ConfigError(f"dtype '{dtype}' is not valid. Valid: auto, {', '.join(names)}")
    return names[dtype]


def require_path(path: str, key: str, what: str) -> str:
    """``path`` when it exists; a ConfigError naming the config ``key`` otherwise."""
    from pathlib import Path

    if not path:
        raise ConfigError(f"{key} is empty: set it to the local {what}")
    if not Path(path).expanduser().exists():
        raise ConfigError(f"{key}: {path} does not exist (expected the local {what})")
    return str(Path(path).expanduser())
