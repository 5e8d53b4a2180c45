"""One policy turns findings into a decision: publish, refine (with actions) or reject.

Refinable failures and their actions:
* a joint whose sweep penetrates after ``min_kept_range`` of its range: shrink its upper limit
  to the last collision-free sample (all joints together: shrink them all to the common one);
* parts that penetrate at rest: decompose the parent of the pair again with finer hulls
  (a carcass wrapped in one solid hull holds its drawers inside it) unless it has many hulls
  already (finer hulls will not fix a misplaced boundary) or its decomposition failed (a
  timeout is not repeated: it would time out again); when that was done and a
  shallow penetration (<= ``max_thin``) is left, thin the child's hulls by that depth;
* a joint that penetrates shallowly from the start of its range: thin its child's hulls.

Everything else (files, inertia, loading, gravity, actuation, a joint that collides almost at
once, a rest penetration that survives re-decomposition) rejects the asset with its reasons.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace
from typing import ClassVar

from rest2art.config import ValidateConfig
from rest2art.validators import Finding


@dataclass(frozen=True)
class Reason:
    """Why an asset is not published as it is: a failed finding, without its data."""

    check: str
    subject: str
    message: str

    @classmethod
    def of(cls, finding: Finding) -> "Reason":
        return cls(finding.check, finding.subject, finding.message)

    def __str__(self) -> str:
        return f"{self.check} {self.subject}: {self.message}"


@dataclass(frozen=True, kw_only=True)
class Action:
    """A refinement the policy asks for; ``done`` says what applying it did (empty until then)."""

    kind: ClassVar[str]
    why: str
    """The message of the finding it answers."""
    done: str = ""

    def to_dict(self) -> dict:
        data = {"kind": self.kind, **asdict(self)}
        if not self.done:
            del data["done"]
        return data


@dataclass(frozen=True, kw_only=True)
class ShrinkLimit(Action):
    """Lower a joint's upper limit to its last collision-free sample."""

    kind: ClassVar[str] = "shrink_limit"
    joint: str
    upper: float
    """The new upper limit, m or rad."""


@dataclass(frozen=True, kw_only=True)
class Redecompose(Action):
    """Decompose a part's collision again with finer hulls."""

    kind: ClassVar[str] = "redecompose"
    part: str


@dataclass(frozen=True, kw_only=True)
class Thin(Action):
    """Shrink every hull of a part by a distance (m)."""

    kind: ClassVar[str] = "thin"
    part: str
    distance: float


@dataclass
class Decision:
    status: str
    """publish, refine or reject."""
    reasons: list[Reason] = field(default_factory=list)
    """The failed findings."""
    actions: list[Action] = field(default_factory=list)
    """Refinements to apply before checking again (status refine only)."""

    def to_dict(self) -> dict:
        return {"status": self.status, "reasons": [asdict(r) for r in self.reasons],
                "actions": [a.to_dict() for a in self.actions]}

    def with_done(self, notes: list[str]) -> "Decision":
        """The same decision, each action carrying what applying it did."""
        return replace(self, actions=[replace(a, done=n) for a, n in zip(self.actions, notes)])


def _first_pair(f: Finding) -> list[str]:
    """The part pair of the first penetrating sample of a sweep finding."""
    for sample in f.data.get("samples", []):
        if sample.get("depth_mm", 0.0) > 0 and sample.get("pair"):
            return sample["pair"]
    return []


def decide(findings: list[Finding], parents: dict[str, str | None], config: ValidateConfig = ValidateConfig(),
           redecomposed: frozenset[str] = frozenset()) -> Decision:
    """The decision for one round of findings.

    ``parents`` maps each part to its parent part (None for the root); ``redecomposed`` names
    parts already decomposed again in an earlier round (not tried twice)."""
    failed = [f for f in findings if not f.ok]
    if not failed:
        return Decision("publish")
    actions, fatal = [], []
    touched = set()  # parts whose hulls change this round: failures involving them wait a round

    def thin(part: str, depth_mm: float, why: str) -> None:
        actions.append(Thin(part=part, distance=depth_mm / 1000.0 + config.thin_margin, why=why))
        touched.add(part)

    hulls = next((f.data["hulls"] for f in findings if f.check == "collision" and f.subject == "hulls"), {})
    failed_decomposition = next((f.data.get("failures", {}) for f in findings
                                 if f.check == "collision" and f.subject == "decomposition"), {})
    rest = next((f for f in failed if f.check == "sweep" and f.subject == "rest"), None)
    if rest is not None:
        pair = _first_pair(rest)
        a, b = pair if pair else ("", "")
        parent, child = (a, b) if parents.get(b) == a else (b, a) if parents.get(a) == b else (a, b)
        if not pair:
            fatal.append(rest)
        elif (parent not in redecomposed and parent not in failed_decomposition
              and hulls.get(parent, 0) < config.redecompose_max_hulls):
            actions.append(Redecompose(part=parent, why=rest.message))
            touched.add(parent)
        elif rest.data["max_depth_mm"] / 1000.0 <= config.max_thin:
            thin(child, rest.data["max_depth_mm"], rest.message)
        else:
            fatal.append(rest)
    joint_failures = [f for f in failed if f.check == "sweep" and "last_free_fraction" in f.data]
    for f in joint_failures:
        if touched & set(_first_pair(f)):
            continue  # it may only be leaving hulls that are about to change: checked again next round
        free = f.data["last_free_fraction"]
        lo, hi = f.data["limit"]
        if free >= config.min_kept_range:
            actions.append(ShrinkLimit(joint=f.subject, upper=lo + free * (hi - lo), why=f.message))
        elif f.data["max_depth_mm"] / 1000.0 <= config.max_thin and f.data["child"] not in touched:
            thin(f.data["child"], f.data["max_depth_mm"], f.message)
        else:
            fatal.append(f)
    for f in failed:
        if f is rest or f in joint_failures:
            continue
        if f.check == "sweep" and f.subject == "all":
            if joint_failures or touched:
                continue  # the per-joint sweeps are settled first; checked again next round
            free = f.data.get("all_free_fraction", 0.0)
            clashing = set(_first_pair(f))  # only the joints that move the clashing parts
            joints = {j: lim for j, lim in f.data["limits"].items() if f.data["children"].get(j) in clashing}
            if free >= config.min_kept_range and joints:
                actions += [ShrinkLimit(joint=joint, upper=lo + free * (hi - lo), why=f.message)
                            for joint, (lo, hi) in joints.items()]
                continue
        fatal.append(f)
    if fatal or not actions:
        return Decision("reject", [Reason.of(f) for f in (fatal or failed)])
    return Decision("refine", [Reason.of(f) for f in failed], actions)
