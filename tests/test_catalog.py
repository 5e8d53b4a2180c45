"""Catalog builds: inputs and keys, the index on disk, real builds (resumed after SIGKILL, planted
crashes, Ray), the loader, the CLI and the pages in a real headless browser."""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import trimesh
import yaml

import rest2art.catalog
from rest2art.catalog.build import build_catalog
from rest2art.catalog.inputs import FAULTS_ENV, collect_jobs, unique_names
from rest2art.catalog.records import file_hashes
from rest2art.catalog.store import INDEX, CatalogStore, read_index, snapshot, verify
from rest2art.config import load_config
from rest2art.errors import InputError
from rest2art.generate import generate_object, write_object

OBJECTS = [("box", 1), ("laptop", 0), ("microwave", 0)]
"""Generated asset-variant objects of the small builds (plus one static block). Box 1 has a handle
on its lid; the plain box 0 shows no front, so its lid's hinge edge is a guess and it is refused."""


def _cli(*args: str, env: dict | None = None, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rest2art.cli", *args], capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, timeout=900, **kwargs)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> Path:
    """A folder of generated objects (asset variant) and a plain block with no movable part."""
    root = tmp_path_factory.mktemp("catalog-inputs")
    for kind, seed in OBJECTS:
        write_object(generate_object(kind, seed, "asset"), root / f"{kind}_{seed:04d}")
    block = root / "block"
    block.mkdir()
    trimesh.creation.box(extents=(0.4, 0.3, 0.5)).export(block / "block.obj")
    return root


@pytest.fixture(scope="module")
def build_config(config, tmp_path_factory) -> Path:
    """Segmentation off (the asset variant's pieces are separate), the session's CoACD cache."""
    path = tmp_path_factory.mktemp("catalog-cfg") / "catalog.yaml"
    path.write_text(yaml.safe_dump({"segment": {"enabled": False},
                                    "collision": {"cache_dir": config.collision.cache_dir}}))
    return path


@pytest.fixture(scope="module")
def reference(inputs, build_config, tmp_path_factory) -> tuple[Path, float]:
    """The small catalog built once without interruption with 2 workers; (folder, seconds)."""
    root = tmp_path_factory.mktemp("catalog-ref") / "assets_out"
    start = time.perf_counter()
    report = build_catalog([inputs], root, load_config(build_config), workers=2)
    assert report.failed == [], report.records
    return root, time.perf_counter() - start


# ---- inputs and keys -----------------------------------------------------------------------------

def test_names_follow_stems_then_folders(tmp_path):
    paths = [tmp_path / "a" / "mesh.obj", tmp_path / "b" / "mesh.obj", tmp_path / "c" / "drawer.obj"]
    assert unique_names(paths) == ["a", "b", "drawer"]


def test_jobs_from_folder_and_manifest_with_content_keys(inputs, tmp_path):
    jobs = collect_jobs([inputs])
    assert sorted(j.name for j in jobs) == ["block", "box_0001", "laptop_0000", "microwave_0000"]
    assert len({j.key for j in jobs}) == len(jobs)
    again = {j.name: j.key for j in collect_jobs([inputs])}
    assert again == {j.name: j.key for j in jobs}  # same bytes, config and version: same key
    other = {j.name: j.key for j in collect_jobs([inputs], load_config(overrides={"joints": {"door_limit_deg": 80}}))}
    assert all(other[n] != k for n, k in again.items())  # a config change rebuilds everything
    timeout = {j.name: j.key for j in collect_jobs([inputs], load_config(overrides={"catalog": {"timeout_s": 5}}))}
    assert timeout == again  # build settings change no result
    cache = {j.name: j.key for j in collect_jobs([inputs], load_config(overrides={"collision": {"cache_dir": str(tmp_path)}}))}
    assert cache == again  # nor does where decompositions are cached

    mesh = inputs / "box_0001" / "mesh.obj"
    manifest = tmp_path / "objects.jsonl"
    manifest.write_text(json.dumps({"path": str(mesh), "name": "my box", "units": "m", "category": "chest"}) + "\n")
    (job,) = collect_jobs([manifest])
    assert (job.name, job.category, job.units) == ("my_box", "chest", "m")
    assert job.key != again["box_0001"]  # hints are part of the key


@pytest.mark.parametrize("line, message", [
    ("{not json", r"objects.jsonl:1: not a JSON object"),
    (json.dumps({"name": "x"}), r"objects.jsonl:1: each line needs a \"path\""),
    (json.dumps({"path": "nowhere.obj"}), r"objects.jsonl:1: mesh file .*nowhere.obj not found"),
    (json.dumps({"path": "x.obj", "colour": 1}), r"objects.jsonl:1: unknown field\(s\) colour"),
])
def test_bad_manifest_line_names_file_and_line(tmp_path, line, message):
    (tmp_path / "x.obj").write_text("v 0 0 0\n")
    manifest = tmp_path / "objects.jsonl"
    manifest.write_text(line + "\n")
    with pytest.raises(InputError, match=message):
        collect_jobs([manifest])


# ---- the index on disk -----------------------------------------------------------------------------

def _record(name: str, key: str, outcome: str = "published") -> dict:
    return {"name": name, "source": f"/in/{name}.obj", "key": key, "outcome": outcome, "category": "box"}


def _commit(store: CatalogStore, name: str, key: str, text: str) -> dict:
    work = store.work_folder(name)
    (work / "a.txt").write_text(text)
    return store.commit({**_record(name, key), "files": file_hashes(work)}, work)


def test_store_repairs_torn_line_and_unindexed_entry(tmp_path):
    root = tmp_path / "cat"
    with CatalogStore(root) as store:
        _commit(store, "one", "k1", "first")
        _commit(store, "two", "k2", "second")
        store.commit(_record("three", "k3", "failed"), None)
    lines = (root / INDEX).read_bytes().splitlines(keepends=True)
    # a build killed after renaming 'two' into place, in the middle of writing its line
    (root / INDEX).write_bytes(lines[0] + lines[1][:25])
    (root / ".work" / "half-written").mkdir(parents=True)
    with CatalogStore(root) as store:
        assert [r["name"] for r in store.records()] == ["one", "two"]  # 'two' indexed from its entry
        assert store.done_keys() == {"k1", "k2"}
    assert (root / INDEX).read_bytes().endswith(b"\n") and not (root / ".work").exists()
    assert verify(root) == []
    (root / "two" / "a.txt").write_text("changed")
    (root / "one" / "extra.txt").write_text("x")
    assert verify(root) == ["one/extra.txt: not listed in entry.json", "two/a.txt: content changed (sha256 differs)"]


def test_second_writer_is_refused(tmp_path):
    with CatalogStore(tmp_path / "cat"):
        with pytest.raises(InputError, match="another build is writing this catalog"):
            with CatalogStore(tmp_path / "cat"):
                pass


MAIN_SCRIPT = """
import os
import pkg.heavy  # noqa: F401  (writes this process's pid once per import)
from rest2art.catalog.isolate import worker_context

def nothing():
    pass

if __name__ == "__main__":
    for _ in range(3):
        worker = worker_context().Process(target=nothing)
        worker.start()
        worker.join()
        assert worker.exitcode == 0
"""


def test_workers_find_the_imports_of_their_parents_main_file(tmp_path):
    """A worker runs its parent's main file again; the forkserver imports it first, so what
    that file imports (all of Ray, in a Ray worker) is imported once, not once per object."""
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "heavy.py").write_text(f"import os\nwith open({str(tmp_path / 'imports')!r}, 'a') as f:\n"
                                               "    f.write(f'{os.getpid()}\\n')\n")
    (tmp_path / "pkg" / "main.py").write_text(MAIN_SCRIPT)
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    subprocess.run([sys.executable, str(tmp_path / "pkg" / "main.py")], env=env, check=True, timeout=300)
    importers = (tmp_path / "imports").read_text().split()
    assert len(importers) == 2  # this script and the forkserver; not each of the three workers


