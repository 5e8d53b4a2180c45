"""Procedural articulated objects with exact ground truth, in the canonical frame.

Frame: metres, +z up (the object stands on z = 0), -y is the front, x to the right.
Every movable front is separated from the carcass by a gap of 2-6 mm, unless a
:class:`~rest2art.generate.variation.Variation` asks for flush or sunk fronts. Hinges sit where real
hardware puts them so that nothing collides while opening: a side-hinged inset door (inside the
opening) pivots on the edge of its front face, a side-hinged overlay door (in front of the
carcass) on the edge of its back face, so its corners never swing into the carcass or a
neighbouring door; a flip-down door pivots on its bottom front edge (its back corner swings up
into its own space, clear of a drawer below); a lid pivots on the back edge of its underside.

A part is a list of *pieces*: closed solids an artist would model separately (a drawer front,
its box, its handle; with ``Variation.primitives`` every board and post). Handles are fixed to
their panel and belong to its part, unless they turn on a joint of their own (then their part's
parent is the panel's part).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rest2art.generate.csg import Box, Cylinder, Solid, box_pieces, union
from rest2art.generate.variation import Variation
from rest2art.geometry.basics import opening_axis

KINDS = ("cabinet", "microwave", "fridge", "oven", "box", "laptop")
HANDLE_STYLES = ("bar", "knob", "recessed", "cup", "edge")
"""The handle catalogue of varied handles (``none`` is drawn for pairs of doors)."""
FIELD_FRAME = 0.07
"""Width (m) of a framed front's frame, at most (``Variation.framed_fronts``)."""
FIELD_DEPTH = 0.006
"""Depth (m) of a framed front's field below its frame, at most."""


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

    def __init__(self, rng: np.random.Generator, kind: str, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None):
        self.rng = rng
        self.spec = ObjectSpec(kind)
        self.gap = float(rng.uniform(0.002, 0.006))
        self.counts: dict[str, int] = {}
        self.variation = variation
        self.alt = alt if alt is not None else np.random.default_rng(0)
        """Draws of the variation, apart from ``rng`` so that the default layout never changes."""
        self.sink = float(self.alt.uniform(0.001, 0.003)) if variation.fit == "sunk" else 0.0
        if self.sink:
            self.spec.params["sink"] = self.sink

    def u(self, lo: float, hi: float) -> float:
        return float(self.rng.uniform(lo, hi))

    # ---- fit of fronts ---------------------------------------------------------------------

    @property
    def side(self) -> float:
        """Gap between a front and its neighbours or the sides of its opening, m."""
        return self.gap if self.variation.fit == "gap" else 0.0

    @property
    def front_offset(self) -> float:
        """Distance of an overlay front (or lid) from the face it closes, m; negative: sunk in."""
        return {"gap": self.gap, "flush": 0.0, "sunk": -self.sink}[self.variation.fit]

    @property
    def recess(self) -> float:
        """Depth of an inset front's face behind the carcass's front face, m."""
        return self.sink

    # ---- primitives ------------------------------------------------------------------------

    def group(self, solids: list[Solid]) -> list[Solid]:
        """Pieces of one rigid component: one closed piece, or its primitives."""
        return list(solids) if self.variation.primitives else [union(solids)]

    def carcass(self, W: float, D: float, H: float, t: float, cavities: list[tuple], z0: float = 0.0) -> list[Solid]:
        """The carcass as one piece (box minus cavities) or as its wall panels."""
        if self.variation.primitives:
            return list(box_pieces((-W / 2, -D / 2, z0), (W / 2, D / 2, H), cavities))
        return [_carcass(W, D, H, t, cavities, z0)]

    def name(self, semantic: str) -> str:
        n = self.counts.get(semantic, 0)
        self.counts[semantic] = n + 1
        return f"{semantic}_{n}"

    # ---- handles ---------------------------------------------------------------------------

    def handle(self, panel_lo, panel_hi, where: np.ndarray, orient: str, style: str) -> tuple[list[Solid], Solid | None]:
        """Handle pieces on the front (-y) of a panel at ``where`` (x, z).

        Returns (pieces to add, solid to cut from the panel or None).
        """
        x, z = float(where[0]), float(where[1])
        y0 = self.face_at(panel_lo, panel_hi, x, z)  # a handle in a framed front's field stands on it
        panel_lo = np.array([panel_lo[0], y0, panel_lo[2]])
        if style == "none":
            return [], None
        if style == "cup":
            return [self.cup_pull(panel_lo, panel_hi, x, z)], None
        if style == "edge":
            return self.group(self.edge_pull(panel_lo, panel_hi, x, z, orient)), None
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
        return self.group([bar, *posts]), None

    def cup_pull(self, panel_lo, panel_hi, x: float, z: float) -> Solid:
        """A cup (bin) pull: a hood proud of the panel, open at the bottom, centred at (x, z),
        or as near it as keeps the hood inside the panel's outline (a pull placed near a door's
        edge must not reach over onto its neighbour)."""
        y0 = panel_lo[1]
        width = min(self.u(0.07, 0.1), 0.8 * (panel_hi[0] - panel_lo[0]))
        margin = 0.1 * (panel_hi[0] - panel_lo[0] - width) + width / 2
        x = float(np.clip(x, panel_lo[0] + margin, panel_hi[0] - margin))
        height, depth, wall = 0.035, 0.02, 0.004
        outer = Box((x - width / 2, y0 - depth, z - height / 2), (x + width / 2, y0, z + height / 2))
        inner = Box((x - width / 2 + wall, y0 - depth + wall, z - height / 2 - 0.001),
                    (x + width / 2 - wall, y0 + 0.001, z + height / 2 - wall))
        return outer - inner

    def edge_pull(self, panel_lo, panel_hi, x: float, z: float, orient: str) -> list[Solid]:
        """An edge pull: an L profile on the panel's top edge (``h``) or on its vertical edge
        nearest to ``x`` (``v``): a plate on the face and a lip 2 cm proud, inside the panel's
        outline."""
        y0 = panel_lo[1]
        plate, lip, proud = 0.03, 0.005, 0.02
        if orient == "h":
            length = min(self.u(0.1, 0.3), 0.8 * (panel_hi[0] - panel_lo[0]))
            top = panel_hi[2]
            return [Box((x - length / 2, y0 - 0.003, top - plate), (x + length / 2, y0, top)),
                    Box((x - length / 2, y0 - proud, top - lip), (x + length / 2, y0 - 0.003, top))]
        length = min(self.u(0.15, 0.4), 0.7 * (panel_hi[2] - panel_lo[2]))
        right = x > (panel_lo[0] + panel_hi[0]) / 2
        edge = panel_hi[0] if right else panel_lo[0]
        inward = -1.0 if right else 1.0
        xs = sorted([edge, edge + inward * plate])
        xl = sorted([edge, edge + inward * lip])
        return [Box((xs[0], y0 - 0.003, z - length / 2), (xs[1], y0, z + length / 2)),
                Box((xl[0], y0 - proud, z - length / 2), (xl[1], y0 - 0.003, z + length / 2))]

    def handle_style(self) -> str:
        return self.style(str(self.rng.choice(["bar", "bar", "knob", "recessed"])))

    def style(self, default: str) -> str:
        """``default`` (drawn as the kind always drew it), or a draw from the whole catalogue
        when the variation asks for varied handles."""
        return str(self.alt.choice(HANDLE_STYLES)) if self.variation.varied_handles else default

    # ---- movable fronts --------------------------------------------------------------------

    def panel(self, lo, hi, cut: Solid | None) -> Solid:
        """A front's board [lo, hi] (its face on -y) less ``cut`` (a recessed pull) and, with
        ``framed_fronts``, less its field."""
        box = Box(tuple(lo), tuple(hi))
        field = self.field(lo, hi)
        if field is not None:
            frame, depth = field
            sunk = Box((lo[0] + frame, lo[1] - 0.01, lo[2] + frame), (hi[0] - frame, lo[1] + depth, hi[2] - frame))
            cut = sunk if cut is None else union([cut, sunk])
        return box - cut if cut is not None else box

    def field(self, lo, hi) -> tuple[float, float] | None:
        """(frame width, field depth) m of a framed front [lo, hi], or None when fronts are
        plain: the frame ``FIELD_FRAME`` wide or a fifth of the front's smaller side, the field
        ``FIELD_DEPTH`` deep or 40 % of the board."""
        if not self.variation.framed_fronts:
            return None
        smaller = min(hi[0] - lo[0], hi[2] - lo[2])
        return min(FIELD_FRAME, 0.2 * smaller), min(FIELD_DEPTH, 0.4 * (hi[1] - lo[1]))

    def face_at(self, lo, hi, x: float, z: float) -> float:
        """y (m) of a front's face [lo, hi] at (x, z): in a framed front's field, its sunk floor."""
        field = self.field(lo, hi)
        if field is None:
            return float(lo[1])
        frame, depth = field
        inside = lo[0] + frame < x < hi[0] - frame and lo[2] + frame < z < hi[2] - frame
        return float(lo[1] + depth) if inside else float(lo[1])

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
        body = self.group([
            Box((bx0, by0, bz0), (bx1, by1, bz0 + wall)),
            Box((bx0, by0, bz0), (bx0 + wall, by1, bz1)),
            Box((bx1 - wall, by0, bz0), (bx1, by1, bz1)),
            Box((bx0, by1 - wall, bz0), (bx1, by1, bz1)),
        ])
        return PartSpec(self.name("drawer"), "drawer", [front, *body, *pieces], {
            "type": "prismatic", "axis": [0.0, -1.0, 0.0], "origin": centre.tolist(),
            "limit": [0.0, float(min(by1 - by0, 0.9 * self.spec.params["depth"]))],
        }, )

    def door(self, lo, hi, hinge: str, style: str, limit_deg: float, overlay: bool, semantic: str = "door",
             latch_gap: bool = True) -> PartSpec:
        """Door panel [lo, hi] hinged on its 'left', 'right' or 'bottom' edge (back face edge
        for an overlay door, front face edge for an inset one).

        Fronts that touch their neighbours (fit ``flush`` or ``sunk``) hinge on the front face
        edge, so that the hinge side's back corner swings into the door's own space and not into
        the front beside it, and leave the least latch clearance that lets them swing (unless
        ``latch_gap`` is False: nothing stands beside the latch edge)."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        fitted = self.variation.fit != "gap"
        if fitted and latch_gap:
            lo, hi = latch_clearance(lo, hi, hinge)
        centre = (lo + hi) / 2
        y_hinge = hi[1] if (overlay and hinge != "bottom" and not fitted) else lo[1]
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


def latch_clearance(lo: np.ndarray, hi: np.ndarray, hinge: str) -> tuple[np.ndarray, np.ndarray]:
    """A door [lo, hi] that meets its opening or a neighbour at the latch edge, narrowed there
    by the least clearance that lets it swing on its front-face hinge: its back corner sweeps
    sqrt(w^2 + t^2) - w past the latch edge (w its width, t its thickness), plus 0.2 mm."""
    lo, hi = lo.copy(), hi.copy()
    t = hi[1] - lo[1]
    span = 2 if hinge == "bottom" else 0
    w = hi[span] - lo[span]
    clearance = float(np.hypot(w, t) - w) + 0.0002
    if hinge == "right":
        lo[0] += clearance
    else:
        hi[span] -= clearance
    return lo, hi


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
    g, off = b.side, b.front_offset
    if overlay:
        grow = t / 2 - g / 2
        lo = [cell_lo[0] - grow, -D / 2 - off - tf, cell_lo[1] - grow]
        hi = [cell_hi[0] + grow, -D / 2 - off, cell_hi[1] + grow]
    else:
        lo = [cell_lo[0] + g, -D / 2 + b.recess, cell_lo[1] + g]
        hi = [cell_hi[0] - g, -D / 2 + b.recess + tf, cell_hi[1] - g]
    return lo, hi


def build_cabinet(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "cabinet", variation, alt)
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
    spans = []  # the parts of each front
    for kind, cell_lo, cell_hi, cavity in fronts:
        built = len(b.spec.parts)
        _build_front(b, kind, cell_lo, cell_hi, cavity, D, t, overlay, tf, style, rng)
        spans.append((built, len(b.spec.parts)))
    shelves: list[Solid] = []
    if b.variation.open_shelves:  # drawn after every other draw, the fronts left are as they were
        opened, shelves = _open_some(b, fronts, t)
        for index in sorted(opened, reverse=True):
            del b.spec.parts[slice(*spans[index])]
    carcass = b.carcass(W, D, H, t, cavities)
    b.spec.parts.insert(0, PartSpec("base", "base", b.group([*carcass, *shelves]) if shelves else carcass, None))
    return b.spec


def _build_front(b: _Builder, kind: str, cell_lo, cell_hi, cavity, D: float, t: float, overlay: bool, tf: float,
                 style: str, rng: np.random.Generator) -> None:
    """Append the parts of one front of a cabinet (a drawer, a door, a flap or a pair of doors)."""
    if kind == "double":
        xm = (cell_lo[0] + cell_hi[0]) / 2
        # varied handles leave half of the pairs of doors without one (push to open)
        pair_style = "none" if b.variation.varied_handles and b.alt.random() < 0.5 else style
        for lo_x, hi_x, hinge in ((cell_lo[0], xm + t / 2, "left"), (xm - t / 2, cell_hi[0], "right")):
            # two leaves meeting at the middle: the shared edge gets one gap
            a, bb = _front(b, (lo_x, cell_lo[1]), (hi_x, cell_hi[1]), D, t, overlay, tf)
            if hinge == "left":
                bb[0] = xm - b.side / 2
            else:
                a[0] = xm + b.side / 2
            b.spec.parts.append(b.door(a, bb, hinge, pair_style, 90.0, overlay))
        return
    lo, hi = _front(b, cell_lo, cell_hi, D, t, overlay, tf)
    if kind == "drawer":
        b.spec.parts.append(b.drawer(lo, hi, *cavity, style))
    elif kind == "flip":
        b.spec.parts.append(b.door(lo, hi, "bottom", style, 90.0, overlay))
    else:
        b.spec.parts.append(b.door(lo, hi, str(rng.choice(["left", "right"])), style, 90.0, overlay))


def _open_some(b: _Builder, fronts: list[tuple], t: float) -> tuple[set[int], list[Solid]]:
    """Indices of the ``fronts`` left open (door cells, each with probability 0.5, drawn from
    the variation stream; at least one front stays) and the shelf boards (``t`` m thick) halfway
    up the open cells taller than 0.3 m."""
    doors = [i for i, f in enumerate(fronts) if f[0] != "drawer"]
    opened = {i for i in doors if b.alt.random() < 0.5}
    if len(opened) == len(fronts):
        opened.discard(max(opened))
    shelves: list[Solid] = []
    for i in sorted(opened):
        (x0, y0, z0), (x1, y1, z1) = fronts[i][3]
        if z1 - z0 > 0.3:
            zm = (z0 + z1) / 2
            shelves.append(Box((x0, y0 + 0.01 + 0.02, zm - t / 2), (x1, y1, zm + t / 2)))
    return opened, shelves


def build_microwave(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "microwave", variation, alt)
    W, D, H = b.u(0.45, 0.62), b.u(0.33, 0.45), b.u(0.26, 0.36)
    t = b.u(0.012, 0.02)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    panel_w = b.u(0.22, 0.3) * W
    x_split = W / 2 - panel_w
    cavity = ([-W / 2 + t, -D / 2 - 0.01, t], [x_split - t, D / 2 - t, H - t])
    base = b.carcass(W, D, H, t, [cavity])
    buttons = []
    for k in range(int(rng.integers(2, 5))):
        z = H - 0.05 - k * 0.045
        if z < 0.04:
            break
        x = x_split + panel_w / 2
        buttons.append(Box((x - 0.02, -D / 2 - 0.004, z - 0.012), (x + 0.02, -D / 2 + 0.001, z + 0.012)))
    b.spec.parts.append(PartSpec("base", "base", b.group([*base, *buttons])))
    tf = b.u(0.02, 0.03)
    lo = [-W / 2 + b.side, -D / 2 - tf - b.front_offset, b.side]
    hi = [x_split - b.side, -D / 2 - b.front_offset, H - b.side]
    b.spec.parts.append(b.door(lo, hi, "left", b.style(str(rng.choice(["bar", "recessed"]))), 110.0, True))
    return b.spec


def build_fridge(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "fridge", variation, alt)
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
    b.spec.parts.append(PartSpec("base", "base", b.carcass(W, D, H, t, cavities)))
    style = b.style("bar")
    for lo, hi, side in cells:
        plo, phi = _front(b, lo, hi, D, t, True, tf)
        b.spec.parts.append(b.door(plo, phi, side, style, 110.0, True))
    return b.spec


def build_oven(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "oven", variation, alt)
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
    b.spec.parts.append(PartSpec("base", "base", b.carcass(W, D, H, t, cavities)))
    tf = b.u(0.03, 0.05)
    lo = [-W / 2 + b.side, -D / 2 - tf - b.front_offset, z_door0 - t / 2 + b.side]
    hi = [W / 2 - b.side, -D / 2 - b.front_offset, z_door1 - t / 2 - b.side]
    b.spec.parts.append(b.door(lo, hi, "bottom", b.style("bar"), 90.0, True))
    if has_drawer:
        cav = cavities[1]
        plo, phi = _front(b, (cav[0][0], cav[0][2]), (cav[1][0], cav[1][2]), D, t, True, 0.02)
        b.spec.parts.append(b.drawer(plo, phi, *cav, b.style(str(rng.choice(["bar", "recessed"])))))
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
    lo = np.array([-W / 2, -D / 2, z_top + b.front_offset])
    hi = np.array([W / 2, D / 2, z_top + b.front_offset + thickness])
    pieces: list[Solid] = [Box(tuple(lo), tuple(hi))]
    if with_handle:
        pieces.append(Box((-0.04, -D / 2 - 0.015, hi[2] - thickness), (0.04, -D / 2, hi[2])))
    # on the back edge of its underside; a sunk lid on the back edge of its top face, so that
    # the part of it sunk into the walls rises out of them as it opens
    q = np.array([0.0, hi[1], hi[2] if b.sink else lo[2]])
    axis = opening_axis(np.array([1.0, 0.0, 0.0]), q, (lo + hi) / 2, np.array([0.0, 0.0, 1.0]))
    return PartSpec(b.name("lid"), "lid", pieces, {
        "type": "revolute", "axis": axis.tolist(), "origin": q.tolist(),
        "limit": [0.0, float(np.radians(b.u(100.0, 120.0)))],
    })


def build_box(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "box", variation, alt)
    W, D, H = b.u(0.2, 0.6), b.u(0.2, 0.5), b.u(0.1, 0.4)
    t = b.u(0.008, 0.02)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    outer, inner = ((-W / 2, -D / 2, 0.0), (W / 2, D / 2, H)), ((-W / 2 + t, -D / 2 + t, t), (W / 2 - t, D / 2 - t, H + 0.01))
    body = box_pieces(*outer, [inner]) if b.variation.primitives else [Box(*outer) - Box(*inner)]
    b.spec.parts.append(PartSpec("base", "base", body))
    b.spec.parts.append(_lid(b, W, D, H, b.u(0.01, 0.025), bool(rng.random() < 0.5)))
    return b.spec


def build_laptop(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    b = _Builder(rng, "laptop", variation, alt)
    W, D, h = b.u(0.28, 0.4), b.u(0.2, 0.28), b.u(0.012, 0.022)
    b.spec.params.update(width=W, depth=D, height=h, gap=b.gap)
    base = ((-W / 2, -D / 2, 0.0), (W / 2, D / 2, h))
    keys = ((-W / 2 + 0.03, -D / 2 + 0.08, h - 0.002), (W / 2 - 0.03, D / 2 - 0.02, h + 0.0005))
    body = box_pieces(*base, [keys]) if b.variation.primitives else [Box(*base) - Box(*keys)]
    b.spec.parts.append(PartSpec("base", "base", body))
    b.spec.parts.append(_lid(b, W, D, h, b.u(0.005, 0.01), False))
    return b.spec


BUILDERS = {
    "cabinet": build_cabinet, "microwave": build_microwave, "fridge": build_fridge,
    "oven": build_oven, "box": build_box, "laptop": build_laptop,
}
