"""The two perception roles of part segmentation and their offline geometric backends.

* ``hierarchy``: rendered views (optionally with masks overlaid) -> a part tree (base root;
  door, drawer, lid, knob children of the base; handles children of their panel), from which
  the prompts S(T) and the expected counts n(s, T) follow. A model backend is a VLM that takes
  the images and returns the tree as JSON.
* ``masks``: one view and one category prompt -> instance masks with confidences; or one view,
  a prompt and point prompts (pixels) -> the one mask those points select. A model backend is
  SAM3 (text or point prompt in, masks and scores out).

The geometric backends read the same rendered maps (normals, depth, face index) that a model
would see as pixels: panels and protrusions from ``panels.analyse_view``, categorised by
``classify_panel``. Backends are chosen by name in ``SegmentConfig`` from the registries of
``rest2art.backends``; the model backends need their optional extra and local weights.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations
from typing import Protocol

import numpy as np

from rest2art.config import ModelsConfig, SegmentConfig
from rest2art.parts.segment.panels import Panel, ViewAnalysis, analyse_view
from rest2art.render.raster import ViewMaps
from rest2art.tolerances import TINY

CATEGORIES = ("door", "drawer", "lid", "knob", "handle")
"""Prompts the roles understand. Doors, drawers, lids and knobs move; handles ride on a panel."""
MOVABLE = ("door", "drawer", "lid", "knob")


@dataclass
class PartNode:
    name: str
    category: str
    parent: str | None


@dataclass
class PartTree:
    """Base root and its parts; ``counts`` gives n(s, T) per category."""

    nodes: list[PartNode] = field(default_factory=list)

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for node in self.nodes:
            if node.category != "base":
                out[node.category] = out.get(node.category, 0) + 1
        return out

    def prompts(self) -> list[str]:
        """S(T): the distinct categories of the tree's parts."""
        return [c for c in CATEGORIES if c in self.counts()]

    @classmethod
    def from_counts(cls, counts: dict[str, int]) -> "PartTree":
        nodes = [PartNode("base", "base", None)]
        for category in MOVABLE:
            for k in range(counts.get(category, 0)):
                nodes.append(PartNode(f"{category}_{k}", category, "base"))
        panels = [n.name for n in nodes if n.category in ("door", "drawer", "lid")]
        for k in range(counts.get("handle", 0)):
            nodes.append(PartNode(f"handle_{k}", "handle", panels[k % len(panels)] if panels else "base"))
        return cls(nodes)


@dataclass
class InstanceMask:
    """One detected instance in one view."""

    view: int
    category: str
    mask: np.ndarray
    """(H, W) bool."""
    score: float
    """Detection confidence in [0, 1]."""


def instance_at_points(instances: list[InstanceMask], pixels: np.ndarray) -> InstanceMask | None:
    """The instance holding most of the (N, 2) integer pixel prompts (x, y), or None when none
    holds half of them: how a masks role answers a point prompt from its text-prompted masks."""
    best, best_hits = None, 0
    for m in instances:
        hits = int(m.mask[pixels[:, 1], pixels[:, 0]].sum())
        if hits > best_hits:
            best, best_hits = m, hits
    return best if best is not None and best_hits >= 0.5 * len(pixels) else None


class HierarchyRole(Protocol):
    def propose(self, views: list[ViewMaps]) -> PartTree: ...

    def revise(self, views: list[ViewMaps], tree: PartTree, view: int, overlay: np.ndarray,
               detected: dict[str, int]) -> PartTree: ...


class MasksRole(Protocol):
    def segment(self, view: int, category: str) -> list[InstanceMask]: ...

    def segment_points(self, view: int, category: str, pixels: np.ndarray) -> InstanceMask | None: ...


def handle_offsets(panel: Panel, config: SegmentConfig) -> list[tuple[float, float, bool]]:
    """(du, dv, vertical bar) of each handle and pocket of ``panel``: its centre's offset from
    the panel's centre as shares of the panel's width and height, and whether it is a vertical
    bar (``bar_vertical_ratio``)."""
    width, height = panel.size
    centre = (panel.lo + panel.hi) / 2
    return [((h.centre[0] - centre[0]) / max(width, TINY), (h.centre[2] - centre[2]) / max(height, TINY),
             bool(h.extents[2] > config.bar_vertical_ratio * h.extents[0])) for h in [*panel.handles, *panel.recesses]]


def at_a_side(du: float, bar_vertical: bool, config: SegmentConfig) -> bool:
    """Whether a handle ``du`` of its panel's width off the centre (``handle_offsets``), or a
    vertical bar, sits at a side: a door's, hinged on the far side (``handle_side_offset``)."""
    return abs(du) >= config.handle_side_offset or bar_vertical


