"""Constructive solid geometry for the generator: analytic SDFs and exact meshes.

Each node gives a signed distance (negative inside, metres) for the fused scan variant and a
manifold3d solid for the artist-style asset variant, so both variants come from one model.
SDFs of unions and differences are the usual min/max bounds, exact on the zero level set.
"""

from __future__ import annotations

from dataclasses import dataclass

import manifold3d as m3d
import numpy as np
import trimesh


class Solid:
    """A CSG node."""

    def sdf(self, points: np.ndarray) -> np.ndarray:
        """(N,) signed distance of (N, 3) points, negative inside."""
        raise NotImplementedError

    def manifold(self) -> m3d.Manifold:
        raise NotImplementedError

    def bounds(self) -> np.ndarray:
        """(2, 3) axis-aligned bounds."""
        raise NotImplementedError

    def mesh(self) -> trimesh.Trimesh:
        """The solid as a watertight triangle mesh."""
        out = self.manifold().to_mesh()
        return trimesh.Trimesh(np.asarray(out.vert_properties)[:, :3].astype(np.float64),
                               np.asarray(out.tri_verts).astype(np.int64), process=False)

    def __add__(self, other: "Solid") -> "Solid":
        return Union((self, other))

    def __sub__(self, other: "Solid") -> "Solid":
        return Difference(self, other)


