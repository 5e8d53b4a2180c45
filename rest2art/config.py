"""Stage configs: one frozen dataclass per stage, all tolerances in one place.

The dataclass defaults are the source of truth; ``configs/default.yaml`` mirrors them (a test
keeps the two equal) and any YAML file given with ``--config`` overrides single fields::

    joints:
      door_limit_deg: 100.0

Lengths are metres, angles degrees unless a field says otherwise.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from rest2art.errors import ConfigError
from rest2art.tolerances import FACING_COS


@dataclass(frozen=True)
class LoadConfig:
    """Loading and sanity checks of an input mesh."""

    max_faces: int = 1_000_000
    """Meshes with more faces are refused, or decimated when ``decimate_large`` is set."""
    decimate_large: bool = False
    """Decimate meshes over ``max_faces`` instead of refusing them (face_part then refers to
    the decimated mesh, which is written beside the asset)."""
    memory_budget_mb: int = 8000
    """Peak memory (MB) one reconstruction may use; ``max_faces`` must keep the largest input
    inside it (benchmarks/bench_memory.py measures peak memory against face count)."""
    max_height: float = 5.0
    """An object taller than this many units is probably not in metres (hint: --units)."""
    min_size: float = 0.02
    """An object whose largest extent is below this is probably not in metres."""
    double_sided_share: float = 0.5
    """A scene node is double-sided when at least this share of its faces come in pairs with
    the same corners: each pair is read once."""
    winding_views: int = 14
    """Cameras spread over a sphere around the object that judge a piece's winding ..."""
    winding_view_size: int = 128
    """... each this many pixels wide ..."""
    winding_camera_radius: float = 3.0
    """... this many bounding radii from the object's centre ..."""
    winding_fov_deg: float = 45.0
    """... with this field of view (degrees) ..."""
    winding_back_ratio: float = 2.0
    """... a piece whose faces they see from behind over this many times as often as from the
    front is wound inward (a mirrored export), and turned."""


@dataclass(frozen=True)
class FrameConfig:
    """Canonical frame estimation (+z up, -y front)."""

    axis_aligned_tol_deg: float = 2.0
    """An OBB axis this close to a coordinate axis snaps to it (keeps artist frames exact)."""
    min_obb_gain: float = 0.05
    """The file's own axes are kept unless the oriented bounding box is this share smaller
    than the axis-aligned one (an object modelled rotated); on a tie the OBB of an L-shaped
    object (an open laptop) may tilt by 45 degrees."""
    support_height: float = 0.02
    """Hull points this close to the bottom (fraction of the height) form the contact patch;
    hull facets this close, facing down, are the flat support (scans chamfer the bottom edge)."""
    support_facing_cos: float = 0.996
    """A hull facet faces down when the cosine of its normal with -up reaches this."""
    snap_min_det: float = 0.99
    """Snapped axes whose determinant falls below this are no longer orthogonal: the raw
    oriented box's axes are kept."""
    relief_ray_start: float = 0.01
    """The depth maps' rays start this far (m) outside the mesh."""
    min_support: float = 0.05
    """A side can carry the object when its contact patch is at least this share of its shadow."""
    relief_resolution: int = 400
    """Rays across the largest extent in the orthographic depth maps used to find the front."""
    relief_jump: float = 0.002
    """A depth step larger than this (m) between neighbouring pixels is relief (seam, handle)."""
    relief_min_edge: float = 0.02
    """Relief is counted only in connected runs of step pixels reaching at least this far (share
    of the depth map's longest side): a seam or a handle's outline is a line, the pits and
    spikes of a scan's noise are specks."""
    flip_support_ratio: float = 0.5
    """The file's up is turned upside down only when its bottom's flat support is less than
    this share of its top's (a window frame stands on a bar no wider than its top one)."""
    flat_ratio: float = 2.5
    """An object at least this many times wider than deep (across the level sides) is flat (a
    door in its frame, a window, a panel): its front is one of its two broad sides."""
    flat_relief_jump: float = 0.01
    """Between a flat object's two broad sides that the format's front does not tell apart, the
    one with more relief edges whose depth steps exceed this (m) is the front: a latch or a
    handle stands out centimetres, a scan's noise and a panel's seams a few millimetres."""
    front_margin: float = 0.5
    """Another side must have this much more relief (relative) than the format's front..."""
    front_min_relief: float = 0.5
    """... and this many metres more, or the format's front stays."""
    front_contrast_margin: float = 1.0
    """A side whose relief less its opposite side's (a front differs from its back) is this
    much more (relative) than the format's front's over its back..."""
    front_min_contrast: float = 0.15
    """... and more by this share of the object's largest extent (metres of relief edges per
    metre of object: a microwave's handle is shorter than a wardrobe's seams), is the front."""
    off_axis_factor: float = 3.0
    """A side along the format's up axis is the front only when it shows this many times more
    relief than the level front, beyond what its opposite side shows (a front differs from its
    back; a lid's parting line seen from above and a scan's underside do not tip a box over)."""
    outline_margin: float = 0.005
    """Band inside a side's outline (fraction of the view) where relief is not counted."""
    fitting_window: float = 0.06
    """Handles and knobs are what stands out of a side's depth map and is narrower than this
    (m) across: a grey opening with a square this wide removes them (a bar handle is a few
    centimetres wide however long; a desk's leg or a door's frame is wider or reaches the
    outline)."""
    fitting_proud: float = 0.008
    """... standing at least this far (m) out of the surface around it (a hand grips behind it) ..."""
    fitting_min_area: float = 4e-4
    """... whose footprint covers at least this much (m^2: a fingertip's knob, not a scan's
    speck or a pin's head) ..."""
    fitting_max_share: float = 0.02
    """... and at most this share of the side ..."""
    fitting_border: float = 0.05
    """... inside this band of the view (share of its longest side) from the side's outline.
    When the side the relief chose shows no fitting and exactly one other level side does, that
    side is the front: a desk's side panel framed by legs shows more relief edges than drawer
    fronts sunk into it, but the knobs are on the drawers."""
    floor_origin_tol: float = 0.01
    """A file puts its floor at the origin along an axis when the object's lowest point there
    lies within this share of its size of 0 ..."""
    floor_centre_tol: float = 0.1
    """... and its middle lies within this share of its size of 0 along the other two axes:
    the asset's pivot at the middle of its base, a convention of its own (``floor_axis``)."""


