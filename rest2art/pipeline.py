"""The reconstruction pipeline for one object: mesh in, ArticulatedAsset out.

Stages are pure functions on arrays (frame, parts, joints, completion, collision); this module
only wires them together and maps canonical results back to the input frame.
"""

from __future__ import annotations

import functools
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part
from rest2art.collision.clearance import clear_asset_hulls, clip_to_solids
from rest2art.collision.hulls import allow_coacd_runs, decompose, hull_signature, stop_coacd_runs, within_budget
from rest2art.completion.solids import drawer_tray, mass_properties, part_solids
from rest2art.config import Config
from rest2art.frame.canonical import CanonicalFrame, estimate_frame, facing_instead, front_shown
from rest2art.geometry.basics import densest_plane, inside_box, outer_plane, panel_frame, thin_along
from rest2art.gate.plausibility import (GateFinding, backed_share, bare_drawer, enclosing_frames, floor_area,
                                       front_plane, facing_share, hinge_guessed, joint_confidence, nearest_box_edge,
                                       open_below_share, open_front_below, open_outline_share, open_share_behind,
                                       plinth_strip, review, slides_for_want_of_a_hinge, worktop)
from rest2art.io.load import LoadedMesh, first_copies, load_mesh
from rest2art.joints.rules import (JointEstimate, bypass_pairs, estimate_joints, find_handle, front_sash_box,
                                  guess_category, held_edges, in_track, opening_caps, pane_behind,
                                  scanned_pane_behind)
from rest2art.joints.sweep import free_range
from rest2art.parts.grips import split_fused_fronts
from rest2art.parts.pieces import (PANELS, PartEstimate, body_pieces, cut_from_surface, extract_parts, floats_clear,
                                   is_panel, pieces_box, renumber)
from rest2art.parts.surface import add_segmented_parts

Progress = Callable[[str], None]


def _quiet(_: str) -> None:
    pass


@dataclass
class StageTimer:
    """Wall time per stage, seconds."""

    times: dict[str, float] = field(default_factory=dict)

    def run(self, name: str, progress: Progress, fn, *args, **kwargs):
        progress(name)
        start = time.perf_counter()
        result = fn(*args, **kwargs)  # a stage run again (another front tried) adds up
        self.times[name] = round(self.times.get(name, 0.0) + time.perf_counter() - start, 3)
        return result


def format_prior_up(path: Path | None) -> str:
    """The up convention of a file format: glTF is +y up, the rest are read as +z up."""
    if path is not None and path.suffix.lower() in (".glb", ".gltf"):
        return "+y"
    return "+z"


def reconstruct_mesh(mesh: LoadedMesh, config: Config = Config(), up: str | None = None, front: str | None = None,
                     progress: Progress = _quiet, timer: StageTimer | None = None,
                     debug: dict | None = None, motion_videos: list[np.ndarray] | None = None) -> ArticulatedAsset:
    """Parts and joints of a loaded mesh (no completion yet), in the input frame.

    With no ``front`` given and nothing moving by evidence on the side the relief chose
    (``moves_by_evidence``: no part, or only bare panels whose hinge side is a guess or that
    slide for want of a hinge), the
    frame's other sides (``front_alternatives``) are tried in turn; the first where a part
    moves by evidence (``opens_towards_front``), with no fewer moving parts than the first
    reading's bare panels, is the front, else the first answer stands.
    ``motion_videos``: (T, H, W, 3) frames per video made from the video view's conditioning
    image; the joints of the parts they show moving come from them (grounded by the mesh).
    A ``debug`` dict receives the stages' intermediate results (``"segmentation"``, and the
    ``"video_view"`` with the parts' semantics). The faces of a double-sided export
    (``first_copies``) are read once."""
    first = first_copies(mesh.vertices, mesh.faces, mesh.face_node, config.load.double_sided_share)
    single = first == np.arange(len(first))
    if not single.all():  # read once; each copy takes the part of the face it repeats
        once = replace(mesh, faces=mesh.faces[single], face_node=mesh.face_node[single],
                       face_component=mesh.face_component[single],
                       notes=[*mesh.notes, f"{int((~single).sum())} faces repeat another (a double-sided export): "
                                           "read once, labelled with the face they repeat"])
        asset = reconstruct_mesh(once, config, up, front, progress, timer, debug, motion_videos)
        asset.face_part = asset.face_part[(np.cumsum(single) - 1)[first]]
        return asset
    timer = timer or StageTimer()
    tm = mesh.trimesh()
    frame = timer.run("canonical frame", progress, estimate_frame, tm, config.frame, up, front,
                      format_prior_up(mesh.path))
    asset = _articulate(mesh, tm, frame, config, progress, timer, debug, motion_videos)
    if front is None and not moves_by_evidence(asset, config.gate.min_turn_confidence):
        # nothing moves by evidence on the side with the most relief: the front is the side whose
        # parts do (a flush door shows fewer seams than a side's overhang or a proud rim seen
        # from behind; a desk's side panel framed by its legs, cut into a bare door, more than
        # drawer fronts sunk into its front)
        shown = "none" if not asset.movable_joints else "only guessed hinges"
        for other in frame.evidence.get("front_alternatives", []):
            turned = facing_instead(frame, np.asarray(other), "the side whose parts move (the relief's "
                                    f"choice showed {shown})")
            seen: dict | None = {} if debug is not None else None
            trial = _articulate(mesh, tm, turned, config, progress, timer, seen, motion_videos)
            # a side that shows fewer moving parts than the bare panels seen first explains less
            if opens_towards_front(trial, config.gate.min_turn_confidence) \
                    and len(trial.movable_joints) >= len(asset.movable_joints):
                if debug is not None:
                    debug.update(seen)
                return trial
    return asset


def moves_by_evidence(asset: ArticulatedAsset, min_confidence: float) -> bool:
    """Whether the side ``asset`` was read from shows a part that moves by evidence: any
    movable part but a bare panel whose hinge side is a guess (its rule says ``no handle``),
    unless ``opens_towards_front`` counts it even so. A lid counts: it opens upwards whichever
    side is the front."""
    evidence = asset.metadata.get("joints", {})
    return any(not hinge_guessed(evidence.get(joint.child, {})) and not slides_for_want_of_a_hinge(
        evidence.get(joint.child, {})) for joint in asset.movable_joints) \
        or opens_towards_front(asset, min_confidence)


