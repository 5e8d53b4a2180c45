"""Kinds that real articulated assets have and the default generator does not.

Same frame and conventions as :mod:`rest2art.generate.objects` (metres, +z up, -y front, joint
value 0 closed, positive opens, every coordinate at rest):

* ``sliding_cabinet``: two sliding doors in two tracks (grooves in the carcass), prismatic
  along the panel's plane, over an optional row of drawers;
* ``window``: a frame (boxes or cylinders) with two sashes in two tracks, sliding up/down or
  sideways; the back sash is sometimes fixed;
* ``button_panel``: a device with push buttons (prismatic inward, 2-6 mm), levers (small
  revolute arms) and knobs;
* ``stove``: an oven with a cooktop and a sloped control panel whose knobs turn about its
  tilted normal;
* ``safe``: a thick door carrying a dial and a spoke handle, each on its own joint whose parent
  is the door;
* ``wardrobe``: pairs of tall doors, without handles or with lever handles that turn on their
  own joint (parent: the door), over an optional drawer;
* ``open_laptop``: a laptop standing open at rest, its screen leaned back on the keyboard's back
  edge; it closes forward (the part that moves does not hold the floor).

Handles are drawn from the whole catalogue. Nothing moving passes through anything else over
its range; only a ``sunk`` fit leaves fronts 1-3 mm deep in the carcass at rest.
"""

from __future__ import annotations

import numpy as np

from rest2art.generate.csg import Box, Cylinder, Solid, Transformed, box_pieces, union
from rest2art.generate.objects import HANDLE_STYLES, ObjectSpec, PartSpec, _Builder, _front, _split
from rest2art.generate.variation import Variation
from rest2art.geometry.basics import opening_axis, rotation_about

REAL_LIKE_KINDS = ("sliding_cabinet", "window", "button_panel", "stove", "safe", "wardrobe", "open_laptop")

PLATE = 0.02
"""Thickness of a button panel's face plate, deeper than any button's hole, m."""
GROOVE_DEPTH = 0.006
"""Depth of the grooves sliding panels run in, m."""
GROOVE_MAX_CLEAR = GROOVE_DEPTH / 2
"""Most room (m) between a sliding panel's edge and the floor of its groove, whatever the gap
of its fit: it runs at least half the groove deep (a looser one would fall out)."""
TRACK_SPACING = 0.003
"""Gap between the front and the back track of sliding panels, m."""
GROOVE_MAX_PLAY = TRACK_SPACING / 3
"""Most play (m) of a sliding panel between the walls of its groove: two grooves side by side
keep a bead between them, and the front one a lip in front."""


def _carcass_pieces(b: _Builder, lo, hi, cuts: list[tuple]) -> list[Solid]:
    """Box [lo, hi] minus ``cuts``: one piece, or its panels with ``primitives``."""
    if b.variation.primitives:
        return list(box_pieces(lo, hi, cuts))
    solid: Solid = Box(tuple(lo), tuple(hi))
    for a, c in cuts:
        solid = solid - Box(tuple(a), tuple(c))
    return [solid]


def _slide(name: str, semantic: str, pieces: list[Solid], axis, origin, travel: float, parent: str = "base") -> PartSpec:
    return PartSpec(name, semantic, pieces, {"type": "prismatic", "axis": [float(v) for v in axis],
                                             "origin": [float(v) for v in origin], "limit": [0.0, float(travel)]},
                    parent)


def _turn(name: str, semantic: str, pieces: list[Solid], axis, origin, upper_rad: float, parent: str = "base") -> PartSpec:
    return PartSpec(name, semantic, pieces, {"type": "revolute", "axis": [float(v) for v in axis],
                                             "origin": [float(v) for v in origin], "limit": [0.0, float(upper_rad)]},
                    parent)


