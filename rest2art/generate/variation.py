"""How a generated object departs from the generator's tidy default, as real assets do.

Meshes made by other people differ from the default objects in ways that matter to the
reconstruction: fronts that touch or sink into the carcass instead of leaving a gap, parts
modelled as many primitives, handles of many shapes (or none), files that are +y up or turned
about the vertical. A :class:`Variation` asks for these; the *real-like* mix draws them, with
the kinds of :mod:`rest2art.generate.real_like`, for a bench set.

The default variation leaves every object exactly as it was: variation draws come from their
own random stream, never from the one that lays the object out.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

FITS = ("gap", "flush", "sunk")
UPS = ("z", "y")
MIXES = ("real-like", "furniture", "framed")


@dataclass(frozen=True)
class Variation:
    """Options of one generated object (all kinds accept them)."""

    fit: str = "gap"
    """How fronts meet the carcass: ``gap`` (2-6 mm all round), ``flush`` (zero gap: fronts
    touch the carcass and each other; a door keeps the least latch clearance it needs to swing)
    or ``sunk`` (as flush, and overlay fronts and lids sit 1-3 mm deep in the carcass at rest;
    inset fronts, sliding panels and buttons, which would drag through it, are recessed by as
    much instead)."""
    primitives: bool = False
    """Asset variant: every part is written as the primitives it is built from (a carcass as
    separate wall panels, a drawer as five boards, a bar pull as a bar and two posts) instead of
    one closed piece per part. The scan variant fuses them anyway."""
    varied_handles: bool = False
    """Draw handles from the whole catalogue (bar pulls, knobs, recessed and cup pulls, edge
    pulls, none on pairs of doors) instead of the default bar / knob / recessed. The kinds of
    :mod:`rest2art.generate.real_like` always do."""
    furnished: bool = False
    """Stand the object as catalog furniture stands: on legs, under a top board overhanging its
    sides and front (:func:`rest2art.generate.furniture.furnish`)."""
    open_shelves: bool = False
    """Leave some of a cabinet's door cells open, as bookcases and sideboards have: a
    compartment with no front (a shelf board halfway up a tall one). At least one front stays."""
    framed_fronts: bool = False
    """Build every door and drawer front framed, as catalog kitchens and wardrobes are (shaker
    fronts): a field sunk ``objects.FIELD_DEPTH`` into a frame up to ``objects.FIELD_FRAME`` wide, the front's
    handle on the frame or in the field."""

    def __post_init__(self) -> None:
        if self.fit not in FITS:
            raise ValueError(f"unknown fit '{self.fit}'. Valid fits: {', '.join(FITS)}")

    def tag(self) -> str:
        """Suffix of the object's name ('' for the default variation)."""
        words = [self.fit] if self.fit != "gap" else []
        words += ["prim"] if self.primitives else []
        words += ["handles"] if self.varied_handles else []
        words += ["furnished"] if self.furnished else []
        words += ["open"] if self.open_shelves else []
        words += ["framed"] if self.framed_fronts else []
        return "".join(f"_{w}" for w in words)


def pose_tag(up: str, yaw_deg: float) -> str:
    """Suffix of an object's name for its file pose ('' for +z up, not turned)."""
    return ("_yup" if up == "y" else "") + (f"_rz{yaw_deg:g}" if yaw_deg else "")


@dataclass(frozen=True)
class MixEntry:
    """One object of a mix: what :func:`rest2art.generate.generate_object` is called with."""

    kind: str
    seed: int
    variation: Variation
    up: str
    """File convention: ``z`` or ``y`` (glTF) up."""
    yaw_deg: float
    """Turn of the file frame about its up axis, degrees."""

    @property
    def name(self) -> str:
        return f"{self.kind}_{self.seed:04d}{self.variation.tag()}{pose_tag(self.up, self.yaw_deg)}"


def mix_entry(mix: str, seed: int, kinds: tuple[str, ...]) -> MixEntry:
    """The ``mix`` object for ``seed``: kind ``kinds[seed % len(kinds)]``, variation and file
    pose drawn from the seed.

    ``real-like``: fit gap / flush / sunk in equal shares, primitives and varied handles half
    of the time each, a quarter of the files +y up, and half of them turned by 90, 180 or 270
    degrees about the vertical. ``furniture``: the same draws, every object ``furnished``
    (``kinds``: the furniture kinds), half of the cabinets with open shelves and a third of them
    desks instead (drawn last, so that the other draws of a seed do not depend on them).
    ``framed``: the furniture mix's object for the same seed with ``framed_fronts``."""
    if mix not in MIXES:
        raise ValueError(f"unknown mix '{mix}'. Valid mixes: {', '.join(MIXES)}")
    rng = np.random.default_rng([seed, 7919])
    furniture = mix in ("furniture", "framed")
    variation = Variation(fit=str(rng.choice(FITS)), primitives=bool(rng.random() < 0.5),
                          varied_handles=bool(rng.random() < 0.5), furnished=furniture)
    up = "y" if rng.random() < 0.25 else "z"
    yaw = float(rng.choice([90.0, 180.0, 270.0])) if rng.random() < 0.5 else 0.0
    kind = kinds[seed % len(kinds)]
    if furniture and kind == "cabinet" and rng.random() < 0.5:
        variation = dataclasses.replace(variation, open_shelves=True)
    if furniture and kind == "cabinet" and rng.random() < 1 / 3:  # stands on its own legs
        kind, variation = "desk", dataclasses.replace(variation, furnished=False, open_shelves=False)
    if mix == "framed":
        variation = dataclasses.replace(variation, framed_fronts=True)
    return MixEntry(kind, seed, variation, up, yaw)