@dataclass(frozen=True)
class PartsConfig:
    """Part extraction from the pieces of the mesh (connected components / scene nodes)."""

    contact_tol: float = 0.0005
    """Pieces closer than this are rigidly joined (touching or interpenetrating)."""
    min_panel_size: float = 0.04
    """A front panel is at least this wide and high."""
    panel_max_thickness: float = 0.08
    """A panel is no thicker than this along its normal."""
    panel_min_aspect: float = 4.0
    """... and its smaller side is at least this many times its thickness."""
    fitting_max_share: float = 0.5
    """A fitting on a panel (that may turn on its own joint) spans at most this share of the
    panel's smaller side."""
    foot_band: float = 0.01
    """A fitting's foot: its vertices within this (m) of its back, where it meets or enters
    its mount ..."""
    foot_link: float = 0.02
    """... one cluster when each lies within this (m) of another (a bar's posts are two)."""
    foot_roundness: float = 0.5
    """... one region, its in-plane sides in at least this ratio (not a pull's strip)."""
    fitting_sectors: int = 12
    """Angular sectors about a fitting's axis for its asymmetry."""
    fitting_min_height: float = 0.15
    """... and stands out of its mount by at least this share of its width (a hinge leaf lies flat)."""
    fitting_min_asymmetry: float = 0.1
    """A fitting at least this asymmetric about its foot's axis turns on its own joint (a lever,
    spokes, a dial's mark); a turned round pull is rigid."""
    cut_fitting_min_asymmetry: float = 0.5
    """A fitting the views cut from a panel's fused surface (a scan) turns only when at least
    this asymmetric: a scan's noise makes a round pull up to ~0.13 asymmetric, as much as a
    dial's mark, so a scanned dial stays with its door and a spoke wheel turns ..."""
    grip_mirror_share: float = 0.12
    """Two fittings whose offsets from a door's middle mirror each other within this share of
    its width or height are both its grip (pulls at both ends); a round fitting beside the grip
    is a control that turns (a safe's dial)."""
    cut_fitting_held_reach: float = 0.5
    """... and when the surface it was cut from meets it no further from its foot than this
    share of its reach (a wheel about its hub, a lever on its rose; a bar pull whose other post
    the scan fused into the panel is held at its far end too)."""
    slider_min_reach: float = 1.0
    """A handle slides in a slot of the carcass (a press's handle) when one of its pieces stands
    out of the carcass's box through one face and reaches behind that face at least this many
    times its own thickness (a handle on a face is sunk millimetres at most)."""
    body_min_span: float = 0.5
    """A piece behind a front is part of a drawer's body (its depth) when it spans at least this
    share of the front's smaller side: boards and boxes do, a handle on a door's back does not."""
    drawer_min_depth_share: float = 0.35
    """A front whose body reaches at least this share of the object's depth behind it is a drawer;
    a shallower one is a door ..."""
    drawer_max_lean_deg: float = 5.0
    """... and so is a front whose face leans more than this (deg) off upright (``lean_deg``): a
    drawer slides out level, a leaned panel (a laptop's open screen) swings."""
    front_band_share: float = 0.25
    front_band_min: float = 0.06
    """A part's panel is its piece with the most area facing out within this share of its depth
    (and at least ``front_band_min`` m) of its front."""
    floor_tol: float = 0.005
    """Groups of pieces reaching this close (m) to the object's bottom stand on the floor: the
    ones that are not flat upright panels form the base together (posts of a door frame)."""
    panel_aspect: float = 3.0
    """A flat panel is at least this many times wider than it is thick."""
    cavity_depth: float = 0.02
    """A front touching the carcass is movable when rays from its back travel this far ..."""
    cavity_min_share: float = 0.3
    """... this share of them or more (a thick-walled carcass's boards stand behind the outer
    rays of a full overlay door; a board of the carcass has a wall behind all of them)."""
    lid_min_cover: float = 0.8
    """A panel resting on a one-piece body covers this share of the body's outline seen from
    above or more to be its lid (``split_touching_lids``)."""
    lid_grip_max_share: float = 0.5
    """A panel resting on a body of several boards is its lid when it carries a grip no wider
    than this share of it (a tab, a handle; a crown moulding runs the whole width)."""
    seen_again_share: float = 0.1
    """A part found by segmentation with at least this share of its area on faces the pieces
    already gave to a movable part is that part seen again: the rest of its faces stay with the
    base (the walls of a box under a lid found both ways)."""
    cavity_grid: int = 5
    cavity_grid_share: float = 0.8
    """Those rays: a grid of this many per side over this share of the front's width and height."""
    front_tolerance: float = 0.03
    """A touching front lies at most this far behind the carcass's front (m) ..."""
    carcass_front_band: float = 0.08
    """... the plane holding the most of the carcass's front-facing area within this (m) of its
    frontmost point: its face, not the edge of a top board overhanging it."""
    attach_tolerance: float = 0.01
    """Slack when testing whether a piece lies inside a panel's footprint (m)."""
    front_fitting_share: float = 0.75
    """A piece standing in front of a front touching the carcass is its fitting only when this
    share of it (its box, seen from the front) lies over the front: a lip of the carcass along
    the front's edge is not."""
    front_member_tolerance: float = 0.003
    """A piece joins a front touching the carcass only if it lies inside the front's outline
    within this slack (m): a drawer's box or handle does; a shelf or divider behind a flush
    front reaches past it by the carcass board's thickness."""
    body_inset: float = 0.005
    """A drawer's body behind its front may hang together with the carcass (it runs on its walls
    or stops against its back); it lies this far (m) or more inside the box of the carcass's
    boards on every side but the front ..."""
    body_gap: float = 0.01
    """... starts at most this far (m) behind the front's back (touching it, or held off it) ...
    """
    body_min_cover: float = 0.5
    """... and spans this share of its front's width and height or more (a shelf does not)."""
    handle_standoff: float = 0.05
    """A loose handle floats at most this far in front of its panel (m)."""
    handle_max_overhang: float = 0.05
    """A handle the views found reaches at most this far (m) past the box of the panel it
    belongs to (an edge pull over its edge); faces of its label further off are another part's
    (the groove between two doors above a drawer, which the label followed)."""
    handle_stray_share: float = 0.05
    """Of a handle cut from a fused surface, patches of connected faces with less than this
    share of its largest patch's area ...
    """
    handle_stray_reach: float = 0.01
    """... lying further than this (m) from that patch are stray facets its label picked up
    elsewhere (along the seam between two doors), not the handle; a facet at its foot is its."""
    fused_grip_max_share: float = 0.25
    """A grip the views found on a door, drawer or lid the pieces found, fused into its panel's
    piece (a scan's front held clear of the carcass is a shell of its own), is cut out of it
    when it holds at most this share of the piece's faces; more is no grip but the panel."""
    box_floor_facing_cos: float = 0.9
    """A drawer cut out of a fused surface (a scan) over open space takes the box the surface
    shows below it (``hanging_box_faces``): its floor faces down within this cosine of straight
    down, ..."""
    box_floor_tolerance: float = 0.005
    """... no lower than the front's lower edge less this (m), within its outline across and at
    least this far inside the object's sides (a scan fuses what lies closer), ..."""
    box_floor_min_clearance: float = 0.05
    """... at least this high (m) over the object's lowest point (an object's own bottom stands on
    the ground: nothing under it either), ..."""
    box_floor_max_height_share: float = 0.5
    """... no higher than this share of the front's height over its lower edge (a box stands low
    behind its front; the underside of a top over it is no floor), ..."""
    box_floor_min_share: float = 0.25
    """... in a connected patch of at least this share of the front's area, with nothing below it."""
    grip_min_proud: float = 0.003
    """A patch of a one-piece front standing more than this (m) in front of its face plane may be
    a grip (``parts.grips``) ..."""
    grip_plane_bin: float = 0.002
    """... its face plane being the outermost level, in bins this deep (m), ..."""
    grip_plane_min_share: float = 0.2
    """... that holds this share of its outward-facing area or more ..."""
    grip_min_area: float = 0.00005
    """... when it covers this much area (m^2) or more ..."""
    grip_min_height: float = 0.008
    """... and reaches this far (m) or more out (a finger's width), ..."""
    grip_max_span: float = 0.9
    """... and runs less than this share of the front's width and height (a rim runs it all)."""
    grip_alike_ratio: float = 1.5
    """Grips whose footprints are within this ratio of each other both ways are alike: the pulls
    of one pair of doors or one column of drawers, not a handle beside a lock."""
    grip_row_tol: float = 0.25
    """Grips whose centres spread at most this share of the front's height are side by side (of
    its width: one above the other)."""
    grip_pair_max_offset: float = 0.25
    """Two alike grips side by side divide a one-piece front into a pair of doors when each is
    within this share of its width of its middle (a pair's pulls stand by the meeting edge; a
    wide drawer's two pulls stand out towards its ends), ..."""
    grip_pair_mirror_tol: float = 0.05
    """... mirrored about it to this share of its width (a safe's lever beside its dial is not) ..."""
    grip_pair_min_height_share: float = 0.5
    """... and the front is at least this share as tall as it is wide (a pair of doors, not a
    drawer front)."""
    grip_share_min_faces: int = 30
    """A one-piece front is divided only when each share holds this many faces or more."""
    grip_seam_reach: float = 0.003
    """A face of a divided front reaching more than this (m) across the cut on both sides is a
    sliver of the scan's fused seam: it stays with the base, not with either front."""
    grip_lying_margin: float = 0.01
    """A front lies on another (its grips count as the other's) inside the other's outline
    grown by this (m)."""
    part_max_gap: float = 0.05
    """A group of pieces further than this (m) from the carcass moves on no joint of it: a door,
    drawer or lid closes against the carcass (a control panel floating above a stove, fixed to
    the wall of the scene the model was cut from, stays with the base)."""
    knob_max_size: float = 0.1
    """Largest extent of a control knob (m) ..."""
    knob_max_share: float = 0.05
    """... or this share of the object's largest extent, when that is more (a large model's
    knobs scale with it)."""
    knob_roundness: float = 0.7
    """Min ratio of a knob's two in-plane extents (1 = round)."""
    plate_min_width: float = 0.08
    """A round fitting on a top at least this wide (m) ..."""
    plate_max_height: float = 0.25
    """... standing out of it at most this share of its width is a burner or a hot plate, no
    grip (``hot_plate``) ..."""
    cooktop_min_plates: int = 2
    """... and a top the views cut as a lid that carries this many is a cooktop: it stays."""
    stick_max_lean_deg: float = 40.0
    """A small piece that is not round about its surface's normal is a stick (a toggle switch,
    a lever's bar) when its long axis leans at most this far (deg) off that normal ..."""
    stick_min_slenderness: float = 2.0
    """... and is at least this many times as long as the piece is thick across it."""
    lever_max_size: float = 0.35
    """A loose group held off a surface by a small round hub turns as a lever when it is no
    larger than this (m): a hand grips it (``hub_lever``)."""
    post_levels: int = 40
    """A fused surface is cut by this many horizontal planes to find a head on a post
    (``post_head``: a tap's handle on its column) ..."""
    post_neck_share: float = 0.6
    """... the post's sections at most this share of the widest section above it ..."""
    post_min_height: float = 1.0
    """... and the post at least this many times as tall as it is wide."""
    post_width_spread: float = 1.25
    """The post's sections are within this factor of its median width; wider ones at its top
    are the head's underside."""
    handle_neck_min_length: float = 0.5
    """A handle standing out of a small fixture's front (``front_handle``: a press's handle on
    its bar) has a neck at least this many times as long as it is wide."""
    neck_outline_margin: float = 0.002
    """What continues a handle's neck into the body lies within the neck's outline grown by
    this (m): the bar in its slot, not the slot's walls."""
    slot_probe_step: float = 0.005
    """Beside a handle's neck, rays look for its slot this far (m) apart ..."""
    slot_room_share: float = 0.8
    """... and find room where they reach this share of the neck's depth into the body."""
    knob_min_height: float = 0.35
    """A knob stands proud of its surface by at least this share of its width."""
    knob_min_grip: float = 0.013
    """... and, cut from a fused surface, by at least this (m): fingers pinch a knob's side to
    turn it; a cap standing out less is pushed (the scanned buttons of a panel stand 7 to
    12 mm out, its knobs and a safe's dial 15 mm and more)."""
    knob_max_gap: float = 0.01
    """A round cap whose underside stands further than this (m) off a side-facing surface, on
    a stem, is a push button ..."""
    stem_button_max_up: float = 0.5
    """... when its axis is this far from vertical at most (|axis . up|); on a post standing up
    (a tap's handle) it turns."""
    control_snap_deg: float = 20.0
    """A small control's own axis within this angle (deg) of the normal of the surface it stands
    on is that normal (``plate_normal``: of the faces that agree, not a hole's walls)."""
    control_isotropy: float = 1.5
    """A small control whose largest principal spread is less than this many times its
    smallest has no axis of its own (a knob about as wide as tall): its axis snaps to its
    surface's normal from further off, ``control_isotropic_snap_deg``."""
    control_isotropic_snap_deg: float = 45.0
    """... within this angle (deg) of it; further off, it is the wall of a button's hole."""
    plate_agree_deg: float = 10.0
    """Faces of a mount whose normals lie within this angle (deg) of each other are one plate."""
    ring_width: float = 0.015
    """The surface around a knob the views found is the base within this (m) of where they meet."""
    ring_max_deg: float = 40.0
    """A knob the views found turns about the normal of the surface around it (its ring of base
    faces) when that lies within this angle of the views' axis-snapped normal."""
    mount_reach: float = 0.005
    """A small piece sits on the surface of the base faces within this distance (m) of it."""
    loose_reach_share: float = 0.3
    """A small group touching nothing is held off the surface within this share of its size
    of it, if more than ``mount_reach`` (a 36 mm button 5 mm clear of its hole's walls)."""
    control_max_down: float = 0.5
    """A small piece on a surface facing down more than this (normal z < -value) is a foot."""
    surface_ring: float = 0.004
    """The surface around a small piece is sampled this far (m) outside its outline."""
    button_min_sunk: float = 0.003
    """A small piece reaching this far (m) below the surface around it sits in a hole: a button
    ..."""
    button_min_proud: float = 0.001
    """... when it stands at least this far (m) out of that surface: a piece flush with it is a
    piece of that surface (a block of a carcass built of boxes, between two grooves)."""
    button_max_travel: float = 0.01
    """A button is pushed in as far as its hole leaves room, at most this far (m)."""
    control_min_neighbours: int = 2
    """A grip the views found on the base, with no panel under it, is one more control where at
    least this many knobs and buttons share its face (``cap_among_controls``; a pull on a
    carcass whose drawer was missed stays a pull)."""
    control_max_elongation: float = 2.0
    """Such a grip is a control only where it is at most this many times as long as it is wide
    across its face (a pull is a bar)."""
    control_facing_cos: float = 0.9
    """Controls share a face where their normals' cosine is above this."""
    control_fragment_margin: float = 0.1
    """Knobs the views cut out of such a control, or of a panel's grip, lie in its box grown by
    this share of its larger side: they are its own."""
    button_min_roundness: float = 0.45
    """A push button's outline across its push is compact: its smaller footprint spread is at
    least this share of its larger (a round or square cap 1, a 2:1 rocker 0.5); a longer
    fitting sunk into a surface with what hangs on it (a spout on its stub, a peg) is fixed."""
    button_tip_band: float = 0.001
    """A button's travel is measured from its vertices within this (m) of its deepest point."""
    stem_slice: float = 0.004
    """A button's stem fused with the surface it stands on (a scan) is followed behind its cap
    in slices this thick (m) along its axis ..."""
    stem_widening: float = 0.2
    """... while the slice's widest reach from the axis stays within this share over the
    narrowest before it (where the surface widens, the collar or the wall begins) ..."""
    stem_max_share: float = 0.8
    """... and a stem is at most this share of its cap's inscribed radius thick (the wall of a
    hole the cap sits in is no narrower than the cap)."""
    surface_ray_start: float = 0.01
    """Rays sampling the surface around a small piece start this far (m) above its top."""


