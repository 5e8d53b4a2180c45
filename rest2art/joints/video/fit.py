"""Fitting a rigid joint to 2D tracks by reprojection error.

Rest-pose anchors p0 (the frame-0 track positions unprojected with the mesh's rendered depth)
are moved by the joint model and projected with the known camera; the parameters minimise the
image distance to the tracked positions over all visible (frame, point) pairs:

* revolute: axis w, a point q on it and one angle per frame; p_t = R(w, theta_t)(p0 - q) + q;
* prismatic: direction v and one offset per frame; p_t = p0 + d_t v.

The axis is parameterised around its starting direction (w0 + a e1 + b e2, normalised) and the
pivot by its offset perpendicular to w0, which keeps the problem free of gauge directions and of
the poles of spherical angles. Each sequence (one video) has its own per-frame values and
shares the joint, so the evidence of several videos fits jointly. The solver is scipy's
trust-region least squares with a robust (soft-L1) loss and an analytic Jacobian; several starting hypotheses are tried, the best is
refitted on the points whose error is not an outlier (trimmed refit).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from rest2art.config import ArticulationConfig
from rest2art.geometry.basics import perpendicular_basis
from rest2art.joints.video.motion import prismatic_points, revolute_points, rotation_matrices
from rest2art.joints.video.tracks import Tracks
from rest2art.render.camera import Camera, project, unproject


@dataclass
class Observation:
    """One video's evidence of one part: camera, rest-pose anchors and their tracks."""

    camera: Camera
    anchors: np.ndarray
    """(N, 3) world positions of the tracked points in frame 0, m."""
    tracks: Tracks
    """(T, N) tracks, frame 0 at the anchors' projections."""


@dataclass
class JointFit:
    type: str
    """revolute or prismatic."""
    axis: np.ndarray
    """(3,) unit axis (revolute) or direction (prismatic); positive values open."""
    origin: np.ndarray
    """(3,) a point on the axis (revolute) or the anchors' centroid (prismatic), m."""
    values: list[np.ndarray]
    """Per sequence, (T_used,) angle (rad) or offset (m) per used frame."""
    frames: list[np.ndarray]
    """Per sequence, the indices of the used frames."""
    rmse_px: float
    """Root mean square reprojection error over inlier observations."""
    inlier_fraction: float
    evidence: dict = field(default_factory=dict)

    @property
    def amplitude(self) -> float:
        """Largest opening seen over the sequences (rad or m)."""
        return float(max(np.max(v) for v in self.values))


def anchors_from_depth(camera: Camera, pixels: np.ndarray, depth_map: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) anchors of (N, 2) frame-0 ``pixels`` unprojected with the rendered (H, W) depth
    (nearest pixel), and the (N,) bool mask of pixels that have a depth."""
    cols = np.clip(np.floor(pixels[:, 0]).astype(int), 0, depth_map.shape[1] - 1)
    rows = np.clip(np.floor(pixels[:, 1]).astype(int), 0, depth_map.shape[0] - 1)
    depth = depth_map[rows, cols]
    ok = np.isfinite(depth)
    anchors = np.zeros((len(pixels), 3))
    anchors[ok] = unproject(camera, pixels[ok], depth[ok])
    return anchors, ok


@dataclass
class _Sequence:
    camera: Camera
    anchors: np.ndarray
    xy: np.ndarray        # (T', N', 2) used frames (frame 0 excluded) and points
    visible: np.ndarray   # (T', N') bool
    frames: np.ndarray    # (T',) indices into the original tracks


def _prepare(obs: Observation, max_frames: int, max_points: int, rng: np.random.Generator) -> _Sequence:
    T = obs.tracks.n_frames
    frames = np.unique(np.linspace(1, T - 1, min(max_frames, T - 1)).round().astype(int)) if T > 1 else np.zeros(0, int)
    points = np.arange(obs.tracks.n_points)
    if len(points) > max_points:
        points = np.sort(rng.choice(points, max_points, replace=False))
    return _Sequence(obs.camera, obs.anchors[points], obs.tracks.xy[frames][:, points],
                     obs.tracks.visible[frames][:, points], frames)


def _transfer(x: np.ndarray, source: "_Problem", target: "_Problem") -> np.ndarray:
    """Parameters of ``source`` carried to ``target`` (same joint, other frames): the joint
    re-expressed around the target's starting axis and pivot, per-frame values interpolated."""
    axis, pivot = source.joint(x)
    out = np.zeros(target.n_params)
    if axis @ target.axis0 < 0:
        axis = -axis
    raw = axis / (axis @ target.axis0)
    out[0], out[1] = raw @ target.basis[0], raw @ target.basis[1]
    if target.kind == "revolute":
        out[2], out[3] = (pivot - target.pivot0) @ target.basis[0], (pivot - target.pivot0) @ target.basis[1]
    for k, (s_src, s_dst) in enumerate(zip(source.sequences, target.sequences)):
        values = np.concatenate([[0.0], x[source.value_slices[k]]])
        out[target.value_slices[k]] = np.interp(s_dst.frames, np.concatenate([[0], s_src.frames]), values)
    return out


