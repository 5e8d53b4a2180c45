"""Writing an output folder atomically, under a lock.

The folder is written under a temporary name beside its destination and renamed when
complete: an interrupted run leaves nothing half-written. While it is written, a lock beside it
(``.OUT.lock``) keeps a second run off the same output, and temporaries a killed run left
beside it are removed. Scratch folders in the system's temporary directory carry their
process id, so that those of a killed process are removed by the next run.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import sys
import tempfile
import uuid
from contextlib import contextmanager
from pathlib import Path

from rest2art.errors import ExportError
from rest2art.io.stop import raise_if_stopped

_HELD: set[Path] = set()


def check_output(out: str | Path, overwrite: bool = False) -> Path:
    """Raise :class:`ExportError` unless ``out`` can be written: it must not exist (unless
    ``overwrite``), must be a folder if it does, and its parent must be creatable and
    writable. Cheap: call it before any long work. Returns the parent."""
    out = Path(out)
    if out.exists() and not overwrite:
        raise ExportError(f"{out}: already exists; pass --overwrite to replace it")
    if out.exists() and not out.is_dir():
        raise ExportError(f"{out}: exists and is not a folder")
    parent = out.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ExportError(f"{parent}: cannot create the output folder ({exc.strerror})") from None
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ExportError(f"{parent}: output folder is not writable")
    return parent


@contextmanager
def output_lock(out: str | Path):
    """Hold the lock of output ``out`` (``.NAME.lock`` beside it) for the block. Raises
    :class:`ExportError` at once when another process holds it. The lock file is removed on
    release; a lock whose holder died is free (the kernel drops it)."""
    out = Path(out).absolute()
    if out in _HELD:
        yield
        return
    check_output(out, overwrite=True)
    path = out.parent / f".{out.name}.lock"
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise ExportError(f"{out.parent}: output folder is not writable ({exc.strerror})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise ExportError(f"{out}: another run (pid {holder}) is writing it; wait for it or choose "
                              "another output") from None
        try:  # its previous holder may have removed the file between our open and our lock
            current = os.stat(path)
        except FileNotFoundError:
            current = None
        if current is not None and os.path.samestat(os.fstat(fd), current):
            break
        os.close(fd)
    os.ftruncate(fd, 0)
    os.write(fd, f"{os.getpid()}\n".encode())
    _HELD.add(out)
    try:
        yield
    finally:
        _HELD.discard(out)
        path.unlink(missing_ok=True)  # still locked: nobody can take the old file after this
        os.close(fd)


def stale_temporaries(out: str | Path) -> list[Path]:
    """Temporaries of ``out`` (``.NAME.tmp-*``, ``.NAME.old-*``) beside it. Only meaningful
    under :func:`output_lock`: then every one of them was left by a run that died."""
    out = Path(out)
    if not out.parent.is_dir():
        return []
    return sorted(p for pattern in (f".{out.name}.tmp-*", f".{out.name}.old-*") for p in out.parent.glob(pattern))


def remove_tree(path: Path) -> None:
    """Remove a file or folder, also where a read-only source left read-only entries in it."""
    def writable_then_retry(func, target, *_):
        for entry in (Path(target).parent, Path(target)):
            if entry.exists() and not entry.is_symlink():
                os.chmod(entry, 0o700 if entry.is_dir() else 0o600)
        func(target)

    if path.is_symlink() or path.is_file():
        path.unlink(missing_ok=True)
    elif path.exists():
        if sys.version_info >= (3, 12):
            shutil.rmtree(path, onexc=writable_then_retry)
        else:
            shutil.rmtree(path, onerror=writable_then_retry)


@contextmanager
def atomic_folder(out: str | Path, overwrite: bool = False):
    """Yield a temporary folder beside ``out``; on success it replaces ``out``.

    Holds ``out``'s lock throughout and first removes temporaries a killed run left beside it.
    Raises ExportError when another run is writing ``out``, when ``out`` already holds
    something and ``overwrite`` is False, or when its parent cannot be written.
    """
    out = Path(out)
    with output_lock(out):
        for stale in stale_temporaries(out):
            remove_tree(stale)
        with _atomic_folder_locked(out, overwrite) as tmp:
            yield tmp


@contextmanager
def _atomic_folder_locked(out: Path, overwrite: bool):
    parent = check_output(out, overwrite)
    tmp = parent / f".{out.name}.tmp-{uuid.uuid4().hex[:8]}"
    try:  # made inside the try: a signal right after mkdir still removes it
        try:
            tmp.mkdir()
        except OSError as exc:
            raise ExportError(f"{parent}: output folder is not writable ({exc.strerror})") from None
        yield tmp
        raise_if_stopped()  # a signal swallowed inside a library still stops the commit
        if out.exists():
            old = parent / f".{out.name}.old-{uuid.uuid4().hex[:8]}"
            out.rename(old)
            tmp.rename(out)
            remove_tree(old)
        else:
            tmp.rename(out)
    except BaseException:
        remove_tree(tmp)
        raise


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def dead_scratch(prefix: str, root: str | Path | None = None) -> list[Path]:
    """Scratch folders ``PREFIX-PID-*`` in ``root`` (the system's temporary directory) whose
    process is gone: left by a run killed before it could remove them (SIGKILL, a power cut)."""
    root = Path(root or tempfile.gettempdir())
    out = []
    for path in root.glob(f"{prefix}-*-*"):
        pid = path.name[len(prefix) + 1:].split("-", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            out.append(path)
    return sorted(out)


@contextmanager
def scratch_folder(prefix: str):
    """A temporary folder ``PREFIX-PID-*`` for the block, removed after it; first removes the
    ones of ``prefix`` that dead processes left (:func:`dead_scratch`)."""
    for stale in dead_scratch(prefix):
        remove_tree(stale)
    with tempfile.TemporaryDirectory(prefix=f"{prefix}-{os.getpid()}-") as folder:
        yield Path(folder)