def opens_towards_front(asset: ArticulatedAsset, min_confidence: float) -> bool:
    """Whether a part of ``asset`` that is no lid moves with a confidence of at least
    ``min_confidence``: a door, drawer, knob or button the evidence (a handle, a drawer's
    depth, a knob's shape) makes movable, on the side it is seen from. A lid opens upwards
    whichever side is the front, and a hinge side guessed for a bare panel says little, nor
    does a panel that slides for want of a hinge, nor a drawer with no grip (``bare_drawer``:
    the wall of a box built of boards, framed by its neighbours' edges, reads as one)."""
    evidence = asset.metadata.get("joints", {})
    return any(asset.part(joint.child).semantic != "lid"
               and evidence.get(joint.child, {}).get("confidence", 0.0) >= min_confidence
               and not slides_for_want_of_a_hinge(evidence.get(joint.child, {}))
               and not bare_drawer(evidence.get(joint.child, {}))
               for joint in asset.movable_joints)


def _articulate(mesh: LoadedMesh, tm: trimesh.Trimesh, frame: CanonicalFrame, config: Config, progress: Progress,
                timer: StageTimer, debug: dict | None, motion_videos: list[np.ndarray] | None) -> ArticulatedAsset:
    """Parts and joints of ``mesh`` (``tm``: the same as a trimesh) seen in ``frame``."""
    canonical = frame.to_canonical(mesh.vertices)
    from rest2art.parts.segment.panels import fused_surface

    parts, pieces = timer.run("parts", progress, extract_parts, canonical, mesh.faces, mesh.face_component,
                              config.parts, fused_surface(mesh.face_component, config.segment))
    parts, pieces = split_fused_fronts(parts, pieces, canonical, mesh.faces, config.parts)
    segmentation = None
    if config.segment.enabled:
        from rest2art.parts.segment import segment_mesh
        from rest2art.parts.segment.roles import make_roles

        consistent = bool(tm.is_winding_consistent)
        flip = consistent and tm.is_watertight and tm.volume < 0  # inside-out: cull the other side
        faces_for_views = mesh.faces[:, ::-1] if flip else mesh.faces
        segmentation = timer.run("segmentation", progress, segment_mesh, canonical, faces_for_views,
                                 mesh.face_component, config.segment, consistent,
                                 roles=functools.partial(make_roles, models=config.models))
        parts, pieces = add_segmented_parts(parts, pieces, segmentation.face_label, segmentation.parts,
                                            canonical, mesh.faces, config.parts)
        if debug is not None:
            debug["segmentation"] = segmentation
    parts = join_sash_panes(parts, pieces, config)
    parts, standing_free = panes_standing_free(parts, pieces, config)
    parts, sliding = drawers_sliding_past_doors(parts, pieces, config)
    standing_free += sliding
    parts, false_panels = demote_false_panels(parts, pieces, config)
    false_panels[:0] = standing_free
    category = guess_category(parts, np.ptp(canonical, axis=0), config.joints)
    joints = timer.run("joints", progress, estimate_joints, parts, pieces, category, config.joints,
                       front_shown(frame))
    if motion_videos or debug is not None or config.articulation.video_backend != "none":
        face_part = faces_to_parts(parts, pieces, len(mesh.faces))
        timer.run("video joints", progress, _video_joints, parts, pieces, canonical, mesh.faces, face_part, category,
                  joints, motion_videos or [], config, debug)
    gate = timer.run("plausibility", progress, review_structure, parts, pieces, joints, category, config)
    gate.findings[:0] = false_panels
    gate.demoted = sorted([*gate.demoted, *(name for f in false_panels if f.action == "demoted" for name in f.parts)])
    parts = demote(parts, gate.demoted, pieces, config.gate.fitting_reach)
    joints = {name: j for name, j in joints.items() if name not in gate.demoted}
    swapped = stand_on_support(parts, pieces, joints, category, config)
    if swapped is not None:
        gate.findings.append(swapped)
        gate.confidence[parts[1].name] = joints[parts[1].name].evidence["confidence"]
    for name, confidence in gate.confidence.items():
        joints[name].evidence["confidence"] = round(confidence, 3)
    part_faces = [np.concatenate([pieces[i].faces for i in part.pieces]) for part in parts]
    face_part = faces_to_parts(parts, pieces, len(mesh.faces), part_faces)

    out_parts, out_joints = [], []
    for part, faces in zip(parts, part_faces):
        part_mesh = trimesh.Trimesh(mesh.vertices, mesh.faces[np.sort(faces)], process=False)
        part_mesh.remove_unreferenced_vertices()
        parent = None if part.semantic == "base" else "base" if part.parent is None else part.parent.name
        out_parts.append(Part(part.name, part.semantic, parent, part_mesh))
        if part.name in joints:
            j = joints[part.name]
            lower_upper = (0.0, float(j.upper))
            out_joints.append(Joint(f"{part.name}_joint", j.type, parent, part.name,
                                    frame.to_input(j.axis), frame.to_input(j.origin), lower_upper))
    asset = ArticulatedAsset(out_parts, out_joints, face_part, {
        "category": category,
        "frame": {"up": frame.up.tolist(), "front": frame.front.tolist(), "evidence": frame.evidence},
        "joints": {name: j.evidence for name, j in joints.items()},
        "gate": gate.to_dict(),
        "segmentation": None if segmentation is None else {
            "tree": segmentation.tree.counts(), **{k: v for k, v in segmentation.log.items() if k != "corefinement"}},
        "input": {"path": str(mesh.path) if mesh.path else None, "faces": int(len(mesh.faces)),
                  "scale_to_metres": mesh.scale_to_metres, "notes": mesh.notes},
    })
    asset.validate()
    return asset


def faces_to_parts(parts: list, pieces: list, n_faces: int, part_faces: list[np.ndarray] | None = None) -> np.ndarray:
    """(F,) int32 index into ``parts`` of every input face; ``part_faces`` (each part's face
    indices) when the caller has them already."""
    if part_faces is None:
        part_faces = [np.concatenate([pieces[i].faces for i in part.pieces]) for part in parts]
    face_part = np.zeros(n_faces, np.int32)
    for index, faces in enumerate(part_faces):
        face_part[faces] = index
    return face_part


