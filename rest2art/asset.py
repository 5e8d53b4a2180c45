"""The central type: an articulated asset (parts, joints, metadata) and its JSON contract.

``articulation.json`` (format ``rest2art/1``)::

    {"format": "rest2art/1", "units": "m", "frame": "input",
     "parts":  [{"name": "base", "semantic": "base", "parent": null, "mesh": "parts/base.obj"}],
     "joints": [{"name": "drawer_0_joint", "type": "prismatic", "parent": "base",
                 "child": "drawer_0", "axis": [0, -1, 0], "origin": [0.1, -0.2, 0.4],
                 "limit": [0.0, 0.3]}],
     "face_part": "face_part.npy"}

Coordinates are in the input mesh's frame and units. Joint value 0 is the closed state,
positive values open, limits are ``[0, upper]`` (radians or metres).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from rest2art.errors import InputError
from rest2art.geometry.basics import joint_transform

FORMAT = "rest2art/1"
JOINT_TYPES = ("revolute", "prismatic", "fixed")


def numbered_names(kinds: list[str]) -> list[str]:
    """``kind_k`` per entry, k counting up per kind in order: [door, drawer, door] ->
    [door_0, drawer_0, door_1]."""
    counts: dict[str, int] = {}
    names = []
    for kind in kinds:
        k = counts.get(kind, 0)
        counts[kind] = k + 1
        names.append(f"{kind}_{k}")
    return names


@dataclass
class MassProperties:
    """Rigid-body properties in the frame the meshes are in."""

    mass: float
    """kg."""
    com: np.ndarray
    """(3,) centre of mass, m."""
    inertia: np.ndarray
    """(3, 3) inertia tensor about the centre of mass, kg m^2."""
    notes: list[str] = field(default_factory=list)


@dataclass
class Part:
    """One rigid part."""

    name: str
    """Unique name, used for links, bodies and mesh files."""
    semantic: str
    """Class: base, door, drawer, lid, knob, ..."""
    parent: str | None
    """Name of the parent part; None for the root (the base)."""
    mesh: trimesh.Trimesh | None = None
    """Visual mesh in the input frame (may be None when only the contract was read)."""
    mesh_path: str | None = None
    """Path of the visual mesh relative to the asset folder."""
    collision: list[trimesh.Trimesh] = field(default_factory=list)
    """Convex collision pieces in the input frame."""
    inertial: MassProperties | None = None
    """Mass, centre of mass and inertia (input frame) once completion has run."""


@dataclass
class Joint:
    """A joint between a parent and a child part, in the input frame."""

    name: str
    type: str
    """revolute, prismatic or fixed."""
    parent: str
    child: str
    axis: np.ndarray
    """(3,) unit vector; positive motion about/along it opens the part."""
    origin: np.ndarray
    """(3,) a point on the axis (revolute) or the child's reference point (prismatic), m."""
    limit: tuple[float, float] = (0.0, 0.0)
    """(0, upper) in rad or m."""

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise ValueError(
                f"joint '{self.name}': type '{self.type}' is not one of {', '.join(JOINT_TYPES)}"
            )
        self.axis = np.asarray(self.axis, dtype=float).reshape(3)
        self.origin = np.asarray(self.origin, dtype=float).reshape(3)
        norm = np.linalg.norm(self.axis)
        if self.type != "fixed":
            if not np.isfinite(norm) or norm < 1e-9:
                raise ValueError(f"joint '{self.name}': axis {self.axis.tolist()} has no direction")
            self.axis = self.axis / norm
        self.limit = (float(self.limit[0]), float(self.limit[1]))

    def transform(self, value: float) -> np.ndarray:
        """(4, 4) motion of the child, in the input frame, at joint value ``value``."""
        return joint_transform(self.type, self.axis, self.origin, value)


