"""Importers of articulated assets made by other people into the ground-truth format.

Both importers return an :class:`ImportedObject`: the rest-state mesh (one piece per visual
geometry, as an artist's file would hold it), per-face part labels and the ground-truth asset,
all in the model's world frame (metres).

*Closed state*: the model's default pose (MJCF ``qpos0``, URDF zero configuration), clamped into
each joint's range. The joint opens towards the farther end of its range from that pose: when
that is the lower end, the axis is negated so that positive values open, as in the contract.

MJCF: MuJoCo itself compiles the file (includes, defaults, mesh frames are resolved exactly as
the simulator sees them). Bodies with a hinge or slide joint are parts; bodies attached without
one merge into their nearest moving ancestor or the base; free joints (a loose object's root)
are ignored; only the top-level bodies that hold a moving joint are kept (scene floors and
tables drop out). A moving body with no geometry of its own (nor in the bodies rigidly attached
to it) is no part: its joint is dropped and its moving children hang on its nearest kept
ancestor. A joint's parent is whatever part the model says (a latch on a door stays on the
door). Visual geometry only: geoms that do not collide (contype = conaffinity = 0) when a body
has any, else its other geoms; planes and invisible geoms are skipped; primitives are meshed.

URDF (including PartNet-Mobility's ``mobility.urdf``): yourdfpy loads the scene at the closed
configuration; every link with a revolute, continuous or prismatic joint and geometry is a part,
fixed joints merge into the parent, moving links without geometry (PartNet-Mobility's helper
links) are dropped the same way as in MJCF.

:func:`prune_parts` then merges movable parts too small to see, or that barely move, into their
parent.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part
from rest2art.errors import InputError
from rest2art.geometry.basics import transform_points
from rest2art.joints.sweep import range_values


@dataclass
class ImportedObject:
    name: str
    mesh: trimesh.Trimesh
    face_part: np.ndarray
    asset: ArticulatedAsset
    piece_faces: list[tuple[str, int, int]] = field(default_factory=list)
    """(piece name, first face, end face): one OBJ object per visual geometry."""


@dataclass(frozen=True)
class ImportConfig:
    """What counts as a movable part of a model made by someone else."""

    min_part_size: float = 0.02
    """A movable part whose bounding-box diagonal is shorter than this (m) is too small to see
    or segment: it merges into its parent."""
    min_motion: float = 0.002
    """A movable part none of whose points moves this far (m) over its range barely moves (a
    joint range written in the wrong unit, a button's click): it merges into its parent."""
    motion_samples: int = 8
    """Joint values sampled over the range to measure how far a part moves."""


def _opening(axis: np.ndarray, lower: float, upper: float, rest: float) -> tuple[np.ndarray, float]:
    """Axis with the opening sign and the range from the rest value to the far end."""
    rest = float(np.clip(rest, lower, upper))
    if upper - rest >= rest - lower:
        return np.asarray(axis, float), float(upper - rest)
    return -np.asarray(axis, float), float(rest - lower)


def _primitive(kind: int, size: np.ndarray) -> trimesh.Trimesh | None:
    import mujoco

    t = mujoco.mjtGeom
    kind = int(kind)
    if kind == int(t.mjGEOM_BOX):
        return trimesh.creation.box(2 * size[:3])
    if kind == int(t.mjGEOM_SPHERE):
        return trimesh.creation.icosphere(2, size[0])
    if kind == int(t.mjGEOM_CAPSULE):
        return trimesh.creation.capsule(2 * size[1], size[0], count=[12, 12])
    if kind == int(t.mjGEOM_CYLINDER):
        return trimesh.creation.cylinder(size[0], 2 * size[1], sections=24)
    if kind == int(t.mjGEOM_ELLIPSOID):
        sphere = trimesh.creation.icosphere(2, 1.0)
        sphere.apply_scale(size[:3])
        return sphere
    return None


def _mjcf_geom_mesh(model, data, g: int) -> trimesh.Trimesh | None:
    import mujoco

    kind = int(model.geom_type[g])
    if kind == int(mujoco.mjtGeom.mjGEOM_MESH):
        mid = int(model.geom_dataid[g])
        v0, nv = int(model.mesh_vertadr[mid]), int(model.mesh_vertnum[mid])
        f0, nf = int(model.mesh_faceadr[mid]), int(model.mesh_facenum[mid])
        mesh = trimesh.Trimesh(model.mesh_vert[v0:v0 + nv].astype(float), model.mesh_face[f0:f0 + nf], process=False)
    else:
        mesh = _primitive(kind, np.asarray(model.geom_size[g], float))
        if mesh is None:
            return None
    T = np.eye(4)
    T[:3, :3] = data.geom_xmat[g].reshape(3, 3)
    T[:3, 3] = data.geom_xpos[g]
    mesh.apply_transform(T)
    return mesh


def import_mjcf(path: str | Path, name: str | None = None) -> ImportedObject:
    """Import an MJCF model at its closed state (see the module docstring)."""
    import mujoco

    path = Path(path)
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        raise InputError(f"{path}: MuJoCo could not compile it ({exc})") from None
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    moving_types = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    for j in range(model.njnt):  # clamp the rest pose into the joint ranges
        if int(model.jnt_type[j]) in moving_types and model.jnt_limited[j]:
            a = model.jnt_qposadr[j]
            data.qpos[a] = np.clip(data.qpos[a], *model.jnt_range[j])
    mujoco.mj_kinematics(model, data)

    body_joint: dict[int, int] = {}
    for j in range(model.njnt):
        if int(model.jnt_type[j]) in moving_types:
            body_joint.setdefault(int(model.jnt_bodyid[j]), j)

    def top(b: int) -> int:
        while model.body_parentid[b] != 0:
            b = int(model.body_parentid[b])
        return b

    kept_tops = {top(b) for b in body_joint}
    if not kept_tops:
        raise InputError(f"{path}: no hinge or slide joint: not an articulated object")

    def owner(b: int) -> int | None:
        while b != 0:
            if b in body_joint:
                return b
            b = int(model.body_parentid[b])
        return None

    part_bodies: list[int | None] = [None]  # None: the base
    for b in range(1, model.nbody):
        if b in body_joint and top(b) in kept_tops:
            part_bodies.append(b)
    index_of = {b: k for k, b in enumerate(part_bodies)}

    visual = (model.geom_contype == 0) & (model.geom_conaffinity == 0)
    alpha = model.geom_rgba[:, 3].copy()
    has_mat = model.geom_matid >= 0
    alpha[has_mat] = model.mat_rgba[model.geom_matid[has_mat], 3]
    meshes, labels, pieces = [], [], []
    start = 0
    for b in range(1, model.nbody):
        if top(b) not in kept_tops:
            continue
        geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == b
                 and int(model.geom_type[g]) != int(mujoco.mjtGeom.mjGEOM_PLANE) and alpha[g] > 0]
        shown = [g for g in geoms if visual[g]] or geoms
        for g in shown:
            mesh = _mjcf_geom_mesh(model, data, g)
            if mesh is None or len(mesh.faces) == 0:
                continue
            meshes.append(mesh)
            labels.append(np.full(len(mesh.faces), index_of[owner(b)], np.int32))
            gname = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom{g}"
            pieces.append((gname, start, start + len(mesh.faces)))
            start += len(mesh.faces)
    if not meshes:
        raise InputError(f"{path}: no visual geometry on the articulated bodies")

    used = set(np.concatenate(labels).tolist())
    present = [b for b in part_bodies if b is None or index_of[b] in used]  # parts with geometry
    names = {b: _part_name(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}") for b in present[1:]}

    def kept_parent(b: int) -> int | None:
        b = int(model.body_parentid[b])
        while b != 0 and b not in names:
            b = int(model.body_parentid[b])
        return b if b != 0 else None

    parts, joints = [Part("base", "base", None)], []
    for b in present[1:]:
        j = body_joint[b]
        kind = "revolute" if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE) else "prismatic"
        lower, upper = (model.jnt_range[j] if model.jnt_limited[j] else ((-np.pi, np.pi) if kind == "revolute" else (0.0, 0.0)))
        axis, travel = _opening(data.xaxis[j], float(lower), float(upper), float(data.qpos[model.jnt_qposadr[j]]))
        parent = names.get(kept_parent(b), "base")
        parts.append(Part(names[b], "door" if kind == "revolute" else "drawer", parent))
        joints.append(Joint(f"{names[b]}_joint", kind, parent, names[b], axis, data.xanchor[j].copy(), (0.0, travel)))
    remap = {index_of[b]: k for k, b in enumerate(present)}
    face_part = np.array([remap[v] for v in np.concatenate(labels)], np.int32)
    return _assemble(name or path.stem, meshes, face_part, parts, joints, pieces,
                     {"model": {"format": "mjcf", "path": path.name}})