def review_structure(parts: list, pieces: list, joints: dict, category: str, config: Config):
    """The plausibility gate over the canonical ``parts`` and their ``joints`` (GateResult)."""
    everything = np.concatenate([pieces[i].mesh.vertices for part in parts for i in part.pieces])
    extents, caps = {"base": np.ptp(everything, axis=0)}, {}
    open_behind, floor_heights, facing, opened, enclosed, backed, door_fronts = {}, {}, {}, {}, set(), {}, {}
    plinths, fronts, below, whole = set(), [], {}, None
    carcass = trimesh.util.concatenate([pieces[i].mesh for i in parts[0].pieces])
    for part in parts[1:]:
        vertices = np.concatenate([pieces[i].mesh.vertices for i in part.pieces])
        extents[part.name] = np.ptp(vertices, axis=0)
        if part.outward is not None and not cut_from_surface(part):
            lo, hi = vertices.min(axis=0), vertices.max(axis=0)
            axis = int(np.argmax(np.abs(part.outward)))  # its front may stand out of the carcass's box
            (lo if part.outward[axis] < 0 else hi)[axis] = carcass.bounds[0 if part.outward[axis] < 0 else 1, axis]
            if inside_box(lo[None], hi[None], *carcass.bounds, config.gate.enclosed_tolerance)[0]:
                enclosed.add(part.name)
        if part.name not in joints:
            continue
        if part.semantic in ("door", "drawer", "lid") and part.outward is not None:
            part_mesh = trimesh.util.concatenate([pieces[i].mesh for i in part.pieces])
            opened[part.name] = open_outline_share(part_mesh, part.outward, config.gate)
            if part.semantic != "drawer":
                facing[part.name] = facing_share(part_mesh, part.outward, config.gate)
            if part.semantic == "door" and joints[part.name].type == "revolute" and abs(part.outward[2]) < 0.5:
                u, v = panel_frame(part.outward)
                flat = vertices @ np.stack([u, v]).T
                door_fronts[part.name] = (np.stack([flat.min(axis=0), flat.max(axis=0)]),
                                          front_plane(part_mesh, part.outward, config.gate))
        # whether a door or drawer has a grip: found once, asked twice below
        front = part.semantic in ("door", "drawer") and part.outward is not None
        gripped = front and find_handle(part, pieces, part.outward, config.joints) is not None
        if front and abs(part.outward[1]) > 0.5:
            if part.semantic == "drawer" and not gripped \
                    and plinth_strip(vertices.min(axis=0), vertices.max(axis=0), carcass.vertices, config.gate):
                plinths.add(part.name)
            if gripped and part.outward[1] < -0.5:
                fronts.append((vertices.min(axis=0), vertices.max(axis=0)))  # a front with a grip
        joint = joints[part.name]
        along = float(extents[part.name] @ np.abs(part.outward)) if part.outward is not None else 0.0
        caps[part.name] = opening_caps(part.semantic, category, along, config.joints)[joint.type]
        if part.semantic in ("knob", "button"):
            floor_heights[part.name] = float(vertices[:, 2].max() - everything[:, 2].min())
        elif part.outward is not None and _opens_outward(part, joint, config) \
                and not _deep_drawer(part, pieces, vertices, everything, config):
            open_behind[part.name] = open_share_behind(vertices, part.outward, carcass,
                                                       float(np.ptp(everything @ part.outward)), config.gate,
                                                       fused=cut_from_surface(part))
            if part.semantic == "drawer":
                backed[part.name] = backed_share(vertices, part.outward, carcass, config.gate)
        # a door, hinged or sliding, facing sideways, its room closed at the back by the
        # object; or a drawer cut out of a fused surface that showed no box hanging behind it
        # (``hanging_box_faces``): over open space, a drawer's box is in sight. A gripped one
        # must hang over open space in front as well (a grip beside an apron board, the next
        # drawer's proud side, puts no box behind it; a scan keeps no inside, so behind a drawer
        # in a stack, or a door, the room is open below too)
        boxless = part.semantic == "drawer" and cut_from_surface(part) and "box_floor" not in part.extra
        if front and (part.semantic == "door" or boxless) and abs(part.outward[2]) < 0.5 \
                and (backed[part.name] if part.name in backed
                     else backed_share(vertices, part.outward, carcass, config.gate)) >= config.gate.min_backed_share:
            below[part.name] = open_below_share(vertices, part.outward, carcass, config.gate)
            if gripped:
                if whole is None:  # the part itself lies above the rays: the whole object will do
                    whole = trimesh.util.concatenate([pieces[i].mesh for other in parts for i in other.pieces])
                below[part.name] = min(below[part.name], open_front_below(vertices, part.outward, whole, config.gate))
    lids = [p for p in parts[1:] if p.semantic == "lid" and p.name in joints]
    boxes = {p.name: pieces_box(p.pieces, pieces) for p in lids}
    worktops = {name for name, (lo, hi) in boxes.items() if worktop(lo, hi, fronts, config.gate)}
    return review(parts, joints, extents, caps, config.gate, open_behind, floor_heights, facing, opened, enclosed,
                  backed, door_fronts, plinths, worktops, below)


def _opens_outward(part, joint, config: Config) -> bool:
    """A hinged door or a drawer pulled out of its front: what should open onto a cavity
    (not a lid, which may close on a flat keyboard, nor a panel sliding in its own plane)."""
    if part.semantic == "door":
        return joint.type == "revolute"
    return part.semantic == "drawer" and joint.type == "prismatic" \
        and abs(float(np.asarray(joint.axis) @ part.outward)) > config.gate.facing_cos


def _deep_drawer(part, pieces: list, vertices: np.ndarray, everything: np.ndarray, config: Config) -> bool:
    """A drawer whose own body reaches ``drawer_body_share`` of the object's depth behind the
    plane of its front (not behind a knob or button standing proud of it): the body is its
    cavity."""
    if part.semantic != "drawer":
        return False
    part_mesh = trimesh.util.concatenate([pieces[i].mesh for i in part.pieces])
    behind = front_plane(part_mesh, part.outward, config.gate) - float((vertices @ part.outward).min())
    return behind >= config.gate.drawer_body_share * float(np.ptp(everything @ part.outward))


