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
tables drop out). Visual geometry only: geoms that do not collide (contype = conaffinity = 0)
when a body has any, else its other geoms; planes and invisible geoms are skipped; primitives
are meshed.

URDF (including PartNet-Mobility's ``mobility.urdf``): yourdfpy loads the scene at the closed
configuration; every link with a revolute, continuous or prismatic joint is a part, fixed
joints merge into the parent.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part
from rest2art.errors import InputError


@dataclass
class ImportedObject:
    name: str
    mesh: trimesh.Trimesh
    face_part: np.ndarray
    asset: ArticulatedAsset
    piece_faces: list[tuple[str, int, int]] = field(default_factory=list)
    """(piece name, first face, end face): one OBJ object per visual geometry."""


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

    parts, joints = [Part("base", "base", None)], []
    used = set(np.concatenate(labels).tolist())
    names = {None: "base"}
    for b in part_bodies[1:]:
        if index_of[b] not in used:
            continue
        bname = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
        names[b] = bname
    # keep only parts that have geometry; re-index the labels
    present = [b for b in part_bodies if b is None or b in names]
    remap = {index_of[b]: k for k, b in enumerate(present)}
    for b in present[1:]:
        j = body_joint[b]
        kind = "revolute" if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE) else "prismatic"
        lower, upper = (model.jnt_range[j] if model.jnt_limited[j] else ((-np.pi, np.pi) if kind == "revolute" else (0.0, 0.0)))
        axis, travel = _opening(data.xaxis[j], float(lower), float(upper), float(data.qpos[model.jnt_qposadr[j]]))
        parent_body = owner(int(model.body_parentid[b]))
        parent = names.get(parent_body, "base")
        parts.append(Part(names[b], "door" if kind == "revolute" else "drawer", parent))
        joints.append(Joint(f"{names[b]}_joint", kind, parent, names[b], axis, data.xanchor[j].copy(), (0.0, travel)))
    face_part = np.array([remap[v] for v in np.concatenate(labels)], np.int32)
    return _assemble(name or path.stem, meshes, face_part, parts, joints, pieces, {"format": "mjcf", "path": path.name})


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
        lo = joint.limit.lower if joint.limit is not None and joint.limit.lower is not None else -np.inf
        hi = joint.limit.upper if joint.limit is not None and joint.limit.upper is not None else np.inf
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
    parts = [Part("base", "base", None)]
    joints = []
    for link in owners[1:]:
        joint = link_joint[link]
        kind = "prismatic" if joint.type == "prismatic" else "revolute"
        T_child = robot.get_transform(link)
        axis_world = T_child[:3, :3] @ np.asarray(joint.axis, float)
        lo = joint.limit.lower if joint.limit is not None and joint.limit.lower is not None else -np.pi
        hi = joint.limit.upper if joint.limit is not None and joint.limit.upper is not None else np.pi
        rest = float(np.clip(0.0, lo, hi))
        axis, travel = _opening(axis_world, lo, hi, rest)
        parent = owner(joint.parent) or "base"
        parts.append(Part(link, "door" if kind == "revolute" else "drawer", parent))
        joints.append(Joint(f"{link}_joint", kind, parent, link, axis, T_child[:3, 3].copy(), (0.0, travel)))
    return _assemble(name or path.stem, meshes, np.concatenate(labels), parts, joints, pieces,
                     {"format": "urdf", "path": path.name})


def _assemble(name: str, meshes: list[trimesh.Trimesh], face_part: np.ndarray, parts: list[Part],
              joints: list[Joint], pieces: list, source: dict) -> ImportedObject:
    """The concatenated rest mesh, part meshes cut from it, and the validated asset."""
    mesh = trimesh.util.concatenate(meshes)
    mesh = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    for k, part in enumerate(parts):
        sub = trimesh.Trimesh(mesh.vertices, mesh.faces[face_part == k], process=False)
        sub.remove_unreferenced_vertices()
        part.mesh = sub
    asset = ArticulatedAsset(parts, joints, face_part, {"source": source})
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