@dataclass
class ArticulatedAsset:
    """Parts, joints and metadata of one object; what every stage passes on."""

    parts: list[Part]
    joints: list[Joint]
    face_part: np.ndarray | None = None
    """(F,) int32, one entry per input face (as loaded), index into ``parts``."""
    metadata: dict[str, Any] = field(default_factory=dict)

    def part(self, name: str) -> Part:
        """The part called ``name``."""
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(
            f"part '{name}' does not exist. Available parts: {', '.join(p.name for p in self.parts)}"
        )

    def part_index(self, name: str) -> int:
        return [p.name for p in self.parts].index(name)

    @property
    def up(self) -> np.ndarray:
        """(3,) the object's up direction in the input frame, from its canonical frame (+z when
        the asset has none)."""
        return np.asarray(self.metadata.get("frame", {}).get("up", (0.0, 0.0, 1.0)), float)

    @property
    def front(self) -> np.ndarray:
        """(3,) the direction the object's front faces in the input frame (-y when unknown)."""
        return np.asarray(self.metadata.get("frame", {}).get("front", (0.0, -1.0, 0.0)), float)

    @property
    def movable_joints(self) -> list[Joint]:
        return [j for j in self.joints if j.type != "fixed"]

    def joint_for(self, child: str) -> Joint | None:
        """The joint whose child is ``child`` (None for the root)."""
        for j in self.joints:
            if j.child == child:
                return j
        return None

    def part_poses(self, values: dict[str, float] | None = None) -> dict[str, np.ndarray]:
        """(4, 4) pose of every part (input frame) with joints at ``values`` (by joint name,
        others 0): a part moves with its parent's pose composed with its own joint's motion."""
        values = values or {}
        poses: dict[str, np.ndarray] = {}

        def pose(name: str) -> np.ndarray:
            if name not in poses:
                joint = self.joint_for(name)
                parent = self.part(name).parent
                local = np.eye(4) if joint is None else joint.transform(values.get(joint.name, 0.0))
                poses[name] = local if parent is None else pose(parent) @ local
            return poses[name]

        for part in self.parts:
            pose(part.name)
        return poses

    def validate(self) -> None:
        """Raise ValueError when names, parents or the tree are inconsistent."""
        names = [p.name for p in self.parts]
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate part names: {names}")
        roots = [p.name for p in self.parts if p.parent is None]
        if len(roots) != 1:
            raise ValueError(f"expected exactly one root part, got {roots}")
        parents = {p.name: p.parent for p in self.parts}
        for name in names:
            seen, at = {name}, parents[name]
            while at is not None:
                if at in seen:
                    raise ValueError(f"part '{name}': its parents form a cycle through '{at}'")
                if at not in parents:
                    raise ValueError(f"part '{name}': parent '{at}' does not exist. Available parts: {', '.join(names)}")
                seen.add(at)
                at = parents[at]
        for j in self.joints:
            for end in (j.parent, j.child):
                if end not in names:
                    raise ValueError(
                        f"joint '{j.name}' refers to part '{end}'. Available parts: {', '.join(names)}"
                    )
            if self.part(j.child).parent != j.parent:
                raise ValueError(f"joint '{j.name}': child '{j.child}' has another parent")
            if not (j.limit[0] <= j.limit[1]):
                raise ValueError(f"joint '{j.name}': limit {j.limit} is not [lower, upper]")
        for p in self.parts:
            if p.parent is not None and self.joint_for(p.name) is None:
                raise ValueError(f"part '{p.name}' has a parent but no joint")
        if self.face_part is not None and len(self.parts):
            fp = np.asarray(self.face_part)
            if fp.size and (fp.min() < 0 or fp.max() >= len(self.parts)):
                raise ValueError("face_part holds indices outside the part list")

    # ---- contract IO -------------------------------------------------------------------------

    def to_json_dict(self) -> dict[str, Any]:
        """The articulation.json content (mesh paths as stored on the parts)."""
        return {
            "format": FORMAT,
            "units": "m",
            "frame": "input",
            "parts": [
                {"name": p.name, "semantic": p.semantic, "parent": p.parent, "mesh": p.mesh_path,
                 **({"inertial": inertial_json(p.inertial)} if p.inertial is not None else {})}
                for p in self.parts
            ],
            "joints": [
                {
                    "name": j.name,
                    "type": j.type,
                    "parent": j.parent,
                    "child": j.child,
                    "axis": [round(float(v), 9) for v in j.axis],
                    "origin": [round(float(v), 9) for v in j.origin],
                    "limit": [float(j.limit[0]), float(j.limit[1])],
                }
                for j in self.joints
            ],
            "face_part": "face_part.npy" if self.face_part is not None else None,
            **({"metadata": self.metadata} if self.metadata else {}),
        }


