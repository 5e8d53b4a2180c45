"""Physics checks beyond loading: rest contacts, and actuation in every engine that can push
(MuJoCo and PyBullet of the registered ones).

* rest: at the closed pose, without gravity, the constraint forces are ~0 (nothing starts
  interpenetrating or outside its limits);
* actuation: each movable joint is pushed toward its upper limit with a bounded generalized
  force, then back; it must reach ``reach`` of its range and come back below ``1 - reach``,
  in every engine, moving the same way.

The force is sized from the asset itself (MuJoCo's mass matrix, dry friction, damping and the
largest gravity load over the range) so that a sound joint opens in about half the time: a
heavy fridge door gets more than a light drawer, and a joint that cannot move with it is stuck.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rest2art.validators import Finding


def push_force(load: dict[str, float], seconds: float, margin: float) -> float:
    """Generalized force (N or N m) that drives one joint through its range in ~seconds / 2."""
    span = load["range"][1] - load["range"][0]
    t = 0.5 * seconds
    accelerate = load["inertia"] * 4.0 * span / t**2  # constant acceleration over half the time
    return margin * (load["friction"] + load["gravity"] + load["damping"] * 2.0 * span / t + accelerate)


def judge_actuation(trajectory: np.ndarray, limit: tuple[float, float], reach: float) -> tuple[bool, float, float]:
    """(ok, fraction of the range reached while pushing, fraction where it ended after the
    push back) for one (T,) trajectory whose first half pushes open and second half closes."""
    lo, hi = limit
    span = max(hi - lo, 1e-12)
    half = len(trajectory) // 2
    if not np.all(np.isfinite(trajectory)) or half == 0:
        return False, float("nan"), float("nan")
    opened = float((trajectory[:half].max() - lo) / span)
    closed = float((trajectory[-1] - lo) / span)
    return opened >= reach and closed <= 1.0 - reach, opened, closed


def disagreement(results: dict[str, tuple[bool, float, float]], contacts: dict[str, list[str]], reach: float) -> str:
    """Why the engines disagree on one joint: per failing engine, how far it got, and the
    contacts on the pushed part at the end of the opening push that the passing engine did not
    have (else that no contact held it: a limit, friction or the force)."""
    notes = []
    for engine, (ok, opened, closed) in results.items():
        if ok:
            continue
        others = set().union(*(contacts[e] for e, r in results.items() if r[0] and e in contacts))
        extra = [c for c in contacts.get(engine, []) if c not in others]
        what = "opened" if opened < reach else "closed"
        held = f"held by contact {', '.join(extra)}" if extra else \
            f"no contact the other engine lacks (touching: {', '.join(contacts.get(engine, [])) or 'nothing'}): " \
            "limit, friction or force"
        notes.append(f"only {engine} fails ({what} {100 * (opened if what == 'opened' else closed):.0f} %): {held}")
    return "; ".join(notes)


def rest_finding(asset_dir: str | Path, name: str, tolerance_n: float, depth_tol: float) -> Finding:
    from rest2art.sim import mujoco_engine

    try:
        force, contacts = mujoco_engine.rest_contacts(asset_dir, name)
    except Exception as exc:
        return Finding("rest", "mujoco", False, f"could not evaluate the rest pose: {type(exc).__name__}: {exc}")
    deep = [c for c in contacts if c[2] > depth_tol]
    ok = force <= tolerance_n and not deep
    message = f"constraint force {force:.3g} N at rest"
    if deep:
        worst = max(deep, key=lambda c: c[2])
        message += f"; {len(deep)} contacts deeper than {1000 * depth_tol:.1f} mm (worst {worst[0]}-{worst[1]} " \
                   f"{1000 * worst[2]:.1f} mm)"
    return Finding("rest", "mujoco", ok, message, {"force_n": force, "contacts": len(contacts), "deep": len(deep)})


def actuation_findings(asset_dir: str | Path, name: str, gravity: np.ndarray, seconds: float, timestep: float,
                       reach: float, margin: float, min_range: float = 0.001,
                       engine_names: tuple[str, ...] = ("mujoco", "pybullet")) -> list[Finding]:
    """One finding per movable joint: pushed open and shut in each of ``engine_names`` that can
    push (MuJoCo sizes the push), together with the joints it carries (a latch is turned while its
    door is pulled: a latched door does not open otherwise). A joint whose range is shorter than
    ``min_range`` (m or rad) fails without a push: it does not open."""
    from rest2art.sim import engines, mujoco_engine

    try:
        loads = mujoco_engine.joint_loads(asset_dir, name, gravity)
    except Exception as exc:
        return [Finding("actuation", "mujoco", False, f"could not size the push: {type(exc).__name__}: {exc}")]
    findings = []
    for joint, load in list(loads.items()):
        span = load["range"][1] - load["range"][0]
        if span < min_range:
            findings.append(Finding("actuation", joint, False, f"range {span:.3g} (m or rad) is shorter than "
                                    f"{min_range:g}: the joint does not open", {"range": span}))
            del loads[joint]
    if not loads:
        return findings
    forces = {joint: push_force(load, seconds, margin) for joint, load in loads.items()}
    # a joint is pushed with the joints it carries (a door with its latch turned, as a hand opens it)
    pushes = {joint: {joint: forces[joint], **{c: forces[c] for c in load["carries"] if c in forces}}
              for joint, load in loads.items()}
    runs, touches = {}, {}
    for adapter in (e for e in engines(engine_names) if e.run_actuation is not None):
        engine = adapter.name
        touches[engine] = {}
        try:
            runs[engine] = adapter.run_actuation(asset_dir, name, gravity, pushes, seconds, timestep, touches[engine])
        except Exception as exc:
            return findings + [Finding("actuation", engine, False, f"{engine} actuation failed: {type(exc).__name__}: {exc}")]
    for joint, load in loads.items():
        results = {engine: judge_actuation(runs[engine][joint], load["range"], reach) for engine in runs}
        ok = all(r[0] for r in results.values())
        directions = {engine: np.sign(runs[engine][joint][: max(2, len(runs[engine][joint]) // 4)][-1]
                                      - load["range"][0]) for engine in runs}
        same_way = len(set(directions.values())) == 1
        ok = ok and same_way
        parts = [f"{engine} opened {100 * r[1]:.0f} % and closed to {100 * r[2]:.0f} %" for engine, r in results.items()]
        if not same_way:
            parts.append("the engines moved it in different directions")
        if len({r[0] for r in results.values()}) > 1:  # one engine opens it, the other does not: say why
            parts.append(disagreement(results, {e: t.get(joint, []) for e, t in touches.items()}, reach))
        findings.append(Finding("actuation", joint, ok, f"push {forces[joint]:.3g}: " + ", ".join(parts),
                                {"force": forces[joint], **{f"{e}_ok": bool(r[0]) for e, r in results.items()},
                                 **{f"{e}_opened": r[1] for e, r in results.items()},
                                 **{f"{e}_contacts": touches[e].get(joint, []) for e in results},
                                 **{f"{e}_closed": r[2] for e, r in results.items()}}))
    return findings
