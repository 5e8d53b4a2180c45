"""Furniture as a catalog sells it: a carcass on legs under a top board that overhangs it.

The default and real-like cabinets are boxes standing on their floor panel or a plinth, their
top flush with their sides. Catalog furniture is often neither: a sideboard stands on four legs
10-20 cm tall, so the floor it stands on holds four small squares or discs and nothing else, and
its top is a thicker board reaching past its sides and over its fronts. :func:`furnish` gives an
object both (the ``furnished`` option of :class:`~rest2art.generate.variation.Variation`, drawn
by the ``furniture`` mix): every part is lifted by the legs' height, the joints with it.
"""

from __future__ import annotations

import numpy as np

from rest2art.generate.csg import Box, Cylinder, Solid, Transformed, union
from rest2art.generate.objects import ObjectSpec, PartSpec, _Builder, _front, _split
from rest2art.generate.real_like import _carcass_pieces
from rest2art.generate.variation import Variation

FURNITURE_KINDS = ("cabinet", "wardrobe", "sliding_cabinet")
"""Kinds that stand as furniture does; the ``furniture`` mix cycles through these (and draws a
desk for some of its cabinets)."""
FREESTANDING_KINDS = ("desk",)
"""Kinds built on their own legs and under their own top: :func:`furnish` leaves them as they are."""


def _lifted(solids: list[Solid], height: float) -> list[Solid]:
    """``solids`` moved up by ``height`` (m)."""
    if height == 0.0:
        return list(solids)
    T = np.eye(4)
    T[2, 3] = height
    return [Transformed.of(s, T) for s in solids]


def furnish(spec: ObjectSpec, rng: np.random.Generator, primitives: bool) -> ObjectSpec:
    """``spec`` on legs (half of the time; 8-20 cm, square or round, at the corners or a few
    cm in) and under a top board (three times in four, always without legs; 1.5-3.5 cm thick,
    reaching 0-3 cm past the sides and 1-4 cm past the carcass's front face, flush at the back).
    An object with a lid gets legs and no top board. The legs and the board are the base's: separate
    pieces with ``primitives``, one piece with its carcass otherwise. Returns a new spec."""
    if spec.kind in FREESTANDING_KINDS:
        return spec
    base = spec.parts[0]
    lo = np.min([s.bounds()[0] for s in base.pieces], axis=0)
    hi = np.max([s.bounds()[1] for s in base.pieces], axis=0)
    lidded = any(p.semantic == "lid" for p in spec.parts)
    legs = bool(rng.random() < 0.5) or lidded  # a lid opens where a top board would lie
    top = not lidded and (not legs or bool(rng.random() < 0.75))
    lift = float(rng.uniform(0.08, 0.2)) if legs else 0.0
    extra: list[Solid] = []
    params = dict(spec.params)
    if legs:
        size, inset, round_ = float(rng.uniform(0.03, 0.05)), float(rng.uniform(0.0, 0.04)), bool(rng.random() < 0.5)
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                x = (lo[0] + hi[0]) / 2 + sx * ((hi[0] - lo[0]) / 2 - inset - size / 2)
                y = (lo[1] + hi[1]) / 2 + sy * ((hi[1] - lo[1]) / 2 - inset - size / 2)
                extra.append(Cylinder((x, y, 0.0), (x, y, lift), size / 2) if round_ else
                             Box((x - size / 2, y - size / 2, 0.0), (x + size / 2, y + size / 2, lift)))
        params.update(legs=lift, leg_size=size)
    if top:
        thickness, side, front = (float(rng.uniform(0.015, 0.035)), float(rng.uniform(0.0, 0.03)),
                                  float(rng.uniform(0.01, 0.04)))
        z = hi[2] + lift
        extra.append(Box((lo[0] - side, lo[1] - front, z), (hi[0] + side, hi[1], z + thickness)))
        params.update(top_thickness=thickness, top_overhang=front)
    pieces = _lifted(base.pieces, lift) + extra
    parts = [PartSpec(base.name, base.semantic, pieces if primitives else [union(pieces)], None, base.parent)]
    for part in spec.parts[1:]:
        joint = None if part.joint is None else dict(part.joint)
        if joint is not None:
            joint["origin"] = [joint["origin"][0], joint["origin"][1], joint["origin"][2] + lift]
        parts.append(PartSpec(part.name, part.semantic, _lifted(part.pieces, lift), joint, part.parent))
    return ObjectSpec(spec.kind, parts, params)