@dataclass(frozen=True)
class GateConfig:
    """The plausibility gate between joints and export (``rest2art.gate.plausibility``)."""

    allow_static: bool = False
    """Publish an object with no movable part as a rigid asset (``--allow-static``); by default
    it is reported as static and refused."""
    min_travel: float = 0.002
    """A prismatic joint opening less than this (m) has no range: its part stays with the base
    (push buttons travel a few millimetres)."""
    min_angle_deg: float = 2.0
    """A revolute joint (not a knob) opening less than this has no range."""
    fitting_reach: float = 0.01
    """A fitting the views gave a demoted panel that comes this close (m) to a knob or button
    goes with that control (a fused scan leaves a few millimetres between a button's cap, a
    piece of its own, and the stem it stands on)."""
    loose_slide_share: float = 0.9
    """A panel that slides free this share of its width or more both ways along one direction is
    held by nothing: it lies on the object, no sliding part."""
    min_facing_share: float = 0.45
    """A door or lid with less than this share of its area facing its outward axis (front and
    back, within ``facing_cos``) is no panel."""
    max_open_outline: float = 0.3
    """A door, drawer or lid whose outline, seen along its outward axis, is open to its edge over
    this share of its area or more is no panel: an open frame (a table's legs and apron)."""
    outline_cells: int = 64
    """... its outline is rasterised on a grid this many cells across its longer side."""
    side_panel_reach: float = 0.03
    """A door without a handle whose edge lies within this (m) of the edge of a door with one,
    beside it over half its height, is the carcass's control panel beside that door (a
    microwave's), not a door, when it is at most ``side_panel_narrow_share`` as wide ..."""
    side_panel_narrow_share: float = 0.35
    """... (no leaf of a pair of doors is a third of the other's width) ..."""
    side_panel_max_share: float = 0.5
    """... or at most this share as wide ...
    """
    side_panel_min_step: float = 0.01
    """... with its face this far (m) or more behind that door's face: French doors' leaves are
    about as wide and share one plane."""
    plinth_width_share: float = 0.97
    """A drawer with no grip whose front reaches across this share of the carcass's width at its
    height ..."""
    plinth_floor_tol: float = 0.01
    """... with nothing of the object more than this (m) below it ..."""
    plinth_below_share: float = 0.3
    """... but legs, in at most this share of ``plinth_columns`` columns across its width, is the
    carcass's plinth or bottom rail."""
    plinth_columns: int = 20
    worktop_min_share: float = 0.5
    """A lid with a door or a drawer facing the front under this share of that front's width or
    more is a worktop over them, not a lid."""
    min_lid_depth_share: float = 0.25
    """A lid less deep than this share of its width is a strip (a window frame's top bar seen
    alone from above), not the cover of a box."""
    min_flap_aspect: float = 0.6
    """A door turning about a horizontal hinge along an edge shorter than this share of the
    length it swings out is no flap (a dishwasher's door, among the tallest, is about 0.8)."""
    min_free_share: float = 0.25
    """A drawer that draws out less than this share of its own box before it collides is stuck:
    something passes through its front (a button's stem through a box's face)."""
    min_swing_deg: float = 5.0
    """A door or lid that collides before this angle (deg) on every hinge tried is stuck, not a
    panel that swings (the joint's limit is floored at ``joints.hinge_min_range_deg`` and does not
    show it): its confidence is 0 and the asset is not published."""
    min_panel_size: float = 0.03
    """A door, drawer or lid narrower than this in either direction of its face is no panel."""
    max_part_share: float = 0.9
    """A movable part at least this share of the whole object's size along every axis is the
    carcass (a segmentation that took the cabinet's shell for a door)."""
    enclosed_tolerance: float = 0.01
    """A part of its own pieces within this (m) of the carcass's box, behind its front, lies
    inside the carcass: never the carcass itself, however large."""
    min_pull_rows: int = 2
    """Front knobs in one column at this many heights or more are drawer pulls, not controls."""
    min_pull_spacing: float = 0.08
    """... whose heights lie at least this far apart (m): stacked drawers, not a keypad ..."""
    min_pull_spacing_share: float = 2.0
    """... and this many times the largest knob's size: a drawer is much taller than its pull,
    a stove's dials sit about a dial apart."""
    pull_align_tol: float = 0.01
    """Knob centres closer than this (m) along an axis share a row or a column."""
    rule_confidence: dict[str, float] = field(default_factory=lambda: {
        "motion video": 0.9, "hinge knuckles": 0.9, "opposite the handle": 0.85, "drawer": 0.8, "lid": 0.7,
        "knob": 0.6, "toggle": 0.6, "support": 0.6, "guess": 0.4, "hinged against its pair": 0.3,
        "hinged off its handle's far edge": 0.3, "lid on a long edge": 0.3, "no front shown": 0.3})
    """Confidence of a joint by the rule that made it (the part of the rule's name before ':'
    or ','); ``guess``: a hinge side chosen with no handle to go by; ``hinged against its
    pair``: a door of a pair in two tracks (``bypass_pairs``) that could not slide past the other;
    ``hinged off its handle's far edge``: a door whose edge opposite its handle could not swing,
    hinged on another; ``lid on a long edge``: a bare lid whose back edge is its short one, turned
    onto a long edge, which of the two a guess (``lid_long_edge_share``); ``no front shown``: on
    an object none of whose sides showed any relief (a plain box of boards), a bare door (which
    board is a door, and its hinge side, a guess) or a bare square lid (which of its four edges is
    the back, the file's guess)."""
    min_publish_confidence: float = 0.35
    """A joint whose confidence is below this is too doubtful to publish: the validator's
    structure check rejects the asset (a hinge side guessed for a door that then opens less
    than half its range)."""
    min_turn_confidence: float = 0.5
    """Where nothing moves on the side the relief chose for the front, another side becomes the
    front only when a part found there that is no lid (a lid opens upwards whatever the front)
    moves with at least this confidence: a handle, a drawer or a knob says so, not a hinge side
    guessed for a bare panel."""
    default_confidence: float = 0.5
    """Confidence of a joint made by a rule not in ``rule_confidence``."""
    open_weight: float = 0.3
    """Share of the confidence that depends on how much of its cap the joint opens freely."""
    open_grid: int = 9
    open_grid_share: float = 0.8
    """Rays per side of the grid cast inward through a door or drawer front (no_opening), over
    this share of its width and height."""
    open_ray_start: float = 0.001
    """The rays start this far (m) in front of the part."""
    min_opening_depth: float = 0.02
    """A ray finds room behind a panel when the carcass lies more than this (m) behind it ..."""
    opening_depth_share: float = 0.1
    """... or more than this share of the object's depth along the panel's facing, if larger."""
    min_open_share: float = 0.25
    """A door or drawer front with room behind less than this share of its face is a facade."""
    min_backed_share: float = 0.5
    """A drawer front with the object behind less than this share of its face (rays cast inward
    that meet nothing) stands free: nothing to draw out of."""
    below_probe_depth: float = 0.05
    """Points this far (m) behind a door's back face probe the room behind it (open_below) ..."""
    below_probe_drop: float = 0.02
    """Points this far (m) under a gripped drawer's bottom edge probe what lies in front below it
    (``open_front_below``) ..."""
    below_probe_reach: float = 0.1
    """... open when rays cast inward from them meet nothing within this far (m) of its face:
    knee room, not the next drawer, a rail or a plinth."""
    open_below_min_share: float = 0.5
    """... and a door without a handle whose room, closed at the back by the object, is open
    below (a ray straight down meets nothing) from at least this share of them is a board over
    knee room (a desk's frame beside its drawer), not a door: a door closes a compartment with a
    floor (a handle says door, whether or not the maker modelled the floor)."""
    drawer_body_share: float = 0.3
    """A drawer whose part reaches this share of the object's depth behind its front needs no
    room test: its own box is the cavity."""
    floor_control_share: float = 0.08
    """A knob or button whose top lies below this share of the object's height is a foot."""
    support_share: float = 0.5
    """A lone movable part holding at least this share of the floor area the object stands on
    is its support: it becomes the base and the rest (a panel of at least this share of its
    area) turns about the same hinge (a laptop standing open, whose keyboard was taken for a
    lid)."""
    support_rise_share: float = 0.5
    """On a fused surface, what is left of the object once the faces under the lone movable part
    go with it must rise above that part by this share of the object's height (a screen above
    its keyboard; the walls of a box beside its lid do not)."""
    floor_band: float = 0.005
    """Faces facing down within this (m) of the object's lowest point are what it stands on."""
    carried_tolerance: float = 0.002
    """A base piece under a movable part (inside its box grown by this (m), seen from above)
    moves with it (a keyboard's bottom plate under its top)."""
    frame_tolerance: float = 0.002
    """A door, drawer or lid whose box, grown by this (m), holds the box of another is the
    frame around it (a window's casing around its sashes), not a panel."""
    facing_cos: float = FACING_COS
    """A face faces a direction when its normal is within this cosine of it (the stages'
    ``rest2art.tolerances.FACING_COS`` unless set)."""
    plane_resolution: float = 0.001
    """Faces whose positions along a direction round to the same multiple of this (m) share a plane."""


