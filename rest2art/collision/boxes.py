"""Box decomposition of closed solids: walls, shelves and frames as boxes.

A carcass is mostly boards aligned with the object's frame. Its collision is built from that:
the solid is sampled on a grid aligned with the frame (the share of each cell inside the solid,
exact along one axis from the surface crossings and sampled 2 x 2 across it), the occupied
cells are merged greedily into the fewest boxes, and each box face is moved to where the solid
actually ends inside its boundary layer of cells. Openings, the space behind a door and a
drawer's cavity stay empty: the result is hollow where the solid is, unlike one convex hull.
Where the solid is not made of boards (a slope, a curve) the staircase needs many boxes, and
the caller keeps CoACD for it (``BoxFit.boxes`` counts them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from rest2art.tolerances import TINY

_JITTER = np.array([0.3183099, 0.2718282]) * 1e-3
"""Sub-column offsets (share of a cell) so that sample lines miss the edges of axis-aligned
triangles, which artist meshes put on round coordinates."""


@dataclass(frozen=True)
class OccupancyGrid:
    """Share of each cell of a grid aligned with ``rotation`` that lies inside a solid."""

    fill: np.ndarray
    """(nx, ny, nz) inside share per cell, 0..1."""
    origin: np.ndarray
    """(3,) the grid's lowest corner, in the rotated frame (m)."""
    pitch: float
    """Cell size (m)."""
    rotation: np.ndarray
    """(3, 3) rows: the grid axes in the mesh frame."""


@dataclass(frozen=True)
class BoxFit:
    """Boxes that fill a solid, and how well."""

    hulls: list[trimesh.Trimesh]
    """One closed box per piece, in the mesh frame (they may overlap)."""
    covered: float
    """Share of the solid's volume inside the boxes (on the grid)."""
    excess: float
    """Empty volume inside the boxes, as a share of the solid's volume (on the grid)."""
    pitch: float
    """Cell size (m) the boxes were found on."""

    @property
    def boxes(self) -> int:
        return len(self.hulls)


def grid_pitch(extents: np.ndarray, pitch: float, max_cells: int) -> float:
    """The cell size for a solid of (3,) ``extents`` (m): ``pitch``, or coarser where the grid
    would exceed ``max_cells`` cells."""
    cells = np.prod(np.maximum(np.asarray(extents, float) / pitch, 1.0))
    return float(pitch * max(1.0, (cells / max_cells) ** (1.0 / 3.0)))


