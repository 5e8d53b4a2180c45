"""What a catalog build is asked to do: one job per input mesh, keyed by content.

Inputs are mesh files, folders (searched recursively for mesh files; a folder holding
``articulation.json`` gives only its own meshes, not its parts) and manifests (``.jsonl``:
one JSON object a line with ``path`` and optional ``name``, ``units``, ``up``, ``front`` and
``category``). A job's key is a hash of the mesh bytes, the resolved config (less the
settings that change no result: build settings, the cache's location), the hints and the project version: the same key
means the same result, so a build skips keys already in the catalog.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from rest2art.config import Config
from rest2art.errors import InputError

MANIFEST_SUFFIXES = (".jsonl",)


def mesh_suffixes() -> dict[str, str]:
    """The mesh file types the loader reads (imported late: the loader pulls in trimesh)."""
    from rest2art.io.load import SUFFIXES

    return SUFFIXES
HINTS = ("units", "up", "front", "category")
FAULTS_ENV = "REST2ART_CATALOG_TEST_FAULTS"
"""Test-only: ``name:fault,name:fault`` plants a fault in the named objects' workers
(``abort``: a native abort, ``sleep``: never returns, ``hog``: allocates until refused)."""
FAULTS = ("abort", "sleep", "hog")


@dataclass(frozen=True)
class Job:
    """One object of a build."""

    name: str
    """Catalog entry name (letters, digits, ``_``, ``-``, ``.``); unique within a build."""
    source: str
    """Absolute path of the mesh file."""
    key: str
    """sha256 hex digest of (mesh bytes, resolved config, hints, project version)."""
    units: str | None = None
    up: str | None = None
    front: str | None = None
    category: str | None = None
    """Category hint; the entry's category when given, else the pipeline's guess."""
    fault: str | None = None
    """Test-only planted fault (see ``FAULTS_ENV``); None in every real build."""


def project_version() -> str:
    """The installed rest2art version (part of every job key)."""
    import rest2art

    return rest2art.__version__


def config_digest(config: Config) -> str:
    """sha256 of the resolved config's settings that change a result (``Config.result_settings``)."""
    return hashlib.sha256(json.dumps(config.result_settings(), sort_keys=True).encode()).hexdigest()


def job_key(mesh_bytes: bytes, config_sha: str, hints: dict[str, str | None], project: str) -> str:
    """The content key of one job: sha256 hex of the mesh bytes, the config digest, the hints
    (units / up / front / category) and the project version."""
    h = hashlib.sha256()
    h.update(hashlib.sha256(mesh_bytes).digest())
    h.update(json.dumps({"config": config_sha, "hints": {k: hints.get(k) for k in HINTS}, "version": project},
                        sort_keys=True).encode())
    return h.hexdigest()


def _mesh_files(folder: Path) -> list[Path]:
    """Mesh files under ``folder``; a folder holding ``articulation.json`` (an object written by
    ``rest2art generate``, or an asset) gives only its own mesh files, not its parts/ or collision/."""
    found = []
    for here, dirs, files in os.walk(folder):
        if "articulation.json" in files:
            dirs.clear()
        dirs.sort()
        found += [Path(here) / f for f in files if Path(f).suffix.lower() in mesh_suffixes()]
    return sorted(found)


def _manifest_items(path: Path) -> list[tuple[Path, dict]]:
    """(mesh path, fields) per line of a manifest; errors name the file and the line."""
    items = []
    for lineno, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}:{lineno}: not a JSON object ({exc.msg})") from None
        if not isinstance(row, dict) or not isinstance(row.get("path"), str):
            raise InputError(f"{path}:{lineno}: each line needs a \"path\" string")
        unknown = set(row) - {"path", "name", *HINTS}
        if unknown:
            raise InputError(f"{path}:{lineno}: unknown field(s) {', '.join(sorted(unknown))}. "
                             f"Valid fields: path, name, {', '.join(HINTS)}")
        mesh = (path.parent / row["path"]).resolve()
        if not mesh.is_file():
            raise InputError(f"{path}:{lineno}: mesh file {mesh} not found")
        if mesh.suffix.lower() not in mesh_suffixes():
            raise InputError(f"{path}:{lineno}: {mesh.name} is not a mesh file ({', '.join(mesh_suffixes())})")
        items.append((mesh, {k: row[k] for k in ("name", *HINTS) if row.get(k) is not None}))
    return items