class _Problem:
    """Residuals and Jacobian sparsity of one joint over several sequences."""

    def __init__(self, kind: str, sequences: list[_Sequence], axis0: np.ndarray, pivot0: np.ndarray):
        self.kind = kind
        self.sequences = sequences
        self.axis0 = axis0 / np.linalg.norm(axis0)
        self.basis = perpendicular_basis(self.axis0)
        self.pivot0 = pivot0 - (pivot0 @ self.axis0) * self.axis0  # the gauge along the axis is fixed
        self.n_global = 4 if kind == "revolute" else 2
        self.masks = [s.visible.copy() for s in sequences]
        self.value_slices = []
        start = self.n_global
        for s in sequences:
            self.value_slices.append(slice(start, start + len(s.frames)))
            start += len(s.frames)
        self.n_params = start

    def joint(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        axis = self.axis0 + x[0] * self.basis[0] + x[1] * self.basis[1]
        axis = axis / np.linalg.norm(axis)
        pivot = self.pivot0 + (x[2] * self.basis[0] + x[3] * self.basis[1] if self.kind == "revolute" else 0.0)
        return axis, pivot

    def predict(self, x: np.ndarray, k: int) -> np.ndarray:
        axis, pivot = self.joint(x)
        s = self.sequences[k]
        values = x[self.value_slices[k]]
        if self.kind == "revolute":
            pts = revolute_points(s.anchors, axis, pivot, values)
        else:
            pts = prismatic_points(s.anchors, axis, values)
        return project(s.camera, pts)

    def residuals(self, x: np.ndarray) -> np.ndarray:
        out = []
        for k, s in enumerate(self.sequences):
            diff = self.predict(x, k) - s.xy
            out.append(diff[self.masks[k]].ravel())
        return np.concatenate(out) if out else np.zeros(0)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """Dense analytic Jacobian of ``residuals`` (rows in the same order)."""
        axis, pivot = self.joint(x)
        raw = self.axis0 + x[0] * self.basis[0] + x[1] * self.basis[1]
        # d axis / d(a, b): the normalisation's tangent projection of e1, e2
        tangent = (np.eye(3) - np.outer(axis, axis)) / np.linalg.norm(raw)
        d_axis = self.basis @ tangent.T                      # (2, 3)
        blocks = []
        for k, s in enumerate(self.sequences):
            values = x[self.value_slices[k]]
            mask = self.masks[k]
            T, N = mask.shape
            if self.kind == "revolute":
                R = rotation_matrices(axis, values)           # (T, 3, 3)
                v = s.anchors - pivot                         # (N, 3)
                rv = np.einsum("tij,nj->tni", R, v)           # (T, N, 3)
                p = rv + pivot
                d_value = np.cross(axis, rv)                  # (T, N, 3)
                sin, cos = np.sin(values)[:, None, None], np.cos(values)[:, None, None]
                wv = v @ axis                                 # (N,)
                d_global = []
                for dw in d_axis:
                    dwv = v @ dw
                    d_global.append(np.cross(dw, v)[None] * sin
                                    + (dw[None, None] * wv[None, :, None] + axis * dwv[None, :, None]) * (1 - cos))
                for e in self.basis:                          # (I - R) e
                    d_global.append(np.broadcast_to(e - np.einsum("tij,j->ti", R, e)[:, None, :], (T, N, 3)))
            else:
                p = s.anchors[None] + values[:, None, None] * axis
                d_value = np.broadcast_to(axis, (T, N, 3))
                d_global = [values[:, None, None] * dw[None, None] * np.ones((1, N, 1)) for dw in d_axis]
            cam = (p - s.camera.eye) @ s.camera.rotation.T    # (T, N, 3)
            z = cam[..., 2]
            f = s.camera.focal
            # d(u, v)/d(world) = f/z [[1, 0, -x/z], [0, 1, -y/z]] R_cam
            P = np.zeros((T, N, 2, 3))
            P[..., 0, 0] = f / z
            P[..., 1, 1] = f / z
            P[..., 0, 2] = -f * cam[..., 0] / z ** 2
            P[..., 1, 2] = -f * cam[..., 1] / z ** 2
            P = P @ s.camera.rotation                          # (T, N, 2, 3)
            J = np.zeros((T, N, 2, self.n_params))
            for g, d in enumerate(d_global):
                J[..., g] = np.einsum("tnij,tnj->tni", P, d)
            cols = np.arange(T) + self.value_slices[k].start
            dv = np.einsum("tnij,tnj->tni", P, d_value)
            J[np.arange(T), :, :, cols] = dv
            blocks.append(J[mask].reshape(-1, self.n_params))
        return np.concatenate(blocks) if blocks else np.zeros((0, self.n_params))

    def point_errors(self, x: np.ndarray, k: int) -> np.ndarray:
        """(N',) median reprojection error (px) of each point over its visible used frames."""
        s = self.sequences[k]
        err = np.linalg.norm(self.predict(x, k) - s.xy, axis=2)
        err = np.where(s.visible, err, np.inf)
        seen = s.visible.sum(axis=0)
        # median over visible frames; a point never seen in the used frames gets inf
        ordered = np.sort(err, axis=0)
        middle = np.clip((seen - 1) // 2, 0, len(err) - 1)
        upper = np.clip(seen // 2, 0, len(err) - 1)
        columns = np.arange(err.shape[1])
        out = 0.5 * (ordered[middle, columns] + ordered[upper, columns])
        return np.where(seen > 0, out, np.inf)


def _grid_values(problem: _Problem, x: np.ndarray, steps: int = 73) -> np.ndarray:
    """``x`` with each frame's value set to the best of a grid (robust cost), the joint held:
    a good start for the per-frame values, which Gauss-Newton from 0 misses for large openings."""
    axis, pivot = problem.joint(x)
    x = x.copy()
    for k, s in enumerate(problem.sequences):
        if problem.kind == "revolute":
            grid = np.linspace(-np.pi, np.pi, steps)
            pts = np.stack([revolute_points(s.anchors, axis, pivot, grid[g:g + 1])[0] for g in range(steps)])
        else:
            reach = 2.0 * float(np.ptp(s.anchors, axis=0).max())
            grid = np.linspace(-reach, reach, steps)
            pts = s.anchors[None] + grid[:, None, None] * axis
        xy = project(s.camera, pts)                                    # (G, N, 2)
        err = np.linalg.norm(xy[:, None] - s.xy[None], axis=3)        # (G, T, N)
        cost = np.where(problem.masks[k][None], np.sqrt(1 + err ** 2) - 1, 0.0).sum(axis=2)
        x[problem.value_slices[k]] = grid[np.argmin(cost, axis=0)]
    return x


def _solve(problem: _Problem, x0: np.ndarray, options: ArticulationConfig, values_only: bool = False,
           max_nfev: int | None = None) -> tuple[np.ndarray, float]:
    """Robust least squares from ``x0``; with ``values_only`` the joint stays fixed and only the
    per-frame values move."""
    if values_only:
        fixed = x0[:problem.n_global]

        def f(v):
            return problem.residuals(np.concatenate([fixed, v]))

        def jac(v):
            return problem.jacobian(np.concatenate([fixed, v]))[:, problem.n_global:]

        r = least_squares(f, x0[problem.n_global:], jac=jac, loss="soft_l1", tr_solver="exact",
                          f_scale=options.loss_scale_px, max_nfev=max_nfev or 20, ftol=1e-6, xtol=1e-6)
        return np.concatenate([fixed, r.x]), float(r.cost)
    r = least_squares(problem.residuals, x0, jac=problem.jacobian, loss="soft_l1", tr_solver="exact",
                      f_scale=options.loss_scale_px, max_nfev=max_nfev or 100, ftol=1e-6, xtol=1e-6)
    return r.x, float(r.cost)


def fit_joint(kind: str, observations: list[Observation], starts: list[tuple[np.ndarray, np.ndarray]],
              options: ArticulationConfig = ArticulationConfig(), seed: int = 0) -> JointFit | None:
    """Best ``kind`` joint ('revolute' or 'prismatic') for the observations (one per video).

    ``starts``: (axis, point) hypotheses to start from (the point is ignored for prismatic).
    Every start first fits only the per-frame values; the ``refine_best`` best go on to the full
    fit; the winner is refitted without outlier points. None when there is nothing to fit."""
    rng = np.random.default_rng(seed)
    usable = [o for o in observations if o.tracks.n_frames > 1 and o.tracks.n_points and o.tracks.visible[1:].any()]
    if not usable or not starts:
        return None
    sequences = [_prepare(o, options.max_frames, options.max_points, rng) for o in usable]
    coarse = [_prepare(o, options.coarse_frames, options.coarse_points, rng) for o in usable]
    tried = []
    for axis0, pivot0 in starts:
        problem = _Problem(kind, coarse, np.asarray(axis0, float), np.asarray(pivot0, float))
        x, cost = _solve(problem, _grid_values(problem, np.zeros(problem.n_params)), options, values_only=True)
        tried.append((cost, problem, x))
    tried.sort(key=lambda item: item[0])
    best = None
    for _, problem, x in tried[:options.refine_best]:
        x, cost = _solve(problem, x, options)
        if best is None or cost < best[0]:
            best = (cost, problem, x)
    coarse_problem, x_coarse = best[1], best[2]
    axis0, pivot0 = coarse_problem.joint(x_coarse)
    problem = _Problem(kind, sequences, axis0, pivot0)
    x, _ = _solve(problem, _transfer(x_coarse, coarse_problem, problem), options)
    # trimmed refit: points whose median error is an outlier are dropped, then fit again
    kept = 0
    total = 0
    for k, s in enumerate(sequences):
        err = problem.point_errors(x, k)
        finite = err[np.isfinite(err)]
        threshold = max(options.outlier_factor * float(np.median(finite)) if len(finite) else 0.0,
                        options.outlier_floor_px)
        inlier = err <= threshold
        problem.masks[k] = s.visible & inlier[None, :]
        kept += int(inlier.sum())
        total += len(inlier)
    x, _ = _solve(problem, x, options)
    residual = problem.residuals(x).reshape(-1, 2)
    rmse = float(np.sqrt(np.mean(np.sum(residual ** 2, axis=1)))) if len(residual) else float("inf")
    axis, pivot = problem.joint(x)
    values = [np.concatenate([[0.0], x[sl]]) for sl in problem.value_slices]
    frames = [np.concatenate([[0], s.frames]) for s in sequences]
    # positive values open: the sign of the largest excursion decides
    extreme = max((v[np.argmax(np.abs(v))] for v in values), key=abs)
    if extreme < 0:
        axis = -axis
        values = [-v for v in values]
    if kind == "prismatic":
        pivot = np.concatenate([s.anchors for s in sequences]).mean(axis=0)
    else:  # the point on the axis nearest the anchors' centroid
        centroid = np.concatenate([s.anchors for s in sequences]).mean(axis=0)
        pivot = pivot + ((centroid - pivot) @ axis) * axis
    return JointFit(kind, axis, pivot, values, frames, rmse, kept / max(total, 1),
                    {"starts": len(starts), "cost": float(best[0])})


def box_starts(kind: str, anchors: np.ndarray, axes: np.ndarray = np.eye(3)) -> list[tuple[np.ndarray, np.ndarray]]:
    """Generic starting hypotheses from the anchors' axis-aligned box: for each of ``axes``
    (rows), a revolute start on each of the four box edges parallel to it (prismatic: the axis
    alone)."""
    lo, hi = anchors.min(axis=0), anchors.max(axis=0)
    centre = (lo + hi) / 2
    starts = []
    for axis in axes:
        if kind == "prismatic":
            starts.append((axis, centre))
            continue
        starts.append((axis, centre))  # a part turning about its own axis (a knob)
        e = perpendicular_basis(axis)
        corners = np.array([lo, hi])
        for s1 in (0, 1):
            for s2 in (0, 1):
                p1 = (corners @ e[0]).min() if s1 == 0 else (corners @ e[0]).max()
                p2 = (corners @ e[1]).min() if s2 == 0 else (corners @ e[1]).max()
                point = centre + (p1 - centre @ e[0]) * e[0] + (p2 - centre @ e[1]) * e[1]
                starts.append((axis, point))
    return starts
