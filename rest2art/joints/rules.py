"""Joints by rules, checked against the mesh (the offline geometric hypothesis source).

* drawer: prismatic along its outward normal; travel = depth of its body, at most
  ``drawer_max_depth_ratio`` of the object's depth;
* door: revolute about an edge of its panel. Candidates are the four edges of the hinge face;
  the preferred one is opposite the handle (a piece standing proud of the panel, faces
  standing proud of its face where the handle is fused with it, or a pocket in it; on a lid,
  also a grip reaching past its edge); without a handle, the edge nearest the carcass's outer
  side, and a lid's back edge. Each candidate is swept open and the first that opens far
  without driving the part into the rest of the object wins; its limit is the last
  collision-free sample. On a fused mesh the seams between parts are left out of the sweep
  (``seam_faces``). A door held in a track, or whose edge opposite the handle meets a closed
  front as wide as itself, slides in its plane instead; so do two doors meeting along an edge
  whose faces lie in two planes (bypass doors: each slides past the other);
* knob: revolute about its own outward axis (the normal of the surface it sits on); a lever
  standing on a drum that lies across its foot swings about the drum's axis instead;
* button: prismatic inward along that normal, by half of how far it stands proud; so is a knob
  the views found that stands out further than it is wide (a plunger).

Hinges follow real hardware: a door inside its opening (inset) pivots on the edge of its front
face, so its corners clear the carcass beside it. A door in front of the carcass (overlay) can
swing on either face's edge or anywhere between, and makers differ (a cabinet's hinge line on the
door's front face, a microwave's on its back, a room door's through its middle); with no knuckles
to show it, its side hinge is tried first halfway through its thickness, never more than half a
thickness from where the maker put it (a fridge door is 5 cm thick). All coordinates canonical
(+z up, -y front), metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import networkx as nx
import numpy as np
import trimesh

from rest2art.config import JointsConfig
from rest2art.geometry.basics import (densest_plane, first_hits, footprint_axes, joint_transform,
                                      opening_axis, outer_plane, panel_frame, perpendicular_basis, principal_axes,
                                      protrusion_size, ray_distances)
from rest2art.geometry.fcl import collides_with_scene, set_pose
from rest2art.joints.sweep import sweep_free_range, sweep_objects, sweep_steps
from rest2art.parts.pieces import (PartEstimate, Piece, contact_graph, cut_from_surface, grip_groups, leaf_piece,
                                   snap_axis)
from rest2art.tolerances import FACING_COS, TINY


def _section_in_plane(mesh: trimesh.Trimesh, outward: np.ndarray, level: float) -> np.ndarray | None:
    """(N, 2) points of the mesh's section at ``level`` (m) along ``outward`` (3,), in the
    plane's ``perpendicular_basis``; None where the plane misses it."""
    section = mesh.section(plane_origin=outward * level, plane_normal=outward)
    if section is None or len(section.vertices) < 2:
        return None
    return section.vertices @ perpendicular_basis(outward).T


def drum_foot(mesh: trimesh.Trimesh, outward: np.ndarray, config: JointsConfig) -> tuple[np.ndarray, np.ndarray] | None:
    """(axis (3,), pivot (3,)) of a lever that stands on a drum lying on its surface, or None.
    A control that meets its surface along a line turns about that line: its section just
    above its lowest point along ``outward`` (3,) is a line (``lever_foot_line``) already as
    long as it gets (``lever_foot_full``: a flat foot cut on a slant grows in both directions)
    and widens like a drum's (``lever_drum_growth``) on both sides of it
    (``lever_drum_centred``), and the control stands out
    ``lever_min_height`` times that line's length or more (a bar knob lies low). The axis runs
    along the line (snapped to a coordinate axis near it), the pivot at the drum's centre
    (radius from the chord at the second probe)."""
    along = mesh.vertices @ outward
    low_point = float(along.min())
    low = _section_in_plane(mesh, outward, low_point + config.lever_foot_probe)
    high = _section_in_plane(mesh, outward, low_point + config.lever_drum_probe)
    if low is None or high is None:
        return None
    centre = low.mean(axis=0)
    _, _, rows = np.linalg.svd(low - centre, full_matrices=False)
    line = rows[0]
    across = np.array([-line[1], line[0]])
    length, width = float(np.ptp(low @ line)), float(np.ptp(low @ across))
    chord = float(np.ptp(high @ across))
    height = float(np.ptp(along))
    line_foot = length > 0 and width <= config.lever_foot_line * length
    full_length = length >= config.lever_foot_full * float(np.ptp(high @ line))
    middle = lambda points: float(points.min() + points.max()) / 2  # noqa: E731
    centred = abs(middle(low @ across) - middle(high @ across)) <= config.lever_drum_centred * chord
    if not (line_foot and full_length and centred and chord >= config.lever_drum_growth * width
            and height >= config.lever_min_height * length):
        return None
    basis = perpendicular_basis(outward)
    probe = config.lever_drum_probe
    radius = min((chord ** 2 / 4 + probe ** 2) / (2 * probe), height / 2)
    axis = line @ basis
    pivot = centre @ basis + (low_point + radius) * outward
    return snap_axis(axis / np.linalg.norm(axis)), pivot


def along_an_axis(direction: np.ndarray) -> bool:
    """Whether the unit ``direction`` (3,) is a signed coordinate axis (as ``snap_axis`` leaves
    one near it)."""
    return int(np.count_nonzero(np.abs(direction) > TINY)) == 1


def stick_lever(mesh: trimesh.Trimesh, outward: np.ndarray, config: JointsConfig) -> tuple[np.ndarray, np.ndarray] | None:
    """(axis (3,), pivot (3,)) of a stick standing out of its surface along ``outward`` (3,)
    that swings as a lever, or None for a plunger: one whose widest section near its tip
    (``stick_tip_levels``) is ``plunger_head_growth`` times its narrowest along its shank
    (``stick_shank_levels``) or more has a head to push or pull (a nail, a pull knob). The
    lever turns about the wider side of its shank's sections (``footprint_axes``: it swings
    along its thin side; ``axis_on_panel``), through the middle of its foot, half the foot's
    depth along the swing above its lowest point (a drum's centre)."""
    along = mesh.vertices @ outward
    low, out = float(along.min()), float(np.ptp(along))

    def sections(levels):
        cuts = [_section_in_plane(mesh, outward, low + level * out) for level in levels]
        return [c for c in cuts if c is not None and len(c) >= 3]

    shank, tip = sections(config.stick_shank_levels), sections(config.stick_tip_levels)
    if not shank:
        return None
    width = lambda points: float(np.ptp(points, axis=0).max())  # noqa: E731
    if tip and max(map(width, tip)) >= config.plunger_head_growth * min(map(width, shank)):
        return None
    _, across = footprint_axes(np.concatenate(shank) @ perpendicular_basis(outward), outward)
    axis = axis_on_panel(across[0], outward)
    swing = np.cross(outward, axis)
    foot = mesh.vertices[along <= low + min(config.stick_shank_levels) * out]
    middle = (foot.min(axis=0) + foot.max(axis=0)) / 2
    middle = middle - (middle @ outward) * outward
    return axis, middle + (low + float(np.ptp(foot @ swing)) / 2) * outward


def axis_on_panel(direction: np.ndarray, outward: np.ndarray) -> np.ndarray:
    """A control's turning axis near ``direction`` (3,) on a surface facing ``outward`` (3,):
    snapped to a coordinate axis near it, and on a panel facing an axis, along the nearer of
    the panel's edges."""
    if not along_an_axis(outward):
        return snap_axis(direction)
    nearest = int(np.argmax(np.abs(direction) * (outward == 0)))
    return np.eye(3)[nearest] * np.sign(direction[nearest])