def build_sliding_cabinet(rng: np.random.Generator, variation: Variation = Variation(),
                          alt: np.random.Generator | None = None) -> ObjectSpec:
    """A cabinet with two sliding doors in two tracks over an optional row of drawers."""
    b = _Builder(rng, "sliding_cabinet", variation, alt)
    W, D, H = b.u(0.7, 1.4), b.u(0.35, 0.5), b.u(0.45, 1.0)
    t = b.u(0.016, 0.025)
    plinth = b.u(0.04, 0.08) if rng.random() < 0.5 else 0.0
    drawers = bool(rng.random() < 0.4)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    x0, x1 = -W / 2 + t, W / 2 - t
    z0 = plinth + t
    cavities, fronts = [], []
    if drawers:
        drawer_h = b.u(0.12, 0.2)
        for (cx0, cx1) in _split(x0, x1, int(rng.integers(1, 4)), t, rng):
            cavity = ([cx0, -D / 2 - 0.01, z0], [cx1, D / 2 - t, z0 + drawer_h])
            cavities.append(cavity)
            fronts.append(cavity)
        z0 += drawer_h + t
    z1 = H - t
    cavities.append(([x0, -D / 2 - 0.01, z0], [x1, D / 2 - t, z1]))
    # two tracks behind the front face; the panels run in grooves of the bottom and the top
    tp = b.u(0.012, 0.018)
    clear = b.side
    front_y = -D / 2 + b.u(0.004, 0.012) + b.recess
    tracks = [(front_y, front_y + tp), (front_y + tp + TRACK_SPACING, front_y + 2 * tp + TRACK_SPACING)]
    seat, play = min(clear, GROOVE_MAX_CLEAR), min(clear, GROOVE_MAX_PLAY)
    for ya, yb in tracks:
        cavities.append(([x0, ya - play, z0 - GROOVE_DEPTH], [x1, yb + play, z0]))
        cavities.append(([x0, ya - play, z1], [x1, yb + play, z1 + GROOVE_DEPTH]))
    b.spec.parts.append(PartSpec("base", "base", _carcass_pieces(b, (-W / 2, -D / 2, 0.0), (W / 2, D / 2, H), cavities)))
    overlap = b.u(0.02, 0.05)
    width = (x1 - x0 - 2 * clear + overlap) / 2
    travel = width - overlap
    za, zb = z0 - GROOVE_DEPTH + seat, z1 + GROOVE_DEPTH - seat
    inset = min(0.05, 0.15 * width)
    # the back panel carries no proud handle: it slides behind the front one
    back_style = str(rng.choice(["recessed", "none"]))
    front_style = str(rng.choice(["recessed", "cup", "bar", "knob", "edge", "none"]))
    if back_style == "none" and rng.random() < 0.5:
        front_style = "none"  # a pair of plain panels
    for (ya, yb), right in zip(tracks, (True, False)):
        xa, xb = (x1 - clear - width, x1 - clear) if right else (x0 + clear, x0 + clear + width)
        lo, hi = np.array([xa, ya, za]), np.array([xb, yb, zb])
        where = np.array([xb - inset if right else xa + inset, (z0 + z1) / 2])
        pieces, cut = b.handle(lo, hi, where, "v", front_style if right else back_style)
        axis = [-1.0 if right else 1.0, 0.0, 0.0]
        b.spec.parts.append(_slide(b.name("door"), "door", [b.panel(lo, hi, cut), *pieces], axis, (lo + hi) / 2, travel))
    style = str(rng.choice(HANDLE_STYLES))
    for cavity in fronts:
        lo, hi = _front(b, (cavity[0][0], cavity[0][2]), (cavity[1][0], cavity[1][2]), D, t, False, b.u(0.016, 0.022))
        b.spec.parts.append(b.drawer(lo, hi, *cavity, style))
    return b.spec


def _sash(b: _Builder, lo: np.ndarray, hi: np.ndarray, bar: float, glass: float) -> list[Solid]:
    """A sash [lo, hi]: four bars (stiles and rails) and a glass pane held in them."""
    (xa, ya, za), (xb, yb, zb) = lo, hi
    ym = (ya + yb) / 2
    bars = [Box((xa, ya, za), (xb, yb, za + bar)), Box((xa, ya, zb - bar), (xb, yb, zb)),
            Box((xa, ya, za + bar), (xa + bar, yb, zb - bar)), Box((xb - bar, ya, za + bar), (xb, yb, zb - bar))]
    hold = min(0.005, bar / 2)
    pane = Box((xa + bar - hold, ym - glass / 2, za + bar - hold), (xb - bar + hold, ym + glass / 2, zb - bar + hold))
    return b.group([*bars, pane])


