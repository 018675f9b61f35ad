"""Fixtures of the Python package's tests (tests/python): the installed package, the command-line
tool to compare with, a material file. scripts/test.sh installs the package into a fresh virtual
environment and runs these after the C++ suite, with BRDFBAKE_CLI naming the tool it built."""

import json
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


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