def classify_panel(panel: Panel, config: SegmentConfig) -> tuple[str, float]:
    """(category, confidence) of a panel: lid when it faces up; else by its handles (a recessed
    pull counts as one): one near a side edge or a vertical bar, door; else one near the top
    edge, flip-down door (one further above the panel than ``handle_top_max_offset``, where a
    view cut the panel short at its pull, says nothing); else a centred one, drawer (a dial or a
    lock in the middle of a safe's door does not make it a drawer, nor does a centred one beside
    another off the middle: a safe's dial beside its spoke handle: fittings off the middle that
    do not mirror each other, as a drawer's pair of pulls does, are a door's); else by
    proportions (wide and low: drawer)."""
    score = config.mask_scores
    if panel.normal[2] > 0.5:
        return "lid", score["lid"]
    readings = set()
    off_middle = []
    for du, dv, bar_vertical in handle_offsets(panel, config):
        if at_a_side(du, bar_vertical, config):
            readings.add("handle at a side")
        elif dv > config.handle_top_max_offset:
            continue  # above the panel: the view cut it short at its pull
        elif dv >= config.handle_top_offset:
            readings.add("handle at the top")  # flip-down door: a bar or a knob near its top edge
        elif abs(du) < config.handle_centred:
            readings.add("handle centred")
        else:
            readings.add("handle off the middle")  # neither a drawer's pull nor a door's
            off_middle.append((du, dv))
    if "handle off the middle" in readings:  # a safe's spoke handle beside a dial near its middle
        readings.discard("handle centred")
        if not any(mirrored(a, b, config.pull_mirror_tolerance) for a, b in combinations(off_middle, 2)) \
                and not readings & {"handle at a side", "handle at the top"}:
            # a drawer's pulls off its middle come in pairs, mirrored about it
            return "door", score["proportions"]
    for reading, category in (("handle at a side", "door"), ("handle at the top", "door"), ("handle centred", "drawer")):
        if reading in readings:
            return category, score[reading]
    if drawer_shaped(panel, config):
        return "drawer", score["proportions"]
    return "door", score["proportions"]


def drawer_shaped(panel: Panel, config: SegmentConfig) -> bool:
    """Whether ``panel`` is wide and low as a drawer's front (``drawer_min_aspect``,
    ``drawer_max_height``)."""
    width, height = panel.size
    return width >= config.drawer_min_aspect * height and height <= config.drawer_max_height


def classify_panels(panels: list[Panel], config: SegmentConfig) -> list[tuple[str, float]]:
    """:func:`classify_panel` of each of one view's ``panels``, then the column rules for
    drawer-shaped fronts stacked one above the other (``stacked_column``): those whose pulls sit
    in the same place are drawers, pulls at the top edge included (alone, a front pulled at its
    top edge is a flip-down door; a chest of drawers pulled at their top edges is not a stack of
    flaps); a bare front as tall as a door handled at its side (``twin_max_height_ratio``) is that
    door's twin, a door (a cupboard's upper and lower doors, only one of them handled; a drawer
    under a door is lower than it)."""
    categories = [classify_panel(p, config) for p in panels]
    offsets = [handle_offsets(p, config) for p in panels]
    side_handled = [bool(o) and any(at_a_side(du, bar, config) for du, _, bar in o) for o in offsets]
    for a, b in combinations(range(len(panels)), 2):
        if not stacked_column(panels[a], panels[b], config):
            continue
        for k in (a, b):
            if categories[k][0] == "door" and offsets[k] and not side_handled[k]:
                categories[k] = ("drawer", config.mask_scores["stacked"])
        heights = sorted([panels[a].size[1], panels[b].size[1]])
        for k, other in ((a, b), (b, a)):
            if not offsets[k] and side_handled[other] and categories[other][0] == "door" \
                    and heights[1] <= config.twin_max_height_ratio * heights[0]:
                categories[k] = ("door", config.mask_scores["stacked"])
    return categories


def stacked_column(a: Panel, b: Panel, config: SegmentConfig) -> bool:
    """Whether two front panels are neighbours in one column of drawer-shaped fronts: left and
    right edges aligned (``stack_edge_tolerance``), one right above the other
    (``stack_max_gap`` of the taller's height), heights alike (``stack_max_height_ratio``),
    and a handle on at least one; where both show handles, each of one's has one of the
    other's in the same place (``stack_handle_tolerance``)."""
    if abs(a.normal[2]) > 0.5 or abs(b.normal[2]) > 0.5 or not (drawer_shaped(a, config) and drawer_shaped(b, config)):
        return False
    lower, upper = (a, b) if a.lo[2] <= b.lo[2] else (b, a)
    width = min(a.size[0], b.size[0])
    heights = sorted([a.size[1], b.size[1]])
    gap = upper.lo[2] - lower.hi[2]
    if max(abs(a.lo[0] - b.lo[0]), abs(a.hi[0] - b.hi[0])) > config.stack_edge_tolerance * width \
            or abs(gap) > config.stack_max_gap * heights[1] \
            or heights[1] > config.stack_max_height_ratio * heights[0]:
        return False
    tol = config.stack_handle_tolerance
    ha, hb = handle_offsets(a, config), handle_offsets(b, config)
    if not (ha and hb):
        return bool(ha or hb)
    return all(any(abs(du - eu) <= tol and abs(dv - ev) <= tol for eu, ev, _ in hb) for du, dv, _ in ha)