def demote(parts: list, names: list[str], pieces: list | None = None, contact: float = 0.0) -> list:
    """``parts`` with the named movable parts' pieces given back to the base (the first part);
    a part mounted on a demoted one is mounted on the base. With ``pieces``, a fitting the views
    gave a demoted panel (``extra["fittings"]``) that comes within ``contact`` (m) of a knob or
    button still movable goes to that control instead: the stem a button stands on, once the
    face it passes through proves no drawer."""
    if not names:
        return parts
    base = parts[0]
    base.pieces = list(base.pieces)
    kept = [base, *[p for p in parts[1:] if p.name not in names]]
    controls = [p for p in kept if p.semantic in ("knob", "button")]
    for part in parts[1:]:
        if part.name not in names:
            continue
        fittings = set(part.extra.get("fittings", ())) if pieces is not None and controls else set()
        for i in part.pieces:
            holder = next((c for c in controls if i in fittings and not floats_clear([i], [c.pieces], pieces, contact)),
                          None)
            (holder or base).pieces.append(i)
    for part in kept:
        if part.parent is not None and part.parent.name in names:
            part.parent = None
    return kept


def join_sash_panes(parts: list, pieces: list, config: Config) -> list:
    """``parts`` with the panes of a scanned sliding window's sashes joined, one door per sash
    (``extra["sash_panes"]``, and its widest ``glazing_bar``). Doors and drawers cut out of a
    fused surface are grouped by the plane holding most of their area facing out (their glass;
    within ``segment.coplanar_tol``): two groups a sash's stagger apart, three panes or more in
    all, each group filling at least ``joints.sash_pane_fill`` of its outline (panes between
    glazing bars), whose outlines meet along an edge as two sashes do (``scanned_pane_behind``,
    the gap across it as wide as the two groups' glazing bars more: their meeting rails). A
    cabinet's drawers in a face frame lie in one plane: no second group. Only in an object thin
    along the panes' facing (``thin_along``): a sliding cabinet's framed drawers, their fields
    sunk behind the rail under them, are no sashes."""
    lo, hi = pieces_box(list(range(len(pieces))), pieces)
    panels = [p for p in parts[1:] if p.semantic in ("door", "drawer") and p.parent is None and cut_from_surface(p)
              and thin_along(hi - lo, p.outward, config.joints.pane_min_flatness)]
    if len(panels) < 3:
        return parts
    surface = {p.name: trimesh.util.concatenate([pieces[i].mesh for i in p.pieces]) for p in panels}
    groups: list[tuple] = []  # (first panel, front plane, members)
    for panel in panels:
        mesh = surface[panel.name]
        facing = mesh.face_normals @ panel.outward > config.segment.strip_frontal_cos
        plane = densest_plane(mesh, facing, panel.outward) if facing.any() else outer_plane(mesh, panel.outward, 0.0)
        group = next((g for g in groups if np.allclose(g[0].outward, panel.outward)
                      and abs(g[1] - plane) <= config.segment.coplanar_tol), None)
        if group is None:
            groups.append((panel, plane, [panel]))
        else:
            group[2].append(panel)

    def outlines(members: list) -> list[np.ndarray]:  # each pane's (2, 2) box seen from the front
        u, v = panel_frame(members[0].outward)
        return [np.stack([b.min(axis=0), b.max(axis=0)]) for b in
                (pieces[m.panel].mesh.vertices @ np.array([u, v]).T for m in members)]

    def fills(boxes: list[np.ndarray]) -> bool:
        area = sum(float(np.prod(b[1] - b[0])) for b in boxes)
        union = np.concatenate(boxes)
        return area >= config.joints.sash_pane_fill * float(np.prod(np.ptp(union, axis=0)))

    def joint_surface(members: list) -> trimesh.Trimesh:
        return trimesh.util.concatenate([surface[m.name] for m in members])

    boxes = [outlines(members) for _, _, members in groups]
    joined: list = []
    for k, (first, plane_a, a) in enumerate(groups):
        for j, (_, plane_b, b) in enumerate(groups[k + 1:], start=k + 1):
            if len(a) + len(b) < 3 or not np.allclose(first.outward, b[0].outward) \
                    or not (fills(boxes[k]) and fills(boxes[j])):
                continue
            front, back = (a, b) if plane_a > plane_b else (b, a)
            bars = glazing_bar(boxes[k]), glazing_bar(boxes[j])
            if scanned_pane_behind(joint_surface(front), joint_surface(back), first.outward, config.joints,
                                   sum(bars)) is not None:
                joined += [(a, bars[0]), (b, bars[1])]
    if not joined:
        return parts
    gone = {id(m) for members, _ in joined for m in members}
    out = [p for p in parts if id(p) not in gone]
    for members, bar in joined:
        main = max(members, key=lambda m: surface[m.name].area)
        extra = {**main.extra, "fittings": [i for m in members for i in m.extra.get("fittings", [])],
                 "sash_panes": len(members), "glazing_bar": bar}
        out.append(PartEstimate("door", [i for m in members for i in m.pieces], main.outward, main.panel, extra=extra))
    renumber(out[1:])
    return out


def glazing_bar(outlines: list[np.ndarray]) -> float:
    """Width (m) of the widest bar between panes of one sash, seen from the front: the widest
    gap from a pane's outline ((2, 2) box) to its nearest neighbour's; 0 for one pane."""
    widest = 0.0
    for k, box in enumerate(outlines):
        gaps = [float(np.max(np.maximum(other[0] - box[1], box[0] - other[1])))
                for j, other in enumerate(outlines) if j != k]
        widest = max(widest, max(0.0, min(gaps, default=0.0)))
    return widest


def panes_standing_free(parts: list, pieces: list, config: Config) -> tuple[list, list[GateFinding]]:
    """``parts`` with every drawer that has the object behind less than ``gate.min_backed_share``
    of its face (``backed_share``: nothing to draw it out of) made a door, renamed, before any
    joint is estimated: a pane standing free, as a window's sash in its open frame or an open
    laptop's screen, is hinged or slides in its own plane, which the door rules tell apart.
    Returns the parts and one finding (action ``door``) naming the new doors."""
    carcass = None
    free = []
    for part in parts[1:]:
        if part.semantic != "drawer" or part.outward is None:
            continue
        if carcass is None:
            carcass = trimesh.util.concatenate([pieces[i].mesh for i in parts[0].pieces])
        vertices = np.concatenate([pieces[i].mesh.vertices for i in part.pieces])
        if backed_share(vertices, part.outward, carcass, config.gate) < config.gate.min_backed_share:
            free.append(part)
    for part in free:
        part.extra["standing_free"] = True  # the door rules look for the edge it stands on
    return parts, drawers_made_doors(parts, free, "standing_free", "a panel with nothing behind it to draw out "
                                     "of (a sash, a screen): a door, not a drawer")


