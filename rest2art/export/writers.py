"""Writing an asset folder: articulation.json, face_part.npy, URDF, MJCF and meshes.

Layout (all paths relative)::

    OUT/articulation.json   OUT/face_part.npy   OUT/NAME.urdf   OUT/NAME.xml
    OUT/parts/<part>.obj                  visual mesh, input frame
    OUT/collision/<part>_<k>.obj          convex collision pieces, input frame

Every link frame sits at its joint's origin with the input frame's orientation, so a mesh in
the input frame is placed with an offset of minus the link origin. The folder is written
atomically (``rest2art.io.atomic``).
"""

from __future__ import annotations

from pathlib import Path
from xml.dom import minidom
from xml.etree import ElementTree as ET

import numpy as np

from rest2art.asset import ArticulatedAsset, write_articulation
from rest2art.config import ExportConfig
from rest2art.errors import ExportError
from rest2art.export.formats import export_format, register_format

GRAVITY = 9.81


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in np.atleast_1d(values))


def link_origins(asset: ArticulatedAsset) -> dict[str, np.ndarray]:
    """Input-frame position of every link frame (the base at the input origin)."""
    origins = {}
    for part in asset.parts:
        joint = asset.joint_for(part.name)
        origins[part.name] = np.zeros(3) if joint is None else joint.origin.copy()
    return origins


def holding_friction(asset: ArticulatedAsset, up: np.ndarray, config: ExportConfig) -> dict[str, float]:
    """Dry friction per joint: at least ``joint_friction``, and enough to hold the child
    against gravity at rest (x ``friction_safety``), so flip-down doors and lids stay shut."""
    gravity = -GRAVITY * np.asarray(up, float)
    out = {}
    for joint in asset.movable_joints:
        props = asset.part(joint.child).inertial
        if joint.type == "revolute":
            load = abs(float(joint.axis @ np.cross(props.com - joint.origin, props.mass * gravity)))
        else:
            load = abs(float(joint.axis @ (props.mass * gravity)))
        out[joint.name] = max(config.joint_friction, config.friction_safety * load)
    return out


def joint_damping(asset: ArticulatedAsset, config: ExportConfig) -> dict[str, float]:
    """Damping per joint: ``joint_damping``, lowered for light children so that the time
    constant (moving inertia about or along the axis) / damping stays >= ``min_damping_time``."""
    out = {}
    for joint in asset.movable_joints:
        props = asset.part(joint.child).inertial
        if joint.type == "revolute":
            r = props.com - joint.origin
            r = r - (r @ joint.axis) * joint.axis
            moving = float(joint.axis @ props.inertia @ joint.axis) + props.mass * float(r @ r)
        else:
            moving = props.mass
        out[joint.name] = min(config.joint_damping, moving / config.min_damping_time)
    return out


def write_meshes(asset: ArticulatedAsset, folder: Path) -> dict[str, list[str]]:
    """Write visual and collision meshes; returns collision file paths per part."""
    collision_files: dict[str, list[str]] = {}
    (folder / "parts").mkdir(exist_ok=True)
    (folder / "collision").mkdir(exist_ok=True)
    for part in asset.parts:
        part.mesh_path = f"parts/{part.name}.obj"
        part.mesh.export(folder / part.mesh_path, file_type="obj", include_normals=False, include_texture=False)
        files = []
        for k, hull in enumerate(part.collision):
            rel = f"collision/{part.name}_{k}.obj"
            hull.export(folder / rel, file_type="obj", include_normals=False, include_texture=False)
            files.append(rel)
        collision_files[part.name] = files
    return collision_files


@register_format("urdf", ".urdf")
def urdf_string(asset: ArticulatedAsset, name: str, collision_files: dict[str, list[str]],
                config: ExportConfig = ExportConfig(), up: np.ndarray = np.array([0.0, 0.0, 1.0])) -> str:
    """The URDF document (fixed base, input frame)."""
    origins = link_origins(asset)
    friction = holding_friction(asset, up, config)
    damping = joint_damping(asset, config)
    robot = ET.Element("robot", name=name)
    for part in asset.parts:
        link = ET.SubElement(robot, "link", name=part.name)
        offset = -origins[part.name]
        inertial = ET.SubElement(link, "inertial")
        props = part.inertial
        ET.SubElement(inertial, "origin", xyz=_fmt(props.com + offset), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=f"{props.mass:.6g}")
        tensor = props.inertia
        ET.SubElement(inertial, "inertia", ixx=f"{tensor[0, 0]:.6g}", ixy=f"{tensor[0, 1]:.6g}",
                      ixz=f"{tensor[0, 2]:.6g}", iyy=f"{tensor[1, 1]:.6g}", iyz=f"{tensor[1, 2]:.6g}",
                      izz=f"{tensor[2, 2]:.6g}")
        visual = ET.SubElement(link, "visual")
        ET.SubElement(visual, "origin", xyz=_fmt(offset), rpy="0 0 0")
        ET.SubElement(ET.SubElement(visual, "geometry"), "mesh", filename=part.mesh_path)
        for rel in collision_files[part.name]:
            col = ET.SubElement(link, "collision")
            ET.SubElement(col, "origin", xyz=_fmt(offset), rpy="0 0 0")
            ET.SubElement(ET.SubElement(col, "geometry"), "mesh", filename=rel)
    for joint in asset.joints:
        el = ET.SubElement(robot, "joint", name=joint.name, type=joint.type)
        ET.SubElement(el, "parent", link=joint.parent)
        ET.SubElement(el, "child", link=joint.child)
        ET.SubElement(el, "origin", xyz=_fmt(origins[joint.child] - origins[joint.parent]), rpy="0 0 0")
        if joint.type != "fixed":
            ET.SubElement(el, "axis", xyz=_fmt(joint.axis))
            effort = config.revolute_effort if joint.type == "revolute" else config.prismatic_effort
            ET.SubElement(el, "limit", lower=f"{joint.limit[0]:.6g}", upper=f"{joint.limit[1]:.6g}",
                          effort=f"{effort:g}", velocity=f"{config.joint_velocity:g}")
            ET.SubElement(el, "dynamics", damping=f"{damping[joint.name]:.4g}", friction=f"{friction[joint.name]:.4g}")
    return minidom.parseString(ET.tostring(robot)).toprettyxml(indent="  ")


