"""Checks on the exported files themselves, before any simulator runs.

An asset folder is untrusted input (it may come from anywhere), so nothing in it reaches a
simulator before these checks pass:

* files: NAME.urdf and NAME.xml parse as XML with DTDs, entities and external references
  refused (defusedxml); every file they reference (meshes, textures, height fields, skins,
  MJCF includes, followed recursively) and every file articulation.json references is a
  relative path that stays inside the asset folder and exists, no symlink in the folder leads
  out of it, and every number they hold is finite and plausible (an asset must be movable as
  one folder, and a NaN axis makes MuJoCo write a log beside whoever runs it);
* inertia: every URDF link has a positive mass and an inertia tensor that is positive definite
  and satisfies the triangle inequality (I1 + I2 >= I3), which MuJoCo and PhysX require.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np

from rest2art.errors import InputError
from rest2art.validators import Finding

MAX_INCLUDE_DEPTH = 8
"""MJCF includes nested deeper than this are refused (a cycle or a bomb)."""
MAX_NUMBER = 1e6
"""A number in an asset's XML larger than this (m, kg, rad, or a solver iteration count) is
refused: no real object needs it, and a simulator may hang or allocate without bound on it."""
MJCF_DIRS = {"mesh": ("meshdir", "assetdir"), "skin": ("meshdir", "assetdir"),
             "texture": ("texturedir", "assetdir"), "hfield": ("assetdir",)}
"""Which ``<compiler>`` folder attribute an MJCF element's ``file`` is relative to."""
NAME_ATTRIBUTES = {"name", "class", "childclass", "joint", "body", "site", "geom", "mesh", "material",
                   "texture", "link", "type", "filename", "file", "version", "xmlns"}
"""Attributes holding names or paths, not numbers (never checked as numbers)."""


def parse_xml(path: str | Path) -> ET.Element:
    """The root element of an XML file an asset folder brings, parsed with DTDs, entity
    declarations and external references refused. Raises :class:`InputError` naming the file
    when it is missing, malformed or hostile."""
    import defusedxml.ElementTree as safe_et
    from defusedxml import DefusedXmlException

    path = Path(path)
    try:
        return safe_et.parse(str(path), forbid_dtd=True).getroot()
    except DefusedXmlException as exc:
        raise InputError(f"{path}: refused: {type(exc).__name__} ({exc}); an asset's XML may not declare "
                         "a DTD or entities") from None
    except ET.ParseError as exc:
        raise InputError(f"{path}: malformed XML ({exc})") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror})") from None


def inside(folder: Path, ref: str) -> Path | None:
    """The file ``ref`` (relative to ``folder``, which must be resolved) names, with every
    symlink followed; None when it is absolute, a URL or lands outside ``folder``."""
    if not ref or "://" in ref or Path(ref).is_absolute():
        return None
    target = _resolved(folder / ref)
    return target if target is not None and target.is_relative_to(folder) else None


def _resolved(path: Path) -> Path | None:
    """``path`` with every symlink followed; None for a symlink loop."""
    try:
        return path.resolve()
    except (RuntimeError, OSError):
        return None


def _number_problems(root: ET.Element, source: str) -> list[str]:
    """Non-finite or implausibly large numbers in any attribute of ``root``'s tree."""
    problems = []
    for el in root.iter():
        for key, value in el.attrib.items():
            if key in NAME_ATTRIBUTES:
                continue
            for token in value.split():
                try:
                    number = float(token)
                except ValueError:
                    continue
                if not math.isfinite(number) or abs(number) > MAX_NUMBER:
                    label = f"<{el.tag}{' name=' + repr(el.get('name')) if el.get('name') else ''}>"
                    problems.append(f"{source}: {label} {key}='{value[:40]}' holds {token}, not a finite "
                                    f"number below {MAX_NUMBER:g}")
                    break
            if len(problems) > 5:
                return problems
    return problems


