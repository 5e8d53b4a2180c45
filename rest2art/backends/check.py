"""``rest2art models check``: which backend each role uses, whether its packages and weights are
here, the device it would run on, and a one-line hint per missing piece."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field
from pathlib import Path

from rest2art.backends.registry import CONFIG_KEYS, ROLES, get
from rest2art.errors import ConfigError


@dataclass
class RoleStatus:
    """What one role needs and what is missing."""

    role: str
    backend: str
    summary: str
    packages: list[str]
    device: str
    missing: list[str] = field(default_factory=list)
    """One line per missing piece: what, and how to get it."""

    @property
    def ready(self) -> bool:
        return not self.missing


def chosen_backends(config) -> dict[str, str]:
    """{role: backend name} of ``config``."""
    return {"hierarchy": config.segment.hierarchy_backend, "masks": config.segment.masks_backend,
            "video": config.articulation.video_backend, "tracks": config.articulation.tracks_backend,
            "prompt": config.articulation.prompt_backend}


def backend_overrides(values: list[str]) -> dict[str, dict[str, str]]:
    """Config overrides of ``--backend role=name`` values (each checked against the registries)."""
    out: dict[str, dict[str, str]] = {}
    for value in values:
        role, sep, name = value.partition("=")
        if not sep or role not in ROLES:
            raise ConfigError(f"--backend {value}: expected ROLE=NAME with ROLE one of {', '.join(ROLES)}")
        get(role, name)
        section, key = CONFIG_KEYS[role].split(".")
        out.setdefault(section, {})[key] = name
    return out


def _device(config, role: str, backend: str) -> str:
    settings = {"masks": config.models.sam3, "video": config.models.wan, "tracks": config.models.cotracker}.get(role)
    if backend == "qwen3vl":
        settings = config.models.qwen3vl
    if backend == "openai":
        return f"remote: {config.models.openai.base_url or 'openai default endpoint'} ({config.models.openai.model})"
    if settings is None or not get(role, backend).packages:
        return "cpu"
    if importlib.util.find_spec("torch") is None:
        return f"{settings.device} (torch missing)"
    from rest2art.backends.registry import resolve_device

    return resolve_device(settings.device)


def check_models(config) -> list[RoleStatus]:
    """The status of every role's configured backend."""
    rows = []
    for role, name in chosen_backends(config).items():
        backend = get(role, name)
        row = RoleStatus(role, name, backend.summary, list(backend.packages), _device(config, role, name))
        for package in backend.missing_packages():
            row.missing.append(f"package {package}: pip install -e \".[{backend.extra}]\"")
        if backend.weights is not None:
            for what, path in backend.weights(config.models).items():
                if not path or not Path(path).expanduser().exists():
                    hint = backend.hints.get(what, "set its path in the config's models section")
                    row.missing.append(f"{what} {'not set' if not path else f'{path} not found'}: {hint}")
        if name == "openai":
            import os

            variable = config.models.openai.api_key_env
            if not config.models.openai.base_url and not os.environ.get(variable):
                row.missing.append(f"API key: set the environment variable {variable}, or models.openai.base_url "
                                   "to a local server")
        rows.append(row)
    return rows


def format_report(rows: list[RoleStatus]) -> str:
    """A plain table, then the hints; the last line says whether every role is ready."""
    lines = [f"{'role':<10} {'backend':<13} {'device':<28} status"]
    for r in rows:
        lines.append(f"{r.role:<10} {r.backend:<13} {r.device:<28} {'ready' if r.ready else 'missing'}")
    for r in rows:
        lines.extend(f"  {r.role}: {m}" for m in r.missing)
    missing = [r.role for r in rows if not r.ready]
    lines.append("all roles ready" if not missing else f"not ready: {', '.join(missing)}")
    return "\n".join(lines)