@dataclass(frozen=True)
class SegmentConfig:
    """Part segmentation from rendered views (paper: Part Segmentation; camera table)."""

    enabled: bool = True
    """Segment the faces that piece structure leaves in the base (fused surfaces, scans)."""
    hierarchy_backend: str = "geometric"
    """Backend of the hierarchy role (part tree). Offline default: ``geometric``."""
    masks_backend: str = "geometric"
    """Backend of the masks role (instance masks per view and prompt). Offline default: ``geometric``."""
    image_size: int = 800
    """Rendered views are square, this many pixels."""
    fov_deg: float = 35.49
    """Horizontal field of view of the mesh-only camera."""
    camera_radius: float = 4.5
    """Camera distance on the normalised object (bounding sphere of radius 1)."""
    azimuth_deg: float = 30.0
    """Views span +-this azimuth around the front (-y)."""
    elevation_deg: tuple[float, float] = (15.0, 45.0)
    """Elevation range of the views."""
    azimuth_steps: int = 4
    """Azimuths in the rig; azimuth_steps x elevation_steps = N' views (paper: 12)."""
    elevation_steps: int = 3
    """Elevations in the rig."""
    cull_backfaces: bool = True
    """Skip back faces when the mesh's winding is consistent (double-sided otherwise)."""
    normal_edge_deg: float = 6.0
    """Neighbouring pixels whose normals differ more than this lie on a seam, groove or corner."""
    edge_stride: int = 3
    """Normals are also compared this many pixels apart (a groove on a scan is a few pixels wide)."""
    groove_depth: float = 0.0007
    """A pixel this much deeper or shallower (m) than its neighbours ``edge_stride`` away on
    both sides lies in a groove or on a ridge."""
    edge_close_px: int = 3
    """Breaks up to about twice this many pixels in an edge line are closed."""
    depth_edge_px: float = 8.0
    """Neighbouring pixels further apart in 3D than this many pixel footprints: an occlusion edge."""
    facet_coherence: float = 0.95
    """A region is a planar facet when the mean of its unit normals is at least this long."""
    parallel_deg: float = 20.0
    """Facets whose normals are this close are parallel (a seam between them separates parts)."""
    occlusion_gap: float = 0.05
    """Facets whose facing pixels are further apart than this (m) meet at an occluding edge."""
    adjacency_band_px: int = 6
    """Facets closer than this many pixels across an edge band are neighbours."""
    fold_groove_share: float = 0.5
    """Two neighbouring facets meeting at a convex fold are one body unless a groove
    (``seam_map``'s deeper pixels) lies on the way from one to the other along at least this
    share of their meeting edge: a door sunk in its carcass's frame beside the carcass's side,
    not a glazing bar's face beside the glass it stands on."""
    min_panel_size: float = 0.06
    """A movable panel is at least this wide and high (m)."""
    panel_max_thickness: float = 0.06
    """A rigid body of facets thicker than this along its main normal is the carcass."""
    lone_face_reach: float = 0.25
    """A face of a primitive no part's faces reach keeps the label lifting gave it, when it
    projects past that label's mask box in its best view by more than this share of the box's
    size, only if most of its pixels the label's views see lie in its masks (refine_labels)."""
    lid_min_thickness: float = 0.005
    """A panel facing up is a lid when its edge strips show this much thickness ..."""
    lid_max_thickness: float = 0.03
    """... or, seen alone, when a parting line runs under its front edge within this (m) ..."""
    lid_seam_share: float = 0.5
    """... along at least this share of its width. A front as large as the whole object's
    needs the same share of grooves on the sides beside it (its parting line)."""
    full_face_margin: float = 0.03
    """A front reaching this close (m) to the object's outline on every side covers the front."""
    mask_grow_px: int = 3
    """A panel's mask grows this many pixels into the edge band around it."""
    protrusion_min: float = 0.006
    """Pixels standing this far (m) proud of their panel's plane belong to a handle or knob."""
    protrusion_foot: float = 0.0015
    """... and, next to one, pixels standing this far (m) proud are its foot: the bottom of its
    side, which a scan fuses into the surface under it (``panels._foot``)."""
    foot_side_deg: float = 45.0
    """... when their surface turns this far (deg) or more off the surface's normal: the knob's
    side, not the surface around it."""
    frame_rings: bool = True
    """A panel whose face is sunk in a flat band all round it is a framed front's field, and the
    panel is the field and its frame (``panels.frame_ring``): the frames a scan leaves too narrow
    to be a facet (framed scans 130-141: 3 -> 5 of 12 right) ..."""
    ring_min_depth_share: float = 0.2
    """... in an object at least this share as deep (along its front's facing) as it is wide or
    tall: a thin one is a window in its frame, its glass sunk in its sash's bars as a field in
    its frame is, and the sashes' joining measures those bars itself (``join_sash_panes``). The
    generators' windows are 0.06-0.16 as deep as tall, their wardrobes 0.23 or more ..."""
    ring_step: tuple[float, float] = (0.002, 0.012)
    """A panel whose face is sunk between this little and this much (m) below a flat band all
    round it is a framed front's field, and the band its frame (``frame_rings``) ..."""
    ring_flat_tol: float = 0.0015
    """... the band flat to this (m) ...,"""
    ring_rise: float = 0.008
    """... reached within this (m) of the field's outline (a scan blurs the step) ..."""
    ring_max_share: float = 1.0
    """... at most this share of the field's smaller side wide ..."""
    ring_width_ratio: float = 2.0
    """... its widest side at most this many times its narrowest ..."""
    ring_outer_reach: float = 0.02
    """... and ended on every side by a parting line: a step up onto the carcass, or a dent
    (the gap to the carcass or a neighbour) that rises back to the band within this (m); a band
    that drops away and stays down ends at the object's edge or a neighbour's sunk face: the
    carcass's frame around an inset door, not a front's."""
    ring_split_max_gap: float = 0.15
    """Two coplanar facets up to this far apart (m), with nothing of a frame between them, are
    one field that a pull as tall as it (or a pocket) cuts in two when the two together have a
    frame all round (``panels._field_across_pull``)."""
    handle_beside_px: int = 3
    """A blob proud of a panel's plane that starts within this many pixels past its outline is
    its handle too (a bar mounted on a door's edge, a microwave's, stands beside its face, not
    on it) ..."""
    handle_beside_reach_px: int = 12
    """... looked for this many pixels out ..."""
    handle_beside_max_share: float = 0.9
    """... when what lies around it past the panel is mostly behind the panel's face (not a
    frame the panel is sunk into, nor a neighbour's face beside it) and it spans less than this
    share of the panel's width or of its height (not the edge of a neighbour or of the carcass
    beside it)."""
    coplanar_tol: float = 0.003
    """Two parallel facets whose planes are this close (m) may be one surface ..."""
    bridge_front_share: float = 0.3
    """... cut in two by a fitting standing in front of it, when at least this share of what
    lies between them stands proud of it (a knob as large as the strip it stands on) ..."""
    bridge_stray_share: float = 0.2
    """... and at most this share lies further than ``adjacency_band_px`` from what stands
    proud (a groove between two flush fronts runs past their handles)."""
    bridge_max_cross_share: float = 0.8
    """... and what stands proud is at most a knob across, or spans at most this share of the
    two facets' extent across the line between them (a cup pull with the drawer's face above
    and below it; a drawer proud between two boards spans them)."""
    protrusion_min_area: float = 0.0002
    """Smallest handle or knob footprint, m^2."""
    knob_max_size: float = 0.08
    """A round protrusion on the carcass at most this wide is a control knob ..."""
    knob_min_roundness: float = 0.6
    """... round when its footprint's smaller side is at least this share of its larger one
    (a bar is not)."""
    sloped_min_deg: float = 10.0
    """A carcass face whose normal lies this far (degrees) or more from every axis is sloped (a
    stove's backsplash): what stands proud of it is measured from its own plane, not the nearest
    axis's."""
    min_view_cos: float = 0.2
    """A pixel's surface area is its footprint over the cosine between the view ray and the
    normal, that cosine floored at this (grazing pixels would weigh without bound)."""
    outline_percentile: float = 0.5
    """A view's outline is the box of its surface points without this percentage at each end
    (a stray far point must not widen it)."""
    recess_max_share: float = 0.1
    """A pocket sunk ``protrusion_min`` into a panel's face, inside its outline, is a recessed
    handle when its footprint is at most this share of the panel's (a larger sunk area is a
    window or a frame-and-panel centre)."""
    fused_handle_min_length: float = 0.02
    """A bar on a carcass facet at least this long (m) is a handle telling a door or drawer
    fused with the carcass (a scan closes the seam of a front flush with its sides) ..."""
    fused_handle_max_share: float = 0.9
    """... when it spans at most this share of the facet along its length ..."""
    fused_handle_max_proud: float = 0.15
    """... stands at most this far (m) out of it ..."""
    fused_handle_surround: float = 0.6
    """... and at least this share of the pixels around it lie on that facet."""
    tab_contact: float = 0.003
    """A handle over a front that comes this close (m) to a top seen alone hangs on the lid's
    edge (a box lid's tab): it cuts no door out of the front below."""
    fused_handle_row_tol: float = 0.25
    """Handles on one fused facet whose centres differ by at most this share of the facet's
    height (width) stand in a row (a column): the facet splits between them."""
    fused_handle_alike_ratio: float = 1.5
    """A front found as one panel that carries two bar handles or more (none round by
    ``knob_min_roundness``), each one's footprint within this ratio of the others' both ways, in
    a row or a column, splits between them the same way (the seams of a chest's drawer fronts a
    few millimetres apart close on a fused scan)."""
    fused_pair_max_offset: float = 0.25
    """Two alike knobs at one height on one front are a pair of doors' pulls, and split it the
    same way, when each is within this share of its width of its middle ..."""
    fused_pair_mirror_tol: float = 0.05
    """... mirrored about it to this share of its width ..."""
    fused_pair_min_height_share: float = 0.5
    """... on a front at least this share as tall as it is wide (``parts.grips.meeting_pair``)."""
    fused_inner_share: float = 0.8
    """A panel lying this much inside a fused front found by its handle is part of that front."""
    drawer_min_aspect: float = 1.3
    """A panel without a telling handle is a drawer when width / height reaches this ..."""
    drawer_max_height: float = 0.4
    """... and it is at most this tall (m)."""
    handle_side_offset: float = 0.25
    """A panel whose handle sits at least this share of its width off its centre, or is a vertical
    bar, is a door (hinged on the far side) ..."""
    handle_top_offset: float = 0.28
    """... one whose handle sits this share of its height above its centre, a flip-down door ..."""
    handle_top_max_offset: float = 0.6
    """... up to this share (past 0.5 the handle's centre lies above the panel's top edge: a pull
    on a lip; further up, the view cut the panel short at its pull, and the handle says nothing
    of where the panel hinges) ..."""
    handle_centred: float = 0.15
    """... and one whose handle sits within this share of its width of its centre, a drawer."""
    pull_mirror_tolerance: float = 0.05
    """Two fittings off a panel's middle are a drawer's pair of pulls when they mirror each other
    about its vertical middle line to this share of its width and height."""
    bar_vertical_ratio: float = 1.5
    """A handle at least this many times taller than wide is a vertical bar."""
    stack_edge_tolerance: float = 0.05
    """Fronts one above the other are a column when their left and right edges agree to this
    share of the narrower one's width ..."""
    stack_max_gap: float = 0.5
    """... the gap between them is at most this share of the taller one's height (a rail, or a
    pull's plate along the top edge) ..."""
    stack_max_height_ratio: float = 2.0
    """... and the taller is at most this many times as tall as the other (graduated drawers; not
    an oven's door over its drawer)."""
    stack_handle_tolerance: float = 0.1
    """Handles of fronts in a column sit in the same place when their offsets from their fronts'
    centres agree to this share of width and height."""
    twin_max_height_ratio: float = 1.25
    """A bare front in a column with a door handled at its side, the taller of the two at most this
    many times as tall as the other, is that door's twin: a door too (``classify_panels``)."""
    mask_scores: dict[str, float] = field(default_factory=lambda: {
        "lid": 0.9, "handle at a side": 0.9, "handle at the top": 0.7, "handle centred": 0.85, "proportions": 0.6,
        "stacked": 0.8, "fitting": 0.8})
    """The geometric masks backend's score of each instance, by the evidence it rests on."""
    top_k_views: int = 4
    """Evidence lifting uses each panel's K best views ..."""
    top_k_views_small: int = 12
    """... and each knob's, handle's or button's this many: no single view sees a small part's
    sides to its foot, and its masks (what stands proud of its surface) hold nothing else."""
    corefine_rounds: int = 2
    """Co-refinement rounds between the hierarchy and the masks (paper: at most 2)."""
    min_view_support: float = 0.6
    """A panel must be detected in at least this share of the views that see it ..."""
    min_view_support_small: float = 0.5
    """... a knob or handle (small, often hidden at grazing angles) in this share."""
    agreement_iou: float = 0.5
    """A point-prompted mask confirms a cached one when their IoU reaches this."""
    track_overlap_share: float = 0.3
    """Without a point prompt, an instance joins a part when they share this share of the
    smaller one's faces."""
    fused_instance_cover: float = 0.5
    """An instance of a part holding this share of a neighbouring part's core seen in its
    view sees the two as one (a seam the view missed) and is dropped from its part when the
    neighbour was found in more views (``segment.drop_fusing_instances``)."""
    fused_instance_overlap: float = 0.2
    """... a neighbour: the two parts' cores share less than this share of the smaller."""
    nested_instance_share: float = 0.8
    """A panel part never found in a view with the one panel part holding this share of its
    core joins it (a shaker door's sunk middle; ``segment.join_nested_tracks``)."""
    graph_refinement: bool = True
    """Run graph refinement after lifting (off only for ablations)."""
    strip_concave_stop_deg: float = 10.0
    """A panel's edge strips are grown over the mesh across convex edges and concave ones below
    this angle; a carcass corner or groove stops them."""
    strip_outline_margin: float = 0.02
    """Grown strips stay inside the panel's outline seen from the front, grown by this (m)."""
    strip_groove_radius: float = 0.008
    """Strips stop at faces lying ``groove_depth`` below their surroundings within this radius (m)."""
    strip_frontal_cos: float = 0.7
    """A panel's front, where its strips start, is its faces whose normal has at least this
    cosine with the panel's."""
    strip_ridge_facing: float = 0.3
    strip_ridge_behind: float = 1.5
    """On a strip, a face facing sideways (|cosine with the panel's normal| below this), lying
    ``groove_depth`` above its surroundings and more than this many ``strip_groove_radius``
    behind the front, is a ridge: the seam to a coplanar carcass side."""
    strip_even_excess: float = 0.015
    """A panel is one thickness all round: a strip reaches at most this (m) deeper than the
    shallowest strip running along most of any of the panel's edges
    (``strip_even_min_cover``). A door whose side is flush with the carcass's, the seam between
    them closed by a scan, would otherwise take the carcass's side down to
    ``panel_max_thickness``."""
    strip_even_min_cover: float = 0.5
    """... strips spanning at least this share of their edge's length (the extent of their
    faces along it) ..."""
    strip_even_min_depth: float = 0.005
    """... and reaching at least this far (m) behind the front (a shallower one is a rim or a
    sliver in the front's plane, not a side)."""
    strip_island_share: float = 0.01
    """A base island smaller than this share of the faces, left inside one panel's strips,
    joins the panel."""
    panel_back_margin: float = 0.008
    """A panel's back lies within this (m) of the deepest point its strips reach (a fused slab's
    rounded back edge): the back of a door standing free in a frame is the door's ..."""
    panel_back_outline_margin: float = 0.002
    """... out to this (m) outside the strips' outline, where the rounded edge turns."""
    fused_piece_share: float = 0.95
    """A mesh whose largest connected piece holds this share of its faces is one fused surface
    (a scan, a few islands aside): its edge strips grow as a fused panel's, and a front on that
    piece as large as the object's needs a parting line on its sides."""
    corefinement: bool = True
    """Run the co-refinement loop and point-prompt checks (off only for ablations)."""


