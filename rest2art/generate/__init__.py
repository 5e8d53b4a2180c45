"""`rest2art generate`: procedural articulated objects with ground truth.

Two variants of every object:

* ``asset``: parts as separate closed pieces, as an artist would model them (interior drawer
  boxes included), one OBJ object per piece;
* ``scan``: one fused outer surface with no part connectivity, like a 2DGS or scanner mesh of
  the closed object: the parts' signed distance fields are joined by a smooth union (blend
  ``scan_blend``, 15 mm, which fills the hidden gap behind a front and leaves a rounded groove
  at its outline), sampled on a grid (``scan_voxel``, 5 mm), meshed with marching cubes, and
  only the outer shell is kept.

Ground truth uses the output contract (articulation.json + face_part.npy), in the file's frame
(``up``, ``yaw_deg``), with a part's parent being any part (a dial on a safe's door). Objects
are seeded and deterministic: the same (kind, seed, variation) gives the same geometry in both
variants. Besides the six default kinds (:data:`KINDS`, the ``generated`` bench set), the
kinds of :mod:`rest2art.generate.real_like` and the options of
:class:`~rest2art.generate.variation.Variation` make what real assets do; the ``real-like``
mix draws all of them. The ``furniture`` mix stands cabinets and wardrobes as a furniture
catalog does, on legs and under overhanging tops, some cabinets with open shelves, and draws
desks (:mod:`rest2art.generate.furniture`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from rest2art.asset import ArticulatedAsset, Joint, Part, write_articulation
from rest2art.generate.csg import union
from rest2art.generate.furniture import FURNITURE_BUILDERS, FURNITURE_KINDS, furnish
from rest2art.generate.objects import BUILDERS as DEFAULT_BUILDERS
from rest2art.generate.objects import KINDS, ObjectSpec
from rest2art.generate.real_like import REAL_LIKE_BUILDERS, REAL_LIKE_KINDS
from rest2art.generate.variation import UPS, Variation, mix_entry, pose_tag
from rest2art.geometry.basics import rotation_about

VARIANTS = ("asset", "scan")
ALL_KINDS = KINDS + REAL_LIKE_KINDS + tuple(FURNITURE_BUILDERS)
"""Every kind; a kind's index seeds its objects, so new kinds only ever go at the end."""
BUILDERS = {**DEFAULT_BUILDERS, **REAL_LIKE_BUILDERS, **FURNITURE_BUILDERS}
MIX_KINDS = {"real-like": KINDS + REAL_LIKE_KINDS, "furniture": FURNITURE_KINDS, "framed": FURNITURE_KINDS}
"""The kinds each mix cycles through (the furniture mix draws desks for some of its cabinets)."""


@dataclass
class GeneratedObject:
    name: str
    spec: ObjectSpec
    mesh: trimesh.Trimesh
    """The input mesh (asset or scan variant), face order as written to mesh.obj."""
    face_part: np.ndarray
    asset: ArticulatedAsset
    """Ground truth; part meshes are the exact closed pieces."""
    piece_faces: list[tuple[str, int, int]]
    """(piece name, first face, end face) for the asset variant's OBJ objects."""


def build_spec(kind: str, seed: int, variation: Variation = Variation()) -> ObjectSpec:
    """The object description for (kind, seed, variation)."""
    if kind not in BUILDERS:
        raise ValueError(f"unknown kind '{kind}'. Valid kinds: {', '.join(ALL_KINDS)}")
    index = ALL_KINDS.index(kind)
    spec = BUILDERS[kind](np.random.default_rng([seed, index]), variation, np.random.default_rng([seed, index, 1]))
    if variation.furnished:
        spec = furnish(spec, np.random.default_rng([seed, index, 2]), variation.primitives)
    return spec