def drawers_sliding_past_doors(parts: list, pieces: list, config: Config) -> tuple[list, list[GateFinding]]:
    """``parts`` with every drawer that meets a door, or another drawer, as two doors sliding
    past each other do (``bypass_pairs`` over doors and drawers: as wide, side by side in one
    row, their fronts a track's step apart) made a door, renamed, before any joint is
    estimated: the views read the front one of a scanned pair of sliding doors, a tall panel
    with a pull, as a drawer, and the door beside it, with no pair left, swung on a hinge; a
    pair of low sliding doors without pulls both read as drawers by their proportions (drawers
    side by side in one row share one plane; a drawer with a grip is one by evidence, and the
    bare boards of a desk's apron step beside it). Returns the parts and one finding (action
    ``door``) naming the new doors."""
    fronts = [p for p in parts if p.semantic in ("door", "drawer") and p.outward is not None]
    bare = {p.name for p in fronts
            if p.semantic == "drawer" and find_handle(p, pieces, p.outward, config.joints) is None}
    # beside in one row (``u``, across): a drawer under a sliding door steps too
    turned = [d for d in fronts if d.semantic == "drawer" and any(
        bypass_pairs([d, other], pieces, config.joints, ("door", "drawer")).get(d.name, "v").startswith("u")
        for other in fronts if other is not d and (other.semantic == "door" or {d.name, other.name} <= bare))]
    return parts, drawers_made_doors(parts, turned, "sliding_pair", "steps past the front beside it as two "
                                     "sliding doors do: a door, not a drawer")


def drawers_made_doors(parts: list, drawers: list, kind: str, reason: str) -> list[GateFinding]:
    """Make each of ``drawers`` (members of ``parts``) a door and renumber ``parts`` in place;
    returns one finding ``kind`` (action ``door``) naming each old and new name and ``reason``,
    or none when ``drawers`` is empty."""
    if not drawers:
        return []
    was = [p.name for p in drawers]
    for part in drawers:
        part.semantic = "door"
    renumber(parts[1:])
    now = [p.name for p in drawers]
    return [GateFinding(kind, tuple(now), ", ".join(f"{a} -> {b}" for a, b in zip(was, now)) + ": " + reason, "door")]


def demote_false_panels(parts: list, pieces: list, config: Config) -> tuple[list, list[GateFinding]]:
    """``parts`` without what only looks like a panel, before any joint is estimated: a door,
    drawer or lid whose box holds another of them (see ``gate.enclosing_frames``; unless it
    carries their grip, :func:`grip_holds_the_rest`: then they join it), and the
    fixed pane a sash slides over (``fixed_panes``). Their pieces go back to the base.
    Returns the parts and the findings."""
    findings = []
    panels = [p for p in parts[1:] if p.semantic in PANELS]
    boxes = [pieces_box(p.pieces, pieces) for p in panels]
    index = {id(p): k for k, p in enumerate(panels)}
    mounted_on = [index.get(id(p.parent)) for p in panels]
    lo, hi = np.array([b[0] for b in boxes]).reshape(-1, 3), np.array([b[1] for b in boxes]).reshape(-1, 3)
    framing, gone = [], set()
    for k in [] if len(panels) < 2 else enclosing_frames(lo, hi, mounted_on, config.gate.frame_tolerance):
        if panels[k].name in gone:
            continue
        inner = [panels[j] for j in np.flatnonzero(inside_box(lo, hi, lo[k], hi[k], config.gate.frame_tolerance))
                 if j != k and panels[j].name not in gone]
        if grip_holds_the_rest(panels[k], inner, pieces, config):
            # the grip is on the frame: a frame-and-panel door whose raised panel a scan left a
            # shell of its own; the panel is the door's
            panels[k].pieces = [*panels[k].pieces, *(i for part in inner for i in part.pieces)]
            gone |= {part.name for part in inner}
        else:
            framing.append(panels[k].name)
    parts = [p for p in parts if p.name not in gone]
    framing = [n for n in framing if n not in gone]
    if framing:
        parts = demote(parts, framing)
        findings.append(GateFinding("frame", tuple(framing), f"{', '.join(framing)}: holds another panel in its "
                                    "own outline and depth: the frame around it, not a panel", "demoted"))
    fixed = fixed_panes(parts, pieces, config)
    if fixed:
        parts = demote(parts, fixed)
        findings.append(GateFinding("fixed_pane", tuple(fixed), f"{', '.join(fixed)}: a pane just behind another "
                                    "that meets it along an edge: the fixed pane the other slides over", "demoted"))
    return parts, findings


def grip_holds_the_rest(frame, inner: list, pieces: list, config: Config) -> bool:
    """Whether a door or drawer ``frame`` of one thin piece (``is_panel``; and the grips cut
    from it), whose box holds the panels ``inner``, is the part they belong to: it carries a grip
    (``find_handle``) and none of them does. A window's frame holds its sashes and carries no
    grip; a scanned frame-and-panel door holds its raised panel, which a gap wider than the
    scan's blur left a shell of its own, and carries the door's knob; a lever's housing is no
    panel."""
    if not inner or frame.semantic not in ("door", "drawer") \
            or not set(frame.pieces) - {frame.panel} <= set(frame.extra.get("fittings", ())) \
            or not is_panel(pieces[frame.panel], frame.outward, config.parts):
        return False
    if find_handle(frame, pieces, frame.outward, config.joints) is None:
        return False
    return all(part.semantic == frame.semantic and find_handle(part, pieces, part.outward, config.joints) is None
               for part in inner)