def gather_inputs(inputs: list[str | Path]) -> list[tuple[Path, dict]]:
    """(absolute mesh path, manifest fields) for every mesh the inputs name, in order, each
    path once."""
    found: dict[Path, dict] = {}
    for raw in inputs:
        path = Path(raw)
        if path.is_dir():
            items = [(p.resolve(), {}) for p in _mesh_files(path)]
            if not items:
                raise InputError(f"{path}: no mesh files ({', '.join(mesh_suffixes())}) in this folder")
        elif path.is_file() and path.suffix.lower() in MANIFEST_SUFFIXES:
            items = _manifest_items(path)
        elif path.is_file() and path.suffix.lower() in mesh_suffixes():
            items = [(path.resolve(), {})]
        elif not path.exists():
            raise InputError(f"{path}: not found")
        else:
            raise InputError(f"{path}: not a mesh file ({', '.join(mesh_suffixes())}), a folder or a manifest (.jsonl)")
        for mesh, fields in items:
            found.setdefault(mesh, fields)
    return list(found.items())


def safe_name(text: str) -> str:
    """``text`` as a file-system and URDF friendly name."""
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("._")
    return name or "object"


def unique_names(paths: list[Path]) -> list[str]:
    """A name per path: its stem, or, where stems repeat (``a/mesh.obj``, ``b/mesh.obj``), its
    folder's name, then more of its path until the names differ."""
    depth = [0] * len(paths)

    def name(i: int) -> str:
        p = paths[i]
        if depth[i] == 0:
            return safe_name(p.stem)
        parents = [q.name for q in p.parents][:depth[i]][::-1]
        return safe_name("_".join(parents) if p.stem in ("mesh", "model", "scene") else "_".join([*parents, p.stem]))

    for _ in range(max((len(p.parts) for p in paths), default=0)):
        counts = Counter(name(i) for i in range(len(paths)))
        clashing = [i for i in range(len(paths)) if counts[name(i)] > 1]
        if not clashing:
            break
        for i in clashing:
            depth[i] += 1
    return [name(i) for i in range(len(paths))]


def planted_faults(text: str | None = None) -> dict[str, str]:
    """Test-only faults by object name, from ``FAULTS_ENV`` (``name:fault,...``)."""
    text = os.environ.get(FAULTS_ENV, "") if text is None else text
    faults = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        name, _, fault = item.partition(":")
        if fault not in FAULTS:
            raise InputError(f"{FAULTS_ENV}: fault '{fault}' for '{name}'. Valid faults: {', '.join(FAULTS)}")
        faults[name] = fault
    return faults


def collect_jobs(inputs: list[str | Path], config: Config = Config()) -> list[Job]:
    """One job per distinct mesh the inputs name (see the module docstring); raises InputError
    with the file and the problem for a missing input or a bad manifest line."""
    items = gather_inputs(inputs)
    names = unique_names([p for p, _ in items])
    manifest_names = Counter(fields["name"] for _, fields in items if "name" in fields)
    repeated = [n for n, c in manifest_names.items() if c > 1]
    if repeated:
        raise InputError(f"manifest: name(s) {', '.join(sorted(repeated))} given to more than one mesh")
    config_sha, project, faults = config_digest(config), project_version(), planted_faults()
    jobs = []
    for (path, fields), name in zip(items, names):
        name = safe_name(fields["name"]) if "name" in fields else name
        hints = {k: fields.get(k) for k in HINTS}
        jobs.append(Job(name, str(path), job_key(path.read_bytes(), config_sha, hints, project),
                        hints["units"], hints["up"], hints["front"], hints["category"], faults.get(name)))
    taken = Counter(j.name for j in jobs)
    if any(c > 1 for c in taken.values()):
        clash = sorted(n for n, c in taken.items() if c > 1)
        raise InputError(f"inputs: more than one mesh would be named {', '.join(clash)}; give names in a manifest")
    return jobs
