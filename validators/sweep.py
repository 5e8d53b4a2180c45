"""Interpenetration sweep over the joint ranges with python-fcl.

The exported URDF is the source of truth: yourdfpy reads the links, joints and collision
elements, and gives every link's pose at a joint configuration; each collision mesh file (a
convex hull) becomes one ``fcl.Convex``. FCL's broad phase finds the hull pairs that touch and
the separating-axis test over their face normals measures how deep (a mesh-vs-mesh query only
says *whether* two surfaces cross). Every pair of parts is checked, parent and child included:
a door that swings through its carcass is exactly the fault to find.

Sweeps: the rest pose; each movable joint through ``samples`` values of its range with the
others at rest; and all joints together at the same fractions of their ranges. The sampling and
the last free value are the one sweep's (``rest2art.joints.sweep``); what is measured per sample
here is the depth per pair of exported hulls.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from rest2art.validators import Finding

from rest2art.geometry.basics import convex_overlap, is_closed_volume
from rest2art.geometry.fcl import scene_manager, set_pose
from rest2art.joints.sweep import last_free, range_values, sweep_range


@dataclass
class CollisionModel:
    """Collision hulls per link (link frame) and the URDF's kinematics."""

    robot: object
    """yourdfpy.URDF."""
    hulls: dict[str, list[trimesh.Trimesh]]
    base: str
    limits: dict[str, tuple[float, float]]
    """Movable joint name -> (lower, upper)."""
    problems: list[str] = field(default_factory=list)
    """Collision files that could not be read."""

    def poses(self, values: dict[str, float]) -> dict[str, np.ndarray]:
        """(4, 4) pose of every link in the base frame with the joints at ``values`` (others 0)."""
        cfg = np.array([values.get(j, 0.0) for j in self.robot.actuated_joint_names], float)
        self.robot.update_cfg(cfg)
        return {link: self.robot.get_transform(link, self.base) for link in self.hulls}


def read_collision_model(asset_dir: str | Path, name: str) -> CollisionModel:
    """Parse ``NAME.urdf`` and load its collision meshes, each moved into its link frame."""
    import yourdfpy

    asset_dir = Path(asset_dir)
    robot = yourdfpy.URDF.load(str(asset_dir / f"{name}.urdf"), build_scene_graph=True, load_meshes=False,
                               build_collision_scene_graph=False, load_collision_meshes=False)
    hulls: dict[str, list[trimesh.Trimesh]] = {}
    problems = []
    for link_name, link in robot.link_map.items():
        hulls[link_name] = []
        for col in link.collisions:
            mesh_ref = getattr(col.geometry, "mesh", None)
            if mesh_ref is None:
                continue
            path = asset_dir / mesh_ref.filename
            try:
                mesh = trimesh.load(path, force="mesh", process=False)
            except Exception as exc:  # a broken file is a finding, not a crash
                problems.append(f"{link_name}: collision mesh {mesh_ref.filename}: {type(exc).__name__}: {exc}")
                continue
            if not is_closed_volume(mesh):
                problems.append(f"{link_name}: collision mesh {mesh_ref.filename} is not a closed volume "
                                "(holes or a flat piece): simulators would treat it as a hull of something else")
                continue
            if col.origin is not None:
                mesh.apply_transform(col.origin)
            hulls[link_name].append(mesh)
    limits = {j.name: (float(j.limit.lower), float(j.limit.upper)) for j in robot.joint_map.values()
              if j.type in ("revolute", "prismatic") and j.limit is not None}
    return CollisionModel(robot, hulls, robot.base_link, limits, problems)


def _convex(hull: trimesh.Trimesh):
    """(fcl.CollisionObject, its fcl.Convex geometry) of a convex mesh."""
    import fcl

    faces = np.hstack([np.full((len(hull.faces), 1), 3), hull.faces]).astype(np.int32).ravel()
    geometry = fcl.Convex(np.asarray(hull.vertices, float), len(hull.faces), faces)
    return fcl.CollisionObject(geometry, fcl.Transform()), geometry


def separating_depth(va: np.ndarray, na: np.ndarray, vb: np.ndarray, nb: np.ndarray) -> float:
    """Penetration depth (m) of two convex polytopes (``geometry.convex_overlap``: the
    separating-axis test over both sets of face normals, exact for face contacts and never below
    the true depth). FCL's EPA answer is not used: on thin slabs it reports several times the
    depth the shapes' extents allow."""
    return convex_overlap(va, na, vb, nb)[0]