def toggle_throw(mesh: trimesh.Trimesh, outward: np.ndarray,
                 config: JointsConfig) -> tuple[np.ndarray, np.ndarray, float] | None:
    """(axis (3,), pivot (3,), range rad) of a headless stick (``mesh``, ``stick_lever``) thrown
    to one side of its surface's normal ``outward`` (3,), or None when its long axis leans less
    than ``stick_lean_deg``. A toggle rests thrown one way and flips over to the mirror side: it
    swings in the plane it leans in, about the line across its lean (``axis_on_panel``), signed
    so that the stick first rises towards the normal, by twice its lean, about where its long
    axis meets the surface (the plane through its lowest point along ``outward``)."""
    centre = mesh.vertices.mean(axis=0)
    long = principal_axes(mesh.vertices)[2]
    long = long if long @ outward > 0 else -long
    lean = float(np.arccos(np.clip(long @ outward, -1.0, 1.0)))
    if lean < np.radians(config.stick_lean_deg):
        return None
    low = float((mesh.vertices @ outward).min())
    pivot = centre + long * (low - centre @ outward) / float(long @ outward)
    sideways = long - (long @ outward) * outward
    axis = axis_on_panel(np.cross(outward, sideways / np.linalg.norm(sideways)), outward)
    signed = -axis if float(np.cross(axis, long) @ sideways) > 0 else axis
    return signed.astype(float), pivot, 2.0 * lean


@dataclass
class JointEstimate:
    """A joint in the canonical frame."""

    type: str
    axis: np.ndarray
    origin: np.ndarray
    upper: float
    evidence: dict


@dataclass
class HingeCandidate:
    name: str
    axis: np.ndarray
    point: np.ndarray


def hinge_candidates(lo: np.ndarray, hi: np.ndarray, outward: np.ndarray, planes: dict[str, float]) -> dict[tuple[str, str], HingeCandidate]:
    """Hinge lines on the four edges (u-/u+/v-/v+) of each panel face in ``planes``
    (face name -> position in m along ``outward``), keyed by (edge, face)."""
    u, v = panel_frame(outward)
    corners = np.array([lo, hi])
    pu, pv = corners @ u, corners @ v
    u_lo, u_hi, v_lo, v_hi = pu.min(), pu.max(), pv.min(), pv.max()
    centre_u, centre_v = (u_lo + u_hi) / 2, (v_lo + v_hi) / 2
    out = {}
    for face, position in planes.items():
        on_face = position * outward
        out[("u-", face)] = HingeCandidate(f"u-/{face}", v, on_face + u_lo * u + centre_v * v)
        out[("u+", face)] = HingeCandidate(f"u+/{face}", v, on_face + u_hi * u + centre_v * v)
        out[("v-", face)] = HingeCandidate(f"v-/{face}", u, on_face + centre_u * u + v_lo * v)
        out[("v+", face)] = HingeCandidate(f"v+/{face}", u, on_face + centre_u * u + v_hi * v)
    return out


def hinge_knuckles(panel: Piece, outward: np.ndarray, others: dict[int, Piece],
                   config: JointsConfig) -> dict[str, tuple[HingeCandidate, list[int]]]:
    """The hinge lines a door's knuckles or pins show: rods among ``others`` (piece index ->
    piece, pieces not of the door) as round across as ``knuckle_roundness``, at least
    ``knuckle_min_aspect`` times longer than wide and at most ``knuckle_max_share`` of the
    panel's width across that edge, lying along an edge of the ``panel`` (facing
    ``outward``) with their axis within their radius (plus ``knuckle_tolerance``) of that edge's
    line, within its span (a frame post may pass each end by its own width); one short rod alone
    (under ``knuckle_single_share`` of the edge) more than ``knuckle_single_offset`` of the edge
    off its middle is a bar handle by the edge, not a knuckle (hinges come in pairs, or one runs
    the edge or sits in its middle: a laptop's barrel). Returns, per edge
    (u-, u+, v-, v+) with rods, the line through them (named ``edge/knuckles``) and their
    indices: one edge is the hinge; rods on two (posts on both sides of a door between them)
    only say where either hinge would turn."""
    u, v = panel_frame(outward)
    corners = np.array([panel.lo, panel.hi])
    pu, pv, pd = np.sort(corners @ u), np.sort(corners @ v), np.sort(corners @ outward)
    found: dict[str, list[int]] = {}
    for index, piece in others.items():
        for edge_axis, across, name_lo, name_hi, edge_lo, edge_hi, span in (
                (v, u, "u-", "u+", pu[0], pu[1], pv), (u, v, "v-", "v+", pv[0], pv[1], pu)):
            box = np.array([piece.lo, piece.hi])
            length = float(np.ptp(box @ edge_axis))
            widths = np.ptp(box @ across), np.ptp(box @ outward)
            if min(widths) <= 0 or min(widths) < config.knuckle_roundness * max(widths) \
                    or length < config.knuckle_min_aspect * max(widths) \
                    or max(widths) > config.knuckle_max_share * (edge_hi - edge_lo):
                continue
            radius = max(widths) / 2 + config.knuckle_tolerance
            centre_across, centre_depth = float(np.mean(box @ across)), float(np.mean(box @ outward))
            along = np.sort(box @ edge_axis)
            overhang = max(widths) + config.knuckle_tolerance
            if not (pd[0] - radius <= centre_depth <= pd[1] + radius) \
                    or along[0] < span[0] - overhang or along[1] > span[1] + overhang:
                continue
            for name, line in ((name_lo, edge_lo), (name_hi, edge_hi)):
                if abs(centre_across - line) <= radius:
                    found.setdefault(name, []).append(index)
    edge_length = {"u": float(pv[1] - pv[0]), "v": float(pu[1] - pu[0])}
    along_edge = {"u": v, "v": u}
    edge_middle = {"u": float(pv.mean()), "v": float(pu.mean())}
    for edge, ids in list(found.items()):
        rod = np.array([others[ids[0]].lo, others[ids[0]].hi]) @ along_edge[edge[0]]
        short = float(np.ptp(rod)) < config.knuckle_single_share * edge_length[edge[0]]
        off_centre = abs(float(rod.mean()) - edge_middle[edge[0]]) > config.knuckle_single_offset * edge_length[edge[0]]
        if len(ids) == 1 and short and off_centre:
            del found[edge]  # one short rod off the edge's middle: a bar handle by the edge, no knuckle
    return {edge: (HingeCandidate(f"{edge}/knuckles", v if edge.startswith("u") else u,
                                  np.mean([others[i].centre for i in ids], axis=0)), ids)
            for edge, ids in found.items()}


def pane_behind(front_lo: np.ndarray, front_hi: np.ndarray, outward: np.ndarray, back_lo: np.ndarray,
                back_hi: np.ndarray, config: JointsConfig) -> str | None:
    """The edge (u-, u+, v-, v+) of a pane (box ``front_lo``, ``front_hi`` (3,), m) facing
    ``outward`` across which a second pane (box ``back_lo``, ``back_hi``) lies in a plane just
    behind it, meeting it along that edge: the two sashes of a sliding window, the front one
    sliding over the other. None when they are not such a pair."""
    corners_f, corners_b = np.array([front_lo, front_hi]), np.array([back_lo, back_hi])
    along_f, along_b = np.sort(corners_f @ outward), np.sort(corners_b @ outward)
    gap = along_f[0] - along_b[1]  # from the back pane's front to the front pane's back
    if not -config.pane_touch <= gap <= config.pane_gap:
        return None
    return meeting_edge(corners_f, corners_b, outward, config.pane_touch, config)


def scanned_pane_behind(front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray,
                        config: JointsConfig, rails: float = 0.0, frame: trimesh.Trimesh | None = None) -> str | None:
    """``pane_behind`` for two panes cut from one fused surface, which shows their fronts only:
    the front plane (``outer_plane``) of ``back`` lies ``pane_touch`` to ``pane_max_stagger``
    (m) behind that of ``front``, and seen along ``outward`` (3,) the two meet along an edge
    (``meeting_edge``) with a gap across it of at most that stagger (the top of the front
    sash's meeting rail, as deep as the stagger, may have gone to neither) plus ``rails`` (m:
    the two sashes' meeting rails, where their glazing bars say how wide a sash's bars are; with
    no bars and the ``frame`` given, twice the bars around the panes, ``sash_stiles``: each sash
    meets the other with a stile as wide as its others), the two about as wide across it as two
    doors sliding past each other are
    (``bypass_min_width_share``; a microwave's door and its control strip a step behind it are
    no pair)."""
    stagger = outer_plane(front, outward, config.carcass_band) - outer_plane(back, outward, config.carcass_band)
    if not config.pane_touch <= stagger <= config.pane_max_stagger:
        return None
    if not rails and frame is not None:
        rails = 2 * sash_stiles(frame, front, back, outward, config)
    edge = meeting_edge(front.bounds, back.bounds, outward, stagger + config.pane_touch + rails, config)
    if edge is None:
        return None
    across = panel_frame(outward)[0 if edge[0] == "u" else 1]
    narrow, wide = sorted(float(np.ptp(mesh.vertices @ across)) for mesh in (front, back))
    return edge if narrow >= config.bypass_min_width_share * wide else None


