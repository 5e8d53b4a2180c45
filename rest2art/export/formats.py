"""The export formats: each is a function that writes one document of the asset, registered
under a name with the file suffix it writes.

A new format is one module that registers itself::

    @register_format("sdf", ".sdf")
    def sdf_string(asset, name, collision_files, config, up) -> str: ...

and is listed in ``export.formats``. URDF and MJCF are registered by ``rest2art.export.writers``
and are what the validation layer loads.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from rest2art.errors import ConfigError

DocumentWriter = Callable[..., str]
"""``(asset, name, collision_files, config: ExportConfig, up: (3,)) -> document text``;
``collision_files`` maps each part to its collision mesh files, relative to the folder."""


@dataclass(frozen=True)
class ExportFormat:
    """One registered export format."""

    name: str
    suffix: str
    """File suffix of the document, with the dot (written as ``NAME<suffix>``)."""
    write: DocumentWriter


FORMATS: dict[str, ExportFormat] = {}
"""Every registered format by name, in registration order."""


def register_format(name: str, suffix: str) -> Callable[[DocumentWriter], DocumentWriter]:
    """Decorator: register ``write`` as export format ``name`` writing ``NAME<suffix>``."""

    def wrap(write: DocumentWriter) -> DocumentWriter:
        FORMATS[name] = ExportFormat(name, suffix, write)
        return write

    return wrap


def export_format(name: str) -> ExportFormat:
    """The registered format ``name``; a ConfigError listing the valid names otherwise."""
    if name not in FORMATS:
        raise ConfigError(f"unknown export format '{name}'. Formats: {', '.join(FORMATS) or 'none registered'}")
    return FORMATS[name]
