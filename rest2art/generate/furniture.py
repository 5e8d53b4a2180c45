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
from rest2art.generate.objects import ObjectSpec, PartSpec

FURNITURE_KINDS = ("cabinet", "wardrobe", "sliding_cabinet")
"""Kinds that stand as furniture does; the ``furniture`` mix draws these."""


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