def pane_planes(front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray, carcass: trimesh.Trimesh,
                config: JointsConfig) -> tuple[float, float, float]:
    """(front pane's plane, back pane's plane, how far the front pane lies sunk behind its bars),
    m along ``outward`` (3,), of two scanned sashes' panes ``front`` and ``back``: a pane's plane
    holds most of its area facing out (its glass); its bars are its own where the views gave it
    them, else measured around it on the ``carcass`` (``sash_recess``)."""
    front_plane, back_plane = (densest_plane(m, m.face_normals @ outward > FACING_COS, outward) for m in (front, back))
    most = front_plane - back_plane - config.pane_touch
    own = outer_plane(front, outward, config.carcass_band) - front_plane
    recess = own if own >= config.pane_touch else sash_recess(carcass, front.bounds, outward, front_plane, most, config)
    return front_plane, back_plane, recess


def sash_stiles(carcass: trimesh.Trimesh, front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray,
                config: JointsConfig) -> float:
    """Width (m) of the bars around two scanned panes (``front``, ``back`` facing the coordinate
    axis ``outward``; the views leave a sash's stiles and rails with the frame): the median gap,
    over the four sides, from the two panes' outline to the frame's opening (``sash_opening``,
    in front of the front pane's bars, ``pane_planes``). Each sash has a stile along the edge
    where the two meet, as wide as its others; 0 when no jamb stands around them."""
    if not along_an_axis(outward):
        return 0.0
    front_plane, _, recess = pane_planes(front, back, outward, carcass, config)
    lo, hi = sash_opening(carcass, front, back, outward, front_plane + recess + config.sash_jamb_margin, config)
    depth = int(np.argmax(np.abs(outward)))
    panes_lo = np.minimum(front.bounds[0], back.bounds[0])
    panes_hi = np.maximum(front.bounds[1], back.bounds[1])
    gaps = np.delete(np.r_[panes_lo - lo, hi - panes_hi], [depth, depth + 3])
    return float(np.median(np.clip(gaps, 0.0, None)))


def front_sash_box(front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray, edge: str,
                   carcass: trimesh.Trimesh, config: JointsConfig) -> tuple[np.ndarray, np.ndarray] | None:
    """Box (lo, hi (3,), m) of the front one of two scanned sashes whose panes (``front``,
    ``back``) meet across ``edge`` (``scanned_pane_behind``), the views having seen the front
    sash's glass and little of its bars: seen along ``outward`` (3,, a coordinate axis; else
    None), the frame's opening (``sash_opening``: a sash in a track spans it across its slide)
    but towards the back pane only as far as the front sash reaches over it (``meeting_reach``);
    in depth, from ``pane_touch`` in front of the back sash's bars to the front of the object
    (the front sash's handle). The panes' planes and how far the front one's bars stand in front
    of it: ``pane_planes`` (one profile makes both sashes)."""
    if not along_an_axis(outward):
        return None
    depth = int(np.argmax(np.abs(outward)))
    front_plane, back_plane, recess = pane_planes(front, back, outward, carcass, config)
    lo, hi = sash_opening(carcass, front, back, outward, front_plane + recess + config.sash_jamb_margin, config)
    near = back_plane + recess + config.pane_touch
    u, v = panel_frame(outward)
    towards = (u if edge[0] == "u" else v) * (1.0 if edge[1] == "+" else -1.0)  # from the front pane to the back
    k = int(np.argmax(np.abs(towards)))
    surface = trimesh.util.concatenate([carcass, front, back])
    reach = meeting_reach(surface, front, back, outward, towards, near, config)
    if towards[k] > 0:
        hi[k] = reach
    else:
        lo[k] = reach
    far = float(np.max(surface.vertices @ outward))
    lo[depth], hi[depth] = np.sort(np.array([near, far]) * outward[depth])
    return lo, hi


def meeting_reach(surface: trimesh.Trimesh, front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray,
                  towards: np.ndarray, near: float, config: JointsConfig) -> float:
    """How far (m, along the coordinate axis of ``towards`` (3,), from the front pane to the
    back one) a scanned front sash reaches over the gap between its pane ``front`` and the
    pane ``back`` behind it, both facing ``outward``: rays along -``outward`` onto the whole
    ``surface``, every ``sash_probe_step`` (m) from the front pane's far side of that gap to
    the back pane's far edge, in ``sash_opening_rays`` rows across the panes, meet the front
    sash (and its meeting rail) in front of ``near`` (m along ``outward``: the back sash's
    bars) and the back sash behind it; the sash ends where most rows first meet the back after
    meeting the sash."""
    k = int(np.argmax(np.abs(towards)))
    sign = float(np.sign(towards[k]))
    depth = int(np.argmax(np.abs(outward)))
    across = 3 - k - depth
    start = front.bounds[1, k] if sign > 0 else front.bounds[0, k]
    stop = back.bounds[1, k] if sign > 0 else back.bounds[0, k]
    steps = np.arange(0.0, abs(stop - start), config.sash_probe_step)
    lo_j = max(front.bounds[0, across], back.bounds[0, across])
    hi_j = min(front.bounds[1, across], back.bounds[1, across])
    rows = lo_j + np.linspace(0.25, 0.75, config.sash_opening_rays) * (hi_j - lo_j)
    origins = np.zeros((len(steps) * len(rows), 3))
    origins[:, k] = np.repeat(start + sign * steps, len(rows))
    origins[:, across] = np.tile(rows, len(steps))
    origins[:, depth] = (float(np.max(surface.vertices @ outward)) + config.pane_touch) * outward[depth]
    hit = float(origins[0] @ outward) - ray_distances(surface, origins, -outward)
    behind = (hit < near).reshape(len(steps), len(rows)).mean(axis=1) > 0.5
    if behind.all():
        return float(start)
    after = behind & (np.arange(len(steps)) > int(np.argmin(behind)))  # a ray along the glass's edge slips past it
    return float(start + sign * steps[int(np.argmax(after)) if after.any() else len(steps) - 1])


def sash_opening(carcass: trimesh.Trimesh, front: trimesh.Trimesh, back: trimesh.Trimesh, outward: np.ndarray,
                 plane: float, config: JointsConfig) -> tuple[np.ndarray, np.ndarray]:
    """Box (lo, hi (3,), m) of a window frame's opening around two scanned panes ``front`` and
    ``back`` facing ``outward`` (a coordinate axis), seen along it: rays in the ``plane`` (m
    along ``outward``, in front of the front sash) from a grid of ``sash_opening_rays`` points
    over the front pane, along each of the four in-plane axes, meet the frame's jambs on the
    ``carcass``; each side is the median of the hits (a handle in a few rays' way is left out),
    less ``sash_jamb_margin`` (the jambs' own faces stay with the frame). A side no ray meets
    (no jamb stands in front of the sash) is the panes' outline."""
    depth = int(np.argmax(np.abs(outward)))
    lo = np.minimum(front.bounds[0], back.bounds[0])
    hi = np.maximum(front.bounds[1], back.bounds[1])
    lateral = [a for a in range(3) if a != depth]
    grid = np.linspace(0.25, 0.75, config.sash_opening_rays)
    a, b = lateral
    fa = front.bounds[0, a] + grid * np.ptp(front.bounds[:, a])
    fb = front.bounds[0, b] + grid * np.ptp(front.bounds[:, b])
    origins = np.zeros((len(fa) * len(fb), 3))
    origins[:, a], origins[:, b] = np.repeat(fa, len(fb)), np.tile(fb, len(fa))
    origins[:, depth] = plane * outward[depth]
    for axis in lateral:
        for sign in (-1.0, 1.0):
            direction = np.zeros(3)
            direction[axis] = sign
            side = float(np.median(origins[:, axis] + sign * ray_distances(carcass, origins, direction)))
            if not np.isfinite(side):  # most rays meet nothing: no jamb stands in front of the sash there
                continue
            if sign > 0:
                hi[axis] = side - config.sash_jamb_margin
            else:
                lo[axis] = side + config.sash_jamb_margin
    return lo, hi


