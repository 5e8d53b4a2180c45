"""The validation checks that run once an asset's files load: each is a function registered
under a name, run in registration order by ``run_checks``.

A new check is one module that registers itself::

    @register_check("max_mass")
    def heavy_parts(asset: CheckInput) -> list[Finding]: ...

The built-in checks register in ``rest2art.validators.validate``; the policy decides on every
finding alike, so a new check's failures reject or refine an asset with no further wiring.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from rest2art.asset import ArticulatedAsset
from rest2art.config import Config
from rest2art.validators import Finding


@dataclass(frozen=True)
class CheckInput:
    """What every check sees: the folder, its documents' name, the asset read from it, the
    configuration and the object's up direction (3,)."""

    asset_dir: Path
    name: str
    asset: ArticulatedAsset
    config: Config
    up: np.ndarray


Check = Callable[[CheckInput], list[Finding]]

CHECKS: dict[str, Check] = {}
"""Every registered check by name, in registration order."""


def register_check(name: str) -> Callable[[Check], Check]:
    """Decorator: register ``check`` under ``name`` (registering a name again replaces it)."""

    def wrap(check: Check) -> Check:
        CHECKS[name] = check
        return check

    return wrap
