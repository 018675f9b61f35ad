#!/usr/bin/env python3
"""Makes the virtual environment in which Filament 1.76 (as the PyPI wheel open3d-cpu==0.20.0 links
it) renders brdfbake's `--target filament` files: filament_render.py runs in it.

    python3 tests/engines/filament/setup_open3d.py            # prints the environment's python

Idempotent: a second run with a working environment does nothing. The environment is
$BRDFBAKE_OPEN3D_VENV, else CACHE/open3d-venv with CACHE = $BRDFBAKE_ENGINES_CACHE, else build/engines/
in the repository. The wheel comes from `pip download --no-deps open3d-cpu==0.20.0` into CACHE/wheels/
(network: PyPI only), unless $BRDFBAKE_OPEN3D_WHEEL names an already downloaded copy; either way its
SHA-256 must be WHEEL_SHA256 (the cp311 manylinux_2_35 x86_64 wheel; another platform's wheel is
accepted with a warning when $BRDFBAKE_OPEN3D_ANY_WHEEL=1).

Installed: the wheel with --no-deps, and numpy (NUMPY): nothing else. open3d declares dash, flask,
werkzeug, nbformat, configargparse and ipywidgets for its web and notebook viewers; the rendering
module needs none of them (its package __init__ imports plotly and dash for draw_plotly only, and
filament_render.import_open3d puts empty stand-ins there). Measured on this machine (2 cores, the
wheel already downloaded, numpy from PyPI): 8.7 s, 399 MiB (open3d 312 MiB unpacked, numpy 73 MiB,
pip 17 MiB). open3d's declared dependencies (six direct ones and their own) are not installed.

Also needed, from Debian: libvulkan1 and mesa-vulkan-drivers (lavapipe, Vulkan on the CPU);
scripts/deps.sh installs them. `--check` only reports whether everything is there (exit 0/1)."""

import hashlib
import os
import pathlib
import shutil
import subprocess
import sys
import time

REPO = pathlib.Path(__file__).resolve().parents[3]
OPEN3D = "open3d-cpu==0.20.0"
WHEEL_NAME = "open3d_cpu-0.20.0-cp311-cp311-manylinux_2_35_x86_64.whl"
WHEEL_SHA256 = "5b7b6ecd566e12fc7d55b1de476b5b35461deb632b40216ad52894cf402aed90"
NUMPY = "numpy==2.4.6"
PYTHON = os.environ.get("BRDFBAKE_OPEN3D_PYTHON", "python3.11")  # the wheel is cp311
LAVAPIPE_ICD = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
STAMP = ".brdfbake-open3d"


class MissingWheel(RuntimeError):
    pass


def cache_dir():
    return pathlib.Path(os.environ.get("BRDFBAKE_ENGINES_CACHE") or REPO / "build" / "engines")


def venv_dir():
    return pathlib.Path(os.environ.get("BRDFBAKE_OPEN3D_VENV") or cache_dir() / "open3d-venv")


def venv_python(venv=None):
    return (venv or venv_dir()) / "bin" / "python"


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def wheel(download=True, quiet=False):
    """The pinned wheel: $BRDFBAKE_OPEN3D_WHEEL, else CACHE/wheels/WHEEL_NAME (downloaded from PyPI
    when missing and `download`). Raises MissingWheel."""
    given = os.environ.get("BRDFBAKE_OPEN3D_WHEEL")
    path = pathlib.Path(given) if given else cache_dir() / "wheels" / WHEEL_NAME
    if not path.is_file():
        if given or not download:
            raise MissingWheel(f"{path} is missing (python3 tests/engines/filament/setup_open3d.py downloads "
                               f"{OPEN3D} from PyPI, 105 MB; or set BRDFBAKE_OPEN3D_WHEEL)")
        path.parent.mkdir(parents=True, exist_ok=True)
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary", ":all:", "--python-version",
               "3.11", "--platform", "manylinux_2_35_x86_64", "-d", str(path.parent), OPEN3D]
        if not quiet:
            print("fetching", OPEN3D, "from PyPI", file=sys.stderr)
        subprocess.run(cmd, check=True, timeout=900, stdout=subprocess.DEVNULL if quiet else None)
    digest = _sha256(path)
    if digest != WHEEL_SHA256:
        if os.environ.get("BRDFBAKE_OPEN3D_ANY_WHEEL") == "1":
            print(f"warning: {path.name} has SHA-256 {digest}, not the pinned {WHEEL_SHA256}", file=sys.stderr)
        else:
            raise MissingWheel(f"{path}: SHA-256 {digest}, expected {WHEEL_SHA256} ({WHEEL_NAME})")
    return path


