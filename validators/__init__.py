"""Validation of exported assets (installed as ``rest2art.validators``).

Checks never raise for a bad asset: they return typed :class:`Finding` objects, and one policy
turns findings into a decision.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any


@dataclass(frozen=True)
class Finding:
    """One result of one check."""

    check: str
    """e.g. 'load', 'gravity'."""
    subject: str
    """What was checked: an engine, a part or a joint name."""
    ok: bool
    message: str
    data: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)