@dataclass(frozen=True)
class JointsConfig:
    """Joint estimation by rules, checked against the mesh."""

    door_limit_deg: float = 90.0
    """Cap on a door/lid opening when no collision stops it earlier."""
    appliance_door_limit_deg: float = 110.0
    """Cap for fridge and microwave doors."""
    plunger_min_ratio: float = 1.0
    """A knob cut out of a surface that stands out more than this times its width is a stick:
    a plunger, pushed in along its axis by half of how far it stands out, when it has a head
    (``plunger_head_growth``); else a lever ..."""
    plunger_head_growth: float = 1.5
    """... a head: the stick's widest section near its tip (``stick_tip_levels``) is at least
    this many times its narrowest along its shank (``stick_shank_levels``): a nail, a pull
    knob. A stick as wide to its tip swings about the wider side of its shank's section at its
    foot (a lever standing out of a panel)."""
    stick_shank_levels: tuple[float, ...] = (0.4, 0.5, 0.6)
    """Sections across a stick at these shares of how far it stands out: its shank ..."""
    stick_tip_levels: tuple[float, ...] = (0.8, 0.9, 0.97)
    """... and its tip."""
    stick_lean_deg: float = 12.0
    """A stick whose long axis leans at least this far (deg) off its surface's normal swings in
    the plane it leans in (a toggle switch)."""
    knob_limit_deg: float = 270.0
    """Range of a control knob."""
    lever_foot_probe: float = 0.0005
    """Height (m) above a control's lowest point along its outward axis of the section that
    shows its foot: a drum lying on its surface meets it along a line (``drum_foot``)."""
    lever_drum_probe: float = 0.004
    """Height (m) of the second section, where a drum has widened and a flat foot has not."""
    lever_foot_line: float = 0.5
    """A foot at most this narrow for its length (at ``lever_foot_probe``) is a line."""
    lever_foot_full: float = 0.9
    """The line is as long at ``lever_foot_probe`` as at ``lever_drum_probe`` (this share or
    more): the side of a drum, not a slanted cut through a flat foot."""
    lever_drum_growth: float = 1.5
    """A drum's section widens at least this much from the first probe to the second."""
    lever_drum_centred: float = 0.25
    """... on both sides of its line: the line's middle lies within this share of the wider
    section's width of that section's middle (a sliver of the surface round the foot, cut
    with a scanned lever at one end of its drum, is no line under it)."""
    lever_min_height: float = 2.0
    """A lever stands out at least this many times its foot's length (a bar knob lying on its
    surface does not)."""
    lever_limit_deg: float = 90.0
    """Cap on a lever's swing about its drum."""
    lever_min_swing_deg: float = 10.0
    """A headless stick that swings less than this about its foot before it meets the rest of
    the object (too thick at its foot for its length) is pushed in as a plunger, not swung."""
    drawer_max_depth_ratio: float = 0.9
    """Drawer travel is at most this fraction of the carcass depth."""
    carcass_band: float = 0.08
    """The carcass front is looked for within this depth of its outermost point (m)."""
    sweep_margin: float = 0.002
    """The swept part is shrunk inward by this much (m) so that resting contact is not a collision."""
    sweep_max_margin: float = 0.006
    """Where the part shrunk by ``sweep_margin`` still meets the rest at rest, the shrink doubles,
    up to this (m): a front sunk a few millimetres into its carcass (3 mm stopped an oven's door
    at once on every hinge)."""
    sweep_steps: int = 12
    """Samples of an opening when checking it for collisions."""
    sweep_max_step: float = 0.01
    """No point of a part moves more than this (m) between two samples of its opening sweep
    (more samples than ``sweep_steps`` where needed): a door swung in 7.5 degree steps jumped
    over a 13 mm panel in front of it."""
    sweep_seam_radius: float = 0.005
    """Where a part shares mesh edges with another (a fused scan), both lose the faces within
    this distance (m) of that seam for the sweep: the seam is ragged, and its teeth would stop
    every hinge in its first degree."""
    handle_offset_min: float = 0.12
    """A handle offset from the panel centre by less than this fraction is 'centred'."""
    lid_long_edge_share: float = 0.8
    """A lid with no grip hinges on a long edge: where the back edge the frame gives it is
    shorter than this share of its side edges, nothing on any side told the front (a closed
    laptop or a plain box turned in its file), and the hinge goes on a side edge, a guess."""
    fitting_contact: float = 0.002
    """Fittings standing proud of a panel this close (m) to each other are one fitting (a bar
    pull and its posts) when the grip is chosen among them."""
    handle_max_proud: float = 0.1
    """A handle fused with its panel stands at most this far (m) in front of the panel's face."""
    handle_max_share: float = 0.2
    """... and covers at most this share of the panel's area ..."""
    handle_max_span: float = 0.9
    """... and is no strip along one of its edges, running this share of its width or height ...
    """
    handle_edge_band: float = 0.015
    """... within this (m) of that edge: the rim of a neighbour cut with a fused panel, not a grip
    (a bar handle the length of a short door stands further in)."""
    handle_min_proud: float = 0.003
    """A piece, or a patch of a fused panel, standing more than this (m) in front of the panel's
    face is a handle."""
    handle_min_area: float = 0.00005
    """A fused panel's proud patch is a handle when it covers this much area (m^2) or more: not
    one facet of a scan standing out at a corner where two fronts meet (0.1 cm^2 on a scanned
    wardrobe door; the smallest knob's face shows 4.5 cm^2) ..."""
    handle_min_height: float = 0.008
    """... and its outermost facet stands this far (m) or more in front of the panel's face: a
    grip stands out by a finger's width (knobs, bars, edge pulls, 2 cm and more), a scan's steps
    along a flush front's rim by a few millimetres (3.6 mm on a scanned wardrobe's doors)."""
    pocket_depth: tuple[float, float] = (0.002, 0.03)
    """A recessed pull: faces of a panel without a handle sunk between these depths (m) below its
    face's plane ..."""
    pocket_min_area: float = 0.00005
    """... covering this much area (m^2) or more: a patch, not one facet of a scan sunk at a
    corner of the panel (0.08 cm^2 on a scanned wardrobe door; a lock's recess on a scanned
    door shows 1.75 cm^2)."""
    pocket_min_width: float = 0.01
    """... and this wide (m) or more across its narrower in-plane side: a finger enters it. A
    sliding cabinet's bottom rail, scanned, shows a ledge 5 mm high under its back door, 63 cm
    long, sunk behind the rail's face; recessed pulls on scans measure 1.5 cm across and more,
    a lock's recess 3 cm."""
    overlay_tolerance: float = 0.001
    """A panel whose back lies at most this far (m) behind the carcass front is an overlay panel
    (hinged on its own back edge), not one inset in the opening."""
    outline_tolerance: float = 0.005
    """A side edge of a door cut out of a fused surface within this distance (m) of the object's
    outline has no carcass beside it: the door hinges there on its back face."""
    hinge_min_range_deg: float = 5.0
    """A hinge's upper limit never goes below this, even where its sweep collides earlier."""
    fridge_min_height: float = 1.2
    """An object whose only movable parts are doors is guessed a fridge from this height (m) up."""
    drawer_front_max_thickness: float = 0.05
    """A drawer's front piece deeper than this (m) is front and box in one piece: its travel is
    the whole depth behind the front, not that depth less the piece's own."""
    slide_min_share: float = 0.3
    """A door whose every hinge collides early slides in its plane when it travels at least
    this share of its width that way before colliding (sliding doors and sashes run in tracks
    that stop any swing)."""
    bypass_min_step: float = 0.008
    """Two doors side by side (or one above the other) whose faces lie this far (m) or more
    apart along their outward axis run in two tracks: each slides past the other (bypass
    sliding doors, a sash over a sash); hinged doors side by side share one plane..."""
    bypass_max_step: float = 0.08
    """... at most this far (m) apart ..."""
    bypass_max_gap: float = 0.01
    """... and meeting (or overlapping) along their common edge within this (m) ..."""
    bypass_min_overlap: float = 0.8
    """... along at least this share of the shorter one's length there ..."""
    bypass_min_width_share: float = 0.5
    """... the narrower at least this share of the wider's width across that edge."""
    track_lip_reach: float = 0.03
    """An edge of a door runs in a track when rays cast outward from just inside it hit the
    carcass within this distance (m): the front wall of a groove or a window frame's stop."""
    track_edge_inset: float = 0.0005
    """Those rays start this far (m) inside the part's outline and in front of its back."""
    track_rays: int = 9
    """Rays per edge."""
    track_span: tuple[float, float] = (0.15, 0.85)
    """Rays along an edge (and across a door's height) are spread over this span of it (fractions)."""
    slide_span: tuple[float, float] = (0.1, 0.9)
    """Rays looking for the room a sliding door runs into are spread over this span of its width
    past the edge (fractions)."""
    track_min_share: float = 0.6
    """Share of an edge's rays that must hit a lip."""
    foot_contact: float = 0.01
    """A panel standing free (a screen, a sash) stands on an edge whose points, halfway through
    its thickness over ``track_span`` of it, lie within this distance (m) of the rest of the
    object on at least ``track_min_share`` of them (``foot_edge``)."""
    slide_face_depth: float = 0.03
    """A door in front of an opening slides towards the edge its handle is far from when, past
    that edge, a closed front as wide as the door lies at most this far (m) behind its back
    (the room it slides into; a hinge there would stand in the middle of a wall). Rays on a
    ``track_rays`` square grid, ``track_min_share`` of them hitting, test both the closed front
    and the opening behind the door (hits further than this behind its back, or none)."""
    leaf_depth_tolerance: float = 0.02
    """The stiles and rails framing a door's panel (a frame-and-panel door built of pieces) lie
    within this much (m) of the panel's depth along its normal; they make one leaf with it, the
    extent its hinge is found from. A handle stands further out."""
    leaf_frame_share: float = 0.8
    """... and run this share of the panel's width or height or more along it (a tab on a lid's
    edge does not)."""
    knuckle_roundness: float = 0.7
    knuckle_min_aspect: float = 2.0
    knuckle_tolerance: float = 0.008
    knuckle_max_share: float = 0.25
    """A door's hinge knuckles or pins: rods at least ``knuckle_min_aspect`` times longer than
    wide, as round across as ``knuckle_roundness``, no wider than ``knuckle_max_share`` of the
    door (the carcass is no pin), along an edge of the door with their axis
    within their radius plus ``knuckle_tolerance`` (m, the few millimetres a door clears its
    frame by) of its line. Knuckles on one edge make it the hinge; either edge turns about its pin."""
    knuckle_single_share: float = 0.6
    knuckle_single_offset: float = 0.15
    """One rod alone along an edge, shorter than ``knuckle_single_share`` of it and more than
    ``knuckle_single_offset`` of it off its middle, is a bar handle by the edge, not a knuckle:
    hinges come in pairs, or one runs the edge (a piano hinge, a post) or sits in its middle (a
    laptop's barrel)."""
    slot_pull_step: float = 0.001
    """A handle in a slot whose tip is sunk into the slot's back is swept drawn out of it by
    the least whole number of these (m) that frees it."""
    pane_gap: float = 0.01
    """Two panes meet as a sliding window's sashes when the plane of one lies at most this far
    (m) behind the other's back and, seen from the front, they meet along an edge: the front
    one slides over the one behind (sashes run in adjacent tracks)."""
    pane_touch: float = 0.005
    """... they meet along an edge when the gap between them across it is at most this (m) ..."""
    pane_meeting_overlap: float = 0.25
    """... or they overlap across it by at most this share of the front pane's size (a meeting
    rail laps over the other) ..."""
    pane_edge_share: float = 0.8
    """... and along it they share at least this share of the longer pane's length."""
    pane_min_flatness: float = 2.5
    """Panes slide over one another (``pane_behind``, ``pane_max_stagger``) only in an object at
    least this many times as wide or tall as it is deep along their facing: a window's sashes
    run in a thin frame, while a step behind a cabinet's door, half a metre deep, lies the back
    of an open compartment beside it, seen through the opening."""
    pane_max_stagger: float = 0.08
    """Two panes cut from one fused surface (a scan shows only their fronts) are a sliding
    window's sashes when the front plane of one lies ``pane_touch`` to this (m) behind the
    other's (the front sash's thickness and the gap between the tracks) and, seen from the
    front, they meet along an edge as above, the gap between them across it at most that
    stagger (the meeting rail's top, between the two fronts, may go to neither)."""
    sash_bar_ring: float = 0.015
    """The bars around a scanned sash's pane (its stiles and rails) are read off the frame's
    surface within this distance (m) outside the pane's outline."""
    sash_opening_rays: int = 5
    """A window frame's opening around two scanned sashes is found by rays from this many points
    a side of a grid over the front pane (``sash_opening``)."""
    sash_jamb_margin: float = 0.002
    """... and lies this far (m) inside the jambs the rays meet: their faces stay with the frame."""
    sash_track_depth: float = 0.005
    """A scanned sash's faces this close (m) to its edges across its slide run in the frame's
    grooves, fused to them by the scan: they are left out of its sweep."""
    sash_probe_step: float = 0.001
    """Where a scanned front sash ends over the pane behind it is probed every this far (m)
    (``meeting_reach``)."""
    sash_pane_fill: float = 0.7
    """Panes in one plane are one sash's, between its glazing bars, when they fill at least this
    share of their joint outline (``join_sash_panes``)."""


