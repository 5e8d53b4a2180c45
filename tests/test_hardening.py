"""Hardening: each defect of the hardening issue, reproduced on real assets the project makes.

Numbers in the test names follow the issue: (1) memory that grows with face density,
(2) symlinks out of an asset folder, (3) MJCF includes, (4) simulators opening outside files,
(5) concurrent runs, (6) killed runs, (7) read-only sources, (8) malformed XML and JSON,
(9) native simulator output, (10) publish and reconstruct options, (11) self-collision.
An outside file is a sentinel whose access time is set before its modification time, so that
any read (the kernel's relatime rule updates it then) shows.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import trimesh
import pytest
from rest2art.validators.load_checks import run_load_checks
from rest2art.validators.static_checks import check_files

from rest2art.cli import main
from rest2art.export.writers import write_asset
from rest2art.generate import generate_object
from rest2art.io.atomic import atomic_folder, output_lock
from rest2art.io.stop import Terminated, stop_on_signals
from rest2art.pipeline import complete_asset

DEMO = Path(__file__).parents[1] / "rest2art" / "data" / "demo_cabinet.obj"


def rest2art(*args, cwd=None, timeout=600):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, "-m", "rest2art.cli", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=timeout)


def sentinel(folder: Path, name: str = "secret.obj", text: str | None = None) -> Path:
    """An outside file whose next read moves its access time (atime set before mtime)."""
    path = folder / name
    path.write_text(text if text is not None else DEMO.read_text())
    os.utime(path, (1_000_000, time.time()))
    return path


def was_read(path: Path) -> bool:
    return os.stat(path).st_atime > 1_000_000


@pytest.fixture(scope="module")
def sound(config, tmp_path_factory) -> Path:
    """A completed, exported ground-truth microwave (one door): a sound asset folder."""
    asset = generate_object("microwave", 5, "asset").asset
    complete_asset(asset, config)
    folder = tmp_path_factory.mktemp("sound") / "microwave"
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "m", config.export, np.array([0.0, 0.0, 1.0]))
    return folder


def copy_of(sound: Path, dest: Path) -> Path:
    shutil.copytree(sound, dest)
    return dest


# (1) memory ------------------------------------------------------------------------------------

def test_1_surface_dent_memory_stays_flat_when_the_face_density_quadruples():
    from rest2art.parts.segment.lifting import surface_dent

    rng = np.random.default_rng(0)
    n = 30_000
    centres = rng.random((n, 3)) * [1.0, 1.0, 0.01]  # a dense slab, like a fine scan's surface
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    area = np.full(n, 1e-6)
    peaks = []
    for radius in (0.03, 0.06):  # about 85 and 340 neighbours per face: 2.5M and 10M pairs
        tracemalloc.start()
        dent = surface_dent(centres, normals, area, radius)
        peaks.append(tracemalloc.get_traced_memory()[1] / 1e6)
        tracemalloc.stop()
        assert dent.shape == (n,) and np.all(np.isfinite(dent))
    # all pairs at once would take about 4 x as much at the larger radius (> 1 GB)
    assert peaks[1] < 1.6 * peaks[0] and peaks[1] < 400, peaks


def test_1_surface_dent_in_chunks_equals_all_at_once(monkeypatch):
    import rest2art.parts.segment.lifting as lifting

    rng = np.random.default_rng(1)
    centres, normals, area = rng.random((3000, 3)), rng.normal(size=(3000, 3)), rng.random(3000)
    whole = lifting.surface_dent(centres, normals, area, 0.1)
    monkeypatch.setattr(lifting, "DENT_PAIRS_PER_CHUNK", 500)
    assert np.array_equal(whole, lifting.surface_dent(centres, normals, area, 0.1))


def test_1_surface_dent_on_a_dense_mesh_averages_a_sample_that_agrees_with_all_faces(monkeypatch):
    """An L-shaped block subdivided until about 500 faces lie within the radius: the sampled
    average follows the full one (the inside corner a groove, the outer edges ridges)."""
    import rest2art.parts.segment.lifting as lifting

    block = trimesh.boolean.union([trimesh.creation.box((0.2, 0.05, 0.1)), trimesh.creation.box((0.05, 0.2, 0.1))])
    while len(block.faces) < 40_000:
        block = block.subdivide()
    args = (block.triangles_center, block.face_normals, block.area_faces, 0.02)
    sampled = lifting.surface_dent(*args)
    monkeypatch.setattr(lifting, "DENT_MAX_NEIGHBOURS", 10**9)
    full = lifting.surface_dent(*args)
    assert np.corrcoef(sampled, full)[0, 1] > 0.99
    for side in (1, -1):  # grooves and ridges 0.7 mm deep, as the edge strips judge them
        assert np.mean((side * sampled > 7e-4) == (side * full > 7e-4)) > 0.99


def test_1_a_dense_knob_has_the_same_single_foot():
    """A knob subdivided to ~100k foot vertices stands on the same foot as the coarse one, in
    bounded memory (every pair within the link distance would take gigabytes)."""
    from rest2art.config import PartsConfig
    from rest2art.parts.pieces import single_mount

    knob = trimesh.creation.cylinder(radius=0.015, height=0.02, sections=64)
    knob.apply_translation([0.3, 0.1, 0.5])
    axis = np.array([0.0, 0.0, 1.0])
    coarse = single_mount(knob, axis, PartsConfig())
    dense = knob
    while len(dense.vertices) < 200_000:
        dense = dense.subdivide()
    tracemalloc.start()
    fine = single_mount(dense, axis, PartsConfig())
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    assert coarse is not None and fine is not None
    assert np.allclose(coarse[:2], fine[:2], atol=1e-3)  # (along the axis, the foot band holds the sides too)
    assert peak < 300, peak


def test_1_merging_thousands_of_hulls_seeds_in_bounded_memory(tile_grid):
    from rest2art.collision.hulls import merged_hulls

    tiles = tile_grid(50, 40, 0.01, 0.002)
    tracemalloc.start()
    merged = merged_hulls(tiles, len(tiles) - 10)
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    assert len(merged) == len(tiles) - 10
    assert peak < 150, peak  # the gaps of every hull to every hull: 2,000 x 2,000 x 3 floats, 96 MB, more in temporaries


# (2), (3), (4) hostile asset folders -------------------------------------------------------------

def test_2_publish_refuses_a_mesh_symlinked_out_of_the_folder(sound, tmp_path, config_file):
    outside = tmp_path / "outside"
    outside.mkdir()
    secret = sentinel(outside)
    source = copy_of(sound, tmp_path / "linked")
    (source / "parts" / "door_0.obj").unlink()
    (source / "parts" / "door_0.obj").symlink_to(secret)
    catalog = tmp_path / "catalog"
    run = rest2art("publish", source, "--catalog", catalog, "--config", config_file)
    assert run.returncode == 3 and "door_0.obj' leads out of the asset folder" in run.stdout + run.stderr
    assert not (catalog / "linked").exists() and not was_read(secret)
    assert not (source / "validation.json").exists()  # the source is left as it is (10)


def test_2_a_folder_symlink_out_fails_the_files_check_and_a_link_inside_passes(sound, tmp_path):
    outside = tmp_path / "outside"
    shutil.copytree(sound / "parts", outside)
    source = copy_of(sound, tmp_path / "a")
    shutil.rmtree(source / "parts")
    (source / "parts").symlink_to(outside, target_is_directory=True)
    finding = check_files(source, "m")
    assert not finding.ok and "symlink 'parts' leads out" in finding.message
    inside = copy_of(sound, tmp_path / "b")
    (inside / "parts_real").mkdir()
    for mesh in (inside / "parts").iterdir():
        mesh.rename(inside / "parts_real" / mesh.name)
    (inside / "parts").rmdir()
    (inside / "parts").symlink_to("parts_real", target_is_directory=True)
    assert check_files(inside, "m").ok


def test_3_and_4_an_mjcf_include_out_of_the_folder_is_refused_before_any_simulator(sound, tmp_path, config):
    outside = tmp_path / "outside"
    outside.mkdir()
    included = sentinel(outside, "extra.xml", "<mujoco><asset/></mujoco>")
    passwd = sentinel(outside, "passwd", "root:x:0:0")
    source = copy_of(sound, tmp_path / "inc")
    mjcf = source / "m.xml"
    mjcf.write_text(mjcf.read_text().replace("<asset>", '<include file="../outside/extra.xml"/>\n  <asset>', 1))
    urdf = source / "m.urdf"
    urdf.write_text(urdf.read_text().replace('filename="parts/base.obj"', f'filename="{passwd}"', 1))
    findings = run_load_checks(source, "m", config.check)
    assert [f.check for f in findings] == ["files"] and not findings[0].ok
    assert "m.xml: path '../outside/extra.xml' points outside the asset folder" in findings[0].message
    assert f"path '{passwd}' is absolute" in findings[0].message
    assert not was_read(included) and not was_read(passwd)


def test_3_includes_inside_the_folder_are_followed_and_their_references_checked(sound, tmp_path):
    source = copy_of(sound, tmp_path / "inc")
    (source / "more.xml").write_text('<mujoco><asset><mesh name="x" file="parts/nothing.obj"/></asset></mujoco>')
    mjcf = source / "m.xml"
    mjcf.write_text(mjcf.read_text().replace("<asset>", '<include file="more.xml"/>\n  <asset>', 1))
    finding = check_files(source, "m")
    assert not finding.ok and "more.xml: 'parts/nothing.obj' does not exist" in finding.message


# (5) concurrent runs ---------------------------------------------------------------------------

def test_5_a_second_run_on_an_output_being_written_fails_at_once(tmp_path):
    out = tmp_path / "out"
    with output_lock(out):  # what a running reconstruct holds from its first second to its last
        start = time.perf_counter()
        run = rest2art("reconstruct", DEMO, "-o", out, "--no-check", "--quiet")
        assert run.returncode == 2 and "another run" in run.stderr and str(out) in run.stderr
        assert time.perf_counter() - start < 60 and not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # the lock file goes with its holder


# (6) killed runs -------------------------------------------------------------------------------

def test_6_stale_temporaries_of_a_killed_run_are_removed_by_the_next(tmp_path):
    out = tmp_path / "out"
    stale = tmp_path / ".out.tmp-deadbeef"
    (stale / "parts").mkdir(parents=True)
    (stale / "parts" / "base.obj").write_text("v 0 0 0\n")
    os.chmod(stale / "parts", 0o500)
    with atomic_folder(out) as tmp:
        (tmp / "articulation.json").write_text("{}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_6_scratch_folders_of_a_killed_process_are_removed_by_the_next_run(tmp_path, monkeypatch):
    """A process killed with SIGKILL inside the simulators' output capture leaves its scratch
    folder in the temporary directory; the next capture removes it, and keeps a live one's."""
    import tempfile

    from rest2art.io.atomic import dead_scratch
    from rest2art.sim.native import captured

    env = {**os.environ, "TMPDIR": str(tmp_path)}
    code = ("import os, time\nfrom rest2art.sim.native import captured\n"
            "ready = os.fdopen(os.dup(2), 'w')  # stderr as it was: the capture takes descriptor 2\n"
            "with captured():\n    ready.write('in\\n'); ready.flush(); time.sleep(60)\n")
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env, stderr=subprocess.PIPE) for _ in range(2)]
    try:
        for proc in procs:
            assert proc.stderr.readline() == b"in\n"
        procs[0].kill()
        procs[0].wait()
        killed, live = ([p.name for p in tmp_path.glob(f"rest2art-native-{proc.pid}-*")] for proc in procs)
        assert len(killed) == 1 and len(live) == 1
        assert [p.name for p in dead_scratch("rest2art-native", tmp_path)] == killed
        monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
        with captured():
            pass
        assert [p.name for p in tmp_path.glob("rest2art-native-*")] == live
    finally:
        for proc in procs:
            proc.kill()
            proc.wait()


