"""Catalogs of simulation-ready assets: build them at scale, browse them, load them.

Build with ``rest2art catalog build INPUTS... --catalog assets_out`` (see
``rest2art.catalog.build``). Load in an environment or a training script::

    import rest2art.catalog

    catalog = rest2art.catalog.open("assets_out")          # published entries only
    drawers = catalog.filter(joint_type="prismatic")        # any prismatic joint
    fridges = catalog.filter(category="fridge")
    entry = drawers.sample(1, seed=0)[0]
    entry.mjcf, entry.urdf                                 # absolute paths
    entry.joints                                           # {"prismatic": 2, "revolute": 1}
    entry.record                                           # the full index line (timings, validation, ...)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rest2art.catalog.store import INDEX, latest_records, read_index
from rest2art.errors import InputError

__all__ = ["Catalog", "Entry", "open"]


@dataclass(frozen=True)
class Entry:
    """One published asset of a catalog."""

    name: str
    folder: Path
    """Absolute path of the entry folder (articulation.json, parts/, collision/, pictures)."""
    urdf: Path
    """Absolute path of the URDF."""
    mjcf: Path
    """Absolute path of the MJCF."""
    category: str | None
    """cabinet, microwave, fridge, oven, box, laptop, ... (manifest hint or the pipeline's guess)."""
    joints: dict[str, int]
    """Number of joints per type (``revolute``, ``prismatic``, ``fixed``)."""
    joint_table: tuple[dict, ...]
    """Per joint: name, type, parent, child, axis, origin, limit (input frame, metres / radians)."""
    parts: int
    mass: float
    """Total mass (kg)."""
    key: str
    """Content key of the build job that made it."""
    record: dict
    """The full index record: source, timings, validation summary, pictures, files."""

    @property
    def joint_types(self) -> frozenset[str]:
        """The joint types the asset has."""
        return frozenset(t for t, n in self.joints.items() if n > 0)


class Catalog(Sequence):
    """The published entries of a catalog folder, in build order; a sequence of :class:`Entry`."""

    def __init__(self, root: Path, entries: list[Entry]):
        self.root = root
        self.entries = list(entries)

    def __getitem__(self, index):
        return self.entries[index]

    def __len__(self) -> int:
        return len(self.entries)

    def __repr__(self) -> str:
        return f"Catalog({str(self.root)!r}, {len(self)} entries)"

    @property
    def categories(self) -> list[str]:
        """The categories present, sorted."""
        return sorted({e.category for e in self.entries if e.category})

    def filter(self, category: str | Iterable[str] | None = None,
               joint_type: str | Iterable[str] | None = None) -> "Catalog":
        """Entries of the given category (or categories) having a joint of the given type (or of
        any of the types); None keeps all."""
        wanted_c = {category} if isinstance(category, str) else set(category) if category is not None else None
        wanted_j = {joint_type} if isinstance(joint_type, str) else set(joint_type) if joint_type is not None else None
        kept = [e for e in self.entries if (wanted_c is None or e.category in wanted_c)
                and (wanted_j is None or e.joint_types & wanted_j)]
        return Catalog(self.root, kept)

    def sample(self, n: int = 1, seed: int | np.random.Generator | None = None, replace: bool = False) -> list[Entry]:
        """``n`` entries drawn uniformly (without replacement unless ``replace``)."""
        if not self.entries:
            raise InputError(f"{self.root}: no catalog entry matches")
        rng = np.random.default_rng(seed)
        picks = rng.choice(len(self.entries), size=n, replace=replace or n > len(self.entries))
        return [self.entries[int(i)] for i in picks]


def open(root: str | Path = "assets_out") -> Catalog:  # noqa: A001 - rest2art.catalog.open, like builtins.open
    """The published entries of the catalog folder ``root`` (built by ``rest2art catalog build``),
    from its ``index.jsonl``. Raises InputError when ``root`` holds no catalog."""
    root = Path(root).resolve()
    if not (root / INDEX).is_file():
        raise InputError(f"{root}: not a catalog (no {INDEX}); build one with 'rest2art catalog build'")
    entries = []
    for record in latest_records(read_index(root)).values():
        if record["outcome"] != "published":
            continue
        folder = root / record["path"]
        entries.append(Entry(record["name"], folder, folder / record["urdf"], folder / record["mjcf"],
                             record.get("category"), dict(record.get("joints", {})),
                             tuple(record.get("joint_table", [])), int(record["parts"]), float(record["mass"]),
                             record["key"], record))
    return Catalog(root, entries)

