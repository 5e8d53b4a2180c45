"""Part segmentation of a mesh from rendered views (paper: Method, Part Segmentation).

``segment_mesh`` renders the canonical mesh from the camera rig, runs the co-refinement loop
between the hierarchy and masks roles, ties the masks of different views to parts by point
prompts, lifts the evidence onto faces and refines the labels over the mesh graph.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import combinations

import numpy as np

from rest2art.asset import numbered_names
from rest2art.config import SegmentConfig
from rest2art.geometry.basics import thin_along
from rest2art.parts.segment.lifting import PartEvidence, grow_edge_strips, lift_evidence, refine_labels, support
from rest2art.parts.segment.panels import FRONT, fused_surface, snap_to_axis
from rest2art.parts.segment.roles import CATEGORIES, InstanceMask, PartTree, make_roles
from rest2art.parts.segment.views import render_rig
from rest2art.render.raster import ViewMaps, blend_masks

PANEL_CATEGORIES = ("door", "drawer", "lid")

COREFINE_CASES = ("agree", "excess", "missing")
"""The paper's cases of one view in one co-refinement round (the ``case`` of its log entry)."""
COREFINE_ACTIONS = ("cached", "revised", "deferred")
"""What a view's case does (the ``action`` of its log entry): its masks are cached as validated
evidence (agree), the tree is revised from its mask overlay (excess, while rounds remain), or
its masks are deferred to the cross-view association (missing, and excess in the last round)."""
PROPOSED, REVISED = "proposed", "excess: tree revised"
"""The ``event`` of the tree's log entries: first proposed, then revised after an excess."""


@dataclass
class SegmentedPart:
    """A part found by segmentation."""

    name: str
    category: str
    """door, drawer, lid, knob or handle."""
    parent: int
    """Index of the parent in ``Segmentation.parts`` (0 = base)."""
    normal: np.ndarray
    """(3,) outward normal of its main face (canonical)."""
    views: int
    """Views it was detected in."""
    seen: int
    """Views that see it."""


@dataclass
class Segmentation:
    """Face labels over the mesh: 0 = base, k = parts[k - 1] (handles keep their own label)."""

    face_label: np.ndarray
    parts: list[SegmentedPart]
    tree: PartTree
    log: dict = field(default_factory=dict)
    views: list[ViewMaps] = field(default_factory=list)
    part_masks: list[dict[int, np.ndarray]] = field(default_factory=list)

    def rigid_labels(self) -> np.ndarray:
        """(F,) labels with every handle folded into the panel it rides on."""
        out = self.face_label.copy()
        for k, part in reversed(list(enumerate(self.parts, start=1))):
            if part.category == "handle":
                out[out == k] = part.parent
        return out


@dataclass
class _Track:
    """A part being assembled from per-view instances."""

    group: str
    votes: np.ndarray
    """(F,) int16: how many of its masks hold each face."""
    instances: dict[int, InstanceMask] = field(default_factory=dict)

    @property
    def faces(self) -> np.ndarray:
        """(F,) bool: the faces under any of its masks."""
        return self.votes > 0

    def core(self) -> np.ndarray:
        """(F,) bool: the faces under half its masks or more."""
        return self.votes * 2 >= max(len(self.instances), 1)


def _group(category: str) -> str:
    return "panel" if category in PANEL_CATEGORIES else category


def corefine_case(detected: dict[str, int], expected: dict[str, int]) -> str:
    """The paper's case of one view: ``excess`` when some prompt finds more instances than the
    tree holds (counts per category), else ``agree`` when every count matches, else ``missing``."""
    if any(n > expected.get(s, 0) for s, n in detected.items()):
        return "excess"
    return "agree" if all(n == expected.get(s, 0) for s, n in detected.items()) else "missing"


def corefine_action(case: str, last_round: bool) -> str:
    """What ``case`` does with its view (``COREFINE_ACTIONS``): agree caches the masks, excess
    revises the tree unless no round is left, everything else defers the masks."""
    if case == "agree":
        return "cached"
    return "revised" if case == "excess" and not last_round else "deferred"