def sash_recess(carcass: trimesh.Trimesh, pane_bounds: np.ndarray, outward: np.ndarray, pane_plane: float,
                most: float, config: JointsConfig) -> float:
    """How far (m) a scanned pane (box ``pane_bounds`` (2, 3), front plane ``pane_plane`` along
    the coordinate axis ``outward``) lies sunk behind the bars around it (a sash's stiles and
    rails, which the views leave with the frame): the plane holding the most ``carcass`` area
    facing ``outward`` within ``sash_bar_ring`` (m) outside the pane's outline, ``pane_touch`` to
    ``most`` (m) in front of the pane. 0 for a pane with no such bars (a flush-faced panel)."""
    centres = carcass.triangles_center
    along = centres @ outward - pane_plane
    depth = int(np.argmax(np.abs(outward)))
    lateral = [axis for axis in range(3) if axis != depth]
    near = np.all([(centres[:, a] >= pane_bounds[0, a] - config.sash_bar_ring)
                   & (centres[:, a] <= pane_bounds[1, a] + config.sash_bar_ring) for a in lateral], axis=0)
    inside = np.all([(centres[:, a] > pane_bounds[0, a]) & (centres[:, a] < pane_bounds[1, a]) for a in lateral], axis=0)
    bars = near & ~inside & (carcass.face_normals @ outward > FACING_COS) & \
        (along >= config.pane_touch) & (along <= most)
    return densest_plane(carcass, bars, outward) - pane_plane if bars.any() else 0.0


def meeting_edge(corners_f: np.ndarray, corners_b: np.ndarray, outward: np.ndarray, touch: float,
                 config: JointsConfig) -> str | None:
    """The edge (u-, u+, v-, v+) of a front pane (box corners ``corners_f`` (2, 3), m) facing
    ``outward`` across which, seen along it, a back pane (``corners_b``) meets it: a gap of at
    most ``touch`` (m) or an overlap of at most ``pane_meeting_overlap`` of the front pane
    across that edge, and ``pane_edge_share`` of the longer pane's length shared along it."""
    u, v = panel_frame(outward)
    spans = {name: (np.sort(corners_f @ axis), np.sort(corners_b @ axis)) for name, axis in (("u", u), ("v", v))}
    overlap = {name: min(f[1], b[1]) - max(f[0], b[0]) for name, (f, b) in spans.items()}
    for across, along in (("u", "v"), ("v", "u")):
        f, b = spans[across]
        fa, ba = spans[along]
        if not -touch <= overlap[across] <= config.pane_meeting_overlap * (f[1] - f[0]):
            continue
        if overlap[along] < config.pane_edge_share * max(fa[1] - fa[0], ba[1] - ba[0]):
            continue
        return across + ("+" if b.mean() > f.mean() else "-")
    return None


def panel_faces(panel: Piece, outward: np.ndarray, carcass_front: float, tolerance: float) -> tuple[dict[str, float], bool]:
    """Positions of the panel's front and back faces along ``outward`` and whether it is an
    overlay panel (entirely in front of the carcass front, less ``tolerance`` m) rather than
    inset in its opening. The front is the plane holding most of the panel's area that faces
    out: on a panel fused with its handle (a scan) its face, not the front of the handle, which
    may stand out further than a handle modelled apart ever does (a lock's lever)."""
    along = panel.mesh.vertices @ outward
    front, back = outer_plane(panel.mesh, outward, float(np.ptp(along))), float(along.min())
    return {"front": front, "back": back}, back >= carcass_front - tolerance


def edge_strip(points: np.ndarray, panel_vertices: np.ndarray, outward: np.ndarray, share: float, band: float) -> bool:
    """Whether ``points`` (N, 3) form a strip along an edge of a panel, its (M, 3)
    ``panel_vertices``: reaching across ``share`` or more of its extent along one in-plane axis
    (``panel_frame`` of ``outward``) and lying within ``band`` (m) of one of its edges across it."""
    u, v = panel_frame(outward)
    for along, across in ((u, v), (v, u)):
        if np.ptp(points @ along) < share * np.ptp(panel_vertices @ along):
            continue
        x, edges = points @ across, panel_vertices @ across
        if x.max() <= edges.min() + band or x.min() >= edges.max() - band:
            return True
    return False


def find_handle(part: PartEstimate, pieces: list[Piece], outward: np.ndarray,
                config: JointsConfig = JointsConfig()) -> np.ndarray | None:
    """(3,) handle position: pieces standing proud of the panel; else, on a panel fused with
    its handle (a scan), the faces standing proud of the plane holding most of its front area
    (a patch of ``handle_min_area`` or more reaching ``handle_min_height`` out), unless they
    are a strip along one of its edges (``handle_max_span``, ``handle_edge_band``: the rim of
    the neighbour below, cut with it); else a pocket in the panel, ``pocket_min_width`` wide
    or more across (a ledge a few millimetres high along a rail is no grip)."""
    panel = pieces[part.panel].mesh
    front = float((panel.vertices @ outward).max())
    proud = [pieces[i] for i in [*part.pieces, *part.extra.get("fittings", [])]
             if i != part.panel and (pieces[i].mesh.vertices @ outward).max() > front + config.handle_min_proud]
    if proud:
        return grip_centre(proud, pieces[part.panel], outward, config)
    along = panel.triangles_center @ outward
    face_plane = outer_plane(panel, outward, config.handle_max_proud)
    fused = along > face_plane + config.handle_min_proud
    if config.handle_min_area <= panel.area_faces[fused].sum() <= config.handle_max_share * panel.area \
            and along.max() >= face_plane + config.handle_min_height \
            and not edge_strip(panel.triangles_center[fused], panel.vertices, outward, config.handle_max_span,
                               config.handle_edge_band):
        w = panel.area_faces[fused]
        return (panel.triangles_center[fused] * w[:, None]).sum(axis=0) / w.sum()
    facing = panel.face_normals @ outward > FACING_COS
    # sunk below the face's plane, not below its highest vertex: a scan's face is not flat
    shallow, deep = config.pocket_depth
    pocket = facing & (along < face_plane - shallow) & (along > face_plane - deep)
    w = panel.area_faces[pocket]
    if w.sum() >= config.pocket_min_area and min(patch_extents(panel.vertices[panel.faces[pocket]], outward)) \
            >= config.pocket_min_width:
        return (panel.triangles_center[pocket] * w[:, None]).sum(axis=0) / w.sum()
    return None


def patch_extents(triangles: np.ndarray, outward: np.ndarray) -> tuple[float, float]:
    """Extents (m) of ``triangles`` (N, 3, 3) along the two in-plane axes of a panel facing
    ``outward`` (``panel_frame``)."""
    points = triangles.reshape(-1, 3)
    return tuple(float(np.ptp(points @ axis)) for axis in panel_frame(outward))


def grip_centre(fittings: list[Piece], panel: Piece, outward: np.ndarray, config: JointsConfig) -> np.ndarray:
    """(3,) where a hand grips a ``panel`` facing ``outward`` (3,) among the ``fittings``
    standing proud of it: fittings within ``fitting_contact`` (m) of each other are one (a bar
    and its posts); the grip is the one :func:`grip_groups` picks, or the point between a
    mirrored pair."""
    groups = [[fittings[i] for i in c] for c in nx.connected_components(contact_graph(fittings, config.fitting_contact))]
    centres = np.array([np.concatenate([f.mesh.vertices for f in g]).mean(axis=0) for g in groups])
    return centres[grip_groups(centres, panel, outward, config.handle_offset_min)].mean(axis=0)