def build_desk(rng: np.random.Generator, variation: Variation = Variation(),
               alt: np.random.Generator | None = None) -> ObjectSpec:
    """A desk: a top board over a frame (apron) on four legs, one or two drawers in the frame's
    front rail; half of the desks stand at one end on a pedestal of two to four drawers instead
    of two legs. Nothing is under the frame's drawers but knee room: a drawer hangs in the frame."""
    b = _Builder(rng, "desk", variation, alt)
    W, D, H = b.u(0.8, 1.5), b.u(0.5, 0.75), b.u(0.72, 0.78)
    top, t, apron = b.u(0.02, 0.035), b.u(0.015, 0.022), b.u(0.1, 0.16)
    side, front = b.u(0.0, 0.03), b.u(0.0, 0.03)  # the top's overhang past the frame
    overlay, tf = bool(rng.random() < 0.5), b.u(0.016, 0.022)
    pedestal_width = b.u(0.35, 0.45) if rng.random() < 0.5 else 0.0
    at = float(rng.choice([-1.0, 1.0]))  # the pedestal's end
    x0, x1, zt = -W / 2 + side, W / 2 - side, H - top  # the frame's sides; the top's underside
    za = zt - apron
    b.spec.params.update(width=x1 - x0, depth=D, height=H, wall=t, gap=b.gap, overlay=overlay, apron=apron,
                         top_thickness=top, top_overhang=front, pedestal=pedestal_width,
                         pedestal_side=at if pedestal_width else 0.0)
    style = b.handle_style()
    pieces: list[Solid] = [Box((-W / 2, -D / 2 - front, zt), (W / 2, D / 2, H))]
    # the frame's span: the whole width, or from the pedestal's inner wall to the far end
    fx0, fx1 = (x0, x1) if not pedestal_width else ((x0, x1 - pedestal_width) if at > 0 else (x0 + pedestal_width, x1))
    # one or two drawers, 35-60 cm wide each, centred in the frame's front rail
    n_frame = 1 if pedestal_width or fx1 - fx0 < 1.0 else int(rng.integers(1, 3))
    width = min(b.u(0.35, 0.6), (fx1 - fx0 - 2 * t - 0.1 - (n_frame - 1) * 0.05) / n_frame)
    centre, rail = (fx0 + fx1) / 2, 0.015  # rail: the strips above and below the drawers' openings
    cells = []  # ((x0, z0), (x1, z1), cavity)
    for k in range(n_frame):
        cx0 = centre - (n_frame * width + (n_frame - 1) * 0.05) / 2 + k * (width + 0.05)
        cells.append(((cx0, za + rail), (cx0 + width, zt - rail),
                      ([cx0, -D / 2 - 0.01, za + rail], [cx0 + width, D / 2 - t, zt - rail])))
    # the frame: a ring of rails under the top, open below (knee room), its end at a pedestal open
    inner = ([fx0 + t if fx0 == x0 else fx0 - 0.01, -D / 2 + t, za - 0.01],
             [fx1 - t if fx1 == x1 else fx1 + 0.01, D / 2 - t, zt])
    frame_lo, frame_hi, frame_cuts = (fx0, -D / 2, za), (fx1, D / 2, zt), [inner, *[c[2] for c in cells]]
    pieces += _carcass_pieces(b, frame_lo, frame_hi, frame_cuts)
    leg, round_ = b.u(0.035, 0.06), bool(rng.random() < 0.5)
    legs_x = [x for x, keep in ((x0, not (pedestal_width and at < 0)), (x1, not (pedestal_width and at > 0))) if keep]
    for x in legs_x:
        for y in (-D / 2, D / 2):
            cx, cy = x - np.sign(x) * leg / 2, y - np.sign(y) * leg / 2
            pieces.append(Cylinder((cx, cy, 0.0), (cx, cy, za), leg / 2) if round_ else
                          Box((cx - leg / 2, cy - leg / 2, 0.0), (cx + leg / 2, cy + leg / 2, za)))
    if pedestal_width:
        px0, px1 = (x1 - pedestal_width, x1) if at > 0 else (x0, x0 + pedestal_width)
        plinth = b.u(0.04, 0.08) if rng.random() < 0.5 else 0.0
        for z0, z1 in _split(plinth + t, zt - t, int(rng.integers(2, 5)), t, rng):
            cells.append(((px0 + t, z0), (px1 - t, z1), ([px0 + t, -D / 2 - 0.01, z0], [px1 - t, D / 2 - t, z1])))
        pieces += _carcass_pieces(b, (px0, -D / 2, 0.0), (px1, D / 2, zt), [c[2] for c in cells[n_frame:]])
    for cell_lo, cell_hi, cavity in cells:
        lo, hi = _front(b, cell_lo, cell_hi, D, t, overlay, tf)
        b.spec.parts.append(b.drawer(lo, hi, *cavity, style))
    b.spec.parts.insert(0, PartSpec("base", "base", pieces if b.variation.primitives else [union(pieces)]))
    return b.spec


FURNITURE_BUILDERS = {"desk": build_desk}