def _part_name(name: str) -> str:
    """A body or link name usable as a part and file name ('knob 1' -> 'knob_1')."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "part"


def import_urdf(path: str | Path, name: str | None = None) -> ImportedObject:
    """Import a URDF (e.g. PartNet-Mobility's mobility.urdf) at its closed configuration."""
    import yourdfpy

    path = Path(path)
    try:
        robot = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=True,
                                   build_collision_scene_graph=False)
    except Exception as exc:
        raise InputError(f"{path}: could not be read as URDF ({type(exc).__name__}: {exc})") from None
    moving = {"revolute", "continuous", "prismatic"}
    cfg = []
    for jname in robot.actuated_joint_names:
        joint = robot.joint_map[jname]
        limited = joint.type != "continuous" and joint.limit is not None
        lo = joint.limit.lower if limited and joint.limit.lower is not None else -np.inf
        hi = joint.limit.upper if limited and joint.limit.upper is not None else np.inf
        cfg.append(float(np.clip(0.0, lo, hi)))
    robot.update_cfg(np.array(cfg))
    link_joint = {j.child: j for j in robot.robot.joints if j.type in moving}

    def owner(link: str) -> str | None:
        while True:
            if link in link_joint:
                return link
            parents = [j for j in robot.robot.joints if j.child == link]
            if not parents:
                return None
            link = parents[0].parent

    owners = [None, *[lk.name for lk in robot.robot.links if lk.name in link_joint]]
    index_of = {o: k for k, o in enumerate(owners)}
    meshes, labels, pieces = [], [], []
    start = 0
    for link in robot.robot.links:
        T_link = robot.get_transform(link.name)
        for k, visual in enumerate(link.visuals):
            mesh = _urdf_visual_mesh(robot, path, visual)
            if mesh is None:
                continue
            T = T_link @ (visual.origin if visual.origin is not None else np.eye(4))
            mesh.apply_transform(T)
            meshes.append(mesh)
            labels.append(np.full(len(mesh.faces), index_of[owner(link.name)], np.int32))
            pieces.append((f"{link.name}_{k}", start, start + len(mesh.faces)))
            start += len(mesh.faces)
    if not meshes:
        raise InputError(f"{path}: no visual meshes")
    used = set(np.concatenate(labels).tolist())
    present = [o for o in owners if o is None or index_of[o] in used]  # parts with geometry
    names = {o: _part_name(o) for o in present[1:]}

    def kept_parent(link: str) -> str | None:
        owner_link = owner(link_joint[link].parent)
        while owner_link is not None and owner_link not in names:
            owner_link = owner(link_joint[owner_link].parent)
        return owner_link

    parts, joints = [Part("base", "base", None)], []
    for link in present[1:]:
        joint = link_joint[link]
        kind = "prismatic" if joint.type == "prismatic" else "revolute"
        T_child = robot.get_transform(link)
        axis_world = T_child[:3, :3] @ np.asarray(joint.axis, float)
        limited = joint.type != "continuous" and joint.limit is not None
        lo = joint.limit.lower if limited and joint.limit.lower is not None else -np.pi
        hi = joint.limit.upper if limited and joint.limit.upper is not None else np.pi
        axis, travel = _opening(axis_world, lo, hi, float(np.clip(0.0, lo, hi)))
        parent = names.get(kept_parent(link), "base")
        parts.append(Part(names[link], "door" if kind == "revolute" else "drawer", parent))
        joints.append(Joint(f"{names[link]}_joint", kind, parent, names[link], axis, T_child[:3, 3].copy(), (0.0, travel)))
    remap = np.zeros(len(owners), np.int32)
    remap[[index_of[o] for o in present]] = np.arange(len(present))
    return _assemble(name or path.stem, meshes, remap[np.concatenate(labels)], parts, joints, pieces,
                     {"model": {"format": "urdf", "path": path.name}})


