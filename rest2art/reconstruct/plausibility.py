"""The plausibility gate: is what the rules found the object, or an artefact of them?

Validation proves an asset is physically sound; it cannot tell that a cabinet whose drawers
became knobs is not the object. This stage reviews the structure before export:

* a joint whose range is (almost) empty is no joint: its part stays with the base;
* a door, drawer or lid smaller than a hand can hold is no panel, and a part as large as the
  whole object in every direction is the carcass: both stay with the base;
* knobs stacked in several rows at the same sideways positions are the pulls of drawers the
  rules missed, not controls: they stay with the base (stove knobs sit in one row);
* an object left with no movable part is *static*: it is not published as an articulated
  asset unless the user asks for it.

Every joint gets a confidence in [0, 1] from the evidence behind it (how its side was chosen,
how freely it opens), recorded with that evidence. All coordinates canonical (+z up, -y front).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rest2art.config import GateConfig


@dataclass(frozen=True)
class GateFinding:
    """One structural finding: what was wrong, about which part, and what the gate did."""

    kind: str
    """zero_travel, tiny_panel, carcass_sized, pull_knobs or static."""
    parts: tuple[str, ...]
    message: str
    action: str
    """demoted (the parts stay with the base) or refused (the object is static)."""

    def to_dict(self) -> dict:
        return {"kind": self.kind, "parts": list(self.parts), "message": self.message, "action": self.action}


@dataclass
class GateResult:
    """The gate's verdict on one object."""

    decision: str
    """articulated or static."""
    demoted: list[str] = field(default_factory=list)
    """Parts the gate returned to the base."""
    findings: list[GateFinding] = field(default_factory=list)
    confidence: dict[str, float] = field(default_factory=dict)
    """Per movable part name, the confidence of its joint in [0, 1]."""

    def to_dict(self) -> dict:
        return {"decision": self.decision, "demoted": list(self.demoted),
                "findings": [f.to_dict() for f in self.findings],
                "confidence": {k: round(v, 3) for k, v in self.confidence.items()}}


def zero_travel(kind: str, upper: float, config: GateConfig) -> bool:
    """Whether a joint of ``kind`` with range (0, ``upper``) (m or rad) barely moves."""
    return upper < (config.min_travel if kind == "prismatic" else np.radians(config.min_angle_deg))


def tiny_panel(extents: np.ndarray, outward: np.ndarray, config: GateConfig) -> bool:
    """Whether a panel with box ``extents`` (3,) m, facing ``outward`` (3,), is smaller across
    than ``min_panel_size`` in either in-plane direction."""
    axis = int(np.argmax(np.abs(outward)))
    return bool(np.delete(extents, axis).min() < config.min_panel_size)


def pull_knob_groups(centres: np.ndarray, outwards: np.ndarray, config: GateConfig) -> list[np.ndarray]:
    """Indices of front knobs laid out like drawer pulls: columns of knobs at one sideways
    position spanning ``min_pull_rows`` or more distinct heights, each at least
    ``min_pull_spacing`` apart.

    ``centres`` (K, 3) knob centres, ``outwards`` (K, 3) their axes. Knobs facing up (a
    cooktop) never count; a single row (a stove's control panel) never counts."""
    front = np.flatnonzero(np.abs(outwards[:, 2]) < 0.5)
    if len(front) < config.min_pull_rows:
        return []
    x, z = centres[front, 0], centres[front, 2]
    rows = _clusters(z, config.pull_align_tol)
    if rows.max() + 1 < config.min_pull_rows:
        return []
    columns = _clusters(x, config.pull_align_tol)
    groups = []
    for c in np.unique(columns):
        members = front[columns == c]
        heights = np.sort([z[rows == r].mean() for r in np.unique(rows[columns == c])])
        # drawers are stacked a hand's height apart; a keypad's buttons are not
        if len(heights) >= config.min_pull_rows and np.diff(heights).min() >= config.min_pull_spacing:
            groups.append(members)
    return groups


