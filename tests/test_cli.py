"""The real CLI in a subprocess: help, demo-like run, errors with one-line reasons."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from rest2art.generate import generate_object, write_object


def rest2art(*args, cwd=None):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, "-m", "rest2art.cli", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=600)


@pytest.mark.parametrize("command", [[], ["reconstruct"], ["demo"], ["generate"], ["validate"], ["render"],
                                     ["bench", "run"], ["bench", "score"], ["publish"],
                                     ["bench", "prepare"]])
def test_help(command):
    out = rest2art(*command, "--help")
    assert out.returncode == 0 and "usage: rest2art" in out.stdout


def test_reconstruct_writes_the_contract_and_refuses_to_overwrite(tmp_path, config_file):
    mesh = write_object(generate_object("microwave", 5, "asset"), tmp_path / "src")
    out = tmp_path / "asset"
    run = rest2art("reconstruct", mesh, "-o", out, "--config", config_file, "--quiet")
    assert run.returncode == 0, run.stderr
    assert "validation: publish" in run.stdout
    for name in ("articulation.json", "face_part.npy", "mesh.urdf", "mesh.xml", "validation.json", "config.json"):
        assert (out / name).is_file(), name
    before = (out / "articulation.json").read_text()
    again = rest2art("reconstruct", mesh, "-o", out, "--config", config_file, "--no-check")
    assert again.returncode == 2 and "already exists; pass --overwrite" in again.stderr
    assert (out / "articulation.json").read_text() == before


def test_bad_input_names_the_file_and_leaves_nothing(tmp_path):
    bad = tmp_path / "broken.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    out = tmp_path / "out"
    run = rest2art("reconstruct", bad, "-o", out)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and "broken.obj" in run.stderr and "zero area" in run.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["broken.obj"]
    missing = rest2art("reconstruct", tmp_path / "nope.ply", "-o", out)
    assert missing.returncode == 2 and "nope.ply: file not found" in missing.stderr


def test_unwritable_output(tmp_path, config_file):
    if os.geteuid() == 0:
        target = Path("/proc/rest2art-out")  # not writable even for root
    else:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        target = ro / "out"
    mesh = write_object(generate_object("laptop", 1, "asset"), tmp_path / "src")
    run = rest2art("reconstruct", mesh, "-o", target, "--config", config_file, "--no-check")
    assert run.returncode == 2
    assert f"rest2art: error: {target.parent}: output folder is not writable" in run.stderr


def test_generate_both_variants(tmp_path):
    run = rest2art("generate", "box", "--count", "2", "--variant", "both", "--scan-voxel", "0.01", "-o", tmp_path)
    assert run.returncode == 0, run.stderr
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["box_0000_asset", "box_0000_scan", "box_0001_asset", "box_0001_scan"]


def test_direction_options_take_values_written_with_a_sign(tmp_path, config_file):
    """`--front -y` as the README writes it (argparse alone reads -y as an option)."""
    mesh = write_object(generate_object("cabinet", 2, "asset"), tmp_path / "src")
    out = tmp_path / "asset"
    run = rest2art("reconstruct", mesh, "-o", out, "--up", "+z", "--front", "-y", "--config", config_file,
                   "--no-check", "--quiet")
    assert run.returncode == 0, run.stderr
    import json

    frame = json.loads((out / "articulation.json").read_text())["metadata"]["frame"]
    assert frame["front"] == [0.0, -1.0, 0.0] and frame["evidence"]["front"] == "given"