def test_ray_flag_without_ray_says_what_to_install(inputs, tmp_path):
    code = ("import sys; sys.modules['ray'] = None; from rest2art.cli import main; "  # as if Ray were not installed
            f"sys.exit(main(['catalog', 'build', {str(inputs)!r}, '--catalog', {str(tmp_path / 'c')!r}, '--ray', 'auto']))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 2
    assert out.stderr.strip() == 'rest2art: error: --ray needs Ray, which is not installed: pip install -e ".[ray]" ' \
                                 '(or pip install "ray>=2.9")'


def test_not_a_catalog_is_one_line(tmp_path):
    out = _cli("catalog", "summary", "--catalog", str(tmp_path))
    assert out.returncode == 2 and out.stderr.strip() == f"rest2art: error: {tmp_path}: not a catalog (no index.jsonl)"


# ---- real builds -----------------------------------------------------------------------------------

@pytest.mark.slow
def test_build_outcomes_and_files(reference):
    root, _ = reference
    records = {r["name"]: r for r in read_index(root)}
    assert {n: r["outcome"] for n, r in records.items()} == {
        "block": "static", "box_0001": "published", "laptop_0000": "published", "microwave_0000": "published"}
    assert len(read_index(root)) == 4
    for name in ("box_0001", "laptop_0000", "microwave_0000"):
        r = records[name]
        folder = root / r["path"]
        assert (folder / r["urdf"]).is_file() and (folder / r["mjcf"]).is_file()
        assert r["validation"]["decision"] == "publish" and r["hulls"] >= 1 and r["mass"] > 0
        assert sum(r["joints"].values()) == len(r["joint_table"]) >= 1
        for joint in r["joint_table"]:
            assert (folder / r["pictures"][joint["name"]]).stat().st_size > 0
    assert verify(root) == []
    assert not (root / ".work").exists() and not list(root.glob(".*tmp*"))


def _processes_writing_under(folder: Path) -> list[int]:
    """Pids of processes with a file open under ``folder`` (workers keep their log open)."""
    pids = []
    for fd_dir in Path("/proc").glob("[0-9]*/fd"):
        try:
            if any(os.readlink(fd).startswith(str(folder)) for fd in fd_dir.iterdir()):
                pids.append(int(fd_dir.parent.name))
        except OSError:  # gone meanwhile, or not ours to read
            continue
    return pids


@pytest.mark.slow
def test_killed_build_resumes_to_the_same_catalog(reference, inputs, build_config, tmp_path):
    ref_root, ref_seconds = reference
    root = tmp_path / "assets_out"
    rng = random.Random()
    delay = rng.uniform(0.2, 0.9) * ref_seconds
    args = ["catalog", "build", str(inputs), "--catalog", str(root), "--workers", "2", "--config", str(build_config),
            "--quiet"]
    proc = subprocess.Popen([sys.executable, "-m", "rest2art.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    time.sleep(delay)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 3  # a worker kills itself within milliseconds of the build
    while _processes_writing_under(root) and time.monotonic() < deadline:
        time.sleep(0.5)
    assert _processes_writing_under(root) == [], "workers outlived the killed build"
    entries = root.glob("*/entry.json")  # renamed into place but maybe killed before its line was written
    before = len({r["key"] for r in read_index(root)} | {json.loads(p.read_text())["key"] for p in entries})
    out = _cli(*args)
    assert out.returncode == 0, out.stdout + out.stderr
    assert f"({before} already built)" in out.stdout, (delay, out.stdout)
    assert snapshot(root) == snapshot(ref_root), f"killed after {delay:.1f} s"
    assert len(read_index(root)) == 4  # nothing indexed twice
    assert verify(root) == []
    again = _cli(*args)  # a finished catalog: everything skipped, nothing appended
    assert again.returncode == 0 and "(4 already built)" in again.stdout
    assert len(read_index(root)) == 4


@pytest.mark.slow
def test_planted_crash_timeout_and_hog_fail_while_others_publish(inputs, build_config, tmp_path):
    faulty = tmp_path / "in"
    for name in ("crash", "slow", "hog", "fine"):  # same object, different bytes: different keys
        (faulty / name).mkdir(parents=True)
        mesh = (inputs / "box_0001" / "mesh.obj").read_text()
        (faulty / name / f"{name}.obj").write_text(f"# {name}\n{mesh}")
    config = yaml.safe_load(build_config.read_text())
    config["catalog"] = {"timeout_s": 40.0, "memory_limit_mb": 3072}
    config_path = tmp_path / "limits.yaml"
    config_path.write_text(yaml.safe_dump(config))
    root = tmp_path / "assets_out"
    args = ["catalog", "build", str(faulty), "--catalog", str(root), "--workers", "2", "--config", str(config_path),
            "--quiet"]
    out = _cli(*args, env={FAULTS_ENV: "crash:abort,slow:sleep,hog:hog"})
    assert out.returncode == 3, out.stdout + out.stderr
    records = {r["name"]: r for r in read_index(root)}
    assert records["fine"]["outcome"] == "published"
    assert records["crash"]["outcome"] == "failed" and "SIGABRT (native abort)" in records["crash"]["error"]
    assert "plant_fault" in records["crash"]["log_tail"]  # the Python stack of the crash, from the worker's log
    assert records["slow"]["outcome"] == "failed" and records["slow"]["error"] == "timed out after 40 s"
    assert records["hog"]["outcome"] == "failed" and "out of memory" in records["hog"]["error"]
    assert "failed: crash: crashed: SIGABRT" in out.stdout
    # failed objects are skipped on resume unless retried; retried without the faults they publish
    assert _cli(*args).returncode == 3
    retried = _cli(*args, "--retry-failed")
    assert retried.returncode == 0, retried.stdout
    assert {r["name"]: r["outcome"] for r in rest2art.catalog.store.latest_records(read_index(root)).values()} == {
        n: "published" for n in ("crash", "slow", "hog", "fine")}


@pytest.mark.slow
def test_allow_static_publishes_a_rigid_asset(inputs, build_config, tmp_path):
    import mujoco

    root = tmp_path / "assets_out"
    out = _cli("catalog", "build", str(inputs / "block"), "--catalog", str(root), "--config", str(build_config),
               "--allow-static", "--quiet")
    assert out.returncode == 0, out.stdout + out.stderr
    (entry,) = rest2art.catalog.open(root)
    assert entry.name == "block" and entry.joints == {} and entry.record["validation"]["decision"] == "publish"
    assert mujoco.MjModel.from_xml_path(str(entry.mjcf)).njnt == 0


@pytest.mark.slow
def test_ray_build_gives_the_same_index(reference, inputs, build_config, tmp_path):
    ray = pytest.importorskip("ray", reason="Ray is not installed (pip install -e \".[ray]\")")
    ref_root, _ = reference
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        report = build_catalog([inputs], tmp_path / "assets_out", load_config(build_config), ray_address="auto")
    finally:
        ray.shutdown()
    assert report.failed == []
    assert snapshot(tmp_path / "assets_out") == snapshot(ref_root)
    assert verify(tmp_path / "assets_out") == []


@pytest.mark.slow
def test_loader_filters_and_the_assets_load_in_mujoco(reference):
    import mujoco

    root, _ = reference
    catalog = rest2art.catalog.open(root)
    assert sorted(e.name for e in catalog) == ["box_0001", "laptop_0000", "microwave_0000"]  # published only
    assert "microwave" in catalog.categories
    microwaves = catalog.filter(category="microwave")
    assert [e.name for e in microwaves] == ["microwave_0000"]
    revolute = catalog.filter(joint_type="revolute")
    assert len(revolute) == 3 and len(catalog.filter(joint_type="prismatic")) == 0
    assert catalog.sample(2, seed=1) == catalog.sample(2, seed=1)
    for entry in catalog:
        model = mujoco.MjModel.from_xml_path(str(entry.mjcf))
        assert model.njnt == sum(n for t, n in entry.joints.items() if t != "fixed")
        assert entry.urdf.is_file() and entry.record["key"] == entry.key
    with pytest.raises(InputError, match="not a catalog"):
        rest2art.catalog.open(root / "box_0001")


@pytest.mark.slow
def test_summary_and_verify_commands(reference, tmp_path):
    ref_root, _ = reference
    root = tmp_path / "copy"
    shutil.copytree(ref_root, root)
    summary = _cli("catalog", "summary", "--catalog", str(root), "--top", "2")
    assert summary.returncode == 0
    assert "4 objects: published 3 rejected 0 static 1 failed 0" in summary.stdout
    assert "slowest 2:" in summary.stdout
    ok = _cli("catalog", "verify", "--catalog", str(root))
    assert ok.returncode == 0 and "3 entries checked, 0 problems" in ok.stdout
    urdf = root / "box_0001" / "box_0001.urdf"
    urdf.write_text(urdf.read_text().replace("revolute", "prismatic"))
    bad = _cli("catalog", "verify", "--catalog", str(root))
    assert bad.returncode == 3 and "box_0001/box_0001.urdf: content changed" in bad.stdout


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.slow
def test_pages_load_in_a_headless_browser(reference, tmp_path):
    playwright = pytest.importorskip("playwright.sync_api", reason="playwright is not installed (test extra)")
    browser_path = _chromium()
    if browser_path is None:
        pytest.skip("Chromium is not installed and could not be (apt-get install chromium; .ci/run does it)")
    root, _ = reference
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=browser_path, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1200, "height": 800})
        page.goto((root / "index.html").as_uri(), wait_until="load")
        loaded = "els => els.map(e => [e.getAttribute('src'), e.complete && e.naturalWidth > 0])"
        images = page.eval_on_selector_all("img", loaded)
        assert len(images) == 3 and all(ok for _, ok in images), images
        assert page.inner_text("#shown") == "4"
        page.uncheck("input[value=static]")
        assert page.inner_text("#shown") == "3"
        page.select_option("#category", "microwave")
        assert page.inner_text("#shown") == "1"
        page.screenshot(path=str(tmp_path / "index.png"), full_page=True)
        page.click("a[href='pages/microwave_0000.html']")
        page.wait_for_load_state("load")
        anims = page.eval_on_selector_all("img.anim", "els => els.map(e => e.complete && e.naturalWidth > 0)")
        pictures = page.eval_on_selector_all("img", "els => els.map(e => e.complete && e.naturalWidth > 0)")
        assert anims and all(anims) and all(pictures)
        assert "Validation: publish" in page.inner_text("body")
        page.screenshot(path=str(tmp_path / "asset.png"), full_page=True)
        browser.close()
    assert (tmp_path / "index.png").stat().st_size > 10_000 and (tmp_path / "asset.png").stat().st_size > 10_000