@dataclass(frozen=True)
class CompletionConfig:
    """Solidification of open shells and physical properties."""

    thickness: float = 0.015
    """Inward offset delta of an open shell (paper: 0.015 m)."""
    thickness_floor: float = 0.0005
    """Never thinner than this."""
    thickness_gap_share: float = 0.45
    """... and never thicker than this share of the distance to the nearest other piece, so
    that two pieces' solids do not meet."""
    boundary_smoothing_rings: int = 3
    """Edge rings along a cut boundary whose offset normals come from the interior (a ragged
    cut edge would otherwise push the inner wall sideways into the neighbouring part)."""
    cap_semantics: tuple[str, ...] = ("knob",)
    """Parts of these classes are closed across their rim (they sit on the surface they were
    cut from) before falling back to thickening, which would push them into the carcass."""
    tray_scale: float = 0.75
    """A drawer's tray is this fraction of its front's width and height (paper: 0.75)."""
    tray_min_depth: float = 0.045
    """A drawer deeper than this along its slide already has a box: no tray is added."""
    tray_clearance: float = 0.005
    """Gap left between the tray and the inside of the carcass back (m)."""
    density: dict[str, float] = field(
        default_factory=lambda: {
            "base": 600.0, "door": 500.0, "drawer": 500.0, "lid": 500.0, "knob": 1200.0,
        }
    )
    """kg/m^3 per semantic class (particle board ~600, knobs plastic)."""
    min_mass: float = 0.01
    """Lower bound on a part's mass (kg)."""
    min_inertia: float = 1e-6
    """Lower bound on a principal inertia (kg m^2); MuJoCo rejects tiny values."""


@dataclass(frozen=True)
class CollisionConfig:
    """Collision geometry: convex hulls, CoACD for concave pieces."""

    convexity_ratio: float = 0.92
    """A piece whose volume is at least this fraction of its hull's uses the hull directly."""
    coacd_threshold: float = 0.03
    """CoACD concavity threshold (fraction of the piece's size)."""
    coacd_max_hulls: int = -1
    """CoACD hull budget per piece (-1: as many as the threshold needs)."""
    coacd_mcts_iterations: int = 50
    """CoACD tree-search iterations (library default 150; 50 is 3x faster, as tight here)."""
    coacd_mcts_nodes: int = 10
    """CoACD tree-search children per node (library default 20)."""
    coacd_merge: bool = False
    """Merge hulls after decomposition (slow; only needed to meet a hull budget)."""
    coacd_remesh_open: bool = True
    """Remesh (CoACD preprocess) pieces that are not watertight; watertight solids are used as
    they are, which is much faster and keeps thin walls thin."""
    coacd_max_faces: int = 10000
    """Solids with more faces are decimated before CoACD (an open shell is decimated to half this
    and thickened again when the solid does not decimate cleanly)."""
    hull_only_size: float = 0.06
    """Parts no larger than this (m, largest extent: knobs, small handles) collide as their convex
    hull; CoACD would cut a thickened scan knob into a hundred slivers."""
    min_hull_volume: float = 1e-9
    """Hulls smaller than this (m^3) are dropped; MuJoCo refuses near-flat meshes."""
    coacd_timeout_s: float = 15.0
    """A CoACD run longer than this is killed (and not run again with the same input and
    parameters) and V-HACD decomposes the piece. Over the real development set's scans a
    finished run took at most 4.3 s, except two 10,000-face open scan shells (21 s, now
    V-HACD's); the runs that did not finish in 30 s (a burner grate: 322 hulls in 21 s alone,
    a lock's knob, a microwave carcass refined finer) make hundreds of hulls that the budget
    merges away, where V-HACD takes 0.6 to 1.2 s."""
    vhacd_fallback: bool = True
    """When CoACD gives nothing for a concave piece (timed out, failed, only slivers), V-HACD
    (PyBullet's, voxel-based: its time is bounded by ``vhacd_resolution``) decomposes it before
    boxes or one hull stand in."""
    vhacd_resolution: int = 100_000
    """V-HACD voxels per piece (its time and detail grow with it)."""
    vhacd_concavity: float = 0.0025
    """V-HACD's largest concavity left in a hull (a share of the piece's size)."""
    vhacd_timeout_s: float = 30.0
    """A V-HACD run longer than this is killed, as CoACD's."""
    strategy: str = "boxes"
    """How concave pieces are decomposed: "boxes" (boards aligned with the object's frame as
    boxes where they fit, CoACD for the rest) or "coacd" (CoACD for every concave piece)."""
    box_pitch: float = 0.005
    """Grid cell (m) on which a piece is sampled for boxes."""
    box_max_cells: int = 4_000_000
    """Most grid cells per piece; the cell grows for large pieces."""
    box_min_fill: float = 0.3
    """A cell at least this share inside the piece is occupied (a 2 mm wall on 5 mm cells is)."""
    box_layer_share: float = 0.8
    """A box grows by a layer of cells only when this share of them is occupied (a floor does
    not grow up through a cavity whose thick walls fill the layer on average)."""
    box_min_share: float = 0.01
    """A box adding less than this share of the occupied cells is left out (rounded edges) ..."""
    box_edge_cells: int = 1
    """... unless it reaches more than this many cells beyond the larger boxes (a handle)."""
    box_surface_cells: float = 1.5
    """Surface standing out of a part's boxes by more than this many cells, beyond their
    outline, gets convex hulls of its own (a fused scan's handle is too thin a shell to fill
    cells); 0 turns this off."""
    box_surface_samples: int = 4000
    """Surface points (beside the vertices) tested against the boxes."""
    box_surface_panel_ratio: float = 0.35
    """... only on a panel (a door's or drawer's board: its boxes' outline at most this share as
    thick as its median extent), and only out along its normal (a scan's rim spreads sideways)."""
    box_min_covered: float = 0.8
    """Boxes are used when they hold at least this share of the piece's volume (a fused scan's
    rounded edges, which no board holds, are 10 to 15 % of a thickened shell) ..."""
    box_max_count: int = 32
    """... with at most this many boxes (when no hull budget is given) ..."""
    box_merge_factor: float = 2.0
    """... or up to this many times as many, merged down to it by least added volume ..."""
    box_merge_max_growth: float = 0.1
    """... when the merged hulls hold at most this share more space than the boxes (merging two
    walls across a cavity fills it)."""

    def __post_init__(self) -> None:
        if self.strategy not in ("boxes", "coacd"):
            raise ConfigError(f"collision.strategy: '{self.strategy}' is not one of: boxes, coacd")
    cache_dir: str = "~/.cache/rest2art/coacd"
    """Decompositions are cached here by a hash of mesh content and parameters."""
    clearance: float = 0.0005
    """Gap (m) left between two parts' hulls where overlapping hulls are clipped apart."""
    sibling_clearance: float = 0.0025
    """Gap (m) left between the hulls of two parts that move on joints of their own (two doors
    meeting in the middle), at rest and over their motions. PyBullet pads every convex shape by
    a 1 mm margin and a parent never collides with its child there, so siblings are the pairs
    that touch in it: closer than 2 mm, friction holds one door on the other."""
    solid_box_margin: float = 0.002
    """A part's hulls reach at most this far (m) past the box, along the object's axes, of
    the completed solids they stand for (``clearance.clip_to_solids``)."""
    speck_share: float = 0.02
    """A hull of a moving part at most this share of the part's extent long, within
    ``sibling_clearance`` of a sibling's hull at rest, is a speck of the seam between them and
    is dropped, not cut (``clearance.drop_specks``)."""
    clearance_max_depth: float = 0.03
    """Deepest overlap (m) that clipping removes: about twice the completion thickness; deeper
    means a wrong part or joint, left for the validator."""
    hinge_clearance_radius: float = 0.04
    """Over a revolute range, ancestor hulls are clipped only within this distance (m) of the
    axis: the strip a door's back edge sweeps next to its hinge."""
    clearance_sweep_samples: int = 24
    """Poses per revolute range at which the swinging part clears its ancestors."""
    slide_clearance_max_depth: float = 0.01
    """Along a drawer's run, its ancestors' hulls give way to the space its hulls sweep by at
    most this much (m), and only by planes parallel to the run: a scan fuses a drawer to the
    board beside it or to its opening's edge, the part boundary falls a few millimetres off
    and the hulls of both reach across it. Deeper, or across the run, is the validator's."""
    sibling_sweep_samples: int = 8
    """Poses per hinge when two moving siblings are checked for meeting in motion (the convex
    hull of a hull's poses over its range)."""


