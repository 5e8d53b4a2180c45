"""The catalog folder on disk, written so that a killed build loses, duplicates and half-writes
nothing.

Layout::

    CATALOG/index.jsonl          one record a line, appended and fsynced per object
    CATALOG/NAME/                a published entry (asset files, pictures, entry.json)
    CATALOG/rejected/NAME/       a rejected object (validation.json, thumbnail, entry.json)
    CATALOG/.work/               workers' output while they run (removed on start)

An entry is written in a work folder and renamed into place; its record is appended to the
index afterwards. A build that was killed in between finds the entry without its line and
appends it on start (the index can be rebuilt from the entries' ``entry.json``); a line torn by
the kill is cut off. The last line for a name is that name's record.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import uuid
from pathlib import Path

from rest2art.catalog.records import ENTRY_FILE
from rest2art.errors import InputError
from rest2art.io.stop import raise_if_stopped

INDEX = "index.jsonl"
REJECTED = "rejected"
WORK = ".work"
LOCK = ".lock"


def read_index(root: str | Path) -> list[dict]:
    """Every complete record of ``root/index.jsonl`` in file order ([] when there is none)."""
    path = Path(root) / INDEX
    if not path.is_file():
        return []
    records = []
    for line in path.read_bytes().split(b"\n"):
        if line.strip():
            try:
                records.append(json.loads(line))
            except json.JSONDecodeError:  # only a torn last line can be incomplete
                continue
    return records


def latest_records(records: list[dict]) -> dict[str, dict]:
    """The last record per name, in order of first appearance."""
    latest: dict[str, dict] = {}
    for record in records:
        latest.pop(record["name"], None)
        latest[record["name"]] = record
    return latest


VOLATILE = ("timings", "entry_sha256")
"""Record fields that differ between two runs of the same job (entry.json holds the timings)."""


def snapshot(root: str | Path) -> dict[str, tuple[dict, dict | None]]:
    """Per name, everything two builds of the same inputs must agree on: the record without its
    timings, and a published entry's articulation.json without its stage timings (its hash is
    left out of the record's files for that reason)."""
    root = Path(root)
    out = {}
    for record in latest_records(read_index(root)).values():
        stable = {k: v for k, v in record.items() if k not in VOLATILE}
        stable["files"] = {k: v for k, v in record.get("files", {}).items() if k != "articulation.json"}
        articulation = None
        if record["outcome"] == "published":
            articulation = json.loads((root / record["path"] / "articulation.json").read_text())
            articulation["metadata"].pop("timing_s", None)
        out[record["name"]] = (stable, articulation)
    return out


def entry_digest(data: bytes) -> str:
    """sha256 hex of an entry.json's bytes (kept in the index line)."""
    return hashlib.sha256(data).hexdigest()


def entry_folder(root: str | Path, record: dict) -> Path | None:
    """The folder a record's files live in, or None (static and failed objects have none)."""
    return Path(root) / record["path"] if record.get("path") else None


def _replace_folder(src: Path, dest: Path) -> None:
    """Rename ``src`` to ``dest``, replacing what is there."""
    raise_if_stopped()
    dest.parent.mkdir(parents=True, exist_ok=True)
    if dest.exists():
        old = dest.parent / f".{dest.name}.old-{uuid.uuid4().hex[:8]}"
        dest.rename(old)
        src.rename(dest)
        shutil.rmtree(old, ignore_errors=True)
    else:
        src.rename(dest)