@pytest.mark.slow
def test_6_sigterm_during_a_run_leaves_nothing_behind(tmp_path, config_file):
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "rest2art.cli", "reconstruct", DEMO, "-o", out, "--quiet",
                             "--config", config_file], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 400
    while time.time() < deadline and proc.poll() is None and not list(tmp_path.glob(".out.tmp-*")):
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before its output folder was being written"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 143 and "interrupted" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_6_a_signal_a_library_swallows_still_stops_the_commit(tmp_path):
    """trimesh catches BaseException in places: a SIGTERM landing there must not let the run
    commit its output."""
    out = tmp_path / "out"
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated), stop_on_signals():
        with atomic_folder(out) as tmp:
            (tmp / "part.obj").write_text("v 0 0 0\n")
            try:  # what a library that guards with ``except BaseException`` does
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(1.0)
            except BaseException:
                pass
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGTERM) is before


def coacd_runs_of(pid: int) -> list[int]:
    """Pids of the CoACD runs (``python -m rest2art.collision.hulls``) whose parent is ``pid``."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            ppid = int(stat.read_text().rsplit(")", 1)[1].split()[1])
            cmdline = (stat.parent / "cmdline").read_bytes()
        except (OSError, ValueError, IndexError):
            continue
        if ppid == pid and b"rest2art.collision.hulls" in cmdline:
            out.append(int(stat.parent.name))
    return out


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="finds the CoACD runs through /proc")
@pytest.mark.parametrize("whole_group", [True, False])
def test_6_ctrl_c_during_coacd_ends_the_run_at_once(tmp_path, whole_group):
    """Ctrl-C in a terminal signals the whole process group; ``kill -INT`` the run alone. Either
    way the run ends within seconds, not when its CoACD runs finish (they ignored the signal,
    and the interpreter waited for the threads waiting on them: 26 s), and no run is left."""
    cache = tmp_path / "cache"  # cold, and CoACD for every part (no boxes): CoACD has to run
    config_file = tmp_path / "config.yaml"
    config_file.write_text(json.dumps({"collision": {"cache_dir": str(cache), "strategy": "coacd"}}))
    from rest2art.generate import write_object

    write_object(generate_object("cabinet", 0, "scan"), tmp_path / "scan")  # a fused carcass: long CoACD runs
    proc = subprocess.Popen([sys.executable, "-m", "rest2art.cli", "reconstruct", tmp_path / "scan" / "mesh.obj",
                             "-o", tmp_path / "out", "--quiet", "--config", config_file],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.time() + 400
    runs: list[int] = []
    while time.time() < deadline and proc.poll() is None and not runs:
        runs = coacd_runs_of(proc.pid)
        time.sleep(0.05)
    assert runs, "the run ended before any CoACD run started"
    time.sleep(1.0)  # CoACD is well into its work
    asked = time.perf_counter()
    if whole_group:
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    took = time.perf_counter() - asked
    assert proc.returncode == 130 and "interrupted" in err
    assert took < 8.0, f"took {took:.1f} s to stop"
    time.sleep(0.5)
    assert not [pid for pid in runs if Path(f"/proc/{pid}").exists()]
    assert not (tmp_path / "out").exists()


# (7) read-only sources -------------------------------------------------------------------------

@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_7_a_read_only_source_is_published_and_validated(sound, tmp_path, config_file):
    source = copy_of(sound, tmp_path / "ro")
    for path in [*source.rglob("*"), source]:
        path.chmod(path.stat().st_mode & ~0o222)
    catalog = tmp_path / "catalog"
    run = rest2art("publish", source, "--catalog", catalog, "--config", config_file)
    assert run.returncode == 0, run.stderr
    assert sorted(p.name for p in catalog.iterdir()) == ["ro"]
    run = rest2art("validate", source, "--config", config_file)
    assert run.returncode == 0 and run.stdout.strip().endswith("publish") and "not written" in run.stderr


# (8) malformed XML and JSON --------------------------------------------------------------------

BOMB = ('<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;">]>\n'
        '<robot name="m">&lol2;</robot>\n')
EXTERNAL = '<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x SYSTEM "file://{secret}">]>\n<robot name="m">&x;</robot>\n'


def _plant(sound, tmp_path, case: str) -> tuple[Path, str, Path]:
    """A copy of the sound asset with one malformed file; (folder, the file's name, sentinel)."""
    outside = tmp_path / "outside"
    outside.mkdir(exist_ok=True)
    secret = sentinel(outside, "secret.txt", "secret")
    folder = copy_of(sound, tmp_path / case)
    urdf, meta = folder / "m.urdf", folder / "articulation.json"
    data = json.loads(meta.read_text())
    if case == "bomb":
        urdf.write_text(BOMB)
    elif case == "external":
        urdf.write_text(EXTERNAL.format(secret=secret))
    elif case == "truncated":
        urdf.write_text(urdf.read_text()[: len(urdf.read_text()) // 2])
    elif case == "nan_urdf":
        text = urdf.read_text()
        start = text.index("<axis xyz=")
        urdf.write_text(text[:start] + '<axis xyz="nan 0 1"/>' + text[text.index("/>", start) + 2:])
    elif case == "nan_json":
        data["joints"][0]["axis"][0] = float("nan")
        meta.write_text(json.dumps(data))
    elif case == "list":
        meta.write_text(json.dumps([data]))
    elif case == "missing":
        del data["joints"][0]["axis"]
        meta.write_text(json.dumps(data))
    return folder, ("articulation.json" if case in ("nan_json", "list", "missing") else "m.urdf"), secret


@pytest.mark.parametrize("case", ["bomb", "external", "truncated", "nan_urdf", "nan_json", "list", "missing"])
def test_8_malformed_xml_or_json_names_the_file_and_never_crashes(sound, tmp_path, case, config, capsys):
    folder, file, secret = _plant(sound, tmp_path, case)
    finding = check_files(folder, "m")
    assert not finding.ok and file in finding.message, finding.message
    code = main(["validate", str(folder)])
    err = capsys.readouterr().err
    assert code in (2, 3) and "internal error" not in err and "Traceback" not in err
    assert not was_read(secret)


def test_8_publish_names_the_users_file_not_its_copy(sound, tmp_path, config_file):
    folder, _, _ = _plant(sound, tmp_path, "truncated")
    run = rest2art("publish", folder, "--catalog", tmp_path / "catalog", "--config", config_file)
    assert run.returncode == 3 and "m.urdf: malformed XML" in run.stdout + run.stderr
    assert ".tmp-" not in run.stdout + run.stderr


# (9) native output -----------------------------------------------------------------------------

def test_9_native_output_goes_into_the_report_not_stdout_or_the_working_directory(sound, tmp_path, config_file):
    import re

    folder = copy_of(sound, tmp_path / "asset")  # a link without inertial: PyBullet warns on stdout
    urdf = folder / "m.urdf"
    urdf.write_text(re.sub(r"<inertial>.*?</inertial>", "", urdf.read_text(), count=1, flags=re.S))
    work = tmp_path / "work"
    work.mkdir()
    run = rest2art("validate", folder, "--config", config_file, cwd=work)
    assert run.returncode == 3 and "internal error" not in run.stderr
    assert run.stdout.strip().splitlines() == [f"{folder}: reject"]
    assert "pybullet build time" not in run.stderr  # printed on descriptor 2 at import
    assert list(work.iterdir()) == []
    findings = json.loads((folder / "validation.json").read_text())["rounds"][-1]["findings"]
    native = [f for f in findings if f["check"] == "native"]
    assert native and "No inertial data for link" in native[0]["data"]["output"]
    assert "pybullet build time" in native[0]["data"]["output"]


# (10) publish and reconstruct options ---------------------------------------------------------

@pytest.mark.parametrize("name", ["../x", "/abs", ".hidden", "a/b"])
def test_10_publish_name_cannot_leave_the_catalog(sound, tmp_path, name, capsys):
    catalog = tmp_path / "catalog"
    assert main(["publish", str(sound), "--catalog", str(catalog), "--name", name]) == 2
    assert "--name" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [] and not (tmp_path.parent / "x").exists()


def test_10_units_do_not_skip_the_size_check(tmp_path):
    from rest2art.errors import InputError
    from rest2art.io.load import load_mesh

    with pytest.raises(InputError, match="with --units m the object is 500 m across"):
        big = tmp_path / "big.obj"
        big.write_text("v 0 0 0\nv 500 0 0\nv 0 500 0\nv 0 0 500\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
        load_mesh(big, units="m")
    assert load_mesh(DEMO, units="m").scale_to_metres == 1.0


def test_10_an_existing_or_unwritable_output_is_refused_before_the_pipeline(tmp_path):
    existing = tmp_path / "existing"
    existing.mkdir()
    start = time.perf_counter()
    run = rest2art("reconstruct", DEMO, "-o", existing)
    assert run.returncode == 2 and "already exists" in run.stderr and "load" not in run.stderr
    blocker = tmp_path / "file"
    blocker.write_text("")
    run = rest2art("reconstruct", DEMO, "-o", blocker / "out")
    assert run.returncode == 2 and str(blocker) in run.stderr and "load" not in run.stderr
    assert time.perf_counter() - start < 60  # two process starts, no reconstruction


def test_10_a_rejected_overwrite_keeps_the_published_entry(sound, tmp_path, config_file):
    catalog = tmp_path / "catalog"
    assert rest2art("publish", sound, "--catalog", catalog, "--name", "m", "--config", config_file).returncode == 0
    before = (catalog / "m" / "validation.json").read_text()
    broken = copy_of(sound, tmp_path / "broken")
    (broken / "m.xml").write_text((broken / "m.xml").read_text().replace("parts/base.obj", "parts/gone.obj"))
    run = rest2art("publish", broken, "--catalog", catalog, "--name", "m", "--overwrite", "--config", config_file)
    assert run.returncode == 3
    assert (catalog / "m" / "validation.json").read_text() == before
    assert json.loads((catalog / "rejected" / "m" / "validation.json").read_text())["decision"]["status"] == "reject"


# (11) the same contacts in every engine --------------------------------------------------------

def test_11_pybullet_and_mujoco_see_the_same_sibling_contact_and_no_parent_one(config, tmp_path):
    """Two drawers of a cabinet pushed into each other: both engines report that pair, and
    neither reports a drawer touching the carcass it slides in (its parent)."""
    import mujoco
    import pybullet as pb
    from rest2art.sim import mujoco_engine, pybullet_engine

    asset = generate_object("cabinet", 2, "asset").asset
    complete_asset(asset, config)
    up = np.array([0.0, 0.0, 1.0])

    def footprint(joint) -> np.ndarray:  # (2, 2) x-y bounds of the drawer's hulls
        return np.vstack([hull.bounds for hull in asset.part(joint.child).collision])[:, :2]

    def stacked(a, b) -> bool:  # b sits above a: their footprints overlap, b's origin is higher
        fa, fb = footprint(a), footprint(b)
        overlap = np.minimum(fa.max(0), fb.max(0)) - np.maximum(fa.min(0), fb.min(0))
        return bool((overlap > 0.0).all()) and float((b.origin - a.origin) @ up) > 0.0

    drawers = [j for j in asset.joints if j.type == "prismatic"]
    pairs = [(a, b) for a in drawers for b in drawers if a is not b and stacked(a, b)]
    assert pairs  # the cabinet has a column of drawers
    lower, upper = min(pairs, key=lambda ab: float((ab[1].origin - ab[0].origin) @ up))
    gap = float((upper.origin - lower.origin) @ up)
    for hull in asset.part(lower.child).collision:  # the lower drawer's hulls reach into the upper one
        hull.apply_translation(0.5 * gap * up)
    folder = tmp_path / "asset"
    with atomic_folder(folder) as tmp:
        write_asset(asset, tmp, "c", config.export, np.array([0.0, 0.0, 1.0]))
    pair = "-".join(sorted((lower.child, upper.child)))

    client = pb.connect(pb.DIRECT)
    try:
        body = pybullet_engine._load_fixed(client, folder, "c", np.zeros(3), 0.002)
        pb.performCollisionDetection(physicsClientId=client)
        links = {pb.getJointInfo(body, j, physicsClientId=client)[12].decode(): j
                 for j in range(pb.getNumJoints(body, physicsClientId=client))}
        bullet = pybullet_engine.touching(client, body, links[lower.child])
    finally:
        pb.disconnect(client)
    model = mujoco_engine.load_model(folder, "c", np.zeros(3))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    muj = mujoco_engine.touching(model, data, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, lower.child))
    assert pair in bullet and pair in muj, (bullet, muj)
    assert bullet == muj  # a drawer beside it, a few mm away, is not a contact in either
    parent = "-".join(sorted((lower.child, lower.parent)))
    assert parent not in bullet and parent not in muj
