"""The validation layer over an exported asset folder: every check, the policy, refinement.

``validate_folder`` runs the checks (files, inertia, loading and gravity in three engines, rest
contacts, the FCL sweep, actuation), asks the policy for a decision, and, when refinement is
allowed, applies the policy's actions to the folder (atomically) and checks again, up to
``refine_rounds`` times. The report of every round goes to ``validation.json``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from rest2art.validators import Finding
from rest2art.validators.budget import check_decomposition, check_hull_budget
from rest2art.validators.policy import Action, Decision, Reason, Redecompose, ShrinkLimit, Thin, decide
from rest2art.validators.registry import CHECKS, CheckInput, register_check
from rest2art.validators.static_checks import check_structure, parse_xml, read_asset, urdf_inertial

from rest2art.asset import ArticulatedAsset, MassProperties
from rest2art.config import Config
from rest2art.export.writers import GRAVITY, link_origins, write_asset
from rest2art.io.atomic import atomic_folder


@dataclass(frozen=True)
class Round:
    """One round of checks and the decision taken on them."""

    findings: list[Finding]
    decision: Decision


@dataclass
class Report:
    """All rounds of checks on one asset and the final decision."""

    name: str
    rounds: list[Round] = field(default_factory=list)
    decision: Decision = field(default_factory=lambda: Decision("reject", [Reason("none", "", "not validated")]))
    written: str | None = None
    """None when validation.json was written, else why not (a read-only folder)."""

    @property
    def findings(self) -> list[Finding]:
        return self.rounds[-1].findings if self.rounds else []

    def to_dict(self) -> dict:
        return {"name": self.name, "decision": self.decision.to_dict(),
                "rounds": [{"findings": [f.to_dict() for f in r.findings], "decision": r.decision.to_dict()}
                           for r in self.rounds]}

    @property
    def refinements(self) -> list[Action]:
        """Every refinement applied, in order, each with what it did."""
        return [a for r in self.rounds for a in r.decision.actions if a.done]


def asset_name(folder: str | Path) -> str:
    """The asset's name: the stem of the single URDF in ``folder``."""
    urdfs = sorted(Path(folder).glob("*.urdf"))
    if len(urdfs) != 1:
        from rest2art.errors import InputError

        raise InputError(f"{folder}: expected exactly one .urdf file, found {len(urdfs)}; pass --name")
    return urdfs[0].stem


def run_checks(asset_dir: str | Path, name: str, config: Config = Config()) -> list[Finding]:
    """Every check on the folder; never raises for a bad asset. What the simulators print
    natively is captured into a 'native' finding, never onto stdout or into the working
    directory."""
    from rest2art.sim.native import captured

    asset_dir = Path(asset_dir).resolve()
    with captured() as native:
        findings = _run_checks(asset_dir, name, config)
    if native.chars:
        findings.append(Finding("native", "simulators", True, f"{native.chars} characters of native simulator "
                                "output captured (in validation.json)", {"output": native.text}))
    return findings


def _run_checks(asset_dir: Path, name: str, config: Config) -> list[Finding]:
    from rest2art.validators.load_checks import run_load_checks

    findings = run_load_checks(asset_dir, name, config.check)
    if not all(f.ok for f in findings if f.check in ("files", "load")):
        return findings  # the rest needs the files to load
    asset = read_asset(asset_dir)
    up = asset.up
    given = CheckInput(asset_dir, name, asset, config, up)
    for check in CHECKS.values():
        findings += check(given)
    return findings


@register_check("structure")
def _structure(given: CheckInput) -> list[Finding]:
    gate = given.config.gate
    return [check_structure(len(given.asset.movable_joints), given.asset.metadata.get("gate"), gate.allow_static,
                            gate.min_publish_confidence)]


@register_check("budget")
def _budget(given: CheckInput) -> list[Finding]:
    return [check_hull_budget(given.asset_dir, given.name, given.config.export),
            check_decomposition(given.asset.metadata)]


@register_check("rest")
def _rest(given: CheckInput) -> list[Finding]:
    from rest2art.validators.physics import rest_finding

    v = given.config.validate
    return [rest_finding(given.asset_dir, given.name, v.rest_force_tol, v.max_penetration)]


