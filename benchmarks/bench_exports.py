"""One object written the ways other people's tools write meshes: does it come out the same?

    python benchmarks/bench_exports.py [--seeds 3 17 42] [--real-dev NAME ...] [-o bench_exports]

Each object (real-like objects of the generator by seed, asset variant; with ``--real-dev``,
assets of the prepared real development set by name: ``rest2art bench prepare``) is written as

* ``obj``: its OBJ as is, one object per piece (the reference);
* ``stl-soup``: an STL, every corner repeated for each triangle (pieces only by position);
* ``mm-turned``: an STL in millimetres, turned 30 degrees about its true up (read with
  ``--units mm``);
* ``mirrored``: every face wound the other way, as a mirrored export writes it;
* ``double``: every face written twice, wound both ways (a double-sided material baked in);

and each file is reconstructed, completed, exported and validated with refinement, as
``rest2art bench run --check`` does. It is scored against its truth, turned and scaled as the
file was (a double-sided file's second copies are left out of the score: they take the part of
the face they repeat). Prints per export how many objects are right and published, and per
object what each export gave; writes OUT/exports.json.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np
import trimesh

EXPORTS = ("obj", "stl-soup", "mm-turned", "mirrored", "double")
TURN_DEG = 30.0


def turn(up: np.ndarray) -> np.ndarray:
    """(3, 3) rotation by ``TURN_DEG`` about ``up`` (3,)."""
    return trimesh.transformations.rotation_matrix(np.radians(TURN_DEG), up)[:3, :3]


def write_export(mesh: trimesh.Trimesh, reference: Path, export: str, folder: Path,
                 up: np.ndarray) -> tuple[Path, str | None]:
    """Write ``mesh`` (the object's faces in their order, metres; ``up`` (3,) its true up) as
    ``export`` into ``folder``; the file and the unit to read it with. ``reference`` is the OBJ
    as is."""
    if export == "obj":
        return reference, None
    corners = mesh.vertices[mesh.faces].reshape(-1, 3)
    soup = np.arange(len(corners)).reshape(-1, 3)
    if export == "stl-soup":
        path = folder / "soup.stl"
        trimesh.Trimesh(corners, soup, process=False).export(path)
        return path, None
    if export == "mm-turned":
        path = folder / "turned_mm.stl"
        trimesh.Trimesh(corners @ turn(up).T * 1000.0, soup, process=False).export(path)
        return path, "mm"
    faces = mesh.faces[:, ::-1] if export == "mirrored" else np.concatenate([mesh.faces, mesh.faces[:, ::-1]])
    path = folder / f"{export}.obj"
    trimesh.Trimesh(mesh.vertices, faces, process=False).export(path)
    return path, None


def truth_as_written(truth, export: str, up: np.ndarray):
    """The truth's joints in the frame the ``export`` wrote the object in."""
    if export != "mm-turned":
        return truth
    rotation = turn(up)
    joints = [dataclasses.replace(j, axis=rotation @ np.asarray(j.axis), origin=rotation @ np.asarray(j.origin))
              for j in truth.joints]
    return dataclasses.replace(truth, joints=joints)


def run_export(name: str, mesh: trimesh.Trimesh, reference: Path, truth, export: str, folder: Path, config) -> dict:
    """Reconstruct, export and validate one export of one object; its score and decision."""
    from rest2art.bench.metrics import is_right, score_object
    from rest2art.export.writers import write_asset
    from rest2art.io.atomic import atomic_folder
    from rest2art.pipeline import reconstruct_file
    from rest2art.validators.validate import validate_folder

    from rest2art.bench import true_frame

    up = np.asarray(true_frame(truth)["up"], float)
    folder.mkdir(parents=True, exist_ok=True)
    path, units = write_export(mesh, reference, export, folder, up)
    try:
        asset, _ = reconstruct_file(path, config, units)
    except Exception as exc:  # a refused input is a result too
        return {"object": name, "export": export, "right": False, "decision": f"error: {exc}"}
    asset.face_part = asset.face_part[:len(mesh.faces)]
    score = score_object(asset, truth_as_written(truth, export, up), mesh.area_faces, name)
    out = folder / "asset"
    with atomic_folder(out, overwrite=True) as tmp:
        write_asset(asset, tmp, name, config.export, asset.up)
    report = validate_folder(out, name, config, refine=True)
    return {"object": name, "export": export, "right": bool(is_right(score)), "miou": round(score.miou, 3),
            "movable": f"{score.n_pred_movable}/{score.n_gt_movable}", "decision": report.decision.status}


def objects(seeds: list[int], real_dev: list[str], folder: Path):
    """(name, mesh, reference OBJ, truth) of each object asked for."""
    from rest2art.asset import read_articulation
    from rest2art.bench import mix_items
    from rest2art.generate import generate_mix_object, write_object
    from rest2art.io.load import load_mesh

    for seed in seeds:
        item = mix_items("real-like", 1, "asset", seed)[0]
        obj = generate_mix_object("real-like", seed, "asset")
        yield item.name, obj.mesh, write_object(obj, folder / item.name), obj.asset
    if real_dev:
        from rest2art.bench.devset import default_cache

        for name in real_dev:
            gt = default_cache() / "sets" / "real-dev" / "asset" / name
            reference = gt / "mesh.obj"
            yield name, load_mesh(reference).trimesh(), reference, read_articulation(gt, load_meshes=False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, nargs="*", default=[3, 17, 42])
    parser.add_argument("--real-dev", nargs="*", default=[])
    parser.add_argument("-o", "--out", type=Path, default=Path("bench_exports"))
    args = parser.parse_args()

    from rest2art.config import Config

    config = Config()
    rows = []
    for name, mesh, reference, truth in objects(args.seeds, args.real_dev, args.out):
        for export in EXPORTS:
            row = run_export(name, mesh, reference, truth, export, args.out / name / export, config)
            rows.append(row)
            print(f"  {name} {export}: {'right' if row['right'] else 'wrong'}, {row['decision']}", flush=True)
    (args.out / "exports.json").write_text(json.dumps(rows, indent=1))
    names = list(dict.fromkeys(r["object"] for r in rows))
    print("\n| export | right | published | published right |\n|---|---|---|---|")
    for export in EXPORTS:
        mine = [r for r in rows if r["export"] == export]
        published = [r for r in mine if r["decision"] == "publish"]
        print(f"| {export} | {sum(r['right'] for r in mine)} / {len(mine)} | {len(published)} / {len(mine)} | "
              f"{sum(r['right'] for r in published)} / {len(mine)} |")
    print("\n| object | " + " | ".join(EXPORTS) + " |\n|---|" + "---|" * len(EXPORTS))
    for name in names:
        cells = {r["export"]: f"{'right' if r['right'] else 'wrong'}, {r['decision']}" for r in rows if r["object"] == name}
        print(f"| {name} | " + " | ".join(cells.get(e, "-") for e in EXPORTS) + " |")


if __name__ == "__main__":
    main()
