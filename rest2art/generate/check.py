"""Physical checks of generated ground truth: do parts pass through each other as they move?

Exact booleans on the closed part meshes (manifold3d), not convex hulls: the overlap of two
posed parts is their intersection solid, and its *depth* is 2 V / A (V its volume, A its area),
the thickness of the slab it would be if it were thin (a front sunk 2 mm into the carcass gives
about 2 mm; touching faces give 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import manifold3d as m3d
import numpy as np

from rest2art.asset import ArticulatedAsset


@dataclass(frozen=True)
class Overlap:
    """The deepest overlap of a pair of parts found over a set of poses."""

    pair: tuple[str, str]
    depth: float
    """2 V / A of the intersection solid, m."""
    volume: float
    """Volume of the intersection solid, m^3."""
    values: dict
    """Joint values (rad or m) where it was found."""


def _manifold(mesh) -> m3d.Manifold:
    return m3d.Manifold(m3d.Mesh(vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
                                 tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))


def overlaps_at(asset: ArticulatedAsset, values: dict[str, float], min_volume: float = 1e-9,
                pairs: list[tuple[str, str]] | None = None,
                solids: dict[str, m3d.Manifold] | None = None) -> list[Overlap]:
    """Every pair of parts (of ``pairs``, default all) whose posed solids share more than
    ``min_volume`` m^3; pairs whose bounding boxes are apart are not intersected. ``solids``:
    the parts' solids at rest, when the caller keeps them."""
    poses = asset.part_poses(values)
    solids = solids or {p.name: _manifold(p.mesh) for p in asset.parts}
    if pairs is None:
        names = [p.name for p in asset.parts]
        pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    posed: dict[str, m3d.Manifold] = {}
    boxes: dict[str, np.ndarray] = {}
    for name in {n for pair in pairs for n in pair}:
        posed[name] = solids[name].transform(poses[name][:3])
        boxes[name] = np.reshape(posed[name].bounding_box(), (2, 3))
    found = []
    for a, b in pairs:
        if np.any(boxes[a][0] >= boxes[b][1]) or np.any(boxes[b][0] >= boxes[a][1]):
            continue
        common = posed[a] ^ posed[b]
        volume = float(common.volume())
        if volume > min_volume:
            found.append(Overlap((a, b), 2 * volume / max(float(common.surface_area()), 1e-12), volume, dict(values)))
    return found


def _subtree(asset: ArticulatedAsset, name: str) -> set[str]:
    children = {name}
    for part in asset.parts:
        if part.parent == name:
            children |= _subtree(asset, part.name)
    return children


def motion_overlaps(asset: ArticulatedAsset, samples: int = 9, min_volume: float = 1e-9) -> dict[str, list[Overlap]]:
    """Overlaps at rest (``"rest"``, every pair), while each joint moves alone over its range
    (by joint name: the parts it moves against the others) and while all joints move together
    (``"all"``, every pair), at ``samples`` evenly spaced fractions of the ranges after rest;
    the deepest per pair."""
    fractions = np.linspace(0.0, 1.0, samples + 1)[1:]
    names = [p.name for p in asset.parts]
    every = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    runs = {"rest": ([{}], every)}
    for joint in asset.movable_joints:
        moving = _subtree(asset, joint.child)
        pairs = [(a, b) for a, b in every if (a in moving) != (b in moving)]
        runs[joint.name] = ([{joint.name: f * joint.limit[1]} for f in fractions], pairs)
    runs["all"] = ([{j.name: f * j.limit[1] for j in asset.movable_joints} for f in fractions], every)
    solids = {p.name: _manifold(p.mesh) for p in asset.parts}
    report = {}
    for run, (poses, pairs) in runs.items():
        deepest: dict[tuple[str, str], Overlap] = {}
        for values in poses:
            for overlap in overlaps_at(asset, values, min_volume, pairs, solids):
                if overlap.pair not in deepest or overlap.depth > deepest[overlap.pair].depth:
                    deepest[overlap.pair] = overlap
        report[run] = sorted(deepest.values(), key=lambda o: -o.depth)
    return report