def inertial_json(inertial: MassProperties) -> dict[str, Any]:
    """A part's mass properties as articulation.json holds them (kg, m, kg m^2, input frame)."""
    return {"mass": float(inertial.mass), "com": [float(v) for v in inertial.com],
            "inertia": [[float(v) for v in row] for row in np.asarray(inertial.inertia)]}


def read_inertial(entry: dict[str, Any]) -> MassProperties:
    """The inverse of :func:`inertial_json`; ValueError for a non-positive or non-finite mass,
    a centre of mass that is not 3 finite numbers or an inertia that is not a finite 3 x 3."""
    mass = float(entry["mass"])
    com = np.asarray(entry["com"], float)
    inertia = np.asarray(entry["inertia"], float)
    if not (np.isfinite(mass) and mass > 0):
        raise ValueError(f"inertial mass {mass} is not a positive number")
    if com.shape != (3,) or inertia.shape != (3, 3) or not (np.isfinite(com).all() and np.isfinite(inertia).all()):
        raise ValueError("inertial needs a finite com of 3 numbers and a finite 3 x 3 inertia")
    return MassProperties(mass, com, inertia)


def write_articulation(asset: ArticulatedAsset, folder: str | Path, write_meshes: bool = True) -> None:
    """Write articulation.json, face_part.npy and (optionally) part meshes into ``folder``.

    Part meshes go to ``parts/<name>.obj`` unless the part already names a path.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for p in asset.parts:
        if p.mesh_path is None:
            p.mesh_path = f"parts/{p.name}.obj"
        if write_meshes and p.mesh is not None:
            target = folder / p.mesh_path
            target.parent.mkdir(parents=True, exist_ok=True)
            p.mesh.export(target, file_type="obj", include_normals=False, include_texture=False)
    asset.validate()
    if asset.face_part is not None:
        np.save(folder / "face_part.npy", np.asarray(asset.face_part, dtype=np.int32))
    (folder / "articulation.json").write_text(json.dumps(asset.to_json_dict(), indent=2) + "\n")


def read_articulation(folder: str | Path, load_meshes: bool = True) -> ArticulatedAsset:
    """Read an asset folder written by :func:`write_articulation` (or by the generator)."""
    folder = Path(folder)
    path = folder / "articulation.json"
    if not path.is_file():
        raise InputError(f"{path}: not found (expected an asset folder with articulation.json)")
    try:
        data = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON ({exc})") from None
    if data.get("format") != FORMAT:
        raise InputError(f"{path}: format is {data.get('format')!r}, expected {FORMAT!r}")
    parts = []
    for entry in data["parts"]:
        mesh = None
        if load_meshes and entry.get("mesh"):
            mesh_file = folder / entry["mesh"]
            if not mesh_file.is_file():
                raise InputError(f"{path}: part '{entry['name']}' mesh {mesh_file} not found")
            mesh = trimesh.load(mesh_file, force="mesh", process=False)
        try:
            inertial = read_inertial(entry["inertial"]) if entry.get("inertial") is not None else None
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{path}: part '{entry['name']}': bad inertial ({exc})") from None
        parts.append(Part(entry["name"], entry.get("semantic", "part"), entry.get("parent"), mesh, entry.get("mesh"),
                          inertial=inertial))
    joints = [
        Joint(j["name"], j["type"], j["parent"], j["child"], j["axis"], j["origin"], tuple(j["limit"]))
        for j in data["joints"]
    ]
    face_part = None
    if data.get("face_part"):
        fp_path = folder / data["face_part"]
        if not fp_path.is_file():
            raise InputError(f"{path}: face_part file {fp_path} not found")
        face_part = np.load(fp_path).astype(np.int32)
    asset = ArticulatedAsset(parts, joints, face_part, data.get("metadata", {}))
    try:
        asset.validate()
    except ValueError as exc:
        raise InputError(f"{path}: {exc}") from None
    return asset