def fixed_panes(parts: list, pieces: list, config: Config) -> list[str]:
    """Names of the doors that lie just behind another door and meet it along an edge
    (``joints.rules.pane_behind``, judged on the boxes of their bodies, without handles)
    and have no handle of their own nor a track (``held_edges``): the fixed pane of a
    sliding window. The door in front gets ``extra["slides_towards"]``, the edge it slides
    over the pane by. Panes cut out of a fused surface show their fronts only
    (``scanned_pane_behind``) and no track to judge by: the one behind is fixed unless the two
    meet as doors sliding past each other do (``bypass_pairs``). Only in a flat object, as
    wide or tall as ``joints.pane_min_flatness`` times its depth along the panes' facing (a
    window in its frame): a step behind a deep cabinet's door lies what an open compartment
    beside it shows."""
    doors = [p for p in parts[1:] if p.semantic == "door"]
    lo, hi = pieces_box(list(range(len(pieces))), pieces)
    size = hi - lo  # the whole object's box
    body, pulled = {}, set()
    for door in doors:
        ids = body_pieces(door.pieces, pieces, door.outward, config.parts.body_min_span)
        body[door.name] = pieces_box(ids, pieces)
        face = max(float(body[door.name][0] @ door.outward), float(body[door.name][1] @ door.outward))
        if any(max(float(pieces[i].lo @ door.outward), float(pieces[i].hi @ door.outward))
               > face + config.joints.handle_min_proud for i in door.pieces if i not in ids):
            pulled.add(door.name)  # a handle of its own: a hand moves it
    fixed, base = set(), {}

    def frame() -> trimesh.Trimesh:  # the base's surface as it stands (a front sash takes pieces of it)
        if "mesh" not in base:
            base["mesh"] = trimesh.util.concatenate([pieces[i].mesh for i in parts[0].pieces])
        return base["mesh"]

    surface = {door.name: trimesh.util.concatenate([pieces[i].mesh for i in door.pieces]) for door in doors}
    bypass = bypass_pairs(parts, pieces, config.joints)
    for front in doors:
        if not thin_along(size, front.outward, config.joints.pane_min_flatness):
            continue  # a deep box: no frame of sashes
        for back in doors:
            if back is front or back.name in pulled or not np.allclose(front.outward, back.outward):
                continue
            if cut_from_surface(back) or cut_from_surface(front):  # no track to judge by: the back one stays
                if front.name in bypass and back.name in bypass:
                    continue  # meeting as two doors in two tracks do: each slides past the other
                rails = front.extra.get("glazing_bar", 0.0) + back.extra.get("glazing_bar", 0.0)
                edge = scanned_pane_behind(surface[front.name], surface[back.name], front.outward, config.joints, rails,
                                           frame())
                if edge is not None:
                    front.extra["slides_towards"] = edge
                    fixed.add(back.name)
                    take_front_sash(front, [parts[0], back], pieces,
                                    front_sash_box(surface[front.name], surface[back.name], front.outward, edge,
                                                   frame(), config.joints), config.joints.sash_track_depth)
                    base.clear()
                continue
            edge = pane_behind(*body[front.name], front.outward, *body[back.name], config.joints)
            if edge is None:
                continue
            back_mesh = trimesh.util.concatenate([pieces[i].mesh for i in back.pieces])
            if in_track(held_edges(back_mesh, back.outward, frame(), config.joints)):
                continue  # in a track of its own: it slides too
            front.extra["slides_towards"] = edge
            fixed.add(back.name)
    return sorted(fixed)


def take_front_sash(sash, holders: list, pieces: list, box: tuple[np.ndarray, np.ndarray] | None,
                    track_depth: float) -> None:
    """Give the scanned ``sash`` the faces of the ``holders`` (the base, the pane behind it)
    wholly inside ``box`` (``front_sash_box``; nothing when None), cut out of their pieces: its back,
    its bars and its meeting rail, which the views did not see as its; and give the base back
    the sash's faces outside the box's outline seen from the front (the frame's jambs the
    views grew the pane into, which would stop it sliding). Its faces within ``track_depth``
    (m) of the box's two edges across its slide (``extra["slides_towards"]``) run in the
    frame's grooves, which the scan fuses to them: they become pieces of their own, listed in
    ``extra["in_track"]`` and left out of its sweep. ``pieces`` gains the cut pieces (in place)."""
    if box is None:
        return
    depth = int(np.argmax(np.abs(sash.outward)))
    lo, hi = box[0].copy(), box[1].copy()
    lo[depth], hi[depth] = -np.inf, np.inf
    sash.pieces, outside = split_part(sash, pieces, lo, hi)
    holders[0].pieces = [*holders[0].pieces, *outside]
    for holder in holders:
        ids, inside, new = split_under(pieces, holder.pieces, *box, 0.0, whole=True)
        pieces.extend(new)
        holder.pieces = [i for i, c in zip(ids, inside) if not c]
        sash.pieces = [*sash.pieces, *(i for i, c in zip(ids, inside) if c)]
    u, v = panel_frame(sash.outward)
    across = int(np.argmax(np.abs(v if sash.extra["slides_towards"][0] == "u" else u)))
    lo[across], hi[across] = lo[across] + track_depth, hi[across] - track_depth
    between, in_track = split_part(sash, pieces, lo, hi)
    sash.extra["in_track"] = [*sash.extra.get("in_track", []), *in_track]
    sash.pieces = [*between, *sash.extra["in_track"]]


def split_part(part, pieces: list, lo: np.ndarray, hi: np.ndarray) -> tuple[list[int], list[int]]:
    """``part``'s pieces cut where their faces' centres lie inside the box (``lo``, ``hi`` (3,),
    m; ``split_under``): the ids inside and those outside. Its panel becomes the panel piece's
    first part inside, when it has one. ``pieces`` gains the cut pieces (in place)."""
    inside_ids, outside_ids = [], []
    for i in part.pieces:
        ids, inside, new = split_under(pieces, [i], lo, hi, 0.0)
        pieces.extend(new)
        within = [j for j, c in zip(ids, inside) if c]
        inside_ids += within
        outside_ids += [j for j, c in zip(ids, inside) if not c]
        if i == part.panel and within:
            part.panel = within[0]
    return inside_ids, outside_ids


