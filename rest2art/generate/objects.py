"""Procedural articulated objects with exact ground truth, in the canonical frame.

Frame: metres, +z up (the object stands on z = 0), -y is the front, x to the right.
Every movable front is separated from the carcass by a gap of 2-6 mm. Hinges sit where real
hardware puts them so that nothing collides while opening: a side-hinged inset door (inside the
opening) pivots on the edge of its front face, a side-hinged overlay door (in front of the
carcass) on the edge of its back face, so its corners never swing into the carcass or a
neighbouring door; a flip-down door pivots on its bottom front edge (its back corner swings up
into its own space, clear of a drawer below); a lid pivots on the back edge of its underside.

A part is a list of *pieces*: closed solids an artist would model separately (a drawer front,
its box, its handle). Handles are fixed to their panel and belong to its part.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rest2art.generate.csg import Box, Cylinder, Solid, union
from rest2art.geometry import opening_axis

KINDS = ("cabinet", "microwave", "fridge", "oven", "box", "laptop")


@dataclass
class PartSpec:
    name: str
    semantic: str
    pieces: list[Solid]
    joint: dict | None = None
    """None for the base; else type, axis, origin, limit (canonical frame)."""
    parent: str = "base"


@dataclass
class ObjectSpec:
    kind: str
    parts: list[PartSpec] = field(default_factory=list)
    params: dict = field(default_factory=dict)


class _Builder:
    """Shared randomness and helpers for one object."""

    def __init__(self, rng: np.random.Generator, kind: str):
        self.rng = rng
        self.spec = ObjectSpec(kind)
        self.gap = float(rng.uniform(0.002, 0.006))
        self.counts: dict[str, int] = {}

    def u(self, lo: float, hi: float) -> float:
        return float(self.rng.uniform(lo, hi))

    def name(self, semantic: str) -> str:
        n = self.counts.get(semantic, 0)
        self.counts[semantic] = n + 1
        return f"{semantic}_{n}"

    # ---- handles ---------------------------------------------------------------------------

    def handle(self, panel_lo, panel_hi, where: np.ndarray, orient: str, style: str) -> tuple[list[Solid], Solid | None]:
        """Handle pieces on the front (-y) of a panel at ``where`` (x, z).

        Returns (pieces to add, solid to cut from the panel or None).
        """
        y0 = panel_lo[1]
        x, z = float(where[0]), float(where[1])
        if style == "recessed":
            w, h = (0.10, 0.025) if orient == "h" else (0.025, 0.10)
            depth = min(0.008, 0.5 * (panel_hi[1] - panel_lo[1]))
            cut = Box((x - w / 2, y0 - 0.01, z - h / 2), (x + w / 2, y0 + depth, z + h / 2))
            return [], cut
        if style == "knob":
            r = self.u(0.012, 0.02)
            return [Cylinder((x, y0, z), (x, y0 - self.u(0.022, 0.032), z), r)], None
        length = self.u(0.10, 0.22) if orient == "h" else self.u(0.15, 0.35)
        standoff, thick = self.u(0.025, 0.035), 0.012
        post = 0.01
        if orient == "v":
            length = min(length, 0.7 * (panel_hi[2] - panel_lo[2]))
            ends = [(x, z - length / 2 + post), (x, z + length / 2 - post)]
            bar = Box((x - thick / 2, y0 - standoff - thick, z - length / 2),
                      (x + thick / 2, y0 - standoff, z + length / 2))
        else:
            length = min(length, 0.7 * (panel_hi[0] - panel_lo[0]))
            ends = [(x - length / 2 + post, z), (x + length / 2 - post, z)]
            bar = Box((x - length / 2, y0 - standoff - thick, z - thick / 2),
                      (x + length / 2, y0 - standoff, z + thick / 2))
        posts = [Box((ex - post / 2, y0 - standoff, ez - post / 2), (ex + post / 2, y0, ez + post / 2))
                 for ex, ez in ends]
        return [union([bar, *posts])], None

    def handle_style(self) -> str:
        return str(self.rng.choice(["bar", "bar", "knob", "recessed"]))

    # ---- movable fronts --------------------------------------------------------------------

    def panel(self, lo, hi, cut: Solid | None) -> Solid:
        box = Box(tuple(lo), tuple(hi))
        return box - cut if cut is not None else box

    def drawer(self, lo, hi, cavity_lo, cavity_hi, style: str) -> PartSpec:
        """Drawer with front panel [lo, hi] and a box filling the cavity behind it."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        centre = (lo + hi) / 2
        pieces, cut = self.handle(lo, hi, np.array([centre[0], centre[2] + 0.15 * (hi[2] - lo[2])]), "h", style)
        front = self.panel(lo, hi, cut)
        clear, wall = 0.005, 0.012
        bx0, bx1 = cavity_lo[0] + clear, cavity_hi[0] - clear
        bz0, bz1 = cavity_lo[2] + clear, cavity_hi[2] - max(0.02, 0.15 * (cavity_hi[2] - cavity_lo[2]))
        by0, by1 = hi[1], cavity_hi[1] - 0.01
        body = union([
            Box((bx0, by0, bz0), (bx1, by1, bz0 + wall)),
            Box((bx0, by0, bz0), (bx0 + wall, by1, bz1)),
            Box((bx1 - wall, by0, bz0), (bx1, by1, bz1)),
            Box((bx0, by1 - wall, bz0), (bx1, by1, bz1)),
        ])
        return PartSpec(self.name("drawer"), "drawer", [front, body, *pieces], {
            "type": "prismatic", "axis": [0.0, -1.0, 0.0], "origin": centre.tolist(),
            "limit": [0.0, float(min(by1 - by0, 0.9 * self.spec.params["depth"]))],
        }, )

    def door(self, lo, hi, hinge: str, style: str, limit_deg: float, overlay: bool, semantic: str = "door") -> PartSpec:
        """Door panel [lo, hi] hinged on its 'left', 'right' or 'bottom' edge (back face edge
        for an overlay door, front face edge for an inset one)."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        centre = (lo + hi) / 2
        y_hinge = hi[1] if (overlay and hinge != "bottom") else lo[1]
        w, h = hi[0] - lo[0], hi[2] - lo[2]
        inset = min(0.06, 0.12 * w)
        if hinge == "left":
            where, orient = np.array([hi[0] - inset, centre[2]]), "v"
            q, axis = np.array([lo[0], y_hinge, centre[2]]), np.array([0.0, 0.0, 1.0])
        elif hinge == "right":
            where, orient = np.array([lo[0] + inset, centre[2]]), "v"
            q, axis = np.array([hi[0], y_hinge, centre[2]]), np.array([0.0, 0.0, 1.0])
        else:
            where, orient = np.array([centre[0], hi[2] - min(0.05, 0.12 * h)]), "h"
            q, axis = np.array([centre[0], y_hinge, lo[2]]), np.array([1.0, 0.0, 0.0])
        pieces, cut = self.handle(lo, hi, where, orient, style)
        axis = opening_axis(axis, q, centre, np.array([0.0, -1.0, 0.0]))
        return PartSpec(self.name(semantic), semantic, [self.panel(lo, hi, cut), *pieces], {
            "type": "revolute", "axis": axis.tolist(), "origin": q.tolist(),
            "limit": [0.0, float(np.radians(limit_deg))],
        })


def _carcass(W: float, D: float, H: float, t: float, cavities: list[tuple], z0: float = 0.0) -> Solid:
    """Outer box minus open-front cavities, each (lo, hi)."""
    outer = Box((-W / 2, -D / 2, z0), (W / 2, D / 2, H))
    solid: Solid = outer
    for lo, hi in cavities:
        solid = solid - Box(tuple(lo), tuple(hi))
    return solid


def _split(lo: float, hi: float, n: int, t: float, rng, jitter: float = 0.25) -> list[tuple[float, float]]:
    """Split [lo, hi] into n cells separated by dividers of thickness t (random proportions)."""
    weights = 1.0 + rng.uniform(-jitter, jitter, n)
    usable = hi - lo - (n - 1) * t
    sizes = usable * weights / weights.sum()
    cells, start = [], lo
    for s in sizes:
        cells.append((start, start + s))
        start += s + t
    return cells


def _front(b: _Builder, cell_lo, cell_hi, D: float, t: float, overlay: bool, tf: float):
    """Panel bounds for a front covering the cell (x, z ranges) in inset or overlay style."""
    g = b.gap
    if overlay:
        grow = t / 2 - g / 2
        lo = [cell_lo[0] - grow, -D / 2 - g - tf, cell_lo[1] - grow]
        hi = [cell_hi[0] + grow, -D / 2 - g, cell_hi[1] + grow]
    else:
        lo = [cell_lo[0] + g, -D / 2, cell_lo[1] + g]
        hi = [cell_hi[0] - g, -D / 2 + tf, cell_hi[1] - g]
    return lo, hi


def build_cabinet(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "cabinet")
    W, D, H = b.u(0.45, 1.2), b.u(0.35, 0.6), b.u(0.45, 1.2)
    t = b.u(0.015, 0.025)
    plinth = b.u(0.05, 0.1) if rng.random() < 0.4 else 0.0
    overlay = bool(rng.random() < 0.5)
    tf = b.u(0.016, 0.022)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap, overlay=overlay)
    n_cols = int(rng.integers(1, 4 if W > 0.8 else 3))
    style = b.handle_style()
    cavities, fronts = [], []
    for (x0, x1) in _split(-W / 2 + t, W / 2 - t, n_cols, t, rng):
        col_kind = rng.choice(["drawers", "doors", "mixed"])
        n_rows = int(rng.integers(1, 5)) if col_kind == "drawers" else int(rng.integers(1, 3))
        for (z0, z1) in _split(plinth + t, H - t, n_rows, t, rng):
            cavity = ([x0, -D / 2 - 0.01, z0], [x1, D / 2 - t, z1])
            cavities.append(cavity)
            h, w = z1 - z0, x1 - x0
            if col_kind == "drawers" or (col_kind == "mixed" and h < 0.3):
                kind = "drawer"
            elif w > 0.55 and rng.random() < 0.7:
                kind = "double"
            elif h < 0.45 and w > h and rng.random() < 0.5:
                kind = "flip"
            else:
                kind = "door"
            fronts.append((kind, (x0, z0), (x1, z1), cavity))
    for kind, cell_lo, cell_hi, cavity in fronts:
        if kind == "double":
            xm = (cell_lo[0] + cell_hi[0]) / 2
            for lo_x, hi_x, hinge in ((cell_lo[0], xm + t / 2, "left"), (xm - t / 2, cell_hi[0], "right")):
                # two leaves meeting at the middle: the shared edge gets one gap
                a, bb = _front(b, (lo_x, cell_lo[1]), (hi_x, cell_hi[1]), D, t, overlay, tf)
                if hinge == "left":
                    bb[0] = xm - b.gap / 2
                else:
                    a[0] = xm + b.gap / 2
                b.spec.parts.append(b.door(a, bb, hinge, style, 90.0, overlay))
            continue
        lo, hi = _front(b, cell_lo, cell_hi, D, t, overlay, tf)
        if kind == "drawer":
            b.spec.parts.append(b.drawer(lo, hi, *cavity, style))
        elif kind == "flip":
            b.spec.parts.append(b.door(lo, hi, "bottom", style, 90.0, overlay))
        else:
            b.spec.parts.append(b.door(lo, hi, str(rng.choice(["left", "right"])), style, 90.0, overlay))
    b.spec.parts.insert(0, PartSpec("base", "base", [_carcass(W, D, H, t, cavities)], None))
    return b.spec


def build_microwave(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "microwave")
    W, D, H = b.u(0.45, 0.62), b.u(0.33, 0.45), b.u(0.26, 0.36)
    t = b.u(0.012, 0.02)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    panel_w = b.u(0.22, 0.3) * W
    x_split = W / 2 - panel_w
    cavity = ([-W / 2 + t, -D / 2 - 0.01, t], [x_split - t, D / 2 - t, H - t])
    base = _carcass(W, D, H, t, [cavity])
    buttons = []
    for k in range(int(rng.integers(2, 5))):
        z = H - 0.05 - k * 0.045
        if z < 0.04:
            break
        x = x_split + panel_w / 2
        buttons.append(Box((x - 0.02, -D / 2 - 0.004, z - 0.012), (x + 0.02, -D / 2 + 0.001, z + 0.012)))
    b.spec.parts.append(PartSpec("base", "base", [union([base, *buttons])]))
    tf = b.u(0.02, 0.03)
    lo = [-W / 2 + b.gap, -D / 2 - tf - b.gap, b.gap]
    hi = [x_split - b.gap, -D / 2 - b.gap, H - b.gap]
    b.spec.parts.append(b.door(lo, hi, "left", str(rng.choice(["bar", "recessed"])), 110.0, True))
    return b.spec


def build_fridge(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "fridge")
    W, D, H = b.u(0.55, 0.85), b.u(0.55, 0.72), b.u(1.3, 1.9)
    t = b.u(0.03, 0.05)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    layout = str(rng.choice(["single", "top-freezer", "side-by-side"]))
    hinge = str(rng.choice(["left", "right"]))
    tf = b.u(0.04, 0.06)
    cells = []
    if layout == "single":
        cells.append(((-W / 2 + t, t), (W / 2 - t, H - t), hinge))
    elif layout == "top-freezer":
        zs = H * b.u(0.6, 0.72)
        cells.append(((-W / 2 + t, t), (W / 2 - t, zs - t / 2), hinge))
        cells.append(((-W / 2 + t, zs + t / 2), (W / 2 - t, H - t), hinge))
    else:
        xs = b.u(-0.1, 0.1) * W
        cells.append(((-W / 2 + t, t), (xs - t / 2, H - t), "left"))
        cells.append(((xs + t / 2, t), (W / 2 - t, H - t), "right"))
    cavities = [([lo[0], -D / 2 - 0.01, lo[1]], [hi[0], D / 2 - t, hi[1]]) for lo, hi, _ in cells]
    b.spec.parts.append(PartSpec("base", "base", [_carcass(W, D, H, t, cavities)]))
    for lo, hi, side in cells:
        plo, phi = _front(b, lo, hi, D, t, True, tf)
        b.spec.parts.append(b.door(plo, phi, side, "bar", 110.0, True))
    return b.spec


def build_oven(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "oven")
    W, D, H = b.u(0.5, 0.78), b.u(0.52, 0.66), b.u(0.8, 0.95)
    t = b.u(0.02, 0.035)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    panel_h = b.u(0.08, 0.13)
    has_drawer = bool(rng.random() < 0.5)
    drawer_h = b.u(0.12, 0.18) if has_drawer else 0.0
    z_door0 = t + (drawer_h + t if has_drawer else 0.0)
    z_door1 = H - panel_h
    cavities = [([-W / 2 + t, -D / 2 - 0.01, z_door0], [W / 2 - t, D / 2 - t, z_door1 - t])]
    if has_drawer:
        cavities.append(([-W / 2 + t, -D / 2 - 0.01, t], [W / 2 - t, D / 2 - t, t + drawer_h]))
    b.spec.parts.append(PartSpec("base", "base", [_carcass(W, D, H, t, cavities)]))
    tf = b.u(0.03, 0.05)
    lo = [-W / 2 + b.gap, -D / 2 - tf - b.gap, z_door0 - t / 2 + b.gap]
    hi = [W / 2 - b.gap, -D / 2 - b.gap, z_door1 - t / 2 - b.gap]
    b.spec.parts.append(b.door(lo, hi, "bottom", "bar", 90.0, True))
    if has_drawer:
        cav = cavities[1]
        plo, phi = _front(b, (cav[0][0], cav[0][2]), (cav[1][0], cav[1][2]), D, t, True, 0.02)
        b.spec.parts.append(b.drawer(plo, phi, *cav, str(rng.choice(["bar", "recessed"]))))
    n_knobs = int(rng.integers(2, 6))
    zk = H - panel_h / 2
    r = b.u(0.016, 0.024)
    for x in np.linspace(-W / 2 + 0.1, W / 2 - 0.1, n_knobs):
        length = b.u(0.02, 0.03)
        knob = Cylinder((float(x), -D / 2, zk), (float(x), -D / 2 - length, zk), r)
        b.spec.parts.append(PartSpec(b.name("knob"), "knob", [knob], {
            "type": "revolute", "axis": [0.0, -1.0, 0.0], "origin": [float(x), -D / 2, zk],
            "limit": [0.0, float(np.radians(270.0))],
        }))
    return b.spec


def _lid(b: _Builder, W: float, D: float, z_top: float, thickness: float, with_handle: bool) -> PartSpec:
    lo = np.array([-W / 2, -D / 2, z_top + b.gap])
    hi = np.array([W / 2, D / 2, z_top + b.gap + thickness])
    pieces: list[Solid] = [Box(tuple(lo), tuple(hi))]
    if with_handle:
        pieces.append(Box((-0.04, -D / 2 - 0.015, hi[2] - thickness), (0.04, -D / 2, hi[2])))
    q = np.array([0.0, hi[1], lo[2]])
    axis = opening_axis(np.array([1.0, 0.0, 0.0]), q, (lo + hi) / 2, np.array([0.0, 0.0, 1.0]))
    return PartSpec(b.name("lid"), "lid", pieces, {
        "type": "revolute", "axis": axis.tolist(), "origin": q.tolist(),
        "limit": [0.0, float(np.radians(b.u(100.0, 120.0)))],
    })


def build_box(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "box")
    W, D, H = b.u(0.2, 0.6), b.u(0.2, 0.5), b.u(0.1, 0.4)
    t = b.u(0.008, 0.02)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    body = Box((-W / 2, -D / 2, 0.0), (W / 2, D / 2, H)) - Box((-W / 2 + t, -D / 2 + t, t), (W / 2 - t, D / 2 - t, H + 0.01))
    b.spec.parts.append(PartSpec("base", "base", [body]))
    b.spec.parts.append(_lid(b, W, D, H, b.u(0.01, 0.025), bool(rng.random() < 0.5)))
    return b.spec


def build_laptop(rng: np.random.Generator) -> ObjectSpec:
    b = _Builder(rng, "laptop")
    W, D, h = b.u(0.28, 0.4), b.u(0.2, 0.28), b.u(0.012, 0.022)
    b.spec.params.update(width=W, depth=D, height=h, gap=b.gap)
    base = Box((-W / 2, -D / 2, 0.0), (W / 2, D / 2, h))
    keys = Box((-W / 2 + 0.03, -D / 2 + 0.08, h - 0.002), (W / 2 - 0.03, D / 2 - 0.02, h + 0.0005))
    b.spec.parts.append(PartSpec("base", "base", [base - keys]))
    b.spec.parts.append(_lid(b, W, D, h, b.u(0.005, 0.01), False))
    return b.spec


BUILDERS = {
    "cabinet": build_cabinet, "microwave": build_microwave, "fridge": build_fridge,
    "oven": build_oven, "box": build_box, "laptop": build_laptop,
}
