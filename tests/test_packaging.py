"""Install layout: sub-packages do not shadow PyPI names; heavy imports stay lazy."""

import importlib
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_sim_and_validators_are_subpackages():
    sim = importlib.import_module("rest2art.sim")
    val = importlib.import_module("rest2art.validators")
    assert Path(sim.__file__).parent.name == "sim"
    assert Path(val.__file__).parent.name == "validators"


def test_pypi_validators_is_not_shadowed(tmp_path):
    """From any folder but the checkout's root, `import validators` is PyPI's package."""
    code = "import validators, rest2art.validators; print(validators.__file__); print(validators.url('https://example.org'))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=tmp_path)
    path, result = out.stdout.split()
    assert Path(path).resolve() != (REPO / "validators" / "__init__.py").resolve()
    assert "site-packages" in Path(path).parts and result == "True"


def test_cli_import_does_not_load_simulators_or_models():
    code = ("import sys, rest2art.cli, rest2art.pipeline; "
            "heavy = [m for m in ('mujoco', 'pybullet', 'sapien', 'coacd', 'torch', 'yourdfpy') if m in sys.modules]; "
            "print(','.join(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_every_source_folder_is_a_listed_package():
    """A folder of modules missing from pyproject's list would be left out of a wheel."""
    import tomllib

    listed = set(tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    folders = {".".join(p.parent.relative_to(REPO).parts) for p in (REPO / "rest2art").rglob("*.py")}
    assert folders <= listed, f"not packaged: {sorted(folders - listed)}"


def test_the_top_level_package_has_its_version_and_a_lazy_public_api():
    from importlib.metadata import version

    code = ("import sys, rest2art; loaded = 'trimesh' in sys.modules; "
            "from rest2art import reconstruct_file, write_asset, validate_folder, ArticulatedAsset; "
            "print(rest2art.__version__, loaded, reconstruct_file.__module__, validate_folder.__module__)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    found, loaded, pipeline, validators = out.stdout.split()
    assert found == version("rest2art") and loaded == "False"
    assert (pipeline, validators) == ("rest2art.pipeline", "rest2art.validators.validate")