def split_under(pieces: list, ids: list[int], lo: np.ndarray, hi: np.ndarray,
                tolerance: float, whole: bool = False) -> tuple[list[int], np.ndarray, list]:
    """Pieces ``ids`` cut in two where their faces' centres (their three corners when
    ``whole``: a primitive's face may span far beyond the box) lie inside the box (``lo``,
    ``hi`` (3,), m, grown by ``tolerance``): the new ids (numbered from ``len(pieces)``), whether
    each lies inside, and the new pieces (not yet in ``pieces``)."""
    from rest2art.parts.pieces import Piece

    out_ids, inside, new = [], [], []
    for i in ids:
        piece = pieces[i]
        points = piece.mesh.triangles if whole else piece.mesh.triangles_center[:, None]
        under = np.all((points >= lo - tolerance) & (points <= hi + tolerance), axis=(1, 2))
        for keep, is_under in ((under, True), (~under, False)):
            if not keep.any():
                continue
            if keep.all():  # the whole piece on one side: kept as it is
                out_ids.append(i)
            else:  # piece.mesh lists its faces in the order of piece.faces
                mesh = piece.mesh.submesh([np.flatnonzero(keep)], append=True)
                new.append(Piece(len(pieces) + len(new), piece.faces[keep], mesh,
                                 mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)))
                out_ids.append(new[-1].index)
            inside.append(is_under)
    return out_ids, np.array(inside, bool), new


def stand_on_support(parts: list, pieces: list, joints: dict, category: str, config: Config) -> GateFinding | None:
    """Make the base the part the object stands on. When the only movable part is hinged and,
    with the base pieces under it (inside its box seen from above; on a part cut from one fused
    surface, the base's faces under it, when what is left rises ``support_rise_share`` of the
    object's height above it), holds ``support_share`` of the floor area, and what is left of
    the base is a panel of at least that share of its area, it and the base trade pieces; the
    joint turns the other way about the same hinge, moved onto the nearest edge of the part
    that now turns, and is swept again.
    ``parts`` and ``joints`` change in place (the new joint's evidence holds its confidence);
    returns the finding, or None."""
    if len(parts) != 2 or parts[1].parent is not None or parts[1].name not in joints \
            or joints[parts[1].name].type != "revolute":
        return None
    base, part = parts
    gate = config.gate
    lo, hi = trimesh.util.concatenate([pieces[i].mesh for i in part.pieces]).bounds
    part_top = float(hi[2])
    lo = np.array([lo[0], lo[1], -np.inf])  # what lies under it, down to the floor
    base_pieces = list(base.pieces)
    carried = inside_box(np.array([pieces[i].lo for i in base_pieces]), np.array([pieces[i].hi for i in base_pieces]),
                         lo, hi, gate.carried_tolerance)
    split = []
    if not carried.any() and cut_from_surface(part):
        # cut from one fused surface, the part has no pieces under it: the base's faces under
        # it (inside its box seen from above) are carried, face by face, when what is left
        # stands well above it (a screen over its keyboard, not a box under its lid)
        base_pieces, carried, split = split_under(pieces, base_pieces, lo, hi, gate.carried_tolerance)
    known = [*pieces, *split]
    mesh_of = lambda ids: trimesh.util.concatenate([known[i].mesh for i in ids])  # noqa: E731
    support = [*part.pieces, *(i for i, c in zip(base_pieces, carried) if c)]
    rest = [i for i, c in zip(base_pieces, carried) if not c]
    if not rest:
        return None
    meshes = {base.name: mesh_of(support), part.name: mesh_of(rest)}
    if meshes[part.name].area < gate.support_share * mesh_of(part.pieces).area:
        return None  # nothing left to turn but trim
    floor = min(float(m.bounds[0, 2]) for m in meshes.values())
    height = max(float(m.bounds[1, 2]) for m in meshes.values()) - floor
    if split and meshes[part.name].bounds[1, 2] - part_top < gate.support_rise_share * height:
        return None  # what is left does not stand above it (a lid on a box): it is no keyboard
    held, left = floor_area(meshes[base.name], floor, gate), floor_area(meshes[part.name], floor, gate)
    if held <= 0 or held < gate.support_share * (held + left):
        return None
    old = joints[part.name]
    pieces.extend(split)
    base.pieces, part.pieces = support, rest
    part.panel = max(rest, key=lambda i: known[i].mesh.area)
    axis = -np.asarray(old.axis, float)
    origin = nearest_box_edge(meshes[part.name].vertices, axis, np.asarray(old.origin, float))
    cap = opening_caps("door", category, 0.0, config.joints)["revolute"]
    free = free_range(meshes, part.name, "revolute", axis, origin, cap, config.joints)
    upper = float(max(free, np.radians(config.joints.hinge_min_range_deg)))
    evidence = {"rule": f"support: the {part.semantic} found held {held / (held + left):.0%} of the floor; "
                        "the rest turns about its hinge", "was": old.evidence, "free_deg": round(float(np.degrees(free)), 1)}
    evidence["confidence"] = round(joint_confidence(evidence, "revolute", upper, cap, gate), 3)
    joints[part.name] = JointEstimate("revolute", axis, origin, upper, evidence)
    return GateFinding("support", (part.name,),
                       f"{part.name}: held {held / (held + left):.0%} of the floor the object stands on: it is the base, "
                       "and the rest turns about the same hinge", "swapped")


def _video_joints(parts: list, pieces: list, canonical: np.ndarray, faces: np.ndarray, face_part: np.ndarray,
                  category: str, joints: dict, videos: list[np.ndarray], config: Config, debug: dict | None) -> None:
    """Replace the geometric joints of the parts the videos show moving (in place); ``face_part``
    (F,) indexes ``parts``."""
    from rest2art.joints.rules import JointEstimate, opening_caps
    from rest2art.joints.video.source import joints_from_videos, video_view

    names = [p.name for p in parts]
    movable = [p for p in parts if p.semantic != "base"]
    if not movable:
        return
    meshes = {part.name: trimesh.util.concatenate([pieces[i].mesh for i in part.pieces]) for part in parts}
    vv = video_view(canonical, faces, face_part, names, [p.name for p in movable], config)
    if debug is not None:
        debug["video_view"] = (vv, {p.name: p.semantic for p in movable})
    if not videos:
        from rest2art.joints.video.source import video_maker

        videos = video_maker(vv, {p.name: p.semantic for p in movable}, config, debug)
        if videos is None:
            return
    caps = {p.name: opening_caps(p.semantic, category, float(np.ptp(canonical @ np.abs(p.outward))), config.joints)
            for p in movable}
    found, report = joints_from_videos(vv, videos, {p.name: meshes[p.name] for p in movable}, meshes["base"],
                                       {p.name: p.outward for p in movable}, caps, config)
    for name, g in found.items():
        joints[name] = JointEstimate(g.type, g.axis, g.origin, g.upper,
                                     {"rule": "motion video, grounded by the mesh", **g.evidence,
                                      "geometric": joints[name].evidence if name in joints else None})
    for name, r in report.items():
        if name in joints:
            joints[name].evidence["video"] = {k: v for k, v in r.items() if k != "grounding"}