def part_motion(joint: Joint, mesh: trimesh.Trimesh, samples: int = 8) -> float:
    """Farthest any vertex of ``mesh`` (V, 3) moves (m) at ``samples`` joint values spread over
    the joint's range (a full turn comes back to the start, so the end alone is not enough)."""
    values = range_values(joint.limit[0], joint.limit[1], samples)
    moved = [np.linalg.norm(transform_points(mesh.vertices, joint.transform(v)) - mesh.vertices, axis=1).max()
             for v in values]
    return float(max(moved, default=0.0))


def prune_parts(obj: ImportedObject, config: ImportConfig = ImportConfig()) -> tuple[ImportedObject, list[str]]:
    """Merge each movable part that is too small to see or barely moves (``config``) into its
    nearest kept ancestor; its faces, and its children, go there. Returns the object (a new
    one when something merged) and one line per merged part saying why."""
    asset = obj.asset
    merged: dict[str, str] = {}
    for joint in asset.movable_joints:
        mesh = asset.part(joint.child).mesh
        size = float(np.linalg.norm(mesh.extents)) if mesh is not None and len(mesh.faces) else 0.0
        motion = part_motion(joint, mesh, config.motion_samples) if size > 0 else 0.0
        if size < config.min_part_size:
            merged[joint.child] = f"{joint.child}: too small ({1000 * size:.1f} mm across)"
        elif motion < config.min_motion:
            merged[joint.child] = f"{joint.child}: barely moves ({1000 * motion:.2f} mm over its range)"
    if not merged:
        return obj, []

    def kept(name: str | None) -> str:
        while name in merged:
            name = asset.part(name).parent
        return name or "base"

    parts = [Part(p.name, p.semantic, None if p.parent is None else kept(p.parent))
             for p in asset.parts if p.name not in merged]
    joints = [Joint(j.name, j.type, kept(j.parent), j.child, j.axis, j.origin, j.limit)
              for j in asset.joints if j.child not in merged]
    index = {p.name: k for k, p in enumerate(parts)}
    remap = np.array([index[kept(p.name)] for p in asset.parts], np.int32)
    reasons = list(merged.values())
    metadata = {**asset.metadata, "merged_parts": reasons}
    return _assemble(obj.name, [obj.mesh], remap[obj.face_part], parts, joints, obj.piece_faces, metadata), reasons