def edge_grip(part: PartEstimate, pieces: list[Piece], outward: np.ndarray,
              config: JointsConfig = JointsConfig()) -> np.ndarray | None:
    """(3,) centre of what a part's other pieces reach past its panel's outline (by more than
    ``handle_min_proud``) across ``outward``: a grip on a lid's front edge, level with it; None
    when nothing does."""
    others = [pieces[i].mesh.vertices for i in [*part.pieces, *part.extra.get("fittings", [])] if i != part.panel]
    if not others:
        return None
    points = np.concatenate(others)
    panel = pieces[part.panel].mesh.vertices
    past = np.zeros(len(points), bool)
    for axis in panel_frame(outward):
        along, span = points @ axis, panel @ axis
        past |= (along < span.min() - config.handle_min_proud) | (along > span.max() + config.handle_min_proud)
    return points[past].mean(axis=0) if past.any() else None


def side_gaps(panel: Piece, outward: np.ndarray, obj_lo: np.ndarray, obj_hi: np.ndarray) -> tuple[float, float]:
    """How far (m) a panel facing ``outward`` stops short of the object's box (``obj_lo``,
    ``obj_hi`` (3,)) at its ``u-`` and its ``u+`` edge (``panel_frame``'s u)."""
    u, _ = panel_frame(outward)
    lo, hi = sorted((float(obj_lo @ u), float(obj_hi @ u)))
    pu = sorted((float(panel.lo @ u), float(panel.hi @ u)))
    return pu[0] - lo, hi - pu[1]


def outline_edges(panel: Piece, outward: np.ndarray, obj_lo: np.ndarray, obj_hi: np.ndarray,
                  tolerance: float) -> tuple[str, ...]:
    """The side edges (``u-``, ``u+``) of a panel facing ``outward`` that lie within
    ``tolerance`` (m) of the object's box: nothing beside them (``side_gaps``)."""
    gaps = side_gaps(panel, outward, obj_lo, obj_hi)
    return tuple(name for name, gap in zip(("u-", "u+"), gaps) if gap <= tolerance)


def order_hinges(part: PartEstimate, pieces: list[Piece], candidates: dict, overlay: bool,
                 obj_lo: np.ndarray, obj_hi: np.ndarray, config: JointsConfig,
                 outline: tuple[str, ...] = (), middle: bool = False,
                 foot: str | None = None, leaf: Piece | None = None,
                 front_shown: bool = True) -> tuple[list[HingeCandidate], str]:
    """Candidates from most to least plausible, and the rule that ordered the edges.

    Edges: the edge opposite the handle (for a lid, also a grip reaching past its edge,
    ``edge_grip``); else a lid's back edge, or a side edge where its back edge is its short one
    (``lid_long_edge_share``; a square lid's back edge, a guess, when not ``front_shown``: no
    side of the object showed any relief, so its back is the file's alone); else the ``foot`` a
    panel standing free stands on (``foot_edge``: an open laptop's screen on its base; that edge
    alone is tried); else the
    vertical edge at the carcass's outer side.
    Faces, per edge: the one whose swing keeps the corners clear (a side hinge of an overlay
    panel or a lid on its inner face, a side hinge of an inset panel and a bottom hinge on the
    outer face; a side hinge on an ``outline`` edge of a door cut out of a fused surface, whose
    thickness the surface does not show, on its inner face too: no carcass beside it to clear);
    the other face follows as a fallback for the sweep. With ``middle`` (an overlay door, or a
    door cut out of a fused surface: which face its hinge is on the mesh does not show), a side
    hinge is tried first halfway through the door's thickness (the ``middle`` plane of
    ``candidates``), never more than half a thickness from either face. Edges are the leaf's (``leaf_piece``; ``leaf``:
    the caller's, when it has it).
    """
    outward = part.outward
    u, v = panel_frame(outward)
    panel = leaf if leaf is not None else leaf_piece(part, pieces, config.leaf_depth_tolerance, config.leaf_frame_share)
    pu = np.array([panel.lo @ u, panel.hi @ u])
    pv = np.array([panel.lo @ v, panel.hi @ v])
    edges, rule = None, ""
    handle = find_handle(part, pieces, outward, config)
    if part.semantic == "lid" and handle is None:
        handle = edge_grip(part, pieces, outward, config)
    if handle is not None:
        du = (handle @ u - pu.mean()) / max(np.ptp(pu), 1e-9)
        dv = (handle @ v - pv.mean()) / max(np.ptp(pv), 1e-9)
        if max(abs(du), abs(dv)) >= config.handle_offset_min:
            if abs(du) >= abs(dv):
                first = "u-" if du > 0 else "u+"
            else:
                first = "v-" if dv > 0 else "v+"
            edges, rule = [first, *[n for n in ("u-", "u+", "v-", "v+") if n != first]], "opposite the handle"
    if edges is None and part.semantic == "lid":
        if np.ptp(pu) < config.lid_long_edge_share * np.ptp(pv):
            # a lid hinges on a long edge; its back edge is a short one, so nothing showed the
            # front, and which long edge it is, nothing shows either
            edges, rule = ["u-", "u+", "v+", "v-"], "lid on a long edge, which one a guess"
        elif not front_shown and np.ptp(pv) >= config.lid_long_edge_share * np.ptp(pu):
            # a square lid on an object that showed no front: its back is the file's alone
            edges, rule = ["v+", "u-", "u+", "v-"], "no front shown, lid: back edge"
        else:
            edges, rule = ["v+", "u-", "u+", "v-"], "lid: back edge"
    if edges is None and foot is not None:  # only there: a screen turned on another edge would leave its base
        edges, rule = [foot], "its foot: the one edge it stands on"
    if edges is None:
        gap_lo, gap_hi = side_gaps(panel, outward, obj_lo, obj_hi)
        first = "u-" if gap_lo <= gap_hi else "u+"
        edges = [first, "u+" if first == "u-" else "u-", "v-", "v+"]
        # on an object that showed no front, nothing says this face holds a door either
        rule = "outer side (no handle)" if front_shown else "no front shown, outer side (no handle)"
    ordered = []
    for edge in edges:
        side_hinge = edge.startswith("u") or part.semantic == "lid"
        inner_first = side_hinge and (overlay or part.semantic == "lid" or edge in outline)
        faces = ("back", "front") if inner_first else ("front", "back")
        if middle and edge.startswith("u") and part.semantic != "lid":
            faces = ("middle", *faces)
        ordered.extend(candidates[(edge, face)] for face in faces)
    return ordered, rule


def opening_caps(semantic: str, category: str, extent: float, config: JointsConfig = JointsConfig()) -> dict[str, float]:
    """Largest opening allowed before any collision, per joint type: revolute (rad) by part
    semantic and object category, prismatic (m) as a share of the object's ``extent`` (m)
    along the slide."""
    degrees = (config.knob_limit_deg if semantic == "knob"
               else config.appliance_door_limit_deg if category in ("fridge", "microwave") else config.door_limit_deg)
    return {"revolute": float(np.radians(degrees)), "prismatic": config.drawer_max_depth_ratio * extent}


