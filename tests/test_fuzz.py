"""Fuzz: seeded mutations of a valid mesh and of a valid asset folder.

Each case must end in a clear error (:class:`InputError`, one line naming the file) or a valid
result (a checked mesh; a files finding), within a time bound, without opening anything
outside its folder. Outside files are sentinels: an audit hook records every path Python
opens, and their access time (set before their modification time, so the kernel's relatime
rule moves it on any read) shows native reads too. 320 mesh cases and 240 folder cases run in
the fast tier; a few folders that pass the files check also go through every simulator (slow).
"""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from rest2art.validators.static_checks import check_files, read_asset

from rest2art.errors import InputError
from rest2art.export.writers import write_asset
from rest2art.generate import generate_object
from rest2art.io.atomic import atomic_folder
from rest2art.io.load import load_mesh
from rest2art.pipeline import complete_asset

MESH_CASES = 320
FOLDER_CASES = 240
CASE_SECONDS = 10
"""A case that runs longer counts as a hang."""
TOTAL_SECONDS = 240
"""Both fast suites together must end within this (CI runs them in under 5 minutes)."""

OPENED: list[str] = []
_WATCH: list[Path] = []


def _audit(event: str, args) -> None:
    if event == "open" and _WATCH and isinstance(args[0], (str, bytes, os.PathLike)):
        path = os.fsdecode(args[0])
        if any(path.startswith(str(w)) for w in _WATCH):
            OPENED.append(path)


sys.addaudithook(_audit)


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang()


