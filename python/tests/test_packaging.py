"""The package as pip installs it (issue 46): `python3 -m build --wheel --no-isolation` makes a wheel from
the repository, which installs into a fresh venv and passes the Python tests there, with no PYTHONPATH.

Run by ctest as `python_wheel` with PORESHELL_CMAKE_BUILD_DIR set to the tests' build directory, so that
setup.py reuses the module built there (`cmake --build` finds nothing to do); skipped elsewhere (the
plain `python` test, which runs from build/python).
"""

import os
import pathlib
import subprocess
import sys
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD_DIR = os.environ.get("PORESHELL_CMAKE_BUILD_DIR")
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable

pytestmark = pytest.mark.skipif(not BUILD_DIR, reason="needs PORESHELL_CMAKE_BUILD_DIR (ctest python_wheel)")
# python3-build and python3-setuptools (scripts/install-deps); the wheel is made with this interpreter.
if BUILD_DIR and subprocess.run([PYTHON, "-c", "import build, setuptools, wheel"], capture_output=True).returncode:
    pytest.skip("python3-build, python3-setuptools or python3-wheel missing: run scripts/install-deps",
                allow_module_level=True)


def clean_env(**extra):
    """The environment without PYTHONPATH: the venv's poreshell must be the one imported."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(extra)
    return env


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    top = tmp_path_factory.mktemp("wheel")
    dist = top / "dist"
    subprocess.run(
        [PYTHON, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(dist), str(ROOT)],
        check=True, cwd=ROOT, env=clean_env(PORESHELL_CMAKE_BUILD_DIR=BUILD_DIR), stdout=subprocess.DEVNULL,
    )
    wheels = list(dist.glob("poreshell-*.whl"))
    assert len(wheels) == 1, wheels
    env_dir = top / "venv"
    # numpy (and pytest) from Debian's site-packages; the system pip installs into the venv it runs in.
    subprocess.run([PYTHON, "-m", "venv", "--system-site-packages", "--without-pip", str(env_dir)], check=True)
    python = env_dir / "bin" / "python"
    subprocess.run(
        [str(python), "-m", "pip", "install", "--no-index", "--no-deps", "-q", str(wheels[0])],
        check=True, env=clean_env(PIP_DISABLE_PIP_VERSION_CHECK="1"),
    )
    return wheels[0], python


def test_wheel_holds_the_package_its_stubs_and_the_module(venv):
    wheel, _ = venv
    assert wheel.name.startswith("poreshell-") and "-cp3" in wheel.name  # a binary wheel for this Python
    names = set(zipfile.ZipFile(wheel).namelist())
    for name in ("poreshell/__init__.py", "poreshell/__init__.pyi", "poreshell/py.typed", "poreshell/batch.py"):
        assert name in names, name
    assert any(n.startswith("poreshell/_poreshell") and n.endswith(".so") for n in names), names


def test_the_venv_imports_the_installed_package(venv, tmp_path):
    _, python = venv
    out = subprocess.run(
        [str(python), "-c", "import poreshell, sys; print(poreshell.__file__); print(poreshell.__version__)"],
        check=True, cwd=tmp_path, env=clean_env(), capture_output=True, text=True,
    ).stdout.split()
    assert pathlib.Path(out[0]).is_relative_to(python.parent.parent), out
    assert out[1] == subprocess.run(
        [PYTHON, "-c", "import re; print(re.search(r'project\\(poreshell VERSION ([0-9.]+)', "
                       "open('CMakeLists.txt').read()).group(1))"],
        check=True, cwd=ROOT, capture_output=True, text=True,
    ).stdout.strip()


def test_the_python_tests_pass_in_the_venv(venv, tmp_path):
    """The package's tests on the installed package; the bunny's 30 s comparison with the CLI and the
    Chromium picture run in the `python` test already, on the very module the wheel holds."""
    _, python = venv
    tests = ROOT / "python" / "tests"
    subprocess.run(
        [str(python), "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tests / "test_poreshell.py"),
         str(tests / "test_api_surface.py"), "-k", "not bunny_matches_cli and not viewer_picture"],
        check=True, cwd=tmp_path, env=clean_env(PYTHONDONTWRITEBYTECODE="1"),
    )