def estimate_joints(parts: list[PartEstimate], pieces: list[Piece], category: str,
                    config: JointsConfig = JointsConfig(), front_shown: bool = True) -> dict[str, JointEstimate]:
    """One joint per movable part (keyed by part name), in the canonical frame. A part mounted
    on another (``parent``) sweeps with it: its pieces join its parent's for the parent's sweep.
    ``front_shown``: whether the object showed which side is its front (``order_hinges``)."""
    carried = {p.name: [*p.pieces, *(i for c in parts if c.parent is p for i in c.pieces)] for p in parts}
    meshes = {p.name: trimesh.util.concatenate([pieces[i].mesh for i in carried[p.name]])
              for p in parts if p.parent is None}
    all_vertices = np.concatenate([m.vertices for m in meshes.values()])
    obj_lo, obj_hi = all_vertices.min(axis=0), all_vertices.max(axis=0)
    joints: dict[str, JointEstimate] = {}
    door_cap = opening_caps("door", category, 0.0, config)["revolute"]
    bypass = bypass_pairs(parts, pieces, config)
    swept: dict[tuple, tuple] = {}

    def sweep_against(part: PartEstimate, left_out: tuple[int, ...]):
        """The sweep objects of ``part`` (``sweep_objects``): its own pieces, without the parts
        mounted on it (each turns on its own joint: a latch is turned back before its door swings),
        against every other part with what it carries, less the pieces ``left_out``."""
        key = (part.name, left_out)
        if key not in swept:
            kept = {n: [i for i in (part.pieces if n == part.name else carried[n]) if i not in left_out]
                    for n in meshes}
            swept[key] = sweep_objects({n: trimesh.util.concatenate([pieces[i].mesh for i in ids])
                                        for n, ids in kept.items() if ids}, part.name, config)
        return swept[key]

    for part in parts:
        if part.semantic == "base":
            continue
        d = part.outward
        if part.semantic == "knob":
            piece = pieces[part.panel]
            lever = drum_foot(meshes[part.name], d, config) if part.name in meshes else None
            if lever is not None:
                joints[part.name] = lever_swing(meshes[part.name], lever, sweep_against(part, ()), config)
                continue
            out, width = protrusion_size(piece.mesh.vertices, d)
            stick = part.extra.get("source") == "segmentation" or part.extra.get("stick", False)
            if stick and out > config.plunger_min_ratio * width:
                lever = stick_lever(piece.mesh, d, config) if part.name in meshes else None
                throw = toggle_throw(piece.mesh, d, config) if lever is not None else None
                if throw is not None:
                    axis, pivot, span = throw
                    joints[part.name] = JointEstimate(
                        "revolute", axis, pivot, min(span, float(np.radians(config.lever_limit_deg))),
                        {"rule": "toggle: a stick thrown to one side flips over to the other",
                         "lean_deg": round(float(np.degrees(span / 2)), 1)})
                    continue
                swing = lever_swing(piece.mesh, lever, sweep_against(part, ()), config) if lever is not None else None
                if swing is not None and swing.upper >= np.radians(config.lever_min_swing_deg):
                    joints[part.name] = swing
                    joints[part.name].evidence["rule"] = "lever: a stick with no head, swung along its thin side"
                    continue
                joints[part.name] = JointEstimate("prismatic", -d, piece.centre.copy(), out / 2,
                                                  {"rule": "plunger: stands out further than it is wide, with a head "
                                                           "or too thick at its foot to swing"})
                continue
            origin = part.extra.get("pivot", piece.centre - d * out / 2)
            joints[part.name] = JointEstimate("revolute", d.copy(), origin, opening_caps("knob", category, 0.0, config)["revolute"],
                                              {"rule": part.extra.get("rule", "knob: own axis")})
            continue
        if part.semantic == "button":
            piece = pieces[part.panel]
            joints[part.name] = JointEstimate("prismatic", -d, piece.centre.copy(), float(part.extra["travel"]),
                                              {"rule": "button: pushed in along its surface's normal"})
            continue
        if part.semantic == "slider":  # it runs in its slot the way the slot leaves most room
            if "slot" in part.extra:  # cut from a fused surface: its slot was measured there
                axis, travel = part.extra["slot"]
                joints[part.name] = JointEstimate("prismatic", axis.copy(), part.extra["pivot"].copy(), travel,
                                                  {"rule": "slides in its slot: the room beside its neck"})
            else:
                joints[part.name] = slot_slide(meshes, part.name, d, obj_hi - obj_lo, config)
            continue
        mesh = meshes[part.name]
        moving, others = sweep_against(part, ())
        panel = pieces[part.panel]
        if part.semantic != "drawer":  # a door hinges on its leaf's edges, the frame round its panel too
            panel = leaf_piece(part, pieces, config.leaf_depth_tolerance, config.leaf_frame_share)
        if part.semantic == "drawer":
            thickness = float(np.ptp(panel.mesh.vertices @ d))
            if thickness > config.drawer_front_max_thickness:  # front and box modelled as one piece
                thickness = 0.0
            depth = part.extra["depth_behind"] - thickness
            obj_depth = float(np.ptp(np.array([obj_lo, obj_hi]) @ d))
            travel = max(min(depth, config.drawer_max_depth_ratio * obj_depth), 0.0)
            origin = panel.centre.copy()
            free = sweep_free_range(moving, others, "prismatic", d, origin, travel,
                                    sweep_steps("prismatic", d, origin, travel, mesh.vertices, config))
            # a drawer that cannot be drawn out at all (another part's panel in front of it) does
            # not open: the gate's zero-travel check takes it back into the base
            # whether it has a grip (a handle or a pocket) is recorded: a bare front cut from a flush
            # face says less of the side it faces than one with a pull
            joints[part.name] = JointEstimate("prismatic", d.copy(), origin, free,
                                              {"rule": "drawer: outward normal", "travel": travel, "free": free,
                                               "grip": find_handle(part, pieces, d, config) is not None})
            continue
        planes, overlay = panel_faces(panel, d, outer_plane(meshes["base"], d, config.carcass_band),
                                      config.overlay_tolerance)
        fused = cut_from_surface(part)
        planes["middle"] = (planes["front"] + planes["back"]) / 2
        candidates = hinge_candidates(panel.lo, panel.hi, d, planes)
        # a part cut out of a fused surface meets its neighbours in one surface: no lip can be
        # told from the seam there, so only separate pieces are judged for a track; and its side
        # edges on the object's outline have no carcass beside them to clear
        outline = outline_edges(panel, d, obj_lo, obj_hi, config.outline_tolerance) if fused else ()
        foot = foot_edge(panel.mesh, d, meshes["base"], config) if part.extra.get("standing_free") else None
        ordered, rule = order_hinges(part, pieces, candidates, overlay, obj_lo, obj_hi, config, outline,
                                     fused or overlay, foot, panel, front_shown)
        held = () if fused else held_edges(mesh, d, meshes["base"], config)
        if in_track(held):  # it slides along the free edges
            along = ("u+", "u-") if held[0].startswith("v") else ("v+", "v-")
            slide = best_slide(moving, others, panel, d, config, along)
            if slide is not None:
                joints[part.name] = slide_estimate(panel, slide, {"rule": "slides in its plane: held in a track",
                                                                  "held": list(held)})
                continue
        if part.name in bypass:  # two doors in two tracks: each slides past the other
            slide = best_slide(moving, others, panel, d, config, (bypass[part.name],))
            if slide is not None:
                joints[part.name] = slide_estimate(panel, slide, {"rule": "slides past the door beside it: their "
                                                                  "faces lie in two planes"})
                continue
        towards = part.extra.get("slides_towards")
        if towards is not None:  # a sash: it slides over the pane behind it (see ``pane_behind``)
            tracked = sweep_against(part, tuple(part.extra.get("in_track", ())))  # its rails in the grooves left out
            slide = best_slide(*tracked, panel, d, config, (towards,), mesh.vertices if "sash_panes" in part.extra else None)
            if slide is not None:
                joints[part.name] = slide_estimate(panel, slide, {"rule": "slides over the pane behind it",
                                                                  "towards": towards})
                continue
        hinge_edge = ordered[0].name.split("/")[0]
        if rule == "opposite the handle" and hinge_edge.startswith("u") and \
                closed_front_beside(panel.mesh, d, meshes["base"], hinge_edge, config):
            slide = best_slide(moving, others, panel, d, config, (hinge_edge,))
            if slide is not None:
                joints[part.name] = slide_estimate(panel, slide, {"rule": "slides in its plane: a closed front "
                                                                  "beside it, its handle on the far edge"})
                continue
        centre = mesh.vertices.mean(axis=0)
        tried = []
        chosen = None
        mine = set(carried[part.name])
        lines = hinge_knuckles(panel, d, {i: p for i, p in enumerate(pieces) if i not in mine}, config)
        pins = {cand.name: ids for cand, ids in lines.values()}
        if len(lines) == 1:  # knuckles on one edge: the hinge is there
            ordered = [cand for cand, _ in lines.values()] + ordered
        elif lines:  # pins on several edges (posts either side): each edge turns about its own pin first
            with_pins = []
            for cand in ordered:
                edge = cand.name.split("/")[0]
                with_pins += [lines.pop(edge)[0], cand] if edge in lines else [cand]
            ordered = with_pins
        for cand in ordered:
            # the knuckles a candidate turns about turn with the door: they are left out of its sweep
            moving, others = sweep_against(part, tuple(pins.get(cand.name, ())))
            axis = opening_axis(cand.axis, cand.point, centre, d)
            free = sweep_free_range(moving, others, "revolute", axis, cand.point, door_cap,
                                    sweep_steps("revolute", axis, cand.point, door_cap, mesh.vertices, config))
            tried.append({"edge": cand.name, "free_deg": round(float(np.degrees(free)), 1)})
            if free >= 0.5 * door_cap:
                chosen = (cand, axis, free)
                break
        if chosen is None:  # every edge collides early: a panel that cannot swing slides in its plane
            moving, others = sweep_against(part, ())
            # (not one standing on its foot: it turns about that edge, however little it clears)
            slide = best_slide(moving, others, panel, d, config) if foot is None else None
            if slide is not None:
                joints[part.name] = slide_estimate(panel, slide, {"rule": "slides in its plane: every hinge "
                                                                  "collides early", "sweep": tried})
                continue
            best = max(range(len(tried)), key=lambda k: tried[k]["free_deg"])
            cand = ordered[best]
            chosen = (cand, opening_axis(cand.axis, cand.point, centre, d), np.radians(tried[best]["free_deg"]))
        cand, axis, free = chosen
        rule = "hinge knuckles" if cand.name.endswith("/knuckles") and len(pins) == 1 else rule
        if part.name in bypass:  # the pair says it slides, the sweep that it cannot: a doubtful hinge
            rule = f"hinged against its pair: {rule}"
        elif rule == "opposite the handle" and cand.name.split("/")[0] != hinge_edge:
            # the handle's far edge cannot swing and another edge can: a door does not hinge
            # where its handle is, so its pieces or its handle are doubtful
            rule = f"hinged off its handle's far edge: {rule}"
        joints[part.name] = JointEstimate("revolute", axis, cand.point.copy(), float(max(free, np.radians(config.hinge_min_range_deg))),
                                          {"rule": rule, "mount": "overlay" if overlay else "inset", "edge": cand.name,
                                           "sweep": tried})
    return joints