def run_bounded(fn, *args):
    """fn(*args) with a CASE_SECONDS alarm."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(CASE_SECONDS)
    try:
        return fn(*args)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.fixture(scope="module")
def outside(tmp_path_factory) -> dict[str, Path]:
    """Sentinel files outside every fuzzed folder; reads of them are watched."""
    folder = tmp_path_factory.mktemp("outside")
    files = {"mesh": folder / "secret.obj", "xml": folder / "secret.xml", "text": folder / "passwd"}
    files["mesh"].write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    files["xml"].write_text("<mujoco><asset/></mujoco>")
    files["text"].write_text("root:x:0:0")
    for path in files.values():
        os.utime(path, (1_000_000, time.time()))
    (folder / "dir").mkdir()
    files["dir"] = folder / "dir"
    _WATCH.append(folder)
    return files


def untouched(outside: dict[str, Path]) -> bool:
    return all(os.stat(p).st_atime <= 1_000_000 for k, p in outside.items() if k != "dir") and not OPENED


# meshes ----------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def obj_text() -> str:
    mesh = generate_object("microwave", 5, "asset").mesh
    return mesh.export(file_type="obj")


TOKENS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "abc", "", "0", "-1", "999999999", "1/2/3", "\x00"]


def mutate_obj(text: str, rng: random.Random) -> tuple[str, str]:
    """(mutated text, suffix) of one seeded mutation of an OBJ file."""
    lines = text.splitlines()
    kind = rng.choice(["drop", "dup", "token", "index", "truncate", "bytes", "scale", "collapse", "points",
                       "empty", "suffix", "long", "faces_only", "quads"])
    if kind == "drop":
        lines = [line for line in lines if rng.random() > 0.3]
    elif kind == "dup":
        lines = lines + rng.sample(lines, min(len(lines), 50))
    elif kind == "token":
        for _ in range(rng.randint(1, 5)):
            k = rng.randrange(len(lines))
            parts = lines[k].split()
            if len(parts) > 1:
                parts[rng.randrange(1, len(parts))] = rng.choice(TOKENS)
                lines[k] = " ".join(parts)
    elif kind == "index":
        faces = [k for k, line in enumerate(lines) if line.startswith("f ")]
        for k in rng.sample(faces, min(5, len(faces))):
            lines[k] = f"f 1 2 {rng.choice([0, -999999, 999999, 10 ** 12])}"
    elif kind == "truncate":
        return text[: rng.randrange(len(text))], ".obj"
    elif kind == "bytes":
        data = bytearray(text.encode())
        for _ in range(rng.randint(1, 200)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        return data.decode(errors="replace"), ".obj"
    elif kind == "scale":
        factor = rng.choice([1e-9, 1e-4, 1e4, 1e9, 1e300])
        lines = [" ".join(["v", *(repr(float(x) * factor) for x in line.split()[1:4])]) if line.startswith("v ")
                 else line for line in lines]
    elif kind == "collapse":
        lines = ["v 0.5 0.5 0.5" if line.startswith("v ") else line for line in lines]
    elif kind == "points":
        lines = [line for line in lines if line.startswith("v ")]
    elif kind == "empty":
        return "", ".obj"
    elif kind == "suffix":
        return text, rng.choice([".ply", ".stl", ".glb", ".gltf", ".off"])
    elif kind == "long":
        lines.insert(rng.randrange(len(lines)), "g " + "x" * 100_000)
    elif kind == "faces_only":
        lines = [line for line in lines if line.startswith("f ")]
    elif kind == "quads":
        lines = [line + " 1" if line.startswith("f ") and rng.random() < 0.2 else line for line in lines]
    return "\n".join(lines) + "\n", ".obj"


def load_case(path: Path):
    try:
        mesh = load_mesh(path)
    except InputError as exc:
        message = str(exc)
        assert "\n" not in message.strip() and str(path) in message, message
        return "error"
    assert np.all(np.isfinite(mesh.vertices)) and len(mesh.faces)
    assert mesh.faces.min() >= 0 and mesh.faces.max() < len(mesh.vertices)
    assert len(mesh.face_node) == len(mesh.faces) == len(mesh.face_component)
    return "valid"


def test_fuzzed_meshes_end_in_a_clear_error_or_a_valid_mesh(obj_text, tmp_path, outside):
    start = time.perf_counter()
    outcomes = {"error": 0, "valid": 0}
    for seed in range(MESH_CASES):
        rng = random.Random(seed)
        text, suffix = mutate_obj(obj_text, rng)
        path = tmp_path / f"case_{seed}{suffix}"
        path.write_text(text, errors="replace")
        try:
            outcomes[run_bounded(load_case, path)] += 1
        except Hang:
            pytest.fail(f"seed {seed}: loading hung for {CASE_SECONDS} s")
        except AssertionError:
            raise
        except Exception as exc:
            pytest.fail(f"seed {seed}: {type(exc).__name__}: {exc}")
        path.unlink()
    assert outcomes["error"] > 0 and outcomes["valid"] > 0, outcomes
    assert untouched(outside)
    assert time.perf_counter() - start < TOTAL_SECONDS / 2


# asset folders ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def sound(config, tmp_path_factory) -> Path:
    asset = generate_object("microwave", 5, "asset").asset
    complete_asset(asset, config)
    folder = tmp_path_factory.mktemp("sound") / "m"
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "m", config.export, np.array([0.0, 0.0, 1.0]))
    return folder


def _deep(tag: str, depth: int) -> str:
    return f"<{tag}>" * depth + f"</{tag}>" * depth


def mutate_folder(folder: Path, rng: random.Random, outside: dict[str, Path]) -> str:
    """Apply one seeded hostile edit to the asset folder; returns its kind."""
    urdf, mjcf, meta = folder / "m.urdf", folder / "m.xml", folder / "articulation.json"
    kind = rng.choice(["entity", "external", "abs_mesh", "up_mesh", "url", "truncate", "flip", "deep", "huge",
                       "nan", "include_out", "include_self", "include_missing", "drop_attr", "json_list",
                       "json_missing", "json_nan", "json_deep", "json_type", "json_path", "link_mesh", "link_dir",
                       "link_loop", "link_dangling", "dir_for_file", "include_deep"])
    xml = rng.choice([urdf, mjcf])
    text = xml.read_text()
    if kind == "entity":
        root = "robot" if xml == urdf else "mujoco"
        body = text.split("?>", 1)[-1]
        xml.write_text(f'<!DOCTYPE {root} [<!ENTITY a "{"x" * 50}"><!ENTITY b "&a;&a;&a;&a;">]>' + body.replace(
            "name=", "foo=\"&b;\" name=", 1))
    elif kind == "external":
        root = "robot" if xml == urdf else "mujoco"
        body = text.split("?>", 1)[-1]
        xml.write_text(f'<!DOCTYPE {root} [<!ENTITY x SYSTEM "file://{outside["text"]}">]>'
                       + body.replace(">", ">&x;", 2))
    elif kind in ("abs_mesh", "up_mesh", "url"):
        target = {"abs_mesh": str(outside["mesh"]), "up_mesh": os.path.relpath(outside["mesh"], folder),
                  "url": "file://" + str(outside["mesh"])}[kind]
        xml.write_text(text.replace("parts/base.obj", target, 1))
    elif kind == "truncate":
        xml.write_text(text[: rng.randrange(len(text))])
    elif kind == "flip":
        data = bytearray(text.encode())
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] = rng.randrange(32, 127)
        xml.write_bytes(bytes(data))
    elif kind == "deep":
        xml.write_text(text.replace("</", _deep("a", rng.choice([100, 5000, 50_000])) + "</", 1))
    elif kind in ("huge", "nan"):
        value = rng.choice(["1e308", "1e12", "-1e30"]) if kind == "huge" else rng.choice(["nan", "inf", "-inf"])
        attr = rng.choice(['xyz="', 'value="', 'ixx="', 'range="', 'pos="', 'mass="', 'axis="'])
        xml.write_text(text.replace(attr, attr + value + " ", 1) if attr in text else text.replace(
            'name="', f'iterations="{value}" name="', 1))
    elif kind.startswith("include"):
        ref = {"include_out": os.path.relpath(outside["xml"], folder), "include_self": "m.xml",
               "include_missing": "nothing.xml", "include_deep": "inc_0.xml"}[kind]
        if kind == "include_deep":
            for k in range(12):
                (folder / f"inc_{k}.xml").write_text(f'<mujoco><include file="inc_{k + 1}.xml"/></mujoco>')
            (folder / "inc_12.xml").write_text("<mujoco/>")
        mjcf.write_text(mjcf.read_text().replace("<asset>", f'<include file="{ref}"/><asset>', 1))
    elif kind == "drop_attr":
        xml.write_text(text.replace(rng.choice(['filename="', 'file="', 'value="', 'name="']), 'x="', 3))
    elif kind.startswith("json"):
        data = json.loads(meta.read_text())
        if kind == "json_list":
            meta.write_text(json.dumps([data]))
        elif kind == "json_missing":
            section = rng.choice(["parts", "joints"])
            del data[section][0][rng.choice(list(data[section][0]))]
            meta.write_text(json.dumps(data))
        elif kind == "json_nan":
            data["joints"][0][rng.choice(["axis", "origin", "limit"])][0] = rng.choice([float("nan"), float("inf")])
            meta.write_text(json.dumps(data))
        elif kind == "json_deep":
            meta.write_text("[" * 200_000 + "]" * 200_000)
        elif kind == "json_type":
            data["joints"][0][rng.choice(["axis", "limit", "type", "child"])] = rng.choice(["x", 3, None, {"a": 1}])
            meta.write_text(json.dumps(data))
        elif kind == "json_path":
            data["parts"][0]["mesh"] = rng.choice([str(outside["mesh"]), "../../secret.obj", "parts"])
            meta.write_text(json.dumps(data))
    elif kind == "link_mesh":
        (folder / "parts" / "base.obj").unlink()
        (folder / "parts" / "base.obj").symlink_to(outside["mesh"])
    elif kind == "link_dir":
        shutil.rmtree(folder / "collision")
        (folder / "collision").symlink_to(outside["dir"], target_is_directory=True)
    elif kind == "link_loop":
        (folder / "parts" / "loop.obj").symlink_to(folder / "parts" / "loop.obj")
        xml.write_text(text.replace("parts/base.obj", "parts/loop.obj", 1))
    elif kind == "link_dangling":
        (folder / "parts" / "base.obj").unlink()
        (folder / "parts" / "base.obj").symlink_to(folder / "parts" / "nowhere.obj")
    elif kind == "dir_for_file":
        (folder / "parts" / "base.obj").unlink()
        (folder / "parts" / "base.obj").mkdir()
    return kind


def folder_case(folder: Path) -> str:
    try:
        finding = check_files(folder, "m")
        if finding.ok:
            read_asset(folder)
    except InputError as exc:
        assert "\n" not in str(exc).strip() and str(folder) in str(exc), str(exc)
        return "error"
    assert finding.message and "\n" not in finding.message
    return "pass" if finding.ok else "fail"


def test_fuzzed_asset_folders_end_in_a_finding_or_a_clear_error(sound, tmp_path, outside):
    start = time.perf_counter()
    outcomes: dict[str, int] = {}
    kinds: dict[str, int] = {}
    for seed in range(FOLDER_CASES):
        rng = random.Random(10_000 + seed)
        folder = tmp_path / f"case_{seed}"
        shutil.copytree(sound, folder, symlinks=True)
        kind = mutate_folder(folder, rng, outside)
        kinds[kind] = kinds.get(kind, 0) + 1
        try:
            outcome = run_bounded(folder_case, folder)
        except Hang:
            pytest.fail(f"seed {seed} ({kind}): the checks hung for {CASE_SECONDS} s")
        except AssertionError:
            raise
        except Exception as exc:
            pytest.fail(f"seed {seed} ({kind}): {type(exc).__name__}: {exc}")
        if kind not in ("drop_attr", "huge", "flip", "deep", "json_type", "json_missing",
                        "include_missing"):
            assert outcome != "pass", f"seed {seed} ({kind}) passed the files check"
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
        assert untouched(outside), f"seed {seed} ({kind}) read an outside file: {OPENED}"
        shutil.rmtree(folder)
    assert len(kinds) >= 20 and outcomes.get("fail", 0) > 0, (kinds, outcomes)
    assert time.perf_counter() - start < TOTAL_SECONDS / 2


@pytest.mark.slow
def test_fuzzed_folders_that_pass_the_files_check_go_through_every_simulator(sound, tmp_path, outside, config):
    """Mutations the files check lets through (a dropped attribute, a big but finite number)
    go through the simulators: a decision or a clear error, never a crash or an outside read."""
    from rest2art.validators.validate import validate_folder

    ran = 0
    for seed in range(400):
        if ran == 8:
            break
        folder = tmp_path / f"case_{seed}"
        shutil.copytree(sound, folder, symlinks=True)
        mutate_folder(folder, random.Random(10_000 + seed), outside)
        if not check_files(folder, "m").ok:
            shutil.rmtree(folder)
            continue
        ran += 1
        try:
            report = validate_folder(folder, "m", config)
            assert report.decision.status in ("publish", "reject")
            assert json.loads((folder / "validation.json").read_text())["decision"]["status"] == report.decision.status
        except InputError as exc:
            assert str(folder) in str(exc)
        assert untouched(outside)
    assert ran == 8
