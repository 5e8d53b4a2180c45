"""The record of one catalog object (its index line), and the small helpers every side needs.

Kept free of the pipeline's imports, so that reading a catalog (``rest2art.catalog.open``, the
summary, the store) stays cheap.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from rest2art.catalog.inputs import Job

OUTCOMES = ("published", "rejected", "static", "failed")
ENTRY_FILE = "entry.json"
"""An entry's own record, inside its folder."""


def base_record(job: Job) -> dict:
    """The fields every record has, whatever its outcome."""
    return {"name": job.name, "source": job.source, "key": job.key, "outcome": None, "category": job.category,
            "hints": {k: v for k, v in (("units", job.units), ("up", job.up), ("front", job.front)) if v}}


def failed_record(job: Job, reason: str, seconds: float) -> dict:
    """The record of an object whose worker raised, crashed, timed out or ran out of memory."""
    return {**base_record(job), "outcome": "failed", "error": reason, "timings": {"total_s": round(seconds, 3)}}


def file_hashes(folder: str | Path) -> dict[str, str]:
    """{relative path: sha256 hex} of every file under ``folder`` but ``entry.json``, sorted."""
    folder = Path(folder)
    out = {}
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        rel = path.relative_to(folder).as_posix()
        if rel != ENTRY_FILE:
            out[rel] = hashlib.sha256(path.read_bytes()).hexdigest()
    return out