def bypass_pairs(parts: list[PartEstimate], pieces: list[Piece], config: JointsConfig,
                 kinds: tuple[str, ...] = ("door",)) -> dict[str, str]:
    """Doors that slide past a neighbour: part name -> the panel direction (``u+``, ``u-``,
    ``v+``, ``v-``) towards it. Two doors facing the same way, meeting (or overlapping) along
    one edge over most of its length, whose faces lie ``bypass_min_step`` to ``bypass_max_step``
    apart along their outward axis, run in two tracks, one behind the other (hinged doors side
    by side share one plane). Scans show the step as well as separate pieces do; where both
    doors are pieces of their own their backs must step too (a glass door beside a thicker
    one, both hinged on one carcass front, steps only in front). The two are about as wide
    (``bypass_min_width_share``): a door beside a post or a narrow panel a step behind it (a
    microwave's) is no pair. ``kinds``: the semantics of the parts paired (doors, unless asked)."""
    doors = [p for p in parts if p.semantic in kinds and p.parent is None and p.outward is not None]
    span = lambda piece, axis: np.array([(piece.mesh.vertices @ axis).min(), (piece.mesh.vertices @ axis).max()])  # noqa: E731
    out: dict[str, str] = {}
    for k, a in enumerate(doors):
        for b in doors[k + 1:]:
            d = a.outward
            if float(d @ b.outward) < FACING_COS:
                continue
            pa, pb = pieces[a.panel], pieces[b.panel]
            fa, fb = panel_faces(pa, d, 0.0, 0.0)[0], panel_faces(pb, d, 0.0, 0.0)[0]
            if not config.bypass_min_step <= abs(fa["front"] - fb["front"]) <= config.bypass_max_step:
                continue
            if not (cut_from_surface(a) or cut_from_surface(b)) \
                    and abs(fa["back"] - fb["back"]) < config.bypass_min_step:
                continue  # backs in one plane: a thick door beside a thin one (glass), both hinged
            u, v = panel_frame(d)
            for name, axis, across in (("u", u, v), ("v", v, u)):
                ia, ib, ja, jb = span(pa, axis), span(pb, axis), span(pa, across), span(pb, across)
                meet = min(ia[1], ib[1]) - max(ia[0], ib[0])  # overlap (> 0) or gap (< 0) along the axis
                shared = min(ja[1], jb[1]) - max(ja[0], jb[0])
                narrow, wide = sorted([np.ptp(ia), np.ptp(ib)])
                if -config.bypass_max_gap <= meet <= 0.5 * narrow and narrow >= config.bypass_min_width_share * wide \
                        and shared >= config.bypass_min_overlap * min(np.ptp(ja), np.ptp(jb)):
                    towards = pb.centre @ axis > pa.centre @ axis
                    out[a.name], out[b.name] = f"{name}{'+' if towards else '-'}", f"{name}{'-' if towards else '+'}"
    return out


def lever_swing(mesh: trimesh.Trimesh, lever: tuple[np.ndarray, np.ndarray], swept,
                config: JointsConfig) -> JointEstimate:
    """The revolute joint of a lever (``mesh``) on its drum (``drum_foot``: axis, pivot): about
    the drum's axis the way that swings it further before it meets the rest of the object
    (``swept``: its sweep objects, ``sweep_objects``), at most ``lever_limit_deg``; raising its
    tip first where both ways swing as far."""
    axis, pivot = lever
    moving, others = swept
    cap = float(np.radians(config.lever_limit_deg))
    tip = mesh.vertices[int(np.argmax(np.linalg.norm(mesh.vertices - pivot, axis=1)))]
    ways = sorted((axis, -axis), key=lambda a: -float(np.cross(a, tip - pivot)[2]))
    free = [sweep_free_range(moving, others, "revolute", a, pivot, cap,
                             sweep_steps("revolute", a, pivot, cap, mesh.vertices, config)) for a in ways]
    best = int(np.argmax(free))
    return JointEstimate("revolute", ways[best].copy(), pivot, float(free[best]),
                         {"rule": "lever: turns about the drum it stands on",
                          "free_deg": [round(float(np.degrees(f)), 1) for f in free]})


def edge_lines(points: np.ndarray, outward: np.ndarray, config: JointsConfig,
               inset: float = 0.0) -> dict[str, np.ndarray]:
    """Per edge (u-, u+, v-, v+) of the box of (N, 3) ``points`` seen along ``outward`` (3,),
    ``track_rays`` points (K, 3) spread over ``track_span`` of the edge, ``inset`` (m) inside
    the outline, in the plane through the origin across ``outward`` (add a depth along it)."""
    u, v = panel_frame(outward)
    pu, pv = points @ u, points @ v
    t = np.linspace(*config.track_span, config.track_rays)
    across_u, across_v = pu.min() + t * np.ptp(pu), pv.min() + t * np.ptp(pv)
    lines = {"u-": (np.full_like(t, pu.min() + inset), across_v), "u+": (np.full_like(t, pu.max() - inset), across_v),
             "v-": (across_u, np.full_like(t, pv.min() + inset)), "v+": (across_u, np.full_like(t, pv.max() - inset))}
    return {name: a[:, None] * u + b[:, None] * v for name, (a, b) in lines.items()}


