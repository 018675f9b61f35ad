"""Fixtures of the Python package's tests (tests/python): the installed package, the command-line
tool to compare with, a material file. scripts/test.sh installs the package into a fresh virtual
environment and runs these after the C++ suite, with BRDFBAKE_CLI naming the tool it built."""

import json
import os
import pathlib
import shutil
import sys
import tempfile

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# BRDFBAKE_TEST_KEEP=1 keeps the tests' temporary folders (and says where), to look at afterwards.
KEEP = os.environ.get("BRDFBAKE_TEST_KEEP") == "1"


@pytest.hookimpl(tryfirst=True)
def pytest_configure(config):
    """The tests' temporary folders (tmp_path, tmp_path_factory) go into one folder made for this
    session, $TMPDIR/brdfbake-pytest-XXXXXX, removed when the session ends, passed or failed (issue 34:
    pytest's own $TMPDIR/pytest-of-USER keeps the last three sessions). Before pytest's tmpdir plugin
    reads --basetemp; a --basetemp given on the command line is left to pytest's rules."""
    if config.option.basetemp is None:
        root = tempfile.mkdtemp(prefix="brdfbake-pytest-")
        config.option.basetemp = os.path.join(root, "tmp")
        config.stash[_TEMP_ROOT] = root
        # Dask's workers (test_dask.py, examples/merl_sweep.py run by test_examples.py) keep their
        # scratch space in $TMPDIR/dask-scratch-space otherwise, left after the cluster closes.
        os.environ.setdefault("DASK_TEMPORARY_DIRECTORY", os.path.join(root, "dask"))


_TEMP_ROOT = pytest.StashKey[str]()


def pytest_unconfigure(config):
    root = config.stash.get(_TEMP_ROOT, None)
    if root is None:
        return
    if KEEP:
        print(f"BRDFBAKE_TEST_KEEP=1: kept {root}", file=sys.stderr)
    else:
        shutil.rmtree(root, ignore_errors=True)


@pytest.fixture
def tmp_path(tmp_path):
    """pytest's tmp_path, removed when the test ends, passed or failed (BRDFBAKE_TEST_KEEP=1 keeps it)."""
    yield tmp_path
    if not KEEP:
        shutil.rmtree(tmp_path, ignore_errors=True)


@pytest.fixture(scope="session")
def cli():
    """The brdfbake tool: $BRDFBAKE_CLI, else build/host/cli/brdfbake; tests that compare with it skip
    with a message when neither exists (scripts/test.sh always sets it)."""
    path = os.environ.get("BRDFBAKE_CLI") or str(REPO / "build" / "host" / "cli" / "brdfbake")
    if not os.access(path, os.X_OK):
        pytest.skip(f"the brdfbake command-line tool is not built ({path}); set BRDFBAKE_CLI")
    return path


RED = {"name": "red", "model": "disney", "baseColor": [0.8, 0.1, 0.1], "roughness": 0.4, "metallic": 0.2}


@pytest.fixture
def red():
    return dict(RED)


@pytest.fixture
def red_file(tmp_path):
    path = tmp_path / "red.json"
    path.write_text(json.dumps({"materials": [RED]}))
    return path


@pytest.fixture(scope="session")
def shared_dir():
    """../shared beside the repository (real HDR maps), or None."""
    for candidate in (os.environ.get("BRDFBAKE_SHARED_DIR"), str(REPO.parent / "shared")):
        if candidate and os.path.isdir(candidate):
            return pathlib.Path(candidate)
    return None