@dataclass(frozen=True)
class Box(Solid):
    """Axis-aligned box between corners ``lo`` and ``hi``."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]

    def sdf(self, points: np.ndarray) -> np.ndarray:
        lo, hi = np.asarray(self.lo), np.asarray(self.hi)
        c, h = (lo + hi) / 2, (hi - lo) / 2
        q = np.abs(points - c) - h
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
        inside = np.minimum(q.max(axis=-1), 0.0)
        return outside + inside

    def manifold(self) -> m3d.Manifold:
        lo, hi = np.asarray(self.lo), np.asarray(self.hi)
        return m3d.Manifold.cube(tuple(hi - lo)).translate(tuple(lo))

    def bounds(self) -> np.ndarray:
        return np.array([self.lo, self.hi], dtype=float)


@dataclass(frozen=True)
class Cylinder(Solid):
    """Cylinder from ``start`` to ``end`` (axis-aligned), radius ``radius``."""

    start: tuple[float, float, float]
    end: tuple[float, float, float]
    radius: float
    segments: int = 24

    def _frame(self) -> tuple[np.ndarray, np.ndarray, float]:
        a, b = np.asarray(self.start, float), np.asarray(self.end, float)
        length = float(np.linalg.norm(b - a))
        return a, (b - a) / length, length

    def sdf(self, points: np.ndarray) -> np.ndarray:
        a, d, length = self._frame()
        rel = points - a
        t = rel @ d
        radial = np.linalg.norm(rel - t[:, None] * d, axis=1) - self.radius
        axial = np.abs(t - length / 2) - length / 2
        q = np.stack([radial, axial], axis=1)
        return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)

    def manifold(self) -> m3d.Manifold:
        a, d, length = self._frame()
        cyl = m3d.Manifold.cylinder(length, self.radius, self.radius, self.segments)
        axis = int(np.argmax(np.abs(d)))
        sign = np.sign(d[axis])
        if axis == 0:
            cyl = cyl.rotate((0.0, 90.0 * sign, 0.0))
        elif axis == 1:
            cyl = cyl.rotate((-90.0 * sign, 0.0, 0.0))
        elif sign < 0:
            cyl = cyl.rotate((180.0, 0.0, 0.0))
        return cyl.translate(tuple(a))

    def bounds(self) -> np.ndarray:
        a, b = np.asarray(self.start, float), np.asarray(self.end, float)
        _, d, _ = self._frame()
        pad = self.radius * np.sqrt(np.clip(1 - d ** 2, 0, 1))
        return np.array([np.minimum(a, b) - pad, np.maximum(a, b) + pad])


@dataclass(frozen=True)
class Union(Solid):
    children: tuple[Solid, ...]

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return np.min([c.sdf(points) for c in self.children], axis=0)

    def manifold(self) -> m3d.Manifold:
        return m3d.Manifold.batch_boolean([c.manifold() for c in self.children], m3d.OpType.Add)

    def bounds(self) -> np.ndarray:
        b = np.array([c.bounds() for c in self.children])
        return np.array([b[:, 0].min(axis=0), b[:, 1].max(axis=0)])


@dataclass(frozen=True)
class Difference(Solid):
    keep: Solid
    cut: Solid

    def sdf(self, points: np.ndarray) -> np.ndarray:
        return np.maximum(self.keep.sdf(points), -self.cut.sdf(points))

    def manifold(self) -> m3d.Manifold:
        return self.keep.manifold() - self.cut.manifold()

    def bounds(self) -> np.ndarray:
        return self.keep.bounds()


@dataclass(frozen=True)
class Transformed(Solid):
    """``child`` moved by a rigid (4, 4) transform (a tilted panel, a knob on it).

    The signed distance of a rigid motion is the child's at the inverse-moved points, so it
    stays exact."""

    child: Solid
    matrix: tuple[tuple[float, ...], ...]
    """(4, 4) rigid transform, row-major, as nested tuples (hashable)."""

    @staticmethod
    def of(child: Solid, T: np.ndarray) -> "Transformed":
        """``child`` moved by the (4, 4) array ``T``."""
        return Transformed(child, tuple(map(tuple, np.asarray(T, float))))

    def sdf(self, points: np.ndarray) -> np.ndarray:
        T = np.asarray(self.matrix)
        return self.child.sdf((points - T[:3, 3]) @ T[:3, :3])

    def manifold(self) -> m3d.Manifold:
        return self.child.manifold().transform(np.asarray(self.matrix)[:3])

    def bounds(self) -> np.ndarray:
        T = np.asarray(self.matrix)
        lo, hi = self.child.bounds()
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        moved = corners @ T[:3, :3].T + T[:3, 3]
        return np.array([moved.min(axis=0), moved.max(axis=0)])


def box_pieces(lo, hi, cuts: list[tuple]) -> list[Box]:
    """The box [lo, hi] minus the boxes ``cuts`` [(lo, hi), ...], as disjoint boxes that touch
    (panels, as an artist builds a carcass from boards).

    The box is cut into a grid at every cut's faces; solid cells are merged greedily, first
    upwards (z), then in depth (y), then across (x), so that walls come out whole."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    clipped = [(np.maximum(np.asarray(a, float), lo), np.minimum(np.asarray(b, float), hi)) for a, b in cuts]
    clipped = [(a, b) for a, b in clipped if np.all(b > a)]
    ticks = [np.unique(np.concatenate([[lo[i], hi[i]], *[[a[i], b[i]] for a, b in clipped]])) for i in range(3)]
    centres = np.meshgrid(*[(t[:-1] + t[1:]) / 2 for t in ticks], indexing="ij")
    points = np.stack([c.ravel() for c in centres], axis=1)
    solid = np.ones(len(points), bool)
    for a, b in clipped:
        solid &= ~np.all((points > a) & (points < b), axis=1)
    solid = solid.reshape(centres[0].shape)
    free = solid.copy()
    pieces = []
    for i, j, k in zip(*np.nonzero(solid)):
        if not free[i, j, k]:
            continue
        k1 = k
        while k1 + 1 < free.shape[2] and free[i, j, k1 + 1]:
            k1 += 1
        j1 = j
        while j1 + 1 < free.shape[1] and free[i, j1 + 1, k:k1 + 1].all():
            j1 += 1
        i1 = i
        while i1 + 1 < free.shape[0] and free[i1 + 1, j:j1 + 1, k:k1 + 1].all():
            i1 += 1
        free[i:i1 + 1, j:j1 + 1, k:k1 + 1] = False
        first, last = (i, j, k), (i1 + 1, j1 + 1, k1 + 1)
        pieces.append(Box(tuple(float(ticks[a][first[a]]) for a in range(3)),
                          tuple(float(ticks[a][last[a]]) for a in range(3))))
    return pieces


def union(solids: list[Solid]) -> Solid:
    """Union of a list (a single solid stays itself)."""
    return solids[0] if len(solids) == 1 else Union(tuple(solids))
