"""``rest2art catalog build``: every input object through the pipeline into one catalog.

Jobs whose key the catalog already holds are skipped; the rest run on a backend (a local pool
of worker processes, or Ray tasks) that yields one finished job at a time, and the driver alone
commits each into the catalog (entry renamed into place, index line appended and fsynced). A
build killed at any moment and started again ends with the same catalog.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path

from rest2art.catalog.inputs import Job, collect_jobs
from rest2art.catalog.records import OUTCOMES
from rest2art.catalog.pages import write_site
from rest2art.catalog.store import CatalogStore, latest_records
from rest2art.config import Config

Finished = tuple[Job, dict, Path | None, float]
"""A backend's result: the job, its record, the work folder holding its files, and the time (s)
the object held a worker slot: from dispatch to result (local pool), or the Ray task's body and
the unpacking of its files (Ray; time queued in Ray is left out)."""


@dataclass
class BuildReport:
    """What a build did."""

    jobs: int
    """Objects the inputs name."""
    skipped: int
    """Of them, already in the catalog."""
    records: list[dict] = field(default_factory=list)
    """Records committed by this build, in commit order."""
    outcomes: Counter = field(default_factory=Counter)
    """Latest outcome of every input object (skipped ones included)."""
    job_wall_s: dict[str, float] = field(default_factory=dict)
    """Per object run here: its worker slot time (see ``Finished``) plus its commit (s)."""
    setup_s: float = 0.0
    """Reading and hashing the inputs, locking and repairing the catalog (s)."""
    pages_s: float = 0.0
    """Writing index.html and the pages (s)."""
    failed: list[str] = field(default_factory=list)
    """Input objects whose latest outcome is failed (this build's or a skipped earlier one)."""
    wall_s: float = 0.0
    """Whole build, inputs and pages included (s)."""


def run_local(jobs: list[Job], config: Config, store: CatalogStore, workers: int) -> Iterator[Finished]:
    """Run ``jobs`` with at most ``workers`` worker processes at a time; yields each as it ends."""
    from rest2art.catalog.isolate import kill_workers, run_isolated

    def one(job: Job) -> Finished:
        start = time.perf_counter()
        work = store.work_folder(job.name)
        record = run_isolated(job, config, work)
        return job, record, work, time.perf_counter() - start

    pool = ThreadPoolExecutor(max_workers=max(1, workers), thread_name_prefix="rest2art-catalog")
    try:
        pending = {pool.submit(one, job) for job in jobs}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield future.result()
    finally:  # interrupted: nothing more starts, running workers are killed
        pool.shutdown(wait=False, cancel_futures=True)
        kill_workers()
        pool.shutdown(wait=True)


def build_catalog(inputs: list[str | Path], catalog: str | Path, config: Config = Config(), workers: int = 2,
                  ray_address: str | None = None, retry_failed: bool = False,
                  on_start: Callable[[int, int, Counter], None] | None = None,
                  on_result: Callable[[dict, Counter], None] | None = None) -> BuildReport:
    """Build (or resume) the catalog at ``catalog`` from ``inputs`` (mesh files, folders,
    manifests). ``ray_address`` (``auto``, ``local`` or HOST:PORT) runs the jobs as Ray tasks
    instead of ``workers`` local processes. ``on_start(total, skipped, counts)`` and
    ``on_result(record, counts)`` report progress; counts are per outcome, skipped objects
    counted by their recorded outcome. Writes index.html and the pages at the end.

    Workers are forked from a server that imports the calling script again as ``__mp_main__``
    (as every multiprocessing program does): a script calling this needs an
    ``if __name__ == "__main__":`` guard."""
    start = time.perf_counter()
    if ray_address is None:
        from rest2art.catalog.isolate import warm_up

        warm_up()
    else:
        from rest2art.catalog.ray_backend import import_ray

        import_ray()  # before any work: without Ray, say what to install
    jobs = collect_jobs(inputs, config)
    with CatalogStore(catalog) as store:
        report = BuildReport(len(jobs), 0)
        done = store.done_keys(retry_failed)
        todo = [j for j in jobs if j.key not in done]
        latest = {r["key"]: r for r in latest_records(store.records()).values()}
        report.skipped = len(jobs) - len(todo)
        report.setup_s = round(time.perf_counter() - start, 3)
        counts = Counter({o: 0 for o in OUTCOMES})
        counts.update(latest[j.key]["outcome"] for j in jobs if j.key in done)
        if on_start:
            on_start(len(jobs), report.skipped, counts)
        if ray_address is not None:
            from rest2art.catalog.ray_backend import run_ray

            finished = run_ray(todo, config, store, ray_address)
        else:
            finished = run_local(todo, config, store, workers)
        for job, record, work, seconds in finished:
            committed = time.perf_counter()
            record = store.commit({**record, "source": job.source}, work)
            report.job_wall_s[job.name] = round(seconds + time.perf_counter() - committed, 3)
            report.records.append(record)
            counts[record["outcome"]] += 1
            if on_result:
                on_result(record, counts)
        latest = {r["key"]: r for r in latest_records(store.records()).values()}
        report.outcomes = Counter(latest[j.key]["outcome"] for j in jobs if j.key in latest)
        report.failed = [j.name for j in jobs if j.key in latest and latest[j.key]["outcome"] == "failed"]
        pages = time.perf_counter()
        write_site(catalog)
        report.pages_s = round(time.perf_counter() - pages, 3)
    report.wall_s = round(time.perf_counter() - start, 3)
    return report