@register_format("mjcf", ".xml")
def mjcf_string(asset: ArticulatedAsset, name: str, collision_files: dict[str, list[str]],
                config: ExportConfig = ExportConfig(), up: np.ndarray = np.array([0.0, 0.0, 1.0])) -> str:
    """The MJCF document: fixed base, parent/child contacts excluded, gravity along -up."""
    origins = link_origins(asset)
    friction = holding_friction(asset, up, config)
    damping = joint_damping(asset, config)
    root = ET.Element("mujoco", model=name)
    ET.SubElement(root, "compiler", angle="radian", meshdir=".", inertiafromgeom="false", autolimits="true")
    ET.SubElement(root, "option", timestep=f"{config.mjcf_timestep:g}", gravity=_fmt(-GRAVITY * np.asarray(up)))
    default = ET.SubElement(root, "default")
    ET.SubElement(ET.SubElement(default, "default", {"class": "visual"}), "geom",
                  type="mesh", contype="0", conaffinity="0", group="2", density="0")
    ET.SubElement(ET.SubElement(default, "default", {"class": "collision"}), "geom",
                  type="mesh", group="3", density="0", friction="0.8 0.01 0.001")
    assets = ET.SubElement(root, "asset")
    for part in asset.parts:
        ET.SubElement(assets, "mesh", name=f"{part.name}_visual", file=part.mesh_path)
        for k, rel in enumerate(collision_files[part.name]):
            ET.SubElement(assets, "mesh", name=f"{part.name}_collision_{k}", file=rel)
    world = ET.SubElement(root, "worldbody")
    bodies: dict[str, ET.Element] = {}
    pending = list(asset.parts)
    while pending:
        for part in list(pending):
            if part.parent is not None and part.parent not in bodies:
                continue
            parent_el = world if part.parent is None else bodies[part.parent]
            parent_origin = np.zeros(3) if part.parent is None else origins[part.parent]
            body = ET.SubElement(parent_el, "body", name=part.name, pos=_fmt(origins[part.name] - parent_origin))
            bodies[part.name] = body
            offset = -origins[part.name]
            props = part.inertial
            tensor = props.inertia
            ET.SubElement(body, "inertial", pos=_fmt(props.com + offset), mass=f"{props.mass:.6g}",
                          fullinertia=_fmt([tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2],
                                            tensor[1, 2]]))
            joint = asset.joint_for(part.name)
            if joint is not None and joint.type != "fixed":
                ET.SubElement(body, "joint", name=joint.name, type="hinge" if joint.type == "revolute" else "slide",
                              axis=_fmt(joint.axis), pos="0 0 0", range=_fmt(joint.limit),
                              damping=f"{damping[joint.name]:.4g}", frictionloss=f"{friction[joint.name]:.4g}",
                              armature=f"{config.joint_armature:g}")
            ET.SubElement(body, "geom", {"class": "visual", "mesh": f"{part.name}_visual", "pos": _fmt(offset)})
            for k in range(len(collision_files[part.name])):
                ET.SubElement(body, "geom", {"class": "collision", "mesh": f"{part.name}_collision_{k}",
                                             "pos": _fmt(offset)})
            pending.remove(part)
    contact = ET.SubElement(root, "contact")
    for joint in asset.joints:
        ET.SubElement(contact, "exclude", body1=joint.parent, body2=joint.child)
    return minidom.parseString(ET.tostring(root)).toprettyxml(indent="  ")


def enforce_hull_budget(asset: ArticulatedAsset, config: ExportConfig) -> None:
    """Hold the asset's collision hulls to the budget (hulls per part and per asset, corners
    per hull; ``collision.within_budget``), in place; what had to change is noted in the
    metadata's ``collision`` section."""
    from rest2art.collision.hulls import within_budget

    hulls, notes = within_budget({p.name: p.collision for p in asset.parts}, config.max_hulls_per_part,
                                 config.max_hulls_per_asset, config.max_hull_vertices)
    for part in asset.parts:
        part.collision = hulls[part.name]
    for name, note in notes.items():
        asset.metadata.setdefault("collision", {}).setdefault(name, {})["export_budget"] = note


def write_asset(asset: ArticulatedAsset, folder: Path, name: str, config: ExportConfig = ExportConfig(),
                up: np.ndarray = np.array([0.0, 0.0, 1.0])) -> None:
    """Write the complete asset into ``folder`` (which must exist, e.g. from atomic_folder)."""
    missing = [p.name for p in asset.parts if p.inertial is None or p.mesh is None]
    if missing:
        raise ExportError(f"parts without mesh or mass properties cannot be exported: {', '.join(missing)}")
    enforce_hull_budget(asset, config)
    collision_files = write_meshes(asset, folder)
    write_articulation(asset, folder, write_meshes=False)
    for fmt in map(export_format, config.formats):
        (folder / f"{name}{fmt.suffix}").write_text(fmt.write(asset, name, collision_files, config, up))