def corefine(hierarchy, masks, views: list[ViewMaps], config: SegmentConfig) -> tuple[PartTree, dict, dict, list]:
    """The co-refinement loop. Returns the final tree, the cached (agreeing) and deferred
    (missing detections) masks per view ({view: {category: [InstanceMask]}}), and the log: the
    tree's events, and per round and view its ``case`` (``COREFINE_CASES``), ``action``,
    detected and expected counts."""
    tree = hierarchy.propose(views)
    log = [{"round": 0, "event": PROPOSED, "counts": tree.counts()}]
    rounds = config.corefine_rounds if config.corefinement else 0
    for round_index in range(rounds + 1):
        cached, deferred, restarted = {}, {}, False
        expected = tree.counts()
        for v in range(len(views)):
            found = {s: masks.segment(v, s) for s in tree.prompts()}
            counts = {s: len(m) for s, m in found.items()}
            case = corefine_case(counts, expected)
            action = corefine_action(case, last_round=round_index == rounds)
            log.append({"round": round_index, "view": v, "case": case, "action": action,
                        "detected": counts, "expected": expected})
            if action == "revised":
                overlay = overlay_masks(views[v], [m for ms in found.values() for m in ms])
                tree = hierarchy.revise(views, tree, v, overlay, counts)
                log.append({"round": round_index, "view": v, "event": REVISED, "counts": tree.counts()})
                restarted = True
                break
            (cached if action == "cached" else deferred)[v] = found
        if not restarted:
            break
    return tree, cached, deferred, log


def associate(masks, views: list[ViewMaps], cached: dict, deferred: dict, n_faces: int,
              config: SegmentConfig) -> list[_Track]:
    """Tie per-view instances to parts. Views are visited from the one with most detections;
    an instance joins a part when the part's surface points, reprojected into its view as point
    prompts, select a mask that agrees with it (IoU >= ``agreement_iou``); otherwise it starts a
    new part. Without co-refinement, instances join by overlap of their face supports."""
    found = {**deferred, **cached}
    order = sorted(found, key=lambda v: (v not in cached, -sum(len(m) for m in found[v].values())))
    tracks: list[_Track] = []
    rng = np.random.default_rng(0)
    for v in order:
        view = views[v]
        for category, instances in found[v].items():
            for inst in instances:
                faces = np.zeros(n_faces, bool)
                faces[support(view, inst.mask)] = True
                match = None
                for track in tracks:
                    if track.group != _group(category) or v in track.instances:
                        continue
                    visible = track.faces[view.face] & view.mask
                    if not visible.any():
                        continue
                    if config.corefinement:
                        ys, xs = np.nonzero(visible)
                        pick = rng.choice(len(xs), min(24, len(xs)), replace=False)
                        points = np.stack([xs[pick], ys[pick]], 1)
                        # a panel may be read as another kind of panel in this view
                        asked = [category, *(c for c in PANEL_CATEGORIES if c != category)] \
                            if category in PANEL_CATEGORIES else [category]
                        prompted = next((m for c in asked if (m := masks.segment_points(v, c, points)) is not None), None)
                        if prompted is None:
                            continue
                        iou = (prompted.mask & inst.mask).sum() / max((prompted.mask | inst.mask).sum(), 1)
                        if iou >= config.agreement_iou:
                            match = track
                            break
                    elif (faces & track.faces).sum() >= config.track_overlap_share * min(faces.sum(), track.faces.sum()):
                        match = track
                        break
                if match is None:
                    match = _Track(_group(category), np.zeros(n_faces, np.int16))
                    tracks.append(match)
                match.instances[v] = inst
                match.votes += faces
    tracks = drop_fusing_instances(tracks, views, n_faces, config)
    return join_nested_tracks(split_fused_tracks(tracks, views, n_faces, config), config)


def seen_faces(view: ViewMaps, n_faces: int) -> np.ndarray:
    """(F,) bool: the faces ``view`` sees."""
    out = np.zeros(n_faces, bool)
    out[view.face[view.mask]] = True
    return out


def drop_fusing_instances(tracks: list[_Track], views: list[ViewMaps], n_faces: int,
                          config: SegmentConfig) -> list[_Track]:
    """``tracks`` without the panel masks that see a part and its neighbour as one (a seam the
    view missed): a mask of a panel part holding ``fused_instance_cover`` of another part's core
    seen in its view, a part sharing less than ``fused_instance_overlap`` of the smaller core
    with its own, and found in more views than the part has such instances. The core of a
    part: the faces under half its masks or more. Joined to one door, the wider mask carried
    its label onto its neighbour; a drawer a few views cut in two keeps its whole masks (its
    halves lie inside its core, in fewer views). A piece found in only as many views as the
    masks holding it is no more evidence of a seam than they are against one: a framed door
    whose stile some views cut off at its pull keeps the views that saw it whole."""
    cores = [track.core() for track in tracks]
    seen = [seen_faces(view, n_faces) for view in views]
    for t, track in enumerate(tracks):
        if track.group != "panel":  # a knob on its rose is one knob, whatever a view saw first
            continue
        held = {v: support(views[v], inst.mask) for v, inst in track.instances.items()}  # seen in v
        neighbours = [o for o, other in enumerate(tracks) if o != t and other.group == track.group
                      and _cores_apart(cores[o], cores[t], config.fused_instance_overlap)]
        fused = set()
        for o in neighbours:
            visible = {v: int((cores[o] & seen[v]).sum()) for v in held}
            holding = [v for v in held if visible[v] and cores[o][held[v]].sum() >= config.fused_instance_cover * visible[v]]
            if len(tracks[o].instances) > len(holding):
                fused.update(holding)
        if fused and len(fused) < len(track.instances):
            track.instances = {v: inst for v, inst in track.instances.items() if v not in fused}
            track.votes = np.bincount(np.concatenate([held[v] for v in track.instances]),
                                      minlength=n_faces).astype(np.int16)
    return tracks