def occupancy(vertices: np.ndarray, faces: np.ndarray, rotation: np.ndarray, pitch: float) -> OccupancyGrid:
    """The inside share of every cell of a closed, outward-wound mesh ((V, 3) ``vertices`` in
    m, (F, 3) ``faces``) on a grid of ``pitch`` (m) aligned with the rows of ``rotation``.

    Along the grid's third axis the share is exact: the inside length of each sample line is
    accumulated from its surface crossings (entering where the face looks down, leaving where
    it looks up). Across it, each cell is sampled by 2 x 2 lines. A mesh that is not closed
    gives meaningless shares."""
    local = np.asarray(vertices, float) @ np.asarray(rotation, float).T
    lo, hi = local.min(axis=0), local.max(axis=0)
    shape = np.maximum(np.ceil((hi - lo) / pitch - 1e-6).astype(int), 1)
    origin = lo  # outer faces on cell borders: a carcass's outer walls fill whole cells
    nx, ny, nz = shape
    tri = local[np.asarray(faces)]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    normal_z = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]  # twice the signed projected area
    keep = np.abs(normal_z) > 1e-14
    tri, normal_z = tri[keep], normal_z[keep]
    # sample lines at (i + 1/4) and (i + 3/4) cells across, slightly jittered
    sub = pitch / 2
    start = origin[:2] + sub * (0.5 + _JITTER)
    tlo = np.ceil((tri[:, :, :2].min(axis=1) - start) / sub).astype(int)
    thi = np.floor((tri[:, :, :2].max(axis=1) - start) / sub).astype(int)
    tlo = np.maximum(tlo, 0)
    thi = np.minimum(thi, [2 * nx - 1, 2 * ny - 1])
    counts = np.maximum(thi - tlo + 1, 0)
    per_tri = counts[:, 0] * counts[:, 1]
    which = np.repeat(np.arange(len(tri)), per_tri)
    offset = np.arange(len(which)) - np.repeat(np.cumsum(per_tri) - per_tri, per_tri)
    width = np.maximum(counts[which, 0], 1)
    col = np.column_stack([tlo[which, 0] + offset % width, tlo[which, 1] + offset // width])
    p = start + col * sub
    a, b, c = tri[which, 0], tri[which, 1], tri[which, 2]
    # barycentric coordinates of the line in the projected triangle
    d = normal_z[which]
    w_a = ((b[:, 0] - p[:, 0]) * (c[:, 1] - p[:, 1]) - (b[:, 1] - p[:, 1]) * (c[:, 0] - p[:, 0])) / d
    w_b = ((c[:, 0] - p[:, 0]) * (a[:, 1] - p[:, 1]) - (c[:, 1] - p[:, 1]) * (a[:, 0] - p[:, 0])) / d
    w_c = 1.0 - w_a - w_b
    inside = (w_a >= 0) & (w_b >= 0) & (w_c >= 0)
    z = (w_a * a[:, 2] + w_b * b[:, 2] + w_c * c[:, 2])[inside]
    sign = np.where(d[inside] < 0, 1.0, -1.0)  # faces looking down are entered going up
    if np.linalg.det(rotation) < 0:  # a mirroring frame turns the winding inside out
        sign = -sign
    cell = col[inside] // 2
    # inside length below each cell edge e: F(e) = e * S(e) - Z(e), S and Z summed over crossings below e
    edge = np.clip(np.ceil((z - origin[2]) / pitch).astype(int), 0, nz)
    index = np.ravel_multi_index((cell[:, 0], cell[:, 1], edge), (nx, ny, nz + 1))
    s_acc = np.bincount(index, sign / 4, minlength=nx * ny * (nz + 1)).reshape(nx, ny, nz + 1)
    z_acc = np.bincount(index, sign * z / 4, minlength=nx * ny * (nz + 1)).reshape(nx, ny, nz + 1)
    edges = origin[2] + pitch * np.arange(nz + 1)
    below = edges * np.cumsum(s_acc, axis=2) - np.cumsum(z_acc, axis=2)
    fill = np.clip(np.diff(below, axis=2) / pitch, 0.0, 1.0)
    return OccupancyGrid(fill, origin, float(pitch), np.asarray(rotation, float))


def greedy_boxes(fill: np.ndarray, min_fill: float, min_layer_share: float = 0.8) -> list[tuple[np.ndarray, np.ndarray]]:
    """Boxes of cells covering every cell of (nx, ny, nz) ``fill`` (inside shares) that is at
    least ``min_fill``: (lo, hi) index pairs, hi exclusive. From each first cell not yet
    covered, the box grows along each axis in turn while the layer it would add is filled on
    average to ``min_fill`` and ``min_layer_share`` of its cells are (a board's partly filled
    outer layer joins the board; a wall grows through the shelf that meets it, so boxes may
    overlap; a floor does not grow up through a cavity whose thick walls fill the layer on
    average); of the three axis orders, the box that covers most new cells is kept."""
    seeds_all = fill >= min_fill
    seeds = seeds_all.copy()
    flat = seeds.reshape(-1)  # a view: covering cells clears their seeds here
    boxes = []
    orders = ((0, 1, 2), (1, 2, 0), (2, 0, 1))
    position = 0
    while position < flat.size:
        position += int(np.argmax(flat[position:]))  # boxes grow forward: every earlier cell is covered
        if not flat[position]:
            break
        seed = np.array(np.unravel_index(position, fill.shape))
        best = None
        for order in orders:
            lo, hi = seed.copy(), seed + 1
            for axis in order:
                while hi[axis] < fill.shape[axis]:
                    slab_lo, slab_hi = lo.copy(), hi.copy()
                    slab_lo[axis], slab_hi[axis] = hi[axis], hi[axis] + 1
                    slab = (slice(slab_lo[0], slab_hi[0]), slice(slab_lo[1], slab_hi[1]),
                            slice(slab_lo[2], slab_hi[2]))
                    if fill[slab].mean() < min_fill or seeds_all[slab].mean() < min_layer_share:
                        break
                    hi[axis] += 1
            new = int(seeds[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]].sum())
            if best is None or new > best[2]:
                best = (lo, hi, new)
        lo, hi, _ = best
        seeds[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]] = False
        boxes.append((lo, hi))
    return boxes