def _mjcf_refs(folder: Path, path: Path, depth: int, seen: set[Path],
               dirs: dict[str, str] | None = None) -> tuple[list[tuple[str, str]], list[str]]:
    """(source, reference) pairs of an MJCF file and the files it includes, and its problems;
    an included file uses the including file's compiler folders unless it sets its own."""
    problems: list[str] = []
    if depth > MAX_INCLUDE_DEPTH:
        return [], [f"{path.name}: includes nest deeper than {MAX_INCLUDE_DEPTH}"]
    root = parse_xml(path)
    problems += _number_problems(root, path.name)
    refs = []
    compiler = root.find("compiler")
    dirs = dict(dirs or {"meshdir": "", "texturedir": "", "assetdir": ""})
    if compiler is not None:
        dirs.update({k: compiler.get(k) for k in dirs if compiler.get(k) is not None})
    for el in root.iter():
        for key, value in el.attrib.items():
            if not key.startswith("file"):
                continue
            base = next((dirs[d] for d in MJCF_DIRS.get(el.tag, ()) if dirs[d]), "")
            ref = value if el.tag == "include" else str(Path(base) / value) if base else value
            refs.append((path.name, ref))
            if el.tag == "include":
                target = inside(folder, ref)
                if target is None or not target.is_file():
                    continue
                if target in seen:
                    problems.append(f"{path.name}: include '{ref}' is included twice (a cycle)")
                    continue
                seen.add(target)
                sub_refs, sub_problems = _mjcf_refs(folder, target, depth + 1, seen, dirs)
                refs += sub_refs
                problems += sub_problems
    return refs, problems


def _urdf_refs(urdf: Path) -> tuple[list[tuple[str, str]], list[str]]:
    root = parse_xml(urdf)
    refs = [(urdf.name, el.get("filename", "")) for el in root.iter() if "filename" in el.attrib]
    return refs, _number_problems(root, urdf.name)


def _json_refs(asset_dir: Path) -> list[tuple[str, str]]:
    path = asset_dir / "articulation.json"
    data = read_json_object(path)
    refs = [("articulation.json", p["mesh"]) for p in data.get("parts", []) if isinstance(p, dict) and p.get("mesh")]
    if data.get("face_part"):
        refs.append(("articulation.json", str(data["face_part"])))
    return refs