@dataclass(frozen=True)
class ExportConfig:
    """URDF / MJCF writing."""

    joint_damping: float = 0.5
    """Joint damping (N m s/rad or N s/m), at most what ``min_damping_time`` allows."""
    min_damping_time: float = 0.02
    """Damping never stops a joint faster than this time constant (inertia / damping, s): a
    knob of a few grams under the default damping makes explicit integrators (PyBullet) blow up."""
    joint_friction: float = 0.2
    """Minimum dry friction (frictionloss), N m or N."""
    friction_safety: float = 1.5
    """Friction is at least this times the gravity load on the joint at rest, so flip-down
    doors and lids do not swing open under their own weight."""
    joint_armature: float = 0.01
    """Added rotor inertia, keeps light parts stable."""
    max_hulls_per_part: int = 32
    """Collision hulls a part may have (more are merged by least added volume)."""
    max_hulls_per_asset: int = 128
    """Collision hulls the whole asset may have (hull count is simulation speed)."""
    max_hull_vertices: int = 64
    """Corners a collision hull may have."""
    revolute_effort: float = 50.0
    """URDF effort limit of a revolute joint (N m)."""
    prismatic_effort: float = 200.0
    """URDF effort limit of a prismatic joint (N)."""
    joint_velocity: float = 2.0
    """URDF velocity limit of every joint (rad/s or m/s)."""
    mjcf_timestep: float = 0.002
    """Simulation step the MJCF asks for (s); validation simulates at ``check.timestep``."""
    formats: tuple[str, ...] = ("urdf", "mjcf")
    """Documents written (``rest2art.export.formats``); validation loads the URDF and the MJCF,
    so both stay in the list when assets are validated."""


@dataclass(frozen=True)
class CheckConfig:
    """Load and gravity checks in the simulators."""

    gravity_seconds: float = 2.0
    """Length of the gravity test."""
    timestep: float = 0.002
    """Simulator step (s)."""
    limit_tol: float = 0.01
    """A joint may exceed its limit by this much (rad or m) before it counts as outside."""
    engines: tuple[str, ...] = ("mujoco", "pybullet", "sapien")
    """Engines to check."""


@dataclass(frozen=True)
class ValidateConfig:
    """The validation layer: FCL sweep, physics checks and the publish / refine / reject policy."""

    sweep_samples: int = 8
    """Samples per joint range (and for all joints together), the rest pose not counted."""
    max_penetration: float = 0.001
    """Deepest hull penetration (m) allowed between any two parts at any sampled pose."""
    rest_force_tol: float = 0.5
    """Constraint-force norm (N) allowed at the closed pose without gravity."""
    actuation_seconds: float = 1.5
    """Push open for this long, then push shut for this long."""
    actuation_reach: float = 0.8
    """Share of the range a pushed joint must reach (and come back below 1 - reach)."""
    actuation_margin: float = 1.5
    """Push force over what friction, gravity, damping and inertia need."""
    actuation_min_range: float = 0.001
    """A movable joint whose range is shorter than this (m or rad) cannot be judged by its
    share of the range: it fails as 'does not open'."""
    refine_rounds: int = 3
    """Refine-and-recheck rounds before an asset is rejected."""
    max_thin: float = 0.005
    """Deepest penetration (m) that refinement may remove by thinning a part's collision hulls
    (hull approximations bulge by millimetres); deeper means a wrong joint or part."""
    thin_margin: float = 0.0005
    """Extra inward offset (m) when hulls are thinned."""
    min_kept_range: float = 0.3
    """A limit may be shrunk to the last collision-free sample only while it keeps this share
    of its range; below it the joint is wrong, not just long."""
    redecompose_max_hulls: int = 100
    """A part with this many hulls or more is not decomposed again (it is slow and gives
    hundreds of slivers; the penetration lies elsewhere)."""
    redecompose_threshold_scale: float = 0.5
    """CoACD threshold factor when a part is decomposed again (finer hulls)."""


@dataclass(frozen=True)
class CatalogConfig:
    """Catalog builds (``rest2art catalog build``): per-object limits, pictures, the Ray backend.

    Nothing here changes a reconstruction, so this section is left out of the job key."""

    timeout_s: float = 1800.0
    """Wall time (s) one object may take in its worker process; past it the worker is killed
    and the object fails as timed out."""
    memory_limit_mb: int = 8192
    """Address-space limit (MiB) of each worker process (and of the CoACD runs it starts); an
    object that needs more fails as out of memory. A normal object peaks under 2 GiB."""
    render_size: int = 400
    """Closed and opened pictures of a published asset are this many pixels square."""
    thumbnail_size: int = 240
    """Each half of the catalog thumbnail (closed | opened) is this many pixels square."""
    animation_size: int = 240
    """Joint animations are this many pixels square."""
    animation_frames: int = 9
    """Frames from closed to the upper limit in a joint animation (it plays there and back)."""
    animation_frame_ms: int = 90
    """Time each animation frame is shown (ms)."""
    ray_num_cpus: float = 1.0
    """CPUs a Ray task asks for (one object, one process)."""
    ray_memory_mb: int = 2048
    """Memory a Ray task asks for (MiB): the scheduler places no more tasks on a node than fit."""
    ray_max_retries: int = 2
    """Times Ray runs an object again when its worker or node died (never for an error)."""


@dataclass(frozen=True)
class ArticulationConfig:
    """Joints from motion evidence (videos and their point tracks), judged against the mesh."""

    seeds: int = 2
    """R: videos per object, each with its own seed."""
    extra_seeds: int = 2
    """More videos when every part came out static in all R."""
    visibility_threshold: float = 0.5
    """Tracks are cut at the first frame with fewer visible points than this share of frame 0's."""
    erosion_fraction: float = 0.02
    """Track grid inside each part's mask eroded by this share of its bounding box's short side."""
    max_track_points: int = 300
    """Grid points per part (the grid spacing follows)."""
    overlay_alpha: float = 0.35
    """Opacity of the part masks on the video's conditioning image."""
    static_px: float = 2.0
    """A part whose median displacement is below this (and three times the track noise) is static."""
    cv_revolute: float = 0.3
    cv_prismatic: float = 0.15
    """Displacement CV at or above / at or below which the motion reads revolute / prismatic."""
    curvature_revolute: float = 0.08
    curvature_prismatic: float = 0.03
    """Path curvature at or above / at or below which the motion reads revolute / prismatic."""
    loss_scale_px: float = 1.5
    """Soft-L1 scale of the reprojection residuals, px."""
    max_frames: int = 20
    max_points: int = 150
    """Frames and points per video used by the fit."""
    coarse_frames: int = 8
    coarse_points: int = 50
    """Starting hypotheses are screened and fitted on this many frames and points per video;
    only the winner is refined on all used frames and points."""
    refine_best: int = 3
    """Starts whose per-frame-only fit is best go on to the full fit."""
    outlier_factor: float = 3.0
    outlier_floor_px: float = 2.0
    """Trimmed refit: points with median error above max(factor x median, floor) are dropped."""
    revolute_margin: float = 0.8
    """When both models are fitted, revolute wins only with an error below this share of the
    prismatic one (it has two more parameters)."""
    reach_factor: float = 2.0
    """A fitted hinge farther from the tracked points than this many times their extent is no
    hinge (the motion is a slide)."""
    grounded_min_share: float = 0.05
    """A grounded joint opens at least this share of its cap, even when every sweep is blocked."""
    snap_angle_deg: float = 10.0
    snap_distance: float = 0.05
    """A fitted joint within this angle and (revolute) axis distance (m) of a geometric
    candidate (a carcass edge or slide direction) snaps onto it."""
    blend_weight: float = 0.5
    blend_max_deg: float = 15.0
    """An unsnapped axis within this angle of the principal direction of the part's boundary
    with its parent is blended towards it with this weight."""
    boundary_distance: float = 0.006
    """Part points within this distance (m) of the parent form their shared boundary."""
    outward_band: float = 0.08
    """The side a part faces is the axis direction with the most of its area facing that way (normals
    within ``acos(outward_min_cos)``) within this distance (m) of the whole object's extreme."""
    outward_min_cos: float = 0.9
    video_backend: str = "none"
    """Backend of the motion video role: ``none`` (videos come from ``--motion-video`` folders)
    or ``wan2.2`` (image-to-video through diffusers, ``models.wan``)."""
    tracks_backend: str = "lucas_kanade"
    """Backend of the tracks role: ``lucas_kanade`` (offline) or ``cotracker3`` (``models.cotracker``)."""
    prompt_backend: str = "template"
    """Writer of the motion video's text prompt: ``template`` (offline), ``openai`` or ``qwen3vl``."""
    video_frames: int = 81
    """Frames per generated video (paper: 81)."""


@dataclass(frozen=True)
class OpenAIChatConfig:
    """A VLM behind an OpenAI-compatible chat-completions endpoint (GPT, or Qwen3-VL served by vLLM)."""

    base_url: str = ""
    """Endpoint, e.g. ``http://127.0.0.1:8000/v1`` for a local vLLM; empty: the ``openai`` client's
    default (``OPENAI_BASE_URL`` or OpenAI's own)."""
    model: str = "gpt-5.2"
    """Model name as the endpoint knows it."""
    api_key_env: str = "OPENAI_API_KEY"
    """Environment variable holding the key (the key itself is never read from a config file,
    logged or written beside an asset)."""
    temperature: float = 0.4
    """Sampling temperature (paper: 0.4)."""
    max_tokens: int = 2048
    """Longest answer."""
    timeout_s: float = 120.0
    """A request not answered within this many seconds fails."""
    views: int = 12
    """Rendered views asked for a tree, one request each; the tree with most parts is kept."""
    image_size: int = 512
    """Images are sent this many pixels square."""


@dataclass(frozen=True)
class Qwen3VLConfig:
    """Qwen3-VL run locally through transformers (hierarchy and video prompt)."""

    path: str = ""
    """Folder of the model (``config.json``, weights, processor files), e.g. Qwen3-VL-8B-Instruct."""
    device: str = "auto"
    """``auto`` (CUDA when available), ``cpu``, ``cuda`` or ``cuda:N``."""
    dtype: str = "auto"
    """``auto`` (bfloat16 on CUDA, float32 on CPU), ``float32``, ``bfloat16`` or ``float16``."""
    max_new_tokens: int = 1024
    """Longest answer."""
    temperature: float = 0.4
    """Sampling temperature; 0 decodes greedily."""
    views: int = 12
    """Rendered views asked for a tree; the tree with most parts is kept."""
    image_size: int = 512
    """Images are given this many pixels square."""


@dataclass(frozen=True)
class Sam3Config:
    """SAM3 through transformers (masks role)."""

    path: str = ""
    """Folder of the model (``config.json``, weights, tokenizer files), e.g. facebook/sam3."""
    device: str = "auto"
    """``auto``, ``cpu``, ``cuda`` or ``cuda:N``."""
    dtype: str = "auto"
    """``auto``, ``float32``, ``bfloat16`` or ``float16``."""
    score_threshold: float = 0.5
    """Instances scoring below this are dropped."""
    mask_threshold: float = 0.5
    """Mask probabilities above this are inside."""
    image_size: int = 1008
    """The model's input size when the folder has no ``preprocessor_config.json``."""


@dataclass(frozen=True)
class WanConfig:
    """Wan2.2 image-to-video through diffusers (motion video role)."""

    path: str = ""
    """Folder of the diffusers pipeline, e.g. Wan2.2-I2V-A14B-Diffusers."""
    lora_paths: tuple[str, ...] = ()
    """LoRA files loaded into both transformers (paper: VBVR and the step-distillation ones)."""
    lora_scale: float = 1.0
    """Strength of every LoRA (paper: 1.0)."""
    device: str = "auto"
    """``auto``, ``cpu``, ``cuda`` or ``cuda:N``."""
    dtype: str = "auto"
    """``auto``, ``float32``, ``bfloat16`` or ``float16``."""
    size: int = 960
    """Videos are made this many pixels square (paper: 960), then resized to the view."""
    steps: int = 4
    """Denoising steps (paper: 4 with the distillation LoRA; about 40 without it)."""
    guidance_scale: float = 3.5
    """Classifier-free guidance (paper: 3.5)."""
    negative_prompt: str = ""
    """Negative prompt; empty: none."""
    cpu_offload: bool = False
    """Move each model to the GPU only while it runs (saves memory, needs accelerate)."""