def tightened(grid: OccupancyGrid, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (3,) low and high corners (rotated frame, m) of the cell box [lo, hi) with each face
    moved inward by the empty share of its boundary layer of cells (a wall 13 mm thick on 5 mm
    cells is 13 mm thick, not 15), keeping at least a tenth of a cell."""
    low = grid.origin + grid.pitch * lo
    high = grid.origin + grid.pitch * hi
    block = grid.fill[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]
    for axis in range(3):
        if hi[axis] - lo[axis] < 1:
            continue
        first = float(np.take(block, 0, axis=axis).mean())
        last = float(np.take(block, -1, axis=axis).mean())
        if hi[axis] - lo[axis] == 1:
            thickness = max(first, 0.1) * grid.pitch
            centre = (low[axis] + high[axis]) / 2
            low[axis], high[axis] = centre - thickness / 2, centre + thickness / 2
            continue
        low[axis] += (1.0 - first) * grid.pitch
        high[axis] -= (1.0 - last) * grid.pitch
    return low, high


def box_mesh(low: np.ndarray, high: np.ndarray, rotation: np.ndarray) -> trimesh.Trimesh:
    """The closed box [low, high] of the frame whose axes are the rows of ``rotation``, as a
    mesh in the unrotated frame."""
    box = trimesh.creation.box(extents=high - low)
    box.apply_translation((low + high) / 2)
    box.vertices = np.asarray(box.vertices) @ rotation
    return box


def fit_boxes(solid: trimesh.Trimesh, rotation: np.ndarray, pitch: float, max_cells: int, min_fill: float,
              min_box_share: float, edge_cells: int = 1, min_layer_share: float = 0.8, surface_cells: float = 0.0,
              surface_samples: int = 4000, surface_panel_ratio: float = 0.35) -> BoxFit:
    """Boxes filling the closed ``solid`` on a grid aligned with ``rotation`` ((3, 3), rows the
    axes): cells whose inside share is at least ``min_fill`` are merged into boxes
    (``greedy_boxes``) and tightened to the solid; a box that adds less than ``min_box_share``
    of the occupied cells to those before it is left out when it stays within ``edge_cells``
    cells of the larger boxes' outline (the rounded edges of a fused scan give rings of thin
    boxes) and kept when it reaches further out and is at least a cell thick (a handle or knob
    on a door's board is a small share of it, but it is what a hand grasps). ``pitch`` (m) is
    coarsened to stay within ``max_cells`` cells; ``min_layer_share`` as in ``greedy_boxes``.
    With ``surface_cells`` > 0, the surface (its vertices and ``surface_samples`` points) that
    stands out of a panel's boxes by more than that many cells gets hulls of its own
    (``proud_hulls``)."""
    extents = np.ptp(np.asarray(solid.vertices) @ np.asarray(rotation, float).T, axis=0)
    grid = occupancy(solid.vertices, solid.faces, rotation, grid_pitch(extents, pitch, max_cells))
    occupied = grid.fill >= min_fill
    total = max(int(occupied.sum()), 1)
    inside = np.zeros(grid.fill.shape, bool)
    large, small = [], []
    for lo, hi in greedy_boxes(grid.fill, min_fill, min_layer_share):
        cells = (slice(lo[0], hi[0]), slice(lo[1], hi[1]), slice(lo[2], hi[2]))
        if (occupied[cells] & ~inside[cells]).sum() < min_box_share * total:
            small.append((lo, hi))
            continue
        inside[cells] = True
        large.append((lo, hi))
    if large:
        outline_lo = np.min([lo for lo, _ in large], axis=0) - edge_cells
        outline_hi = np.max([hi for _, hi in large], axis=0) + edge_cells
        small = [(lo, hi) for lo, hi in small if (lo < outline_lo).any() or (hi > outline_hi).any()]
    hulls, corners = [], []
    for k, (lo, hi) in enumerate(large + small):
        low, high = tightened(grid, lo, hi)
        if k >= len(large) and (high - low).min() < grid.pitch:
            continue  # a strip of a scan's ragged rim, thinner than a cell: nothing to hold
        inside[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]] = True
        corners.append((low, high))
        hulls.append(box_mesh(low, high, grid.rotation))
    if corners and surface_cells > 0:
        hulls += proud_hulls(solid, corners, surface_cells * grid.pitch, grid.rotation, grid.pitch,
                             surface_panel_ratio, surface_samples)
    volume = max(float(grid.fill.sum()), TINY)
    return BoxFit(hulls, float(grid.fill[inside].sum()) / volume, float((1.0 - grid.fill[inside]).sum()) / volume,
                  grid.pitch)


def proud_hulls(solid: trimesh.Trimesh, corners: list[tuple[np.ndarray, np.ndarray]], tolerance: float,
                rotation: np.ndarray, min_thickness: float, panel_ratio: float, samples: int, min_points: int = 8
                ) -> list[trimesh.Trimesh]:
    """Hulls for what the boxes miss and a hand would touch: points of the ``solid``'s surface
    (its vertices and ``samples`` seeded samples) farther than ``tolerance`` (m) from every box
    (``corners``: (low, high) in the frame whose axes are the rows of ``rotation``) are grouped
    (neighbours within two tolerances). Only a panel has them (its boxes' outline is at most ``panel_ratio``
    as thick as its median extent): each group that reaches out of the outline along the
    panel's normal, stands at least two tolerances off the boxes and is at least
    ``min_thickness`` (m) thick gets its convex hull (in the mesh frame); a scan's ragged rim
    spreads in the panel's plane instead. A fused scan's handle is a thin
    thickened shell that fills too little of its cells to become a box, and without it a
    gripper closes on nothing; thin walls inside the outline stay out (their hull could span
    a cavity)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    from rest2art.collision.hulls import box_gaps, closed_hull

    outline_lo = np.min([lo for lo, _ in corners], axis=0) - tolerance
    outline_hi = np.max([hi for _, hi in corners], axis=0) + tolerance
    extents = outline_hi - outline_lo
    normal = int(np.argmin(extents))
    if extents[normal] > panel_ratio * np.median(extents):
        return []  # not a panel: what stands out of a carcass is not a handle to hold it by
    points = np.concatenate([np.asarray(solid.vertices), trimesh.sample.sample_surface(solid, samples, seed=0)[0]])
    points = points @ rotation.T
    low, high = np.array([lo for lo, _ in corners]), np.array([hi for _, hi in corners])
    distance = box_gaps(points, points, low, high).min(axis=1)
    keep = distance > tolerance
    far, distance = points[keep], distance[keep]
    if len(far) < min_points:
        return []
    pairs = cKDTree(far).query_pairs(2 * tolerance, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(far), len(far)))
    _, labels = connected_components(graph, directed=False)
    hulls = []
    for label in np.unique(labels):
        mine = labels == label
        group = far[mine]
        out = ((group[:, normal] < outline_lo[normal]) | (group[:, normal] > outline_hi[normal])).any()
        if len(group) < min_points or not out or distance[mine].max() < 2 * tolerance:
            continue  # a scan's ragged rim along the boxes, not something standing out
        thinnest = np.linalg.svd(group - group.mean(axis=0), compute_uv=False)[-1] / np.sqrt(len(group))
        if 4 * thinnest < min_thickness:  # a strip: about 4 standard deviations across
            continue
        hull = closed_hull(group @ rotation)
        if hull is not None:
            hulls.append(hull)
    return hulls