def _cores_apart(a: np.ndarray, b: np.ndarray, overlap: float) -> bool:
    """Whether two parts' cores ((F,) bool) share less than ``overlap`` of the smaller."""
    return bool((a & b).sum() < overlap * min(a.sum(), b.sum()))


def _core_inside(inner: np.ndarray, outer: np.ndarray, share: float) -> bool:
    """Whether ``share`` or more of a part's core ``inner`` ((F,) bool) lies in ``outer``."""
    return bool((inner & outer).sum() >= share * max(inner.sum(), 1))


def split_fused_tracks(tracks: list[_Track], views: list[ViewMaps], n_faces: int,
                       config: SegmentConfig) -> list[_Track]:
    """``tracks`` with each panel part whose core (the faces under half its masks or more) two
    or more other panel parts tile handed to them: parts never found in a view with it, each
    with ``nested_instance_share`` of its core inside it, whose cores overlap by less than
    ``fused_instance_overlap`` of the smaller and together cover ``nested_instance_share`` of
    it. Those are neighbours the part's views saw as one (two drawers side by side whose seam
    half the views missed): each view's mask of it is a mask of each of them, cut to their
    cores. Kept whole, one of them was joined to it (``join_nested_tracks``) and the other,
    found apart in too few views, was pruned: one part was left for two."""
    cores = [track.core() for track in tracks]
    fused: set[int] = set()
    for f, track in enumerate(tracks):
        if track.group != "panel" or not cores[f].any():
            continue
        inside = [p for p, other in enumerate(tracks) if p != f and p not in fused and other.group == "panel"
                  and cores[p].any() and not set(other.instances) & set(track.instances)
                  and _core_inside(cores[p], cores[f], config.nested_instance_share)]
        apart = all(_cores_apart(cores[a], cores[b], config.fused_instance_overlap) for a, b in combinations(inside, 2))
        tiled = np.any([cores[p] for p in inside], axis=0) if inside else np.zeros(n_faces, bool)
        if len(inside) < 2 or not apart or (tiled & cores[f]).sum() < config.nested_instance_share * cores[f].sum():
            continue
        for v, inst in track.instances.items():
            face = views[v].face
            for p in inside:
                mask = inst.mask & (face >= 0) & cores[p][np.maximum(face, 0)]
                if not mask.any():
                    continue
                kinds = [i.category for i in tracks[p].instances.values()]
                tracks[p].instances[v] = InstanceMask(v, max(set(kinds), key=kinds.count), mask, inst.score)
                tracks[p].votes[support(views[v], mask)] += 1
        fused.add(f)
    return [track for f, track in enumerate(tracks) if f not in fused]


def join_nested_tracks(tracks: list[_Track], config: SegmentConfig) -> list[_Track]:
    """``tracks`` with each panel part never found in a view with the one panel part whose core
    holds ``nested_instance_share`` of its own core (the faces under half its masks or more)
    joined to that part: a shaker door's sunk middle panel, seen as a panel where its groove
    shows better than the door's seam, is the door seen in part. A window found in the same
    views as its door is a part of its own."""
    merged: set[int] = set()
    for t, track in sorted(enumerate(tracks), key=lambda item: len(item[1].instances)):
        if track.group != "panel":
            continue
        core = track.core()
        holding = [h for h, other in enumerate(tracks) if h != t and h not in merged and other.group == "panel"
                   and _core_inside(core, other.core(), config.nested_instance_share)]
        if len(holding) != 1 or set(track.instances) & set(tracks[holding[0]].instances):
            continue
        host = tracks[holding[0]]
        host.instances.update(track.instances)
        host.votes = host.votes + track.votes
        merged.add(t)
    return [track for t, track in enumerate(tracks) if t not in merged]