class CatalogStore:
    """Exclusive writer of one catalog folder (a lock file keeps a second build out).

    Use as a context manager: entering locks the folder and repairs what a killed build left."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self._lock = None
        self._index = None

    def __enter__(self) -> "CatalogStore":
        try:
            self.root.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"{self.root}: cannot create the catalog folder ({exc.strerror})") from None
        self._lock = open(self.root / LOCK, "w")
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._lock.close()
            raise InputError(f"{self.root}: another build is writing this catalog") from None
        self.repair()
        self._index = open(self.root / INDEX, "ab")
        return self

    def __exit__(self, *exc) -> None:
        if self._index is not None:
            self._index.close()
        if self._lock is not None:
            fcntl.flock(self._lock, fcntl.LOCK_UN)
            self._lock.close()
        shutil.rmtree(self.root / WORK, ignore_errors=True)

    def repair(self) -> list[str]:
        """Undo what a killed build left: work and temporary folders go, a torn last index
        line is cut off, and entries whose line never made it are indexed. Returns what was done."""
        done = []
        shutil.rmtree(self.root / WORK, ignore_errors=True)
        for folder in (self.root, self.root / REJECTED):
            for path in folder.glob(".*.old-*") if folder.is_dir() else []:
                shutil.rmtree(path, ignore_errors=True)
                done.append(f"removed {path.name}")
        index = self.root / INDEX
        if index.is_file():
            data = index.read_bytes()
            if data and not data.endswith(b"\n"):
                with open(index, "r+b") as f:
                    f.truncate(data.rfind(b"\n") + 1)
                    os.fsync(f.fileno())
                done.append("cut off a torn index line")
        keys = {r["key"] for r in read_index(self.root)}
        entries = sorted(self.root.glob(f"*/{ENTRY_FILE}")) + sorted(self.root.glob(f"{REJECTED}/*/{ENTRY_FILE}"))
        missing = []
        for path in entries:
            data = path.read_bytes()
            record = json.loads(data)
            if record["key"] not in keys:
                missing.append({**record, "entry_sha256": entry_digest(data)})
        if missing:
            with open(index, "ab") as f:
                for record in missing:
                    f.write(json.dumps(record).encode() + b"\n")
                f.flush()
                os.fsync(f.fileno())
            done += [f"indexed {r['name']} from its entry" for r in missing]
        return done

    def records(self) -> list[dict]:
        """Every record in the index, in file order."""
        return read_index(self.root)

    def done_keys(self, retry_failed: bool = False) -> set[str]:
        """Keys a build skips: the latest record of each name, failed ones unless retried."""
        return {r["key"] for r in latest_records(self.records()).values()
                if not (retry_failed and r["outcome"] == "failed")}

    def work_folder(self, name: str) -> Path:
        """A fresh folder for a worker's output (inside the catalog, so it is renamed, not copied)."""
        path = self.root / WORK / f"{name}-{uuid.uuid4().hex[:8]}"
        path.mkdir(parents=True)
        return path

    def commit(self, record: dict, work: Path | None) -> dict:
        """Put a finished object in the catalog: its work folder becomes the entry (published) or
        ``rejected/NAME``; then its line is appended to the index and fsynced. Returns the
        indexed record."""
        name = record["name"]
        homes = {"published": self.root / name, "rejected": self.root / REJECTED / name}
        dest = homes.get(record["outcome"])
        record = {**record, "path": dest.relative_to(self.root).as_posix() if dest else None}
        if dest is not None:
            data = json.dumps(record, indent=1).encode()
            (work / ENTRY_FILE).write_bytes(data)
            _replace_folder(work, dest)
            record["entry_sha256"] = entry_digest(data)
        elif work is not None:
            shutil.rmtree(work, ignore_errors=True)
        self._index.write(json.dumps(record).encode() + b"\n")
        self._index.flush()
        os.fsync(self._index.fileno())
        for other in homes.values():  # a name that changed outcome keeps one home
            if other != dest and other.exists():
                shutil.rmtree(other)
        return record


def verify(root: str | Path) -> list[str]:
    """Problems found re-checking every entry of the catalog against its hashes: entry.json
    against the index, each file against entry.json, files missing or not listed. [] when sound."""
    root = Path(root)
    problems = []
    for record in latest_records(read_index(root)).values():
        folder = entry_folder(root, record)
        if folder is None:
            continue
        entry = folder / ENTRY_FILE
        if not entry.is_file():
            problems.append(f"{record['path']}: {ENTRY_FILE} is missing")
            continue
        if entry_digest(entry.read_bytes()) != record.get("entry_sha256"):
            problems.append(f"{record['path']}/{ENTRY_FILE}: does not match its index line")
        files = record.get("files", {})
        present = {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()} - {ENTRY_FILE}
        for rel in sorted(set(files) - present):
            problems.append(f"{record['path']}/{rel}: missing")
        for rel in sorted(present - set(files)):
            problems.append(f"{record['path']}/{rel}: not listed in {ENTRY_FILE}")
        for rel in sorted(set(files) & present):
            if hashlib.sha256((folder / rel).read_bytes()).hexdigest() != files[rel]:
                problems.append(f"{record['path']}/{rel}: content changed (sha256 differs)")
    return problems