class PenetrationQuery:
    """Deepest penetration between the hulls of every pair of links at a given pose."""

    def __init__(self, model: CollisionModel):
        self.model = model
        self.objects, self.owner, self.shapes = {}, {}, {}
        for link, hulls in model.hulls.items():
            if not hulls:
                continue
            self.objects[link] = []
            for k, mesh in enumerate(hulls):
                hull = mesh if mesh.is_convex else mesh.convex_hull
                obj, geometry = _convex(hull)
                self.objects[link].append(obj)
                self.owner[id(geometry)] = (link, k)
                normals = np.unique(np.round(hull.face_normals, 9), axis=0)
                self.shapes[(link, k)] = (np.asarray(hull.vertices, float), normals)
        self.managers = {link: scene_manager(objects) for link, objects in self.objects.items()}
        self.links = sorted(self.objects)

    def depths(self, values: dict[str, float], pairs: list[tuple[str, str]] | None = None) -> dict[tuple[str, str], float]:
        """Penetration depth (m, 0 when apart) per link pair at joint ``values``."""
        import fcl

        poses = self.model.poses(values)
        for link, objects in self.objects.items():
            for obj in objects:
                set_pose(obj, poses[link])
            self.managers[link].update()
        pairs = pairs if pairs is not None else [(a, b) for i, a in enumerate(self.links) for b in self.links[i + 1:]]
        out = {}
        for a, b in pairs:
            data = fcl.CollisionData(request=fcl.CollisionRequest(num_max_contacts=100000, enable_contact=True))
            self.managers[a].collide(self.managers[b], data, fcl.defaultCollisionCallback)
            depths = [0.0]
            for contact in data.result.contacts:
                ka, kb = self.owner[id(contact.o1)], self.owner[id(contact.o2)]
                (va, na), (vb, nb) = self._posed(ka, poses), self._posed(kb, poses)
                depths.append(separating_depth(va, na, vb, nb))
            out[(a, b)] = max(depths)
        return out

    def _posed(self, key: tuple[str, int], poses: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        vertices, normals = self.shapes[key]
        T = poses[key[0]]
        return vertices @ T[:3, :3].T + T[:3, 3], normals @ T[:3, :3].T


def _moving_links(model: CollisionModel, joint: str) -> set[str]:
    """Links carried by ``joint`` (its child and everything below it)."""
    robot = model.robot
    child = robot.joint_map[joint].child
    moving, frontier = {child}, [child]
    while frontier:
        link = frontier.pop()
        for j in robot.joint_map.values():
            if j.parent == link and j.child not in moving:
                moving.add(j.child)
                frontier.append(j.child)
    return moving


def sweep(model: CollisionModel, samples: int) -> dict[str, list[dict]]:
    """Per sweep ("rest", each joint, "all"): one record per sample with the fraction of the
    range, the joint values, the deepest penetration and the pair it came from."""
    query = PenetrationQuery(model)
    fractions = range_values(0.0, 1.0, samples)

    def record(fraction: float, values: dict[str, float], pairs=None) -> dict:
        depths = query.depths(values, pairs)
        worst = max(depths, key=depths.get) if depths else None
        return {"fraction": round(float(fraction), 4), "values": {k: round(v, 5) for k, v in values.items()},
                "depth": depths[worst] if worst else 0.0, "pair": list(worst) if worst else None}

    out = {"rest": [record(0.0, {})]}
    for joint, (lo, hi) in model.limits.items():
        moving = _moving_links(model, joint) & set(query.links)
        pairs = [(a, b) for i, a in enumerate(query.links) for b in query.links[i + 1:]
                 if (a in moving) != (b in moving)]
        out[joint] = sweep_range(fractions, lambda f, joint=joint, lo=lo, hi=hi, pairs=pairs:
                                 record(f, {joint: lo + f * (hi - lo)}, pairs))
    if len(model.limits) > 1:
        out["all"] = sweep_range(fractions, lambda f: record(f, {j: lo + f * (hi - lo)
                                                                 for j, (lo, hi) in model.limits.items()}))
    return out


def last_free_fraction(records: list[dict], tolerance: float) -> float:
    """The largest sampled fraction of a range reached before the first penetration."""
    return last_free([r["fraction"] for r in records], records, lambda r: r["depth"] > tolerance)


def sweep_findings(asset_dir: str | Path, name: str, samples: int, tolerance: float) -> list[Finding]:
    """One finding per sweep: ok when no sample penetrates deeper than ``tolerance`` (m)."""
    try:
        model = read_collision_model(asset_dir, name)
    except Exception as exc:
        return [Finding("sweep", "urdf", False, f"{name}.urdf: {type(exc).__name__}: {exc}")]
    findings = [Finding("collision", "files", False, "; ".join(model.problems))] if model.problems else []
    hull_counts = {link: len(h) for link, h in model.hulls.items()}
    empty = [link for link, n in hull_counts.items() if n == 0]
    if empty:
        findings.append(Finding("collision", "hulls", False, f"links without collision geometry: {', '.join(empty)}",
                                {"hulls": hull_counts}))
    else:
        findings.append(Finding("collision", "hulls", True,
                                ", ".join(f"{k} {v}" for k, v in hull_counts.items()) + " hulls", {"hulls": hull_counts}))
    for subject, records in sweep(model, samples).items():
        worst = max(records, key=lambda r: r["depth"])
        ok = worst["depth"] <= tolerance
        where = "at rest" if subject == "rest" else f"at {100 * worst['fraction']:.0f} % of the range"
        message = (f"deepest penetration {1000 * worst['depth']:.1f} mm" +
                   ("" if ok else f" between {' and '.join(worst['pair'])} {where}"))
        data = {"samples": [{"fraction": r["fraction"], "depth_mm": round(1000 * r["depth"], 3), "pair": r["pair"]}
                            for r in records],
                "max_depth_mm": round(1000 * worst["depth"], 3)}
        if subject in model.limits:
            data["last_free_fraction"] = last_free_fraction(records, tolerance)
            data["limit"] = list(model.limits[subject])
            data["child"] = model.robot.joint_map[subject].child
        elif subject == "all":
            data["all_free_fraction"] = last_free_fraction(records, tolerance)
            data["limits"] = {j: list(lim) for j, lim in model.limits.items()}
            data["children"] = {j: model.robot.joint_map[j].child for j in model.limits}
        findings.append(Finding("sweep", subject, ok, message, data))
    return findings
