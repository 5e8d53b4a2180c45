"""One catalog job, run inside its worker process: reconstruct, validate (and refine), picture.

``run_job`` writes the entry's files into a work folder and returns its record (the line the
index keeps): outcome ``published`` (the policy publishes it), ``rejected`` (the policy rejects
it: only ``validation.json`` and a thumbnail are kept), or ``static`` (no movable part: nothing
is written, unless the config's ``gate.allow_static`` publishes it as a rigid asset). Errors
propagate; the worker wrapper (``rest2art.catalog.isolate``) turns them and crashes into
``failed`` records.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from collections import Counter
from pathlib import Path

import numpy as np
from rest2art.validators.validate import read_asset_folder, validate_folder

from rest2art.asset import read_articulation
from rest2art.catalog.inputs import Job
from rest2art.catalog.media import write_pictures
from rest2art.catalog.records import base_record, file_hashes
from rest2art.config import Config
from rest2art.export.writers import write_asset
from rest2art.io.load import load_mesh
from rest2art.pipeline import StageTimer, complete_asset, reconstruct_mesh


def plant_fault(fault: str | None, memory_limit_mb: int) -> None:
    """Test-only: act out a planted fault (``abort``, ``sleep``, ``hog``); nothing for None."""
    if fault == "abort":
        os.abort()
    if fault == "sleep":
        time.sleep(10 ** 6)
    if fault == "hog":
        hoard = []
        while True:  # touch every page, as a leaking native library would, until refused
            hoard.append(np.ones(2 ** 24))  # 128 MiB
            if len(hoard) * 128 > 4 * memory_limit_mb:  # the limit is not enforced here
                raise MemoryError(f"planted hog reached {len(hoard) * 128} MiB without being stopped")


def is_static(asset) -> bool:
    """No movable part: the plausibility gate says so (``metadata["gate"]``), or no joint moves."""
    return asset.metadata.get("gate", {}).get("decision") == "static" or not asset.movable_joints


def asset_summary(asset) -> dict:
    """Parts, joints by type, hulls and total mass (kg) of a completed asset."""
    return {"parts": len(asset.parts),
            "joints": dict(sorted(Counter(j.type for j in asset.joints).items())),
            "hulls": int(sum(len(p.collision) for p in asset.parts)),
            "mass": round(float(sum(p.inertial.mass for p in asset.parts if p.inertial is not None)), 4)}


def validation_summary(report) -> dict:
    """Decision, refinements done (with why), reasons, and check counts of a validation report."""
    findings = report.findings
    return {"decision": report.decision.status, "rounds": len(report.rounds),
            "checks_passed": sum(f.ok for f in findings), "checks_failed": sum(not f.ok for f in findings),
            "refinements": [{"done": a.done, "why": a.why} for a in report.refinements],
            "reasons": [str(r) for r in report.decision.reasons]}


def run_job(job: Job, config: Config, out: str | Path) -> dict:
    """Reconstruct ``job.source``, validate and refine it, and write the entry into ``out``
    (created; left empty for a static object). Returns the record (no ``path`` yet: the catalog
    decides where the entry goes)."""
    start = time.perf_counter()
    plant_fault(job.fault, config.catalog.memory_limit_mb)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    record = base_record(job)
    timer = StageTimer()
    mesh = timer.run("load", _quiet, load_mesh, job.source, config.load, job.units)
    asset = reconstruct_mesh(mesh, config, job.up, job.front, timer=timer)
    record["category"] = job.category or asset.metadata.get("category")
    gate = asset.metadata.get("gate")
    if gate is not None:
        record["gate"] = gate
    if is_static(asset) and not getattr(getattr(config, "gate", None), "allow_static", False):
        record.update(outcome="static", parts=len(asset.parts), joints={}, hulls=0, mass=None,
                      timings={"total_s": round(time.perf_counter() - start, 3), "stages": timer.times})
        return record
    complete_asset(asset, config, timer=timer)
    asset.metadata["timing_s"] = timer.times
    write_asset(asset, out, job.name, config.export, asset.up)
    (out / "config.json").write_text(json.dumps(config.result_settings(), indent=1))
    checked = time.perf_counter()
    report = validate_folder(out, job.name, config, refine=True)
    validated = time.perf_counter()
    final = read_asset_folder(out, job.name)  # refinement may have changed limits and hulls
    published = report.decision.status == "publish"
    if not published:  # keep the reasons and a picture, not the asset
        for path in out.iterdir():
            if path.name != "validation.json":
                shutil.rmtree(path) if path.is_dir() else path.unlink()
    pictures = write_pictures(final, out, config.catalog, animations=published)
    record.update(outcome="published" if published else "rejected", **asset_summary(final),
                  validation=validation_summary(report), pictures=pictures)
    if published:
        record.update(urdf=f"{job.name}.urdf", mjcf=f"{job.name}.xml",
                      joint_table=[{"name": j.name, "type": j.type, "parent": j.parent, "child": j.child,
                                    "axis": np.round(j.axis, 6).tolist(), "origin": np.round(j.origin, 6).tolist(),
                                    "limit": [round(float(v), 6) for v in j.limit]}
                                   for j in read_articulation(out, load_meshes=False).joints])
    record["timings"] = {"total_s": round(time.perf_counter() - start, 3), "stages": timer.times,
                         "validate_s": round(validated - checked, 3),
                         "pictures_s": round(time.perf_counter() - validated, 3)}
    record["files"] = file_hashes(out)
    return record


def _quiet(_: str) -> None:
    pass
