"""Issue 24's hostile classes for the Python package: first calls from many threads at once, arrays
whose shape passes the limits before they take memory, and where the OpenImageIO module is loaded
from. Each case that could crash or load foreign code runs in a subprocess, so that a crash is a
failed test, not a dead test runner."""

import os
import pathlib
import shutil
import struct
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import brdfbake
from tolerances import ENV_FURNACE

PACKAGE = pathlib.Path(brdfbake.__file__).resolve().parent


def _python(code, env=None, timeout=120):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=timeout, env=env)


def test_first_calls_from_many_threads_at_once():
    # Eight threads make their process's first calls together (device discovery, opening the
    # default device, a table, the reference), released at once by a barrier; in six fresh
    # processes. Before, about half such processes died in device selection (SIGSEGV) or raised a
    # false "no OpenCL device is available".
    code = """
        import threading, brdfbake
        barrier = threading.Barrier(8)
        errors = []
        def work(i):
            barrier.wait()
            try:
                if i % 4 == 0:
                    assert any(d["default"] for d in brdfbake.devices())
                elif i % 4 == 1:
                    assert brdfbake.lut(kind="ggx", size=4).array.shape == (4, 4, 3)
                elif i % 4 == 2:
                    brdfbake.fresnel("dielectric", ior=1.5, size=4)
                else:
                    brdfbake.lut(kind="ggx", size=4, device="reference")
            except Exception as e:
                errors.append(repr(e))
        threads = [threading.Thread(target=work, args=(i,)) for i in range(8)]
        for t in threads: t.start()
        for t in threads: t.join()
        assert not errors, errors
        print("ok")
    """
    failures = []
    for run in range(6):
        got = _python(code)
        if got.returncode != 0 or "ok" not in got.stdout:
            failures.append(f"run {run}: exit {got.returncode}: {got.stderr[-600:]}")
    assert not failures, "\n".join(failures)


def test_a_broadcast_array_is_refused_on_its_shape():
    # 16384x32768 RGB is 2^29 pixels, past the limit of 2^28 (16384x16384) that files have: refused
    # naming the limit, before the view (no memory) is converted (6 GiB as float32, twice that with
    # the library's copy). In a subprocess with a 2 GiB address-space limit, so that
    # materialising it fails loudly instead of paging the machine.
    code = """
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
        import numpy as np, brdfbake
        for shape in [(16384, 32768, 3), (1 << 15, 1 << 16, 3)]:
            view = np.broadcast_to(np.float32(0.5), shape)
            try:
                brdfbake.load_environment(view)
            except brdfbake.InputError as e:
                print(str(e))
            else:
                print("accepted")
    """
    got = _python(code)
    assert got.returncode == 0, got.stderr[-2000:]
    lines = got.stdout.strip().splitlines()
    assert len(lines) == 2, got.stdout
    assert "32768x16384 (536870912 pixels)" in lines[0] and "268435456 pixels (16384x16384)" in lines[0], lines[0]
    assert "65536x32768" in lines[1] and "268435456 pixels" in lines[1], lines[1]


def test_broadcast_directions_are_refused_on_their_shape():
    # The same class for eval's pairs: one wi against a broadcast view of 2^33 wo (float32, so the
    # conversion to float64 would copy it) needs 576 GiB as float64 pairs and values: refused naming
    # the memory budget before anything is converted or joined (before: a MemoryError, or the
    # memory taken when the machine allows it).
    code = """
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
        import numpy as np, brdfbake
        wo = np.broadcast_to(np.array([0.0, 0.6, 0.8], dtype=np.float32), (1 << 33, 3))
        try:
            brdfbake.eval({"model": "lambert"}, [0.0, 0.0, 1.0], wo)
        except brdfbake.InputError as e:
            print(str(e))
        else:
            print("accepted")
    """
    got = _python(code)
    assert got.returncode == 0, got.stderr[-2000:]
    message = got.stdout.strip()
    assert "8589934592 pairs need 576.0 GiB" in message and "memory budget" in message, message


def test_a_broadcast_array_within_the_limit_is_taken():
    view = np.broadcast_to(np.float32(1.0), (64, 128, 3))
    env = brdfbake.load_environment(view)
    assert (env.width, env.height) == (128, 64)
    r = brdfbake.irradiance(env, sh_order=3)
    # A white environment: E/pi = 1, so the L0 coefficient of irradiance/pi is 1 / Y00 = 2 sqrt(pi).
    np.testing.assert_allclose(r.sh[0], 2 * np.sqrt(np.pi), rtol=ENV_FURNACE)  # E/pi coefficients, (9, 3)


def _white_pfm(path, width, height):
    # Portable float map, little-endian (scale -1), value 1.0: read only through the OpenImageIO module.
    path.write_bytes(f"PF\n{width} {height}\n-1.0\n".encode() + struct.pack(f"<{3 * width * height}f", *([1.0] * (3 * width * height))))


def test_the_openimageio_module_is_loaded_only_from_the_package(tmp_path):
    # A copy of the installed package without brdfbake_oiio.so: reading a format only the module
    # reads fails naming the one place looked at, the package's folder; never a path from the build
    # (pip builds in a temporary folder that is deleted, and anyone could create it again with a
    # module of their own), nor the interpreter's folder. Before, the library looked at its build
    # tree's path and loaded whatever was there.
    if not (PACKAGE / "brdfbake_oiio.so").is_file():
        pytest.skip("the installed package has no OpenImageIO module")
    copy = tmp_path / "site" / "brdfbake"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("brdfbake_oiio.so", "__pycache__"))
    _white_pfm(tmp_path / "white.pfm", 8, 4)
    env = {k: v for k, v in os.environ.items() if k not in ("BRDFBAKE_OIIO_MODULE", "PYTHONPATH")}
    env["PYTHONPATH"] = str(tmp_path / "site")
    code = f"""
        import os, brdfbake
        assert os.path.dirname(brdfbake.__file__) == {str(copy)!r}, brdfbake.__file__
        try:
            brdfbake.load_environment({str(tmp_path / "white.pfm")!r})
        except brdfbake.Error as e:
            print(str(e))
        else:
            print("loaded")
    """
    got = _python(code, env=env)
    assert got.returncode == 0, got.stderr[-2000:]
    message = got.stdout.strip()
    want = str(copy / "brdfbake_oiio.so")
    assert f"is not installed (looked for {want};" in message, message
    # With the module named explicitly, the same file reads.
    env["BRDFBAKE_OIIO_MODULE"] = str(PACKAGE / "brdfbake_oiio.so")
    got = _python(code.replace('print("loaded")', 'print("loaded")'), env=env)
    assert got.returncode == 0 and got.stdout.strip() == "loaded", got.stdout + got.stderr[-2000:]


def test_the_installed_package_reads_through_its_own_module(tmp_path):
    # The package's own module, found in the package's folder (PFM: no reader of the library's own).
    if not (PACKAGE / "brdfbake_oiio.so").is_file():
        pytest.skip("the installed package has no OpenImageIO module")
    _white_pfm(tmp_path / "white.pfm", 64, 32)
    env = brdfbake.load_environment(tmp_path / "white.pfm")
    assert (env.width, env.height) == (64, 32)
    assert "pfm" in env.description.lower() or "pnm" in env.description.lower(), env.description