def read_json_object(path: str | Path) -> dict:
    """A JSON file that must hold an object; InputError naming the file otherwise."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f"{path}: not found") from None
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        raise InputError(f"{path}: not valid JSON ({str(exc)[:120]})") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror})") from None
    if not isinstance(data, dict):
        raise InputError(f"{path}: holds a JSON {type(data).__name__}, expected an object")
    return data


def read_asset(asset_dir: str | Path, load_meshes: bool = False):
    """The folder's ArticulatedAsset; every malformed articulation.json (not an object, keys
    missing, a non-finite axis, origin or limit) raises :class:`InputError` naming it. Load
    meshes only after :func:`check_files` passed: their paths come from the file."""
    from rest2art.asset import read_articulation

    path = Path(asset_dir) / "articulation.json"
    read_json_object(path)
    try:
        asset = read_articulation(asset_dir, load_meshes)
    except InputError:
        raise
    except KeyError as exc:
        raise InputError(f"{path}: missing key {exc}") from None
    except (TypeError, ValueError, AttributeError, IndexError) as exc:
        raise InputError(f"{path}: malformed ({type(exc).__name__}: {str(exc)[:120]})") from None
    for joint in asset.joints:
        values = np.concatenate([joint.axis, joint.origin, np.asarray(joint.limit, float)])
        if not np.all(np.isfinite(values)):
            raise InputError(f"{path}: joint '{joint.name}' has a non-finite axis, origin or limit")
    return asset


def outside_links(asset_dir: Path) -> list[str]:
    """Symlinks anywhere in ``asset_dir`` (resolved) whose target lies outside it or does not
    exist, as folder-relative names; the walk never follows a link."""
    found = []
    for top, dirs, files in os.walk(asset_dir, followlinks=False):
        for entry in dirs + files:
            path = Path(top) / entry
            if path.is_symlink():
                target = _resolved(path)
                if target is None or not target.is_relative_to(asset_dir) or not target.exists():
                    found.append(str(path.relative_to(asset_dir)))
    return found


def file_problems(asset_dir: str | Path, name: str) -> tuple[int, list[str]]:
    """(number of references, problems) of the asset folder's files; see the module docstring.
    Raises :class:`InputError` naming the file when an XML or JSON file cannot be parsed."""
    asset_dir = Path(asset_dir).resolve()
    problems = [f"symlink '{link}' leads out of the asset folder or nowhere" for link in outside_links(asset_dir)]
    refs: list[tuple[str, str]] = []
    urdf, mjcf = asset_dir / f"{name}.urdf", asset_dir / f"{name}.xml"
    for path, reader in ((urdf, _urdf_refs), (mjcf, lambda p: _mjcf_refs(asset_dir, p, 0, {p.resolve()}))):
        if path.is_symlink() and inside(asset_dir, path.name) is None:
            continue  # reported as a symlink that leaves the folder; never opened
        if path.is_file():
            found, bad = reader(path)
            refs += found
            problems += bad
    mesh_refs = len(refs)
    if (asset_dir / "articulation.json").is_file() and inside(asset_dir, "articulation.json") is not None:
        refs += _json_refs(asset_dir)
        read_asset(asset_dir)
    for source, ref in refs:
        if not ref or "://" in ref or Path(ref).is_absolute():
            problems.append(f"{source}: path '{ref}' is absolute or a URL")
            continue
        target = inside(asset_dir, ref)
        if target is None:
            problems.append(f"{source}: path '{ref}' points outside the asset folder")
        elif not target.is_file():
            problems.append(f"{source}: '{ref}' does not exist")
    if not mesh_refs:
        problems.append(f"no meshes referenced by {name}.urdf / {name}.xml")
    return len(refs), problems


def check_files(asset_dir: str | Path, name: str) -> Finding:
    """The files finding (see the module docstring); a file that cannot be parsed fails it."""
    try:
        count, problems = file_problems(asset_dir, name)
    except InputError as exc:
        count, problems = 0, [str(exc)]
    message = f"{count} file references, all inside the folder" if not problems else "; ".join(problems[:8])
    return Finding("files", "asset folder", not problems, message, {"references": count, "problems": problems[:50]})


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
    for link in parse_xml(urdf).iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            problems.append(f"link '{link.get('name')}': no inertial")
            continue
        try:
            mass, tensor = urdf_inertial(inertial)
        except (AttributeError, TypeError, ValueError):
            problems.append(f"link '{link.get('name')}': inertial has no readable mass or inertia")
            continue
        problems += [f"link '{link.get('name')}': {p}" for p in inertia_problems(mass, tensor, min_mass, min_inertia)]
    return Finding("inertia", "links", not problems, "every link has valid mass and inertia" if not problems
                   else "; ".join(problems))


def check_structure(movable_joints: int, gate: dict | None, allow_static: bool,
                    min_confidence: float = 0.0) -> Finding:
    """The plausibility gate's verdict as a finding: an asset with no movable joint is static
    and fails unless ``allow_static``; a joint whose recorded confidence is below
    ``min_confidence`` (a hinge side guessed for a door that then barely opens) fails too.
    ``gate`` (articulation metadata, may be None) adds what the gate demoted and why."""
    data = {"movable_joints": movable_joints, "gate": gate or {}}
    notes = [f["message"] for f in (gate or {}).get("findings", []) if f.get("kind") != "static"]
    suffix = f" (gate: {'; '.join(notes)})" if notes else ""
    if movable_joints == 0 and not allow_static:
        return Finding("structure", "gate", False,
                       "static: no movable part found; not published as an articulated asset "
                       "(pass --allow-static to publish it as a rigid one)" + suffix, data)
    doubtful = {k: v for k, v in (gate or {}).get("confidence", {}).items() if v < min_confidence}
    if doubtful:
        listed = ", ".join(f"{k} {v:.2f}" for k, v in sorted(doubtful.items()))
        return Finding("structure", "gate", False,
                       f"joints too doubtful to publish (confidence below {min_confidence:g}): {listed}" + suffix, data)
    what = "static, allowed" if movable_joints == 0 else f"{movable_joints} movable joints"
    return Finding("structure", "gate", True, what + suffix, data)
