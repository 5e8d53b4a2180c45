"""Load and gravity checks in MuJoCo, PyBullet and SAPIEN (after the static file checks).

Each engine loads the exported asset (MJCF for MuJoCo, URDF for the others, base fixed) and
runs ``gravity_seconds`` under gravity along -up: the check passes when the model loads, no
value is NaN, every joint stays inside its limits (within ``limit_tol``) and, for MuJoCo,
every warning counter stays zero. yourdfpy must parse the URDF too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rest2art.sim import run_engine
from rest2art.validators import Finding
from rest2art.validators.static_checks import check_files, check_inertia, read_asset

from rest2art.config import CheckConfig
from rest2art.export.writers import GRAVITY


def check_urdf_parses(asset_dir: Path, name: str) -> Finding:
    import yourdfpy

    path = asset_dir / f"{name}.urdf"
    try:
        robot = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
        ok = robot.validate()
        return Finding("load", "yourdfpy", bool(ok), "URDF parses" if ok else "URDF failed yourdfpy validation")
    except Exception as exc:
        return Finding("load", "yourdfpy", False, f"{path.name}: {type(exc).__name__}: {exc}")


def run_load_checks(asset_dir: str | Path, name: str, config: CheckConfig = CheckConfig()) -> list[Finding]:
    """Findings for the asset in ``asset_dir`` (files NAME.urdf / NAME.xml)."""
    asset_dir = Path(asset_dir).resolve()
    files = check_files(asset_dir, name)
    if not files.ok:  # nothing in a folder that failed the files check reaches a parser or simulator
        return [files]
    asset = read_asset(asset_dir)
    up = asset.up
    limits = {j.name: j.limit for j in asset.movable_joints}
    findings = [files, check_inertia(asset_dir, name), check_urdf_parses(asset_dir, name)]
    for engine in config.engines:
        run = run_engine(engine, asset_dir, name, -GRAVITY * up, config.gravity_seconds, config.timestep)
        if not run.loaded:
            findings.append(Finding("load", engine, False, f"{engine} could not load the asset: {run.error}"))
            continue
        findings.append(Finding("load", engine, True, "loads"))
        findings.append(gravity_finding(run, limits, config))
    return findings


def gravity_finding(run, limits: dict[str, tuple[float, float]], config: CheckConfig) -> Finding:
    """Judge one engine's gravity run."""
    traj = run.trajectory
    problems = []
    worst = {}
    if traj is not None and traj.size and not np.all(np.isfinite(traj)):
        problems.append("NaN or infinite joint values")
    elif traj is not None and traj.size:
        for k, joint in enumerate(run.joint_names):
            if joint not in limits:
                continue
            lo, hi = limits[joint]
            below = float(lo - traj[:, k].min())
            above = float(traj[:, k].max() - hi)
            worst[joint] = round(max(below, above, 0.0), 5)
            if max(below, above) > config.limit_tol:
                problems.append(f"joint '{joint}' left its limits [{lo:.3f}, {hi:.3f}] by {max(below, above):.4f}")
    if run.warnings:
        problems.append("warnings: " + ", ".join(f"{k}={v}" for k, v in run.warnings.items()))
    ok = not problems
    message = f"{config.gravity_seconds:.1f} s of gravity: " + ("joints inside limits" if ok else "; ".join(problems))
    return Finding("gravity", run.engine, ok, message, {"limit_excess": worst, "max_speed": round(run.max_speed, 4),
                                                        "warnings": run.warnings})