def build_window(rng: np.random.Generator, variation: Variation = Variation(),
                 alt: np.random.Generator | None = None) -> ObjectSpec:
    """A window frame (boxes or cylinders) with two sashes sliding up and down or sideways."""
    b = _Builder(rng, "window", variation, alt)
    W, H, D = b.u(0.5, 1.2), b.u(0.5, 1.3), b.u(0.07, 0.11)
    frame_style = str(rng.choice(["boxes", "cylinders"]))
    vertical = bool(rng.random() < 0.5)
    fb = D if frame_style == "cylinders" else b.u(0.04, 0.07)
    b.spec.params.update(width=W, depth=D, height=H, wall=fb, gap=b.gap, frame=frame_style,
                         slide="vertical" if vertical else "horizontal")
    x0, x1, z0, z1 = -W / 2 + fb, W / 2 - fb, fb, H - fb
    ts = b.u(0.022, min(0.032, (D - 0.016) / 2))
    clear = b.side
    seat, play = min(clear, GROOVE_MAX_CLEAR), min(clear, GROOVE_MAX_PLAY)
    ya = -(2 * ts + TRACK_SPACING) / 2 + b.recess
    tracks = [(ya, ya + ts), (ya + ts + TRACK_SPACING, ya + 2 * ts + TRACK_SPACING)]
    # grooves run along the slide in the two bars either side of the sashes, as deep as GROOVE_DEPTH
    # where the sashes' faces meet the bars: a round bar's surface falls back off its crest
    groove = GROOVE_DEPTH
    if frame_style == "cylinders":
        reach = max(abs(tracks[0][0] - play), abs(tracks[1][1] + play))
        groove += D / 2 - float(np.sqrt((D / 2) ** 2 - reach ** 2))
    overlap, bar, glass = b.u(0.03, 0.06), b.u(0.03, 0.05), 0.008
    # cup pulls are wide: only on a meeting rail (vertical slide), not on a meeting stile
    front_style = str(rng.choice(["bar", "knob", "cup", "recessed", "none"] if vertical else ["bar", "knob", "recessed", "none"]))
    back_moves = bool(rng.random() < 0.6)
    grooves = []
    for ta, tb in tracks if back_moves else tracks[:1]:  # a fixed back sash is set in the frame
        if vertical:
            grooves += [([x0 - groove, ta - play, z0], [x0 + 0.001, tb + play, z1]),
                        ([x1 - 0.001, ta - play, z0], [x1 + groove, tb + play, z1])]
        else:
            grooves += [([x0, ta - play, z0 - groove], [x1, tb + play, z0 + 0.001]),
                        ([x0, ta - play, z1 - 0.001], [x1, tb + play, z1 + groove])]
    if frame_style == "cylinders":
        r = D / 2
        bars: list[Solid] = [Cylinder((-W / 2, 0.0, r), (W / 2, 0.0, r), r), Cylinder((-W / 2, 0.0, H - r), (W / 2, 0.0, H - r), r),
                             Cylinder((-W / 2 + r, 0.0, 0.0), (-W / 2 + r, 0.0, H), r), Cylinder((W / 2 - r, 0.0, 0.0), (W / 2 - r, 0.0, H), r)]
    else:
        bars = [Box((-W / 2, -D / 2, 0.0), (W / 2, D / 2, fb)), Box((-W / 2, -D / 2, H - fb), (W / 2, D / 2, H)),
                Box((-W / 2, -D / 2, fb), (x0, D / 2, H - fb)), Box((x1, -D / 2, fb), (W / 2, D / 2, H - fb))]
    cut = union([Box(tuple(lo), tuple(hi)) for lo, hi in grooves])
    frame = [bar - cut for bar in bars]
    base = PartSpec("base", "base", b.group(frame))
    b.spec.parts.append(base)
    for k, (ta, tb) in enumerate(tracks):  # k = 0: front sash (lower / right), k = 1: back sash
        if vertical:
            size = (z1 - z0 - 2 * clear + overlap) / 2
            za, zb = (z0 + clear, z0 + clear + size) if k == 0 else (z1 - clear - size, z1 - clear)
            lo, hi = np.array([x0 - groove + seat, ta, za]), np.array([x1 + groove - seat, tb, zb])
            axis = [0.0, 0.0, 1.0 if k == 0 else -1.0]
            meeting = np.array([(x0 + x1) / 2, zb - max(bar / 2, 0.025)]), "h"
        else:
            size = (x1 - x0 - 2 * clear + overlap) / 2
            xa, xb = (x1 - clear - size, x1 - clear) if k == 0 else (x0 + clear, x0 + clear + size)
            lo, hi = np.array([xa, ta, z0 - groove + seat]), np.array([xb, tb, z1 + groove - seat])
            axis = [-1.0 if k == 0 else 1.0, 0.0, 0.0]
            meeting = np.array([xa + max(bar / 2, 0.025), (z0 + z1) / 2]), "v"
        travel = size - overlap
        pieces = _sash(b, lo, hi, bar, glass)
        if k == 0:
            handle, hole = b.handle(lo, hi, meeting[0], meeting[1], front_style)
            if hole is not None:  # a finger recess in the meeting bar
                pieces = [p - hole for p in pieces]
            pieces += handle
        if k == 1 and not back_moves:
            base.pieces.extend(pieces)  # a fixed sash is part of the frame
            continue
        b.spec.parts.append(_slide(b.name("sash"), "sash", pieces, axis, (lo + hi) / 2, travel))
    return b.spec