def check(venv=None):
    """None when the environment can render, else the reason (one line)."""
    venv = venv or venv_dir()
    if not os.path.exists(LAVAPIPE_ICD) and not os.environ.get("BRDFBAKE_VK_ICD"):
        return f"no lavapipe Vulkan driver ({LAVAPIPE_ICD}; apt-get install libvulkan1 mesa-vulkan-drivers)"
    stamp = venv / STAMP
    if not venv_python(venv).exists() or not stamp.exists() or stamp.read_text().strip() != WHEEL_SHA256:
        return f"no open3d environment at {venv} (python3 tests/engines/filament/setup_open3d.py makes it)"
    return None


def _smoke(venv):
    """The environment imports open3d's renderer (the stand-ins of filament_render included)."""
    code = ("import sys; sys.path.insert(0, %r); import filament_render as f; o3d, r = f.import_open3d(); "
            "assert o3d.__version__ == '0.20.0', o3d.__version__; print(o3d.__version__)" % str(pathlib.Path(__file__).parent))
    r = subprocess.run([str(venv_python(venv)), "-c", code], capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        raise RuntimeError(f"the open3d environment does not import: {r.stderr[-2000:]}")


DFG_RAW = "filament-1.76-dfg.f16"  # in the cache folder: Filament's built-in DFG table as the wheel ships it
DFG_BYTES = 128 * 128 * 3 * 2


def extract_dfg_raw(library):
    """The bytes of Filament's built-in DFG table (128 x 128 RGB16F, little-endian half floats, [row][column][rgb]
    as uploaded) out of a library that links Filament: the only Zstd frame whose declared content size is
    DFG_BYTES (filament/src/DFG.cpp, DFG::init: a compressed resource), decompressed with Debian's `zstd`.
    Returns None when there is no such frame."""
    blob = pathlib.Path(library).read_bytes()
    magic, start = b"\x28\xb5\x2f\xfd", 0
    while True:
        p = blob.find(magic, start)
        if p < 0:
            return None
        start = p + 1
        fhd = blob[p + 4]
        fcs_flag, single, dict_flag = fhd >> 6, (fhd >> 5) & 1, fhd & 3
        off = p + 5 + (0 if single else 1) + (0, 1, 2, 4)[dict_flag]
        nbytes = (1 if single else 0, 2, 4, 8)[fcs_flag]
        if nbytes == 0:
            continue
        content = int.from_bytes(blob[off:off + nbytes], "little") + (256 if nbytes == 2 else 0)
        if content != DFG_BYTES:
            continue
        r = subprocess.run(["zstd", "-d", "-c"], input=blob[p:p + DFG_BYTES + 4096], capture_output=True, timeout=60)
        if len(r.stdout) >= DFG_BYTES:
            return r.stdout[:DFG_BYTES]


def write_dfg_raw(venv):
    """CACHE/DFG_RAW from the environment's libOpen3D (for tests/host/test_filament_dfg.cpp); its path."""
    out = cache_dir() / DFG_RAW
    if out.is_file() and out.stat().st_size == DFG_BYTES:
        return out
    libs = sorted(venv.rglob("libOpen3D.so*"))
    if not libs:
        raise MissingWheel(f"no libOpen3D.so in {venv}")
    raw = extract_dfg_raw(libs[0])
    if raw is None:
        raise MissingWheel(f"no DFG table found in {libs[0]}")
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    tmp.write_bytes(raw)
    tmp.replace(out)
    return out


def setup(download=True, quiet=False):
    """Makes (or finds) the environment and the extracted DFG table; returns its python."""
    venv = venv_dir()
    if check(venv) is None:
        write_dfg_raw(venv)
        return venv_python(venv)
    whl = wheel(download, quiet)
    t0 = time.time()
    if venv.exists():
        shutil.rmtree(venv)
    python = shutil.which(PYTHON) or PYTHON
    subprocess.run([python, "-m", "venv", str(venv)], check=True, timeout=300)
    pip = [str(venv_python(venv)), "-m", "pip", "install", "--disable-pip-version-check", "--no-input"]
    if quiet:
        pip.append("--quiet")
    subprocess.run(pip + ["--no-deps", str(whl), NUMPY], check=True, timeout=900)
    _smoke(venv)
    (venv / STAMP).write_text(WHEEL_SHA256 + "\n")
    write_dfg_raw(venv)
    if not quiet:
        size = sum(f.stat().st_size for f in venv.rglob("*") if f.is_file())
        print(f"open3d environment {venv}: {time.time() - t0:.1f} s, {size / 2 ** 20:.0f} MiB", file=sys.stderr)
    return venv_python(venv)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if "--check" in argv:
        why = check()
        print(why or f"ok: {venv_python()}")
        return 1 if why else 0
    try:
        print(setup(download="--no-download" not in argv))
    except MissingWheel as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