def segment_mesh(vertices: np.ndarray, faces: np.ndarray, face_piece: np.ndarray | None = None,
                 config: SegmentConfig = SegmentConfig(), consistent_winding: bool = True,
                 roles=make_roles) -> Segmentation:
    """Segment a canonical (+z up, -y front) mesh into base, movable parts and handles.

    ``roles(views, face_piece, config) -> (hierarchy, masks)`` builds the two roles (the
    configured backends by default)."""
    if config.frame_rings and thin_along(np.ptp(vertices, axis=0), FRONT, 1.0 / config.ring_min_depth_share):
        config = replace(config, frame_rings=False)  # a window: its sashes' bars are measured as sashes
    views = render_rig(vertices, faces, config, consistent_winding)
    hierarchy, masks = roles(views, face_piece, config)
    tree, cached, deferred, log = corefine(hierarchy, masks, views, config)
    tracks = associate(masks, views, cached, deferred, len(faces), config)
    visible = [seen_faces(view, len(faces)) for view in views]

    # prune parts without enough evidence: detected in too few of the views that see them
    kept = []
    pruned = []
    for track in tracks:
        seen = sum(1 for faces_seen in visible if faces_seen[track.faces].mean() >= 0.5)
        detected = len(track.instances)
        share = config.min_view_support if track.group == "panel" else config.min_view_support_small
        if config.corefinement and detected < share * max(seen, detected):
            pruned.append({"group": track.group, "detected": detected, "seen": seen})
            continue
        kept.append((track, seen))

    parts, evidence = [], []
    for k, (track, seen) in enumerate(kept):
        votes: dict[str, float] = {}
        for inst in track.instances.values():
            votes[inst.category] = votes.get(inst.category, 0.0) + inst.score
        category = max(votes, key=votes.get)
        parts.append(SegmentedPart("", category, 0, _track_normal(track, views), len(track.instances), seen))
        evidence.append(PartEvidence({v: i.mask for v, i in track.instances.items()},
                                     {v: i.score for v, i in track.instances.items()}))
    # handles hang under the panel whose masks hold them; parents are boosted by visible children
    for k, part in enumerate(parts):
        if part.category != "handle":
            continue
        best, best_hits = 0, 0
        for j, other in enumerate(parts):
            if other.category not in PANEL_CATEGORIES:
                continue
            hits = sum(int((evidence[j].masks[v] & m).sum()) for v, m in evidence[k].masks.items() if v in evidence[j].masks)
            if hits > best_hits:
                best, best_hits = j + 1, hits
        part.parent = best
    for j, part in enumerate(parts):
        children = [k for k, p in enumerate(parts) if p.parent == j + 1]
        if children:
            evidence[j].boost = {v: 1.0 + sum(v in evidence[c].masks for c in children) / len(children)
                                 for v in evidence[j].masks}
    for part, name in zip(parts, numbered_names([p.category for p in parts])):
        part.name = name

    top_k = [config.top_k_views if _group(p.category) == "panel" else config.top_k_views_small for p in parts]
    labels, _, weights = lift_evidence(views, evidence, len(faces), top_k)
    refine_log = {}
    if config.graph_refinement and parts:
        best_masks = {k: (max(w, key=w.get), evidence[k - 1].masks[max(w, key=w.get)])
                      for k, w in enumerate(weights, start=1) if w}
        all_masks = {k: [(v, evidence[k - 1].masks[v]) for v in w] for k, w in enumerate(weights, start=1) if w}
        # doors and drawers; a lid's strips run down coplanar sides to a parting line too faint
        # on a thin laptop lid to stop the growth, and its views already show the front strip
        panels = {k: part.normal for k, part in enumerate(parts, start=1) if part.category in ("door", "drawer")}
        labels, refine_log = refine_labels(vertices, faces, labels, len(parts) + 1, views, best_masks, all_masks,
                                           panels, config.panel_max_thickness, config.lone_face_reach)
        labels, strips = grow_edge_strips(vertices, faces, labels, panels, config, fused_surface(face_piece, config))
        refine_log["strips"] = strips["claimed"]
    return Segmentation(labels.astype(np.int32), parts, tree,
                        {"corefinement": log, "pruned": pruned, "graph_refinement": refine_log,
                         "parts": [{"name": p.name, "views": p.views, "seen": p.seen} for p in parts]},
                        views, [e.masks for e in evidence])


def _track_normal(track: _Track, views: list[ViewMaps]) -> np.ndarray:
    normals = np.concatenate([views[v].normals[inst.mask] for v, inst in track.instances.items()])
    return snap_to_axis(normals.mean(axis=0))


def overlay_masks(view: ViewMaps, instances: list[InstanceMask]) -> np.ndarray:
    """(H, W, 3) uint8: the shaded view with each mask blended in a vivid colour."""
    return blend_masks(view.shaded(), [inst.mask for inst in instances], 0.55)


__all__ = ["CATEGORIES", "COREFINE_ACTIONS", "COREFINE_CASES", "PROPOSED", "REVISED", "Segmentation", "SegmentedPart",
           "corefine_action", "corefine_case", "segment_mesh", "overlay_masks"]