@register_check("sweep")
def _sweep(given: CheckInput) -> list[Finding]:
    from rest2art.validators.sweep import sweep_findings

    v = given.config.validate
    return sweep_findings(given.asset_dir, given.name, v.sweep_samples, v.max_penetration)


@register_check("actuation")
def _actuation(given: CheckInput) -> list[Finding]:
    from rest2art.validators.physics import actuation_findings

    if not given.asset.movable_joints:
        return []
    v = given.config.validate
    return actuation_findings(given.asset_dir, given.name, -GRAVITY * given.up, v.actuation_seconds,
                              given.config.check.timestep, v.actuation_reach, v.actuation_margin,
                              v.actuation_min_range, given.config.check.engines)


def read_asset_folder(asset_dir: str | Path, name: str) -> ArticulatedAsset:
    """The asset with part meshes and mass properties read back from articulation.json and the
    collision hulls from NAME.urdf (input frame), ready to be changed and written again."""

    asset_dir = Path(asset_dir)
    asset = read_asset(asset_dir, load_meshes=True)
    origins = link_origins(asset)
    links = {link.get("name"): link for link in parse_xml(asset_dir / f"{name}.urdf").iter("link")}

    def xyz(el) -> np.ndarray:
        origin = el.find("origin")
        return np.zeros(3) if origin is None else np.array([float(x) for x in origin.get("xyz", "0 0 0").split()])

    for part in asset.parts:
        link = links[part.name]
        inertial = link.find("inertial")
        if part.inertial is None:  # a folder written before articulation.json held inertials
            mass, tensor = urdf_inertial(inertial)
            part.inertial = MassProperties(mass, xyz(inertial) + origins[part.name], tensor)
        part.collision = []
        for col in link.iter("collision"):
            hull = trimesh.load(asset_dir / col.find("geometry/mesh").get("filename"), force="mesh", process=False)
            hull.apply_translation(xyz(col) + origins[part.name])
            part.collision.append(hull)
    return asset


def apply_actions(asset: ArticulatedAsset, actions: list[Action], config: Config) -> list[str]:
    """Apply the policy's refinements to ``asset`` in place; returns what was done."""
    from rest2art.collision.clearance import clear_asset_hulls, clip_to_solids, shrink_hull
    from rest2art.collision.hulls import decompose, hull_signature
    from rest2art.completion.solids import part_solids
    from rest2art.pipeline import object_axes

    done = []
    for action in actions:
        if isinstance(action, ShrinkLimit):
            joint = next(j for j in asset.joints if j.name == action.joint)
            old = joint.limit[1]
            joint.limit = (joint.limit[0], float(action.upper))
            done.append(f"{joint.name}: upper limit {old:.4g} -> {joint.limit[1]:.4g}")
        elif isinstance(action, Redecompose):
            part = asset.part(action.part)
            others = np.concatenate([p.mesh.vertices for p in asset.parts if p is not part])
            scale = config.validate.redecompose_threshold_scale
            finer = dataclasses.replace(config.collision, coacd_threshold=config.collision.coacd_threshold * scale,
                                        box_pitch=config.collision.box_pitch * scale)
            solids, pieces, _ = part_solids(part.mesh, others, part.semantic, config.completion, finer.coacd_max_faces)
            axes = object_axes(asset.metadata.get("frame"))
            results = [decompose(s, finer, axes, config.export.max_hulls_per_part) for s in pieces]
            hulls, _ = clip_to_solids([h for r in results for h in r.hulls], solids, axes,
                                      config.collision.solid_box_margin, config.collision.min_hull_volume)
            record = asset.metadata.get("collision", {}).get(part.name, {})
            failures = sorted({r.failure for r in results if r.failure})
            if hull_signature(hulls) == record.get("signature"):
                done.append(f"{part.name}: decomposed again finer: the same {len(hulls)} hulls; left as it was")
                continue
            methods = ", ".join(sorted({r.method for r in results}))
            done.append(f"{part.name}: decomposed again finer ({methods}): {len(part.collision)} -> {len(hulls)} hulls"
                        + (f" ({'; '.join(failures)})" if failures else ""))
            part.collision = hulls
            record.update(signature=hull_signature(hulls), failures=failures, hulls=len(hulls))
        elif isinstance(action, Thin):
            part = asset.part(action.part)
            thinned = [shrink_hull(h, action.distance) for h in part.collision]
            kept = [h for h in thinned if h is not None]
            if kept:  # a part must keep some collision geometry
                done.append(f"{part.name}: {len(kept)} hulls thinned by {1000 * action.distance:.1f} mm"
                            + (f", {len(thinned) - len(kept)} too thin dropped" if len(kept) < len(thinned) else ""))
                part.collision = kept
            else:
                done.append(f"{part.name}: too thin to thin by {1000 * action.distance:.1f} mm; left as it was")
    if any(isinstance(a, Redecompose) for a in actions):  # new hulls bulge like the first ones did
        cleared = clear_asset_hulls(asset, config.collision)
        for k, action in enumerate(actions):
            if isinstance(action, Redecompose):
                log = cleared[action.part]
                done[k] += f"; clearance clipped {log['clipped']}, dropped {log['dropped']}"
    return done


