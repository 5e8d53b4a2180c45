"""Ray backend of catalog builds: the same jobs as Ray tasks, across the machines of a cluster.

Each task asks for ``catalog.ray_num_cpus`` CPUs and ``catalog.ray_memory_mb`` of memory, runs
its job through the same isolated worker as the local pool (so a native crash or a timeout is
a failed record, not a lost task) and sends the entry's files back packed in a tar archive: the
driver commits them into the catalog, so workers need no shared file system. Ray runs a task
again only when its worker or node died (``ray_max_retries``), never for an error. Ray is an
optional extra: ``pip install -e ".[ray]"``.
"""

from __future__ import annotations

import hashlib
import io
import tarfile
import tempfile
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

from rest2art.catalog.inputs import Job
from rest2art.catalog.records import failed_record
from rest2art.catalog.store import CatalogStore
from rest2art.config import Config
from rest2art.errors import InputError

INSTALL_HINT = "--ray needs Ray, which is not installed: pip install -e \".[ray]\" (or pip install \"ray>=2.9\")"


def import_ray():
    """The ``ray`` module, or an InputError saying what to install."""
    try:
        import ray
    except ImportError:
        raise InputError(INSTALL_HINT) from None
    return ray


def pack_folder(folder: Path) -> bytes:
    """Uncompressed tar of ``folder``'s contents (paths relative to it)."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as tar:
        for path in sorted(folder.rglob("*")):
            tar.add(path, arcname=path.relative_to(folder).as_posix(), recursive=False)
    return buffer.getvalue()


def unpack_folder(data: bytes, folder: Path) -> None:
    """Extract a ``pack_folder`` archive into ``folder`` (plain files and folders only)."""
    with tarfile.open(fileobj=io.BytesIO(data), mode="r") as tar:
        tar.extractall(folder, filter="data")


def ray_task(job: Job, config: Config, mesh: bytes) -> tuple[dict, bytes, float]:
    """Body of a Ray task: the job in an isolated worker on this node; (record, packed files,
    seconds in this body). The mesh is read from ``job.source`` when this node has the same
    file, else from ``mesh``."""
    from rest2art.catalog.isolate import run_isolated

    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="rest2art-") as tmp:
        source = Path(job.source)
        same = source.is_file() and hashlib.sha256(source.read_bytes()).digest() == hashlib.sha256(mesh).digest()
        if not same:
            source = Path(tmp) / f"input{source.suffix}"
            source.write_bytes(mesh)
        out = Path(tmp) / "out"
        out.mkdir()
        record = run_isolated(replace(job, source=str(source)), config, out)
        return {**record, "source": job.source}, pack_folder(out), time.perf_counter() - start


def _connect(ray, address: str) -> None:
    if ray.is_initialized():
        return
    if address == "local":
        ray.init(include_dashboard=False, log_to_driver=False)
    else:
        try:
            ray.init(address=address, log_to_driver=False)
        except ConnectionError as exc:
            raise InputError(f"--ray {address}: no Ray cluster there ({exc}); "
                             "use --ray local to start one here") from None


def run_ray(jobs: list[Job], config: Config, store: CatalogStore, address: str) -> Iterator[tuple]:
    """Run ``jobs`` as Ray tasks on the cluster at ``address`` (``auto``, ``local`` or
    HOST:PORT; an already initialised Ray is used as it is); yields (job, record, work folder,
    seconds) as each ends, with at most twice the cluster's CPUs of tasks in flight."""
    ray = import_ray()
    _connect(ray, address)
    c = config.catalog
    task = ray.remote(ray_task).options(num_cpus=c.ray_num_cpus, memory=int(c.ray_memory_mb) * 2 ** 20,
                                        max_retries=c.ray_max_retries, retry_exceptions=False)
    window = max(2, int(2 * ray.cluster_resources().get("CPU", 1) / max(c.ray_num_cpus, 1e-3)))
    queue = list(reversed(jobs))
    in_flight: dict = {}
    while queue or in_flight:
        while queue and len(in_flight) < window:
            job = queue.pop()
            in_flight[task.remote(job, config, Path(job.source).read_bytes())] = (job, time.perf_counter())
        ready, _ = ray.wait(list(in_flight), num_returns=1)
        job, start = in_flight.pop(ready[0])
        work, seconds = None, 0.0
        try:
            record, payload, seconds = ray.get(ready[0])
            unpacking = time.perf_counter()
            work = store.work_folder(job.name)
            unpack_folder(payload, work)
            seconds += time.perf_counter() - unpacking
        except ray.exceptions.RayError as exc:  # the worker or node died more often than retried
            lines = str(exc).strip().splitlines()
            seconds = time.perf_counter() - start
            record = failed_record(job, f"Ray task lost: {type(exc).__name__}: {lines[0] if lines else ''}", seconds)
        yield job, record, work, seconds