def complete_asset(asset: ArticulatedAsset, config: Config = Config(), progress: Progress = _quiet,
                   timer: StageTimer | None = None) -> ArticulatedAsset:
    """Closed solids, mass properties and collision pieces for every part (in place)."""
    timer = timer or StageTimer()
    completed: dict[str, list[trimesh.Trimesh]] = {}  # part -> its closed solids (for mass), tray included

    def complete() -> dict[str, list[trimesh.Trimesh]]:
        densities = config.completion.density
        solids, to_decompose, notes, trays = {}, {}, {}, {}
        up = asset.up
        root = next((p for p in asset.parts if p.parent is None), None)
        carcass = np.asarray(root.mesh.vertices) if root is not None else np.zeros((0, 3))
        for part in asset.parts:
            others = [p.mesh.vertices for p in asset.parts if p is not part]
            others = np.concatenate(others) if others else None
            solids[part.name], to_decompose[part.name], part_notes = part_solids(
                part.mesh, others, part.semantic, config.completion, config.collision.coacd_max_faces)
            joint = asset.joint_for(part.name)
            if part.semantic == "drawer" and joint is not None and joint.type == "prismatic" and len(carcass):
                tray = drawer_tray(part.mesh, joint.axis, up, float((carcass @ joint.axis).min()), config.completion)
                if tray is not None:
                    trays[part.name] = tray
                    solids[part.name].append(tray)
                    to_decompose[part.name].append(tray)
                    part_notes.append(f"tray {np.round(tray.extents, 3).tolist()} m added behind the front")
            density = densities.get(part.semantic, densities["base"])
            part.inertial = mass_properties(solids[part.name], density, config.completion)
            notes[part.name] = {"density": density, "mass": round(part.inertial.mass, 4),
                                "notes": part_notes + part.inertial.notes}
        for name, tray in trays.items():  # after the loop: trays must not thin the walls around them
            part = asset.part(name)
            part.mesh = trimesh.util.concatenate([part.mesh, tray])
        asset.metadata["completion"] = notes
        completed.update(solids)
        return to_decompose

    def collide(solids: dict[str, list[trimesh.Trimesh]]) -> None:
        from concurrent.futures import ThreadPoolExecutor

        rotation = object_axes(asset.metadata.get("frame"))
        budget = config.export.max_hulls_per_part
        jobs = [(name, solid) for name, pieces in solids.items() for solid in pieces]
        # each CoACD run is its own subprocess: threads are enough to use every core
        allow_coacd_runs()
        with ThreadPoolExecutor(max_workers=max(1, os.cpu_count() or 1)) as pool:
            try:
                results = list(pool.map(lambda job: decompose(job[1], config.collision, rotation, budget), jobs))
            except BaseException:  # interrupted: leaving waits for the threads, and they for CoACD
                pool.shutdown(wait=False, cancel_futures=True)
                stop_coacd_runs()
                raise
        report = {}
        for part in asset.parts:
            mine = [r for (name, _), r in zip(jobs, results) if name == part.name]
            part.collision, cut = clip_to_solids([h for r in mine for h in r.hulls], completed.get(part.name, []),
                                                 rotation, config.collision.solid_box_margin,
                                                 config.collision.min_hull_volume)
            report[part.name] = {"hulls": len(part.collision), "methods": sorted({r.method for r in mine}),
                                 "cut_to_solids": cut,
                                 "hollow": any(r.hollow for r in mine),
                                 "failures": sorted({r.failure for r in mine if r.failure}),
                                 "signature": hull_signature(part.collision)}
        asset.metadata["collision"] = report

    def clear() -> None:
        e = config.export
        hulls, notes = within_budget({p.name: p.collision for p in asset.parts}, e.max_hulls_per_part,
                                     e.max_hulls_per_asset, e.max_hull_vertices)
        for part in asset.parts:  # merged hulls bulge: clear after the budget is met
            part.collision = hulls[part.name]
            if part.name in notes:
                asset.metadata["collision"][part.name]["budget"] = notes[part.name]
        for name, log in clear_asset_hulls(asset, config.collision).items():
            asset.metadata["collision"][name]["clearance"] = log
            asset.metadata["collision"][name]["hulls"] = len(asset.part(name).collision)

    solids = timer.run("completion", progress, complete)
    timer.run("collision", progress, collide, solids)
    timer.run("clearance", progress, clear)
    return asset


def object_axes(frame: dict | None) -> np.ndarray:
    """(3, 3) rows: the object's side, front and up axes in the input frame, from the
    ``frame`` metadata (``up``, ``front``); the input axes when it is missing."""
    if not frame or "up" not in frame or "front" not in frame:
        return np.eye(3)
    up, front = np.asarray(frame["up"], float), np.asarray(frame["front"], float)
    front = front - (front @ up) * up
    side = np.cross(front, up)
    return np.stack([side / np.linalg.norm(side), front / np.linalg.norm(front), up / np.linalg.norm(up)])


def reconstruct_file(path: str | Path, config: Config = Config(), units: str | None = None,
                     up: str | None = None, front: str | None = None, progress: Progress = _quiet,
                     timer: StageTimer | None = None, debug: dict | None = None,
                     motion_videos: list[np.ndarray] | None = None) -> tuple[ArticulatedAsset, LoadedMesh]:
    """Load ``path`` and run every stage up to a complete asset (``debug``, ``motion_videos``:
    see reconstruct_mesh)."""
    timer = timer or StageTimer()
    mesh = timer.run("load", progress, load_mesh, path, config.load, units)
    asset = reconstruct_mesh(mesh, config, up, front, progress, timer, debug, motion_videos)
    complete_asset(asset, config, progress, timer)
    asset.metadata["timing_s"] = timer.times
    return asset, mesh
