"""Thin helpers around python-fcl for triangle meshes (BVH models)."""

from __future__ import annotations

import numpy as np


def bvh_object(vertices: np.ndarray, faces: np.ndarray):
    """An fcl.CollisionObject holding the triangle mesh (identity transform)."""
    import fcl

    model = fcl.BVHModel()
    model.beginModel(len(vertices), len(faces))
    model.addSubModel(np.ascontiguousarray(vertices, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int32))
    model.endModel()
    return fcl.CollisionObject(model, fcl.Transform())


def set_pose(obj, T: np.ndarray) -> None:
    """Move an fcl object to the (4, 4) pose ``T``."""
    import fcl

    obj.setTransform(fcl.Transform(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3])))


def collides(a, b) -> bool:
    """True when the two objects' surfaces intersect."""
    import fcl

    return fcl.collide(a, b, fcl.CollisionRequest(), fcl.CollisionResult()) > 0


def distance(a, b) -> float:
    """Minimum surface distance (0 when intersecting), metres."""
    import fcl

    if collides(a, b):
        return 0.0
    return float(fcl.distance(a, b, fcl.DistanceRequest(), fcl.DistanceResult()))


def scene_manager(objects: list):
    """A broad-phase manager over ``objects`` (for one-vs-many queries)."""
    import fcl

    manager = fcl.DynamicAABBTreeCollisionManager()
    manager.registerObjects(objects)
    manager.setup()
    return manager


def collides_with_scene(obj, manager) -> bool:
    """True when ``obj`` intersects any object of the manager."""
    import fcl

    data = fcl.CollisionData(request=fcl.CollisionRequest())
    manager.collide(obj, data, fcl.defaultCollisionCallback)
    return bool(data.result.is_collision)