def _assemble(name: str, meshes: list[trimesh.Trimesh], face_part: np.ndarray, parts: list[Part],
              joints: list[Joint], pieces: list, metadata: dict) -> ImportedObject:
    """The concatenated rest mesh, part meshes cut from it, and the validated asset."""
    mesh = trimesh.util.concatenate(meshes)
    mesh = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    for k, part in enumerate(parts):
        sub = trimesh.Trimesh(mesh.vertices, mesh.faces[face_part == k], process=False)
        sub.remove_unreferenced_vertices()
        part.mesh = sub
    asset = ArticulatedAsset(parts, joints, face_part, metadata)
    asset.validate()
    return ImportedObject(name, mesh, face_part, asset, pieces)


def _urdf_visual_mesh(robot, path: Path, visual) -> trimesh.Trimesh | None:
    geometry = visual.geometry
    if geometry.mesh is not None:
        file = Path(geometry.mesh.filename)
        file = file if file.is_absolute() else path.parent / file
        loaded = trimesh.load(file, force="mesh", process=False)
        if geometry.mesh.scale is not None:
            loaded.apply_scale(geometry.mesh.scale)
        return loaded
    if geometry.box is not None:
        return trimesh.creation.box(geometry.box.size)
    if geometry.cylinder is not None:
        return trimesh.creation.cylinder(geometry.cylinder.radius, geometry.cylinder.length, sections=24)
    if geometry.sphere is not None:
        return trimesh.creation.icosphere(2, geometry.sphere.radius)
    return None