def rewrite_folder(asset_dir: str | Path, asset: ArticulatedAsset, name: str, config: Config) -> None:
    """Write ``asset`` over ``asset_dir`` atomically, keeping its other files (config, pictures)."""
    asset_dir = Path(asset_dir)
    up = asset.up
    with atomic_folder(asset_dir, overwrite=True) as tmp:
        shutil.copytree(asset_dir, tmp, dirs_exist_ok=True,
                        ignore=lambda d, names: [n for n in names if Path(d) == asset_dir and n in ("parts", "collision")])
        write_asset(asset, tmp, name, config.export, up)


def validate_folder(asset_dir: str | Path, name: str | None = None, config: Config = Config(),
                    refine: bool = False, progress=None) -> Report:
    """Check the asset; with ``refine``, apply the policy's refinements and check again.
    Writes ``validation.json`` into the folder (``report.written`` says why it could not) and
    returns the report. A symlinked folder is refined where it leads: the link stays."""
    asset_dir = Path(asset_dir).resolve()
    name = name or asset_name(asset_dir)
    report = Report(name)
    redecomposed: set[str] = set()
    for round_ in range(config.validate.refine_rounds + 1):
        if progress:
            progress(f"checks, round {round_ + 1}")
        findings = run_checks(asset_dir, name, config)
        parents = _parents(asset_dir) if all(f.ok for f in findings if f.check == "files") else {}
        decision = decide(findings, parents, config.validate, frozenset(redecomposed))
        if decision.status != "refine" or not refine or round_ == config.validate.refine_rounds:
            report.rounds.append(Round(findings, decision))
            break
        if progress:
            progress(f"refining: {', '.join(a.kind for a in decision.actions)}")
        full = read_asset_folder(asset_dir, name)
        notes = apply_actions(full, decision.actions, config)
        full.metadata.setdefault("validation", {}).setdefault("refinements", []).extend(notes)
        redecomposed |= {a.part for a in decision.actions if isinstance(a, Redecompose)}
        report.rounds.append(Round(findings, decision.with_done(notes)))
        rewrite_folder(asset_dir, full, name, config)
    final = report.rounds[-1].decision
    if final.status == "refine":  # out of rounds (or not allowed to refine): what is left rejects it
        final = Decision("reject", final.reasons + ([Reason("policy", "refine", f"still failing after "
                         f"{config.validate.refine_rounds} refinement rounds")] if refine else []), final.actions)
    report.decision = final
    tmp = asset_dir / f".validation.json.tmp-{os.getpid()}"
    try:
        tmp.write_text(json.dumps(report.to_dict(), indent=1, default=float))
        tmp.replace(asset_dir / "validation.json")
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        report.written = f"{asset_dir / 'validation.json'}: not written ({exc.strerror})"
    return report


def _parents(asset_dir: Path) -> dict[str, str | None]:
    """Part -> parent name, or nothing when articulation.json cannot be read."""
    from rest2art.errors import InputError

    try:
        return {p.name: p.parent for p in read_asset(asset_dir).parts}
    except InputError:
        return {}