@dataclass(frozen=True)
class CoTrackerConfig:
    """CoTracker3, not on PyPI: a local checkout and checkpoint, or a TorchScript export."""

    path: str = ""
    """A TorchScript file (``.pt``) called as ``model(video, queries) -> (tracks, visibility)``,
    or the folder of a co-tracker checkout (its ``cotracker`` package)."""
    checkpoint: str = ""
    """Checkpoint of a checkout, e.g. scaled_offline.pth (unused for TorchScript)."""
    device: str = "auto"
    """``auto``, ``cpu``, ``cuda`` or ``cuda:N``."""
    visibility_threshold: float = 0.5
    """A model that returns visibility as a probability: points above this are visible."""


@dataclass(frozen=True)
class ModelsConfig:
    """Where the model backends find their weights and how they run (``rest2art models check``)."""

    openai: OpenAIChatConfig = field(default_factory=OpenAIChatConfig)
    qwen3vl: Qwen3VLConfig = field(default_factory=Qwen3VLConfig)
    sam3: Sam3Config = field(default_factory=Sam3Config)
    wan: WanConfig = field(default_factory=WanConfig)
    cotracker: CoTrackerConfig = field(default_factory=CoTrackerConfig)


@dataclass(frozen=True)
class PolicyConfig:
    """The scripted policy of the environments: approach, grasp, pull along the joint, release."""

    pregrasp_distance: float = 0.08
    """Stand-off (m) along the grasp normal from which the gripper comes in."""
    clearance_distance: float = 0.25
    """The gripper first comes down over a point this far (m) out along the grasp normal, so that
    it passes round open doors and lids."""
    clearance_tol: float = 0.04
    """Those first waypoints count as passed within this distance (m)."""
    reach_tol: float = 0.01
    """The gripper is at a waypoint when within this distance (m)..."""
    reach_angle_deg: float = 8.0
    """... and this angle of its orientation."""
    press_depth: float = 0.004
    """How far past the surface (m) the fingertips are driven when pressing a flat face."""
    grip_steps: int = 8
    """Control steps spent closing the fingers before pulling."""
    lead: float = 0.12
    """The commanded joint value runs at most this share of the range ahead of the measured one."""
    overshoot: float = 0.12
    """Pull this share of the range past the target, so that the part stays past it after release."""
    release_steps: int = 6
    """Control steps spent opening the fingers and backing off."""
    waypoint_steps: int = 20
    """An approach waypoint is given up when the gripper got no closer to it (by 5 mm) in this
    many control steps."""


@dataclass(frozen=True)
class EnvConfig:
    """Gymnasium environments on MuJoCo: scene, floating gripper, reward, randomisation."""

    timestep: float = 0.002
    """Physics step (s)."""
    control_dt: float = 0.04
    """Time per environment step (s): control_dt / timestep physics steps."""
    max_steps: int = 250
    """Steps before an episode is truncated."""
    max_translation: float = 0.025
    """Largest gripper translation per step (m), for an action of 1."""
    max_rotation_deg: float = 10.0
    """Largest gripper rotation per step, for an action of 1."""
    target_fraction: float = 0.8
    """Open: success when the joint is past this share of its range (with the fingers released)."""
    close_fraction: float = 0.05
    """Close: success when the joint is below this share of its range (fingers released)."""
    close_start_fraction: float = 0.9
    """Close: the joint starts at this share of its range."""
    finger_opening: float = 0.05
    """Travel of each finger from closed (m); the fingers open to twice this."""
    finger_force: float = 80.0
    """Largest force of each finger (N)."""
    adhesion_force: float = 80.0
    """Adhesion of each finger pad while the grip is closed (N), to hold flat faces."""
    weld_time: float = 0.02
    """Time constant (s) of the weld that makes the gripper follow its mocap target."""
    handle_min_proud: float = 0.008
    """Vertices this far (m) proud of a part's outward face form its handle."""
    handle_min_points: int = 4
    """A handle needs at least this many proud vertices."""
    face_band: float = 0.004
    """Vertices within this distance (m) of the outermost plane form the outward face."""
    edge_inset: float = 0.03
    """With no handle: the grasp point sits this far (m) inside the face's edge far from the hinge."""
    twist_ratio: float = 0.35
    """A revolute part whose centre is nearer to the axis than this share of its farthest point
    turns in place (a knob): it is grasped on its axis."""
    image_width: int = 128
    image_height: int = 96
    """Size of the rgb and depth observations (pixels)."""
    render_width: int = 480
    render_height: int = 360
    """Size of render() frames (pixels)."""
    camera_fovy_deg: float = 45.0
    """Vertical field of view of the fixed camera."""
    camera_distance: float = 1.1
    """Camera distance from the object's centre: this many times the distance at which the
    object's bounding sphere just fills the field of view."""
    camera_elevation_deg: float = 25.0
    camera_azimuth_deg: float = 30.0
    """Camera direction: above the floor, and around from the object's front."""
    reach_weight: float = 1.0
    """Dense reward: minus this times the fingertip-handle distance (m)."""
    progress_weight: float = 2.0
    """Dense reward: this times the progress of the joint towards the target (share of range)."""
    success_reward: float = 10.0
    """Sparse reward on success."""
    pose_jitter: float = 0.05
    """Randomisation: object offset on the floor (m, each horizontal direction)."""
    yaw_jitter_deg: float = 15.0
    """Randomisation: object rotation about the vertical."""
    dynamics_scale: tuple[float, float] = (0.5, 2.0)
    """Randomisation: joint friction and damping are scaled by a log-uniform factor in this range."""
    camera_jitter: float = 0.03
    """Randomisation: camera position offset (m, each direction)."""
    camera_jitter_deg: float = 3.0
    """Randomisation: camera rotation."""
    policy: PolicyConfig = field(default_factory=PolicyConfig)
    """The scripted policy."""


@dataclass(frozen=True)
class Config:
    """All stage configs."""

    load: LoadConfig = field(default_factory=LoadConfig)
    frame: FrameConfig = field(default_factory=FrameConfig)
    parts: PartsConfig = field(default_factory=PartsConfig)
    segment: SegmentConfig = field(default_factory=SegmentConfig)
    joints: JointsConfig = field(default_factory=JointsConfig)
    gate: GateConfig = field(default_factory=GateConfig)
    articulation: ArticulationConfig = field(default_factory=ArticulationConfig)
    completion: CompletionConfig = field(default_factory=CompletionConfig)
    collision: CollisionConfig = field(default_factory=CollisionConfig)
    export: ExportConfig = field(default_factory=ExportConfig)
    check: CheckConfig = field(default_factory=CheckConfig)
    validate: ValidateConfig = field(default_factory=ValidateConfig)
    catalog: CatalogConfig = field(default_factory=CatalogConfig)
    envs: EnvConfig = field(default_factory=EnvConfig)
    models: ModelsConfig = field(default_factory=ModelsConfig)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict (tuples become lists), suitable for YAML/JSON."""
        return _plain(dataclasses.asdict(self))

    def result_settings(self) -> dict[str, Any]:
        """``to_dict()`` less the settings that change no asset: the ``catalog`` section (build
        settings) and ``collision.cache_dir`` (where decompositions are cached, a local path). What
        an asset's ``config.json`` records and a catalog job's key hashes."""
        data = {k: v for k, v in self.to_dict().items() if k != "catalog"}
        data["collision"].pop("cache_dir")
        return data


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _apply(section: Any, overrides: dict[str, Any], where: str) -> Any:
    if not isinstance(overrides, dict):
        raise ConfigError(f"{where}: expected a mapping, got {type(overrides).__name__}")
    names = {f.name: f for f in dataclasses.fields(section)}
    changes = {}
    for key, value in overrides.items():
        if key not in names:
            raise ConfigError(
                f"{where or 'config'}: unknown key '{key}'. Valid keys: {', '.join(sorted(names))}"
            )
        current = getattr(section, key)
        if dataclasses.is_dataclass(current):
            changes[key] = _apply(current, value, f"{where}.{key}" if where else key)
        elif isinstance(current, tuple):
            changes[key] = tuple(value)
        elif isinstance(current, dict):
            changes[key] = {**current, **value}
        elif isinstance(current, bool) or current is None:
            changes[key] = value
        elif isinstance(current, (int, float)) and not isinstance(value, (int, float)):
            raise ConfigError(f"{where + '.' if where else ''}{key}: expected a number, got {value!r}")
        else:
            changes[key] = type(current)(value)
    return dataclasses.replace(section, **changes)


def load_config(path: str | Path | None = None, overrides: dict[str, Any] | None = None,
                overrides_source: str = "overrides") -> Config:
    """Defaults, then the YAML file at ``path`` (if any), then ``overrides`` (nested dict);
    errors in ``overrides`` name their keys after ``overrides_source`` ("" for the bare keys)."""
    config = Config()
    if path is not None:
        path = Path(path)
        if not path.is_file():
            raise ConfigError(f"{path}: config file not found")
        try:
            data = yaml.safe_load(path.read_text()) or {}
        except yaml.YAMLError as exc:
            raise ConfigError(f"{path}: not valid YAML ({exc})") from None
        config = _apply(config, data, str(path))
    if overrides:
        config = _apply(config, overrides, overrides_source)
    return config


def field_docs(cls: type) -> dict[str, str]:
    """The docstring under each field of dataclass ``cls`` of this module (the string literal
    that follows the field in its source), by field name; consecutive fields share the
    docstring under the last of them (``cv_revolute`` and ``cv_prismatic``); fields without one
    are left out."""
    return _docs_by_class().get(cls.__name__, {})


@functools.cache
def _docs_by_class() -> dict[str, dict[str, str]]:
    """``field_docs`` of every class of this module, from one parse of its source (the CLI
    asks for every section each time it starts)."""
    import ast

    docs: dict[str, dict[str, str]] = {}
    for cls in ast.parse(Path(__file__).read_text()).body:
        if not isinstance(cls, ast.ClassDef):
            continue
        found, pending = docs.setdefault(cls.name, {}), []
        for node in cls.body:
            if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                pending.append(node.target.id)
            elif isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
                found.update({name: " ".join(node.value.value.split()) for name in pending})
                pending = []
            else:
                pending = []
    return docs


def config_fields(section: Any = None, prefix: str = "") -> list[tuple[str, Any, str]]:
    """Every leaf field of the config as (dotted key, default value, docstring), e.g.
    ``("gate.min_opening_depth", 0.02, "...")``, in declaration order."""
    section = Config() if section is None else section
    docs = field_docs(type(section))
    out = []
    for f in dataclasses.fields(section):
        value = getattr(section, f.name)
        if dataclasses.is_dataclass(value):
            out += config_fields(value, f"{prefix}{f.name}.")
        else:
            out.append((f"{prefix}{f.name}", value, docs.get(f.name, "")))
    return out


def dotted_overrides(values: dict[str, str]) -> dict[str, Any]:
    """``{"gate.min_opening_depth": "0.03"}`` as the nested overrides ``load_config`` takes;
    each value is read as YAML (``true``, ``0.03``, ``[urdf, mjcf]``) and checked there."""
    nested: dict[str, Any] = {}
    for key, text in values.items():
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            raise ConfigError(f"--{key}: cannot read {text!r} ({exc})") from None
        *path, leaf = key.split(".")
        node = nested
        for name in path:
            node = node.setdefault(name, {})
        node[leaf] = value
    return nested
