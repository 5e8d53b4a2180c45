"""Crash isolation: each job in its own worker process, with a wall-time and a memory limit.

Workers are forked from a ``forkserver`` that has imported the pipeline once, so a worker
starts in milliseconds instead of re-importing trimesh, the simulators and the stages. In the
worker, an address-space limit (``RLIMIT_AS``, inherited by the CoACD runs it starts) turns
an allocation past ``memory_limit_mb`` into a MemoryError; the worker is in its own process
group, killed whole at the wall-time limit, and killed whole when the build is killed.
Its output goes to a log beside its work folder; the end of it is kept in a failed record.
Whatever happens (an error, a native abort, a timeout, running out of memory) the caller gets a
record back.
"""

from __future__ import annotations

import faulthandler
import importlib.util
import multiprocessing as mp
import os
import resource
import signal
import sys
import threading
import time
import traceback
from multiprocessing.connection import wait
from pathlib import Path

from rest2art.catalog.inputs import Job
from rest2art.catalog.records import failed_record
from rest2art.config import Config
from rest2art.errors import Rest2ArtError

PRELOAD = ["rest2art.catalog.job", "mujoco", "pybullet"]
"""Modules the forkserver imports once for every worker."""
LOG_TAIL = 2000
"""Characters of a failed worker's output kept in its record."""
_context = None
_running: set = set()
"""Worker processes now running (pids), so that an interrupted build can kill them."""


def main_module_name() -> list[str]:
    """The name under which this process's ``__main__`` file imports, as a one-item list (empty
    when it has none). Every worker runs its parent's main file again (as ``__mp_main__``); that
    is cheap only if the forkserver imported what the file imports. A Ray worker's main file
    imports all of Ray: 0.4 s per object when the forkserver has not."""
    main = sys.modules["__main__"]
    path = getattr(main, "__file__", None)
    if path is None or getattr(main.__spec__, "name", None) or not path.endswith(".py"):
        return []
    path = Path(path).resolve()
    names = []
    for root in sys.path:
        try:
            name = ".".join(path.relative_to(Path(root or ".").resolve()).with_suffix("").parts)
            spec = importlib.util.find_spec(name)
        except (ValueError, ImportError):
            continue
        if spec is not None and spec.origin and Path(spec.origin).resolve() == path:
            names.append(name)
    # the forkserver starts with the interpreter's own path (not this process's additions), where
    # the name relative to the outermost folder (site-packages, not the script's own) imports
    return [max(names, key=lambda n: n.count("."))] if names else []


def worker_context():
    """The forkserver multiprocessing context (started on first use) that forks workers."""
    global _context
    if _context is None:
        _context = mp.get_context("forkserver")
        _context.set_forkserver_preload(PRELOAD + main_module_name())
    return _context


def warm_up() -> None:
    """Start the forkserver now, so that its imports overlap with the build's own set-up."""
    from multiprocessing import forkserver

    worker_context()
    forkserver.ensure_running()


def signal_reason(exitcode: int) -> str:
    """Why a worker that sent no result ended, from its exit code."""
    if exitcode is None or exitcode >= 0:
        return f"worker exited with code {exitcode} before sending a result"
    sig = signal.Signals(-exitcode)
    what = {signal.SIGABRT: "native abort", signal.SIGSEGV: "segmentation fault", signal.SIGBUS: "bus error",
            signal.SIGKILL: "killed from outside, e.g. by the system's out-of-memory killer"}.get(sig, "killed")
    return f"crashed: {sig.name} ({what})"


def _die_with_driver() -> None:
    """Kill this worker's process group as soon as the build that started it is gone.

    The forkserver does not notice a killed build while its workers live (they hold its
    liveness pipe), so each worker watches its own pipe from the build: the build holds the
    write end until the worker has ended, and the end reads EOF when the build dies."""
    parent = mp.parent_process()
    if parent is None:
        return

    def watch() -> None:
        wait([parent.sentinel])
        os.killpg(0, signal.SIGKILL)

    threading.Thread(target=watch, name="rest2art-driver-watch", daemon=True).start()


def log_path(out: str | Path) -> Path:
    """Where a worker writes its stdout and stderr: beside its output folder."""
    return Path(out).with_name(Path(out).name + ".log")


def _worker(job: Job, config: Config, out: str, conn) -> None:
    """Body of a worker process: limits, output to its log, the job, one record sent back."""
    os.setpgid(0, 0)
    _die_with_driver()
    log = os.open(log_path(out), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(log, 1)
    os.dup2(log, 2)
    faulthandler.enable()  # a native crash leaves the Python stack that led to it in the log
    limit = int(config.catalog.memory_limit_mb) * 2 ** 20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    start = time.perf_counter()
    try:
        from rest2art.catalog.job import run_job  # imported once by the forkserver (PRELOAD)

        record = run_job(job, config, out)
    except MemoryError:
        record = failed_record(job, f"out of memory: needed more than the worker's limit of "
                                    f"{config.catalog.memory_limit_mb} MiB", time.perf_counter() - start)
    except Rest2ArtError as exc:
        record = failed_record(job, str(exc), time.perf_counter() - start)
    except Exception as exc:
        record = failed_record(job, f"internal error: {type(exc).__name__}: {exc}", time.perf_counter() - start)
        record["traceback"] = traceback.format_exc()
    conn.send(record)
    conn.close()


def run_isolated(job: Job, config: Config, out: str | Path) -> dict:
    """Run ``job`` in a fresh worker process writing into ``out``; its record, or a ``failed``
    record naming the timeout, the signal or the exit code. Blocks until the worker is gone."""
    ctx = worker_context()
    receive, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_worker, args=(job, config, str(out), send), name=f"rest2art-{job.name}")
    start = time.perf_counter()
    proc.start()
    _running.add(proc.pid)
    send.close()
    timeout = float(config.catalog.timeout_s)
    record = None
    if receive.poll(timeout):
        try:
            record = receive.recv()
        except (EOFError, OSError):
            record = None
        proc.join(max(1.0, timeout - (time.perf_counter() - start)))
    if proc.is_alive():  # past its time (or hanging after sending): the worker and its children go
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):  # not yet its own group leader
            proc.kill()
        proc.join()
        if record is None:
            record = failed_record(job, f"timed out after {timeout:g} s", time.perf_counter() - start)
    elif record is None:
        record = failed_record(job, signal_reason(proc.exitcode), time.perf_counter() - start)
    _running.discard(proc.pid)
    receive.close()
    proc.close()
    log = log_path(out)
    if record["outcome"] == "failed" and log.is_file():
        lines = log.read_text(errors="replace").splitlines()  # faulthandler ends with a long module list
        tail = "\n".join(line for line in lines if not line.startswith("Extension modules:"))[-LOG_TAIL:].strip()
        if tail:
            record["log_tail"] = tail
    log.unlink(missing_ok=True)
    return record


def kill_workers() -> None:
    """Kill every running worker and its children (an interrupted build)."""
    for pid in list(_running):
        try:
            os.killpg(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
