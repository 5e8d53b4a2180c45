"""Checks on the exported files themselves, before any simulator runs.

* files: every mesh referenced by the URDF and the MJCF is a relative path that stays inside
  the asset folder and exists (an asset must be movable as one folder);
* inertia: every URDF link has a positive mass and an inertia tensor that is positive definite
  and satisfies the triangle inequality (I1 + I2 >= I3), which MuJoCo and PhysX require.
"""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np

from rest2art.validators import Finding


def _mesh_refs(asset_dir: Path, name: str) -> list[tuple[str, str]]:
    """(source file, referenced path) for every mesh in NAME.urdf and NAME.xml."""
    refs = []
    urdf = asset_dir / f"{name}.urdf"
    if urdf.is_file():
        refs += [(urdf.name, m.get("filename", "")) for m in ET.parse(urdf).getroot().iter("mesh")]
    mjcf = asset_dir / f"{name}.xml"
    if mjcf.is_file():
        root = ET.parse(mjcf).getroot()
        compiler = root.find("compiler")
        meshdir = compiler.get("meshdir", "") if compiler is not None else ""
        refs += [(mjcf.name, str(Path(meshdir) / m.get("file", ""))) for m in root.iter("mesh") if m.get("file")]
    return refs


def check_files(asset_dir: str | Path, name: str) -> Finding:
    asset_dir = Path(asset_dir).resolve()
    problems = []
    refs = _mesh_refs(asset_dir, name)
    for source, ref in refs:
        path = Path(ref)
        if path.is_absolute():
            problems.append(f"{source}: mesh path '{ref}' is absolute")
            continue
        target = (asset_dir / path).resolve()
        if not target.is_relative_to(asset_dir):
            problems.append(f"{source}: mesh path '{ref}' points outside the asset folder")
        elif not target.is_file():
            problems.append(f"{source}: mesh '{ref}' does not exist")
    if not refs:
        problems.append(f"no meshes referenced by {name}.urdf / {name}.xml")
    message = f"{len(refs)} mesh references, all inside the folder" if not problems else "; ".join(problems)
    return Finding("files", "asset folder", not problems, message, {"references": len(refs)})


def inertia_problems(mass: float, tensor: np.ndarray, min_mass: float, min_inertia: float) -> list[str]:
    """What is physically wrong with a rigid body's mass and (3, 3) inertia, if anything."""
    problems = []
    if not np.isfinite(mass) or mass < min_mass:
        problems.append(f"mass {mass:g} kg is below {min_mass:g}")
    if not np.all(np.isfinite(tensor)):
        return problems + ["inertia is not finite"]
    principal = np.sort(np.linalg.eigvalsh((tensor + tensor.T) / 2))
    if principal[0] < min_inertia:
        problems.append(f"smallest principal inertia {principal[0]:.3g} is below {min_inertia:g}")
    elif principal[0] + principal[1] < principal[2] * (1 - 1e-6):
        problems.append("principal inertias violate I1 + I2 >= I3")
    return problems


def urdf_inertial(inertial: ET.Element) -> tuple[float, np.ndarray]:
    """(mass kg, (3, 3) inertia tensor) of a URDF ``<inertial>`` element."""
    mass = float(inertial.find("mass").get("value"))
    i = {k: float(inertial.find("inertia").get(k, 0.0)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    return mass, np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]])


def check_inertia(asset_dir: str | Path, name: str, min_mass: float = 1e-3, min_inertia: float = 1e-9) -> Finding:
    urdf = Path(asset_dir) / f"{name}.urdf"
    problems = []
    for link in ET.parse(urdf).getroot().iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            problems.append(f"link '{link.get('name')}': no inertial")
            continue
        mass, tensor = urdf_inertial(inertial)
        problems += [f"link '{link.get('name')}': {p}" for p in inertia_problems(mass, tensor, min_mass, min_inertia)]
    return Finding("inertia", "links", not problems, "every link has valid mass and inertia" if not problems
                   else "; ".join(problems))


def check_structure(movable_joints: int, gate: dict | None, allow_static: bool) -> Finding:
    """The plausibility gate's verdict as a finding: an asset with no movable joint is static
    and fails unless ``allow_static``; ``gate`` (articulation metadata, may be None) adds what
    the gate demoted and why."""
    data = {"movable_joints": movable_joints, "gate": gate or {}}
    notes = [f["message"] for f in (gate or {}).get("findings", []) if f.get("kind") != "static"]
    suffix = f" (gate: {'; '.join(notes)})" if notes else ""
    if movable_joints == 0 and not allow_static:
        return Finding("structure", "gate", False,
                       "static: no movable part found; not published as an articulated asset "
                       "(pass --allow-static to publish it as a rigid one)" + suffix, data)
    what = "static, allowed" if movable_joints == 0 else f"{movable_joints} movable joints"
    return Finding("structure", "gate", True, what + suffix, data)