def _asset_mesh(spec: ObjectSpec) -> tuple[trimesh.Trimesh, np.ndarray, list]:
    meshes, labels, pieces = [], [], []
    start = 0
    for index, part in enumerate(spec.parts):
        for k, piece in enumerate(part.pieces):
            m = piece.mesh()
            meshes.append(m)
            labels.append(np.full(len(m.faces), index, np.int32))
            pieces.append((f"{part.name}_piece{k}", start, start + len(m.faces)))
            start += len(m.faces)
    mesh = trimesh.util.concatenate(meshes)
    return trimesh.Trimesh(mesh.vertices, mesh.faces, process=False), np.concatenate(labels), pieces


def smooth_min(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Polynomial smooth minimum of two distance fields; blends surfaces closer than ``k``."""
    h = np.clip(k - np.abs(a - b), 0.0, None) / k
    return np.minimum(a, b) - h * h * k / 4.0


def _scan_mesh(spec: ObjectSpec, voxel: float, max_faces: int, blend: float) -> tuple[trimesh.Trimesh, np.ndarray]:
    from skimage.measure import marching_cubes

    part_solids = [union(p.pieces) for p in spec.parts]
    whole = union(part_solids)
    lo, hi = whole.bounds()
    # an irrational-ish offset keeps grid samples off the (axis-aligned) surfaces: samples with
    # a distance of exactly 0 make marching cubes leave holes
    lo, hi = lo - 3.37 * voxel, hi + 3 * voxel
    axes = [np.arange(lo[i], hi[i] + voxel, voxel) for i in range(3)]
    shape = tuple(len(a) for a in axes)
    field = np.empty(shape, np.float32)
    gx, gy = np.meshgrid(axes[0], axes[1], indexing="ij")
    for k, z in enumerate(axes[2]):  # one z-slice at a time keeps memory small
        pts = np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, z)], axis=1)
        fused = part_solids[0].sdf(pts)
        for solid in part_solids[1:]:
            fused = smooth_min(fused, solid.sdf(pts), blend)
        field[:, :, k] = fused.reshape(gx.shape)
    verts, faces, _, _ = marching_cubes(field, level=0.0, spacing=(voxel,) * 3)
    mesh = trimesh.Trimesh(verts + lo, faces, process=True)  # skimage winds outward for this axis order
    # keep the outer shell only: closed cavities inside are invisible to a scanner
    parts = mesh.split(only_watertight=False)
    mesh = max(parts, key=lambda m: np.prod(m.extents))
    if len(mesh.faces) > max_faces:
        import fast_simplification

        v, f = fast_simplification.simplify(mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32),
                                            target_reduction=1 - max_faces / len(mesh.faces))
        mesh = trimesh.Trimesh(v.astype(np.float64), f, process=True)
    centres = mesh.triangles_center
    distance = np.stack([np.abs(s.sdf(centres)) for s in part_solids], axis=1)
    return mesh, distance.argmin(axis=1).astype(np.int32)


def file_pose(up: str, yaw_deg: float) -> np.ndarray:
    """(4, 4) transform from the canonical frame to the written file's frame."""
    if up not in UPS:
        raise ValueError(f"unknown up axis '{up}'. Valid: {', '.join(UPS)}")
    T = np.eye(4)
    R = rotation_about(np.array([0.0, 0.0, 1.0]), np.radians(yaw_deg))
    if up == "y":  # z-up to y-up (glTF convention): rotate -90 deg about x
        R = rotation_about(np.array([1.0, 0.0, 0.0]), -np.pi / 2) @ R
    T[:3, :3] = R
    return T


def generate_object(kind: str, seed: int, variant: str = "asset", scan_voxel: float = 0.005,
                    scan_max_faces: int = 200_000, up: str = "z", yaw_deg: float = 0.0,
                    scan_blend: float = 0.015, variation: Variation = Variation()) -> GeneratedObject:
    """One object of ``kind`` with ground truth; ``up``/``yaw_deg`` pose it in its file frame
    (``up="y"``: +y up as in glTF; ``yaw_deg``: turned about the up axis), ``variation`` asks
    for flush or sunk fronts, primitives and varied handles."""
    if variant not in VARIANTS:
        raise ValueError(f"unknown variant '{variant}'. Valid variants: {', '.join(VARIANTS)}")
    spec = build_spec(kind, seed, variation)
    if variant == "asset":
        mesh, face_part, pieces = _asset_mesh(spec)
    else:
        mesh, face_part = _scan_mesh(spec, scan_voxel, scan_max_faces, scan_blend)
        pieces = [("scan", 0, len(mesh.faces))]
    T = file_pose(up, yaw_deg)
    mesh.apply_transform(T)
    parts, joints = [], []
    for p in spec.parts:
        part_mesh = union(p.pieces).mesh()
        part_mesh.apply_transform(T)
        parts.append(Part(p.name, p.semantic, None if p.joint is None else p.parent, part_mesh))
        if p.joint is not None:
            j = p.joint
            joints.append(Joint(f"{p.name}_joint", j["type"], p.parent, p.name,
                                T[:3, :3] @ np.asarray(j["axis"]), T[:3, :3] @ np.asarray(j["origin"]) + T[:3, 3],
                                tuple(j["limit"])))
    name = f"{kind}_{seed:04d}{variation.tag()}{pose_tag(up, yaw_deg)}"
    options = {} if variation == Variation() else {"fit": variation.fit, "primitives": variation.primitives,
                                                   "varied_handles": variation.varied_handles,
                                                   **({"furnished": True} if variation.furnished else {}),
                                                   **({"open_shelves": True} if variation.open_shelves else {})}
    asset = ArticulatedAsset(parts, joints, face_part, {
        "generator": {"kind": kind, "seed": seed, "variant": variant, "up": up, "yaw_deg": yaw_deg, **options,
                      **{k: (round(v, 6) if isinstance(v, float) else v) for k, v in spec.params.items()}},
        "frame": {"up": (T[:3, :3] @ [0.0, 0.0, 1.0]).round(12).tolist(),
                  "front": (T[:3, :3] @ [0.0, -1.0, 0.0]).round(12).tolist()},
    })
    asset.validate()
    return GeneratedObject(name, spec, mesh, face_part, asset, pieces)


def generate_mix_object(mix: str, seed: int, variant: str = "asset", scan_voxel: float = 0.005,
                        kinds: tuple[str, ...] | None = None) -> GeneratedObject:
    """Object ``seed`` of ``mix`` (see :func:`~rest2art.generate.variation.mix_entry`; ``kinds``:
    the mix's own, :data:`MIX_KINDS`, when not given), named after its kind, seed, variation and
    file pose."""
    entry = mix_entry(mix, seed, MIX_KINDS.get(mix, ALL_KINDS) if kinds is None else kinds)
    obj = generate_object(entry.kind, entry.seed, variant, scan_voxel=scan_voxel, up=entry.up,
                          yaw_deg=entry.yaw_deg, variation=entry.variation)
    obj.asset.metadata["generator"]["mix"] = mix
    return obj


def write_mesh_obj(mesh: trimesh.Trimesh, pieces: list[tuple[str, int, int]], path: Path, title: str) -> None:
    """Write ``mesh`` as OBJ with one ``o`` object per (name, first face, end face) piece, in
    face order, under a temporary name first."""
    v, f = mesh.vertices, mesh.faces
    lines = [f"# rest2art {title}", *(f"v {a:.7f} {b:.7f} {c:.7f}" for a, b, c in v)]
    for piece, start, end in pieces:
        lines.append(f"o {piece}")
        lines.extend(f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f[start:end])
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(path)


def write_object(obj: GeneratedObject, folder: str | Path) -> Path:
    """Write ``mesh.obj`` (one OBJ object per piece) and the ground truth into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    write_mesh_obj(obj.mesh, obj.piece_faces, folder / "mesh.obj", f"generated {obj.name}")
    write_articulation(obj.asset, folder)
    return folder / "mesh.obj"