def build_button_panel(rng: np.random.Generator, variation: Variation = Variation(),
                       alt: np.random.Generator | None = None) -> ObjectSpec:
    """A device whose face carries push buttons, levers and knobs in a grid."""
    b = _Builder(rng, "button_panel", variation, alt)
    W, D, H = b.u(0.25, 0.6), b.u(0.12, 0.3), b.u(0.18, 0.4)
    b.spec.params.update(width=W, depth=D, height=H, gap=b.gap)
    pitch_x, pitch_z, margin = 0.07, 0.075, 0.04
    cols = int((W - 2 * margin) // pitch_x) + 1
    rows = int((H - 2 * margin) // pitch_z) + 1
    xs = np.linspace(-(cols - 1) * pitch_x / 2, (cols - 1) * pitch_x / 2, cols)
    zs = H / 2 + np.linspace(-(rows - 1) * pitch_z / 2, (rows - 1) * pitch_z / 2, rows)
    y0 = -D / 2
    # the top row: levers (their arms swing up, into free space) and knobs; the rows below: buttons
    top = [str(rng.choice(["lever", "knob", "button"])) for _ in xs]
    holes, movers = [], []
    clear = b.side
    for row, z in enumerate(zs[::-1]):
        for col, x in enumerate(xs):
            what = top[col] if row == 0 else ("button" if rng.random() < 0.8 else "empty")
            x, z = float(x), float(z)
            if what == "button":
                proud, stem, travel = b.u(0.006, 0.012) - b.recess, 0.01, b.u(0.002, 0.006)
                if rng.random() < 0.5:
                    s = b.u(0.012, 0.02)
                    cap = Box((x - s, y0 - proud, z - s), (x + s, y0 + stem, z + s))
                    hole = Box((x - s - clear, y0 - 0.01, z - s - clear), (x + s + clear, y0 + stem + travel + 0.001, z + s + clear))
                else:
                    r = b.u(0.01, 0.018)
                    cap = Cylinder((x, y0 - proud, z), (x, y0 + stem, z), r)
                    hole = Cylinder((x, y0 - 0.01, z), (x, y0 + stem + travel + 0.001, z), r + clear)
                holes.append(hole)
                movers.append(_slide(b.name("button"), "button", [cap], [0.0, 1.0, 0.0], [x, y0, z], travel))
            elif what == "lever":
                hub_r, width, arm, thick = b.u(0.008, 0.012), b.u(0.012, 0.02), b.u(0.04, 0.07), 0.008
                pivot = np.array([x, y0 - hub_r, z])
                hub = Cylinder((x - width / 2, pivot[1], z), (x + width / 2, pivot[1], z), hub_r)
                bar = Box((x - width / 2 + 0.002, pivot[1] - arm, z - thick / 2), (x + width / 2 - 0.002, pivot[1], z + thick / 2))
                axis = opening_axis(np.array([1.0, 0.0, 0.0]), pivot, pivot + [0.0, -arm, 0.0], np.array([0.0, 0.0, 1.0]))
                movers.append(_turn(b.name("lever"), "lever", b.group([hub, bar]), axis, pivot, np.radians(b.u(45.0, 75.0))))
            elif what == "knob":
                r, length = b.u(0.012, 0.022), b.u(0.015, 0.03)
                knob = Cylinder((x, y0, z), (x, y0 - length, z), r)
                movers.append(_turn(b.name("knob"), "knob", [knob], [0.0, -1.0, 0.0], [x, y0, z], np.radians(270.0)))
    # a housing and a face plate as deep as the buttons' holes (one piece unless primitives)
    plate = Box((-W / 2, -D / 2, 0.0), (W / 2, -D / 2 + PLATE, H))
    housing = Box((-W / 2, -D / 2 + PLATE, 0.0), (W / 2, D / 2, H))
    base = b.group([plate - union(holes) if holes else plate, housing])
    b.spec.parts.append(PartSpec("base", "base", base))
    b.spec.parts.extend(movers)
    return b.spec


def build_stove(rng: np.random.Generator, variation: Variation = Variation(),
                alt: np.random.Generator | None = None) -> ObjectSpec:
    """An oven with a cooktop and knobs turning on a sloped control panel."""
    b = _Builder(rng, "stove", variation, alt)
    W, D, H = b.u(0.5, 0.9), b.u(0.55, 0.7), b.u(0.85, 0.95)
    t = b.u(0.02, 0.035)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    has_drawer = bool(rng.random() < 0.5)
    drawer_h = b.u(0.12, 0.18) if has_drawer else 0.0
    z_door0 = t + (drawer_h + t if has_drawer else 0.0)
    z_door1 = H - t
    cavities = [([-W / 2 + t, -D / 2 - 0.01, z_door0], [W / 2 - t, D / 2 - t, z_door1 - t])]
    if has_drawer:
        cavities.append(([-W / 2 + t, -D / 2 - 0.01, t], [W / 2 - t, D / 2 - t, t + drawer_h]))
    base = b.carcass(W, D, H, t, cavities)
    # the sloped control panel at the back of the top, leaning back by `tilt`, facing front-up
    tilt, depth, height = np.radians(b.u(15.0, 40.0)), b.u(0.03, 0.05), b.u(0.1, 0.16)
    R = rotation_about(np.array([1.0, 0.0, 0.0]), -tilt)
    T = np.eye(4)
    T[:3, :3] = R
    reach = depth * np.cos(tilt) + height * np.sin(tilt)
    T[:3, 3] = [0.0, D / 2 - reach + depth / 2 * np.cos(tilt), H - depth / 2 * np.sin(tilt)]
    base.append(Transformed.of(Box((-W / 2, -depth / 2, -0.02), (W / 2, depth / 2, height)), T))
    n_burners = int(rng.integers(2, 5))
    free_back = D / 2 - reach
    for k in range(n_burners):
        col, row = k % 2, k // 2
        r = b.u(0.05, 0.08)
        x = (col - 0.5) * W / 2 if n_burners > 1 else 0.0
        y = -D / 2 + (0.3 + 0.4 * row) * (free_back + D / 2)
        base.append(Cylinder((x, y, H), (x, y, H + b.u(0.008, 0.015)), r))
    b.spec.parts.append(PartSpec("base", "base", b.group(base)))
    tf = b.u(0.03, 0.05)
    lo = [-W / 2 + b.side, -D / 2 - tf - b.front_offset, z_door0 - t / 2 + b.side]
    hi = [W / 2 - b.side, -D / 2 - b.front_offset, z_door1 - t / 2 - b.side]
    b.spec.parts.append(b.door(lo, hi, "bottom", str(rng.choice(["bar", "edge", "bar"])), 90.0, True))
    if has_drawer:
        cav = cavities[1]
        plo, phi = _front(b, (cav[0][0], cav[0][2]), (cav[1][0], cav[1][2]), D, t, True, 0.02)
        b.spec.parts.append(b.drawer(plo, phi, *cav, str(rng.choice(HANDLE_STYLES))))
    normal = R @ np.array([0.0, -1.0, 0.0])
    r_knob = b.u(0.014, 0.022)
    # half the stoves model their knobs a little off the panel, the spindle left out (they touch nothing)
    standoff = float(b.alt.uniform(0.001, 0.003)) if b.alt.random() < 0.5 else 0.0
    if standoff:
        b.spec.params["knob_standoff"] = standoff
    y_knob = -depth / 2 - standoff
    for x in np.linspace(-W / 2 + 0.08, W / 2 - 0.08, int(rng.integers(2, 7))):
        length = b.u(0.02, 0.03)
        local = [Cylinder((float(x), y_knob, height / 2), (float(x), y_knob - length, height / 2), r_knob),
                 Box((float(x) - 0.003, y_knob - length - 0.006, height / 2 - 0.7 * r_knob),
                     (float(x) + 0.003, y_knob - length, height / 2 + 0.7 * r_knob))]
        origin = R @ np.array([x, -depth / 2, height / 2]) + T[:3, 3]
        b.spec.parts.append(_turn(b.name("knob"), "knob", b.group([Transformed.of(p, T) for p in local]), normal,
                                  origin, np.radians(270.0)))
    return b.spec


def _spoke_handle(b: _Builder, centre: np.ndarray, y0: float, reach: float) -> list[Solid]:
    """Hub on the face at ``y0`` and three spokes of length ``reach`` turning in front of it."""
    x, z = float(centre[0]), float(centre[1])
    hub_r, hub_len, spoke_r = 0.016, b.u(0.03, 0.045), 0.006
    yf = y0 - hub_len + spoke_r
    spokes = [Transformed.of(Cylinder((0.0, 0.0, 0.0), (reach, 0.0, 0.0), spoke_r),
                             _pose(rotation_about(np.array([0.0, 1.0, 0.0]), -angle), (x, yf, z)))
              for angle in np.radians([90.0, 210.0, 330.0])]
    return b.group([Cylinder((x, y0, z), (x, y0 - hub_len, z), hub_r), *spokes])


def _pose(R: np.ndarray, t) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def build_safe(rng: np.random.Generator, variation: Variation = Variation(),
               alt: np.random.Generator | None = None) -> ObjectSpec:
    """A safe whose door carries a dial and a spoke handle, each on a joint of its own."""
    b = _Builder(rng, "safe", variation, alt)
    W, D, H = b.u(0.3, 0.6), b.u(0.3, 0.55), b.u(0.3, 0.7)
    t = b.u(0.03, 0.06)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap)
    cavity = ([-W / 2 + t, -D / 2 - 0.01, t], [W / 2 - t, D / 2 - t, H - t])
    b.spec.parts.append(PartSpec("base", "base", b.carcass(W, D, H, t, [cavity])))
    td = b.u(0.04, 0.07)
    lo = np.array([-W / 2 + b.side, -D / 2 - b.front_offset - td, b.side])
    hi = np.array([W / 2 - b.side, -D / 2 - b.front_offset, H - b.side])
    hinge = str(rng.choice(["left", "right"]))
    door = b.door(lo, hi, hinge, "none", b.u(100.0, 120.0), True, latch_gap=False)
    b.spec.parts.append(door)
    y0 = lo[1]
    centre = (lo + hi) / 2
    latch = 1.0 if hinge == "left" else -1.0
    w, h = hi[0] - lo[0], hi[2] - lo[2]
    r_dial = b.u(0.03, min(0.05, 0.12 * min(w, h)))
    dial_at = np.array([centre[0] - 0.12 * latch * w, centre[2] + 0.15 * h])
    handle_at = np.array([centre[0] + 0.2 * latch * w, centre[2] - 0.1 * h])
    room = min(float(np.linalg.norm(dial_at - handle_at)) - r_dial - 0.015,  # spokes clear of the dial
               0.3 * w - 0.02, handle_at[1] - lo[2] - 0.02, hi[2] - handle_at[1] - 0.02)  # and inside the door
    reach = float(min(b.u(0.06, 0.1), room))
    dial_len = b.u(0.015, 0.025)
    dial = [Cylinder((dial_at[0], y0, dial_at[1]), (dial_at[0], y0 - dial_len, dial_at[1]), r_dial),
            Box((dial_at[0] - 0.003, y0 - dial_len - 0.004, dial_at[1] + 0.4 * r_dial),
                (dial_at[0] + 0.003, y0 - dial_len, dial_at[1] + 0.9 * r_dial))]
    outward = [0.0, -1.0, 0.0]
    b.spec.parts.append(_turn(b.name("dial"), "dial", b.group(dial), outward, [dial_at[0], y0, dial_at[1]],
                              2 * np.pi, parent=door.name))
    hub = np.array([handle_at[0], y0, handle_at[1]])
    b.spec.parts.append(_turn(b.name("handle"), "handle", _spoke_handle(b, handle_at, y0, reach), outward, hub,
                              np.radians(b.u(60.0, 120.0)), parent=door.name))
    return b.spec


def _lever_handle(b: _Builder, at: np.ndarray, y0: float, towards: float) -> tuple[list[Solid], np.ndarray, np.ndarray]:
    """A lever handle: a rose and a neck on the face at ``y0`` and a horizontal lever pointing
    along ``towards`` (+1 / -1 in x); (pieces, pivot, axis that turns the lever's end down)."""
    x, z = float(at[0]), float(at[1])
    rose_r, neck_r, neck = b.u(0.02, 0.027), 0.009, b.u(0.04, 0.055)
    length, thick = b.u(0.1, 0.14), 0.016
    ends = sorted([x, x + towards * length])
    pieces = [Cylinder((x, y0, z), (x, y0 - 0.01, z), rose_r), Cylinder((x, y0 - 0.01, z), (x, y0 - neck, z), neck_r),
              Box((ends[0], y0 - neck - thick / 2, z - thick / 2), (ends[1], y0 - neck + thick / 2, z + thick / 2))]
    pivot = np.array([x, y0, z])
    axis = opening_axis(np.array([0.0, -1.0, 0.0]), pivot, pivot + [towards * length, 0.0, 0.0], np.array([0.0, 0.0, -1.0]))
    return b.group(pieces), pivot, axis


def build_wardrobe(rng: np.random.Generator, variation: Variation = Variation(),
                   alt: np.random.Generator | None = None) -> ObjectSpec:
    """A tall pair of doors, bare or with lever handles on their own joints, over an optional drawer."""
    b = _Builder(rng, "wardrobe", variation, alt)
    W, D, H = b.u(0.7, 1.4), b.u(0.45, 0.62), b.u(1.5, 2.1)
    t = b.u(0.018, 0.025)
    tf = b.u(0.018, 0.024)
    b.spec.params.update(width=W, depth=D, height=H, wall=t, gap=b.gap, overlay=True)
    drawer_h = b.u(0.18, 0.26) if rng.random() < 0.4 else 0.0
    z0 = t + (drawer_h + t if drawer_h else 0.0)
    handles = str(rng.choice(["none", "lever", "fixed"]))
    fixed_style = str(rng.choice(HANDLE_STYLES))
    # one pair of doors hinged on the carcass's sides: two pairs would hinge side by side on a
    # partition, and their hinge edges swing into each other
    cx0, cx1 = -W / 2 + t, W / 2 - t
    cavities = [([cx0, -D / 2 - 0.01, z0], [cx1, D / 2 - t, H - t])]
    if drawer_h:
        cavities.append(([-W / 2 + t, -D / 2 - 0.01, t], [W / 2 - t, D / 2 - t, t + drawer_h]))
    b.spec.parts.append(PartSpec("base", "base", b.carcass(W, D, H, t, cavities)))
    xm = (cx0 + cx1) / 2
    for lo_x, hi_x, hinge in ((cx0, xm + t / 2, "left"), (xm - t / 2, cx1, "right")):
        lo, hi = _front(b, (lo_x, z0), (hi_x, H - t), D, t, True, tf)
        if hinge == "left":
            hi[0] = xm - b.side / 2
        else:
            lo[0] = xm + b.side / 2
        door = b.door(lo, hi, hinge, fixed_style if handles == "fixed" else "none", 100.0, True)
        b.spec.parts.append(door)
        if handles == "lever":
            lo, hi = np.asarray(door.pieces[0].bounds())  # after the latch clearance
            towards = -1.0 if hinge == "left" else 1.0  # the lever points back to the hinge
            x = (hi[0] if hinge == "left" else lo[0]) + towards * min(0.06, 0.15 * (hi[0] - lo[0]))
            z = float(np.clip(1.0, lo[2] + 0.2, hi[2] - 0.2))
            pieces, pivot, axis = _lever_handle(b, np.array([x, z]), lo[1], towards)
            b.spec.parts.append(_turn(b.name("handle"), "handle", pieces, axis, pivot, np.radians(45.0),
                                      parent=door.name))
    if drawer_h:
        cav = cavities[-1]
        lo, hi = _front(b, (cav[0][0], cav[0][2]), (cav[1][0], cav[1][2]), D, t, True, tf)
        b.spec.parts.append(b.drawer(lo, hi, *cav, fixed_style if handles == "fixed" else str(rng.choice(HANDLE_STYLES))))
    return b.spec


def build_open_laptop(rng: np.random.Generator, variation: Variation = Variation(),
                      alt: np.random.Generator | None = None) -> ObjectSpec:
    """A laptop standing open at rest, as simulation models ship one: a keyboard base (a bottom
    plate and a top with the keys sunk in it, separate pieces with ``primitives``) and a screen
    standing on the base's back edge, leaned back, that closes forward onto the keys."""
    b = _Builder(rng, "open_laptop", variation, alt)
    W, D, h = b.u(0.28, 0.4), b.u(0.2, 0.28), b.u(0.015, 0.025)
    thickness, height, lean = b.u(0.006, 0.012), b.u(0.18, 0.26), np.radians(b.u(0.0, 20.0))
    b.spec.params.update(width=W, depth=D, height=h, screen=height, lean_deg=float(np.degrees(lean)), gap=b.gap)
    plate = Box((-W / 2, -D / 2, 0.0), (W / 2, D / 2, h / 3))
    top = Box((-W / 2, -D / 2, h / 3), (W / 2, D / 2, h)) \
        - Box((-W / 2 + 0.03, -D / 2 + 0.08, h - 0.002), (W / 2 - 0.03, D / 2 - 0.02, h + 0.001))
    b.spec.parts.append(PartSpec("base", "base", b.group([plate, top])))
    # hinged a barrel's radius above the base's top, below the screen's inner face: the barrel
    # (on the screen, about the hinge line) rests on the base, and closed, the screen lies on
    # the keyboard's rim that far above it
    barrel = max(b.gap, 0.003)
    hinge = np.array([0.0, D / 2 - thickness, h + barrel])
    bezel = b.u(0.01, 0.02)
    display = Box((-W / 2 + bezel, -0.001, barrel + bezel), (W / 2 - bezel, 0.003, barrel + height - bezel))
    upright = Box((-W / 2, 0.0, barrel), (W / 2, thickness, barrel + height)) - display  # on the barrel
    screen = Transformed.of(upright, _pose(rotation_about(np.array([1.0, 0.0, 0.0]), -lean), hinge))
    pin = Cylinder((-W / 4, hinge[1], hinge[2]), (W / 4, hinge[1], hinge[2]), barrel)
    axis = np.array([1.0, 0.0, 0.0])  # positive turns the top forward, onto the keys
    b.spec.parts.append(_turn(b.name("lid"), "lid", b.group([screen, pin]), axis, hinge,
                              np.pi / 2 + lean - np.radians(1.0)))
    return b.spec


REAL_LIKE_BUILDERS = {
    "sliding_cabinet": build_sliding_cabinet, "window": build_window, "button_panel": build_button_panel,
    "stove": build_stove, "safe": build_safe, "wardrobe": build_wardrobe, "open_laptop": build_open_laptop,
}