def _clusters(values: np.ndarray, tol: float) -> np.ndarray:
    """(N,) cluster ids of 1-D ``values``: sorted neighbours closer than ``tol`` share one."""
    order = np.argsort(values)
    ids = np.zeros(len(values), int)
    ids[order] = np.concatenate([[0], np.cumsum(np.diff(values[order]) > tol)])
    return ids


def joint_confidence(evidence: dict, kind: str, upper: float, cap: float, config: GateConfig) -> float:
    """Confidence in [0, 1] of one joint from its rule's ``evidence`` and how far it opens
    (``upper`` of ``cap``, rad or m).

    A side chosen by a handle or a lid's back edge is evidence; a side chosen for want of one
    (``outer side (no handle)``) is a guess; a joint that stops early in its sweep is doubtful."""
    rule = str(evidence.get("rule", ""))
    base = config.rule_confidence.get(rule.split(":")[0].split(",")[0].strip(), config.default_confidence)
    if "no handle" in rule:
        base = config.rule_confidence.get("guess", base)
    share = float(np.clip(upper / cap, 0.0, 1.0)) if cap > 0 else 1.0
    return float(np.clip(base * (config.open_weight * share + 1.0 - config.open_weight), 0.0, 1.0))


def review(parts: list, joints: dict, extents: dict[str, np.ndarray], caps: dict[str, float],
           config: GateConfig) -> GateResult:
    """Review the structure of ``parts`` (PartEstimate, the base first) and their ``joints``
    (part name -> JointEstimate); ``extents`` maps part names to their (3,) box size (m), the
    whole object's under ``base``,
    ``caps`` to the largest range their joint could have (rad or m). Returns the verdict; the
    caller demotes the parts it names."""
    result = GateResult("articulated")
    demoted: set[str] = set()
    movable = [p for p in parts if p.semantic != "base"]
    for part in movable:
        joint = joints.get(part.name)
        if joint is None:
            continue
        if part.semantic != "knob" and zero_travel(joint.type, joint.upper, config):
            result.findings.append(GateFinding("zero_travel", (part.name,),
                                               f"{part.name}: its {joint.type} joint opens by only {joint.upper:.4g}",
                                               "demoted"))
            demoted.add(part.name)
    knobs = [p for p in movable if p.semantic == "knob" and p.name in joints]
    if knobs:
        centres = np.array([joints[p.name].origin for p in knobs])
        outwards = np.array([joints[p.name].axis for p in knobs])
        for group in pull_knob_groups(centres, outwards, config):
            names = tuple(knobs[k].name for k in group)
            result.findings.append(GateFinding(
                "pull_knobs", names, f"{len(names)} knobs stacked in one column at {len(group)} heights look like "
                                     "the pulls of drawers that were not found, not controls", "demoted"))
            demoted.update(names)
    whole = extents.get("base")
    for part in movable:
        size = extents.get(part.name)
        if whole is not None and size is not None and part.name not in demoted \
                and np.all(size >= config.max_part_share * whole):
            result.findings.append(GateFinding("carcass_sized", (part.name,),
                                               f"{part.name}: a {part.semantic} as large as the whole object "
                                               "is the carcass, not a part of it", "demoted"))
            demoted.add(part.name)
    for part in movable:
        if part.semantic in ("door", "drawer", "lid") and part.name not in demoted:
            size = extents.get(part.name)
            if size is not None and tiny_panel(np.asarray(size), part.outward, config):
                result.findings.append(GateFinding("tiny_panel", (part.name,),
                                                   f"{part.name}: a {part.semantic} only "
                                                   f"{np.round(np.asarray(size) * 100, 1).tolist()} cm across",
                                                   "demoted"))
                demoted.add(part.name)
    result.demoted = sorted(demoted)
    for part in movable:
        if part.name in demoted or part.name not in joints:
            continue
        j = joints[part.name]
        result.confidence[part.name] = joint_confidence(j.evidence, j.type, j.upper, caps.get(part.name, 0.0), config)
    if not result.confidence:
        result.decision = "static"
        result.findings.append(GateFinding("static", (), "no movable part was found",
                                           "allowed (--allow-static)" if config.allow_static else "refused"))
    return result