def mirrored(a: tuple[float, float], b: tuple[float, float], tolerance: float) -> bool:
    """Whether two fittings at (du, dv) (offsets from a panel's centre as shares of its width
    and height) mirror each other about its vertical middle line: the pair of pulls of a wide
    drawer, to ``tolerance`` (share)."""
    return abs(a[0] + b[0]) <= tolerance and abs(a[1] - b[1]) <= tolerance


class GeometricBackend:
    """Offline masks role: panels and knobs from the rendered maps of each view (cached)."""

    def __init__(self, views: list[ViewMaps], face_piece: np.ndarray | None, config: SegmentConfig):
        self.views = views
        self.face_piece = face_piece
        self.config = config
        self._analyses: dict[int, ViewAnalysis] = {}

    def analysis(self, view: int) -> ViewAnalysis:
        if view not in self._analyses:
            self._analyses[view] = analyse_view(self.views[view], self.face_piece, self.config)
        return self._analyses[view]

    def instances(self, view: int) -> list[InstanceMask]:
        """Every instance in the view, all categories."""
        analysis = self.analysis(view)
        out = []
        for panel, (category, score) in zip(analysis.panels, classify_panels(analysis.panels, self.config)):
            out.append(InstanceMask(view, category, panel.mask, score))
            out.extend(InstanceMask(view, "handle", h.mask, self.config.mask_scores["fitting"]) for h in panel.handles)
        out.extend(InstanceMask(view, "knob", _seen(k), self.config.mask_scores["fitting"]) for k in analysis.knobs)
        return out

    def segment(self, view: int, category: str) -> list[InstanceMask]:
        return [m for m in self.instances(view) if m.category == category]

    def segment_points(self, view: int, category: str, pixels: np.ndarray) -> InstanceMask | None:
        """The instance of ``category`` holding most of the (N, 2) integer pixel prompts (x, y),
        or None when none holds half of them."""
        return instance_at_points(self.segment(view, category), pixels)


def _seen(protrusion) -> np.ndarray:
    """(H, W) bool: what a knob is seen with, its foot included when looked for (a handle on a
    panel is seen without: its shape, posts and all, tells a pull from a lever)."""
    return protrusion.mask if protrusion.foot is None else protrusion.foot


def most_of_each(counts: list[dict[str, int]]) -> dict[str, int]:
    """Per category, the most instances any of the ``counts`` holds."""
    most: dict[str, int] = {}
    for count in counts:
        for category, n in count.items():
            most[category] = max(most.get(category, 0), n)
    return most


class GeometricHierarchy:
    """Offline hierarchy role: the paper keeps the richest prediction; here richest per
    category, each at the most any view found (the single richest view's tree lost every
    drawer that view split in two doors: no other view was asked for one); on revision, counts
    grow to what the overlay shows."""

    def __init__(self, masks: GeometricBackend):
        self.masks = masks

    def _counts(self, view: int) -> dict[str, int]:
        counts: dict[str, int] = {}
        for m in self.masks.instances(view):
            counts[m.category] = counts.get(m.category, 0) + 1
        return counts

    def propose(self, views: list[ViewMaps]) -> PartTree:
        return PartTree.from_counts(most_of_each([self._counts(v) for v in range(len(views))]))

    def revise(self, views: list[ViewMaps], tree: PartTree, view: int, overlay: np.ndarray,
               detected: dict[str, int]) -> PartTree:
        return PartTree.from_counts(most_of_each([tree.counts(), detected]))


def make_roles(views: list[ViewMaps], face_piece: np.ndarray | None, config: SegmentConfig,
               models: ModelsConfig = ModelsConfig()) -> tuple[HierarchyRole, MasksRole]:
    """The hierarchy and masks backends named in ``config`` (``rest2art.backends`` registries);
    ``models`` says where the model backends find their weights."""
    from rest2art.backends import create

    masks = create("masks", config.masks_backend, views, face_piece, config, models)
    hierarchy = create("hierarchy", config.hierarchy_backend, views, face_piece, masks, config, models)
    return hierarchy, masks