def held_edges(part_mesh: trimesh.Trimesh, outward: np.ndarray, carcass: trimesh.Trimesh,
               config: JointsConfig) -> tuple[str, ...]:
    """The edges (u-, u+, v-, v+) of a part facing ``outward`` that run behind a lip of the
    ``carcass``: rays cast outward from just inside the edge, starting inside the part's back,
    hit the carcass before ``track_lip_reach`` past the part's front (a groove's front wall,
    a window frame's stop). On a carcass that bounds a volume (closed, wound outward), a ray
    that meets the inside of its surface first started in its solid: that edge is set into the
    carcass (a fixed pane), not held in a groove (an open or inside-out surface's normals say
    nothing of its inside)."""
    along = part_mesh.vertices @ outward
    back, front = float(along.min()), float(along.max())
    inset = config.track_edge_inset
    held, closed = [], carcass.is_volume
    for name, line in edge_lines(part_mesh.vertices, outward, config, inset).items():
        origins = line + (back + inset) * outward
        distance, inside = first_hits(carcass, origins, outward, closed)
        hit = np.where(inside, np.inf, back + inset + distance)  # position along outward of the lip each ray meets
        if np.mean(hit <= front + config.track_lip_reach) >= config.track_min_share:
            held.append(name)
    return tuple(held)


def foot_edge(panel_mesh: trimesh.Trimesh, outward: np.ndarray, carcass: trimesh.Trimesh,
              config: JointsConfig) -> str | None:
    """The one edge (u-, u+, v-, v+) along which a panel facing ``outward`` meets the
    ``carcass``: ``track_rays`` points on each edge line, halfway through the panel's thickness
    and over ``track_span`` of the edge, at least ``track_min_share`` of them within
    ``foot_contact`` (m) of the carcass surface. None unless exactly one edge does (a sash
    meets its frame all round; a screen stands on its base along its foot)."""
    along = panel_mesh.vertices @ outward
    middle = (along.min() + along.max()) / 2
    touching = []
    for name, line in edge_lines(panel_mesh.vertices, outward, config).items():
        distance = trimesh.proximity.closest_point(carcass, line + middle * outward)[1]
        if np.mean(distance <= config.foot_contact) >= config.track_min_share:
            touching.append(name)
    return touching[0] if len(touching) == 1 else None


def in_track(held: tuple[str, ...]) -> bool:
    """Whether the edges ``held_edges`` found are two opposite ones: the part runs in a track."""
    return held in (("v-", "v+"), ("u-", "u+"))


def closed_front_beside(panel_mesh: trimesh.Trimesh, outward: np.ndarray, carcass: trimesh.Trimesh,
                        edge: str, config: JointsConfig) -> bool:
    """Whether a door facing ``outward`` covers an opening of the ``carcass`` and, past its
    side ``edge`` (``u-`` or ``u+``), a closed front at least as wide as the door lies within
    ``slide_face_depth`` behind its back: the room a sliding door runs into."""
    u, v = panel_frame(outward)
    pts = panel_mesh.vertices
    back = float((pts @ outward).min())
    pu, pv = pts @ u, pts @ v
    width, sign = float(np.ptp(pu)), (1.0 if edge == "u+" else -1.0)
    start = pu.max() if edge == "u+" else pu.min()
    t = np.linspace(*config.slide_span, config.track_rays)
    grid_u, grid_v = np.meshgrid(t, pv.min() + np.linspace(*config.track_span, config.track_rays) * np.ptp(pv))
    grid_u, grid_v = grid_u.ravel(), grid_v.ravel()

    def depth_behind(along_u: np.ndarray) -> np.ndarray:
        origins = along_u[:, None] * u + grid_v[:, None] * v + (back + config.track_edge_inset) * outward
        return ray_distances(carcass, origins, -outward) - config.track_edge_inset

    beside = depth_behind(start + sign * grid_u * width)
    behind = depth_behind(pu.min() + grid_u * width)
    share = config.track_min_share
    return bool(np.mean(beside <= config.slide_face_depth) >= share
                and np.mean(behind > config.slide_face_depth) >= share)


def best_slide(moving, others, panel: Piece, outward: np.ndarray, config: JointsConfig,
               directions: tuple[str, ...] = ("u+", "u-", "v+", "v-"),
               span: np.ndarray | None = None) -> tuple[np.ndarray, float, list[dict]] | None:
    """The in-plane slide of a panel facing ``outward`` (among ``directions``) that travels
    furthest before it collides, swept up to its width along it (that of the (N, 3) ``span``
    points when given: a sash joined from panes): (axis (3,), travel m, every direction tried),
    or None when none travels ``slide_min_share`` of that width (a door that is stuck)."""
    u, v = panel_frame(outward)
    tried, best = [], None
    for name, axis in (("u+", u), ("u-", -u), ("v+", v), ("v-", -v)):
        if name not in directions:
            continue
        width = float(np.ptp((panel.mesh.vertices if span is None else span) @ axis))
        free = sweep_free_range(moving, others, "prismatic", axis, panel.centre, width,
                                sweep_steps("prismatic", axis, panel.centre, width, panel.mesh.vertices, config))
        tried.append({"direction": name, "free_m": round(free, 4), "width_m": round(width, 4)})
        if free >= config.slide_min_share * width and (best is None or free / width > best[1] / best[2]):
            best = (axis.copy(), free, width)
    if best is None:
        return None
    return best[0], best[1], tried


def slot_slide(meshes: dict[str, trimesh.Trimesh], name: str, outward: np.ndarray, extents: np.ndarray,
               config: JointsConfig) -> JointEstimate:
    """The prismatic joint of part ``name`` of ``meshes``, a handle running in a slot of a face
    facing ``outward``: along the in-plane direction (of the face's four) it travels furthest
    before it collides, swept up to the object's ``extents`` (3,) along it, from the handle's
    centre. A tip sunk into the slot's back (a modelling overlap) would stop every slide: the
    handle is swept drawn out along ``outward`` by the least whole ``slot_pull_step`` (m) that
    frees it, at most its own thickness."""
    mesh = meshes[name]
    u, v = panel_frame(outward)
    origin = mesh.vertices.mean(axis=0)
    thickness = float(min(np.ptp(mesh.vertices @ u), np.ptp(mesh.vertices @ v)))
    moving, others = sweep_objects(meshes, name, config)
    pull = 0.0
    while pull < thickness:
        set_pose(moving, joint_transform("prismatic", outward, origin, pull))
        if not collides_with_scene(moving, others):
            break
        pull += config.slot_pull_step
    set_pose(moving, np.eye(4))
    if pull > 0:  # the sweep starts from the drawn-out pose
        drawn = {**meshes, name: trimesh.Trimesh(mesh.vertices + pull * outward, mesh.faces, process=False)}
        moving, others = sweep_objects(drawn, name, config)
    tried, best = [], None
    for direction, axis in (("u+", u), ("u-", -u), ("v+", v), ("v-", -v)):
        reach = float(np.abs(axis) @ extents)
        free = sweep_free_range(moving, others, "prismatic", axis, origin, reach,
                                sweep_steps("prismatic", axis, origin, reach, mesh.vertices, config))
        tried.append({"direction": direction, "free_m": round(free, 4)})
        if best is None or free > best[1]:
            best = (axis.copy(), free)
    return JointEstimate("prismatic", best[0], origin, best[1],
                         {"rule": "slides in its slot", "drawn_out_m": round(pull, 4), "slides": tried})


def slide_estimate(panel: Piece, slide: tuple[np.ndarray, float, list[dict]], evidence: dict) -> JointEstimate:
    """The prismatic joint of a panel sliding in its plane, from ``best_slide``'s result."""
    axis, travel, slides = slide
    return JointEstimate("prismatic", axis, panel.centre.copy(), travel, {**evidence, "slides": slides})


def guess_category(parts: list[PartEstimate], extents: np.ndarray, config: JointsConfig = JointsConfig()) -> str:
    """A coarse object category from the parts and the canonical extents (w, d, h)."""
    kinds = [p.semantic for p in parts if p.semantic != "base"]
    w, _, h = extents
    if kinds and all(k == "door" for k in kinds):
        if h >= config.fridge_min_height:
            return "fridge"
        if len(kinds) == 1 and h < 0.5 and w > h:
            return "microwave"
    if "knob" in kinds:
        return "oven"
    if kinds and all(k == "lid" for k in kinds):
        return "box"
    return "cabinet"
