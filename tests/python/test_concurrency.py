"""A device is opened once per process and reused; device work runs without the GIL; threads share
a device safely."""

import subprocess
import sys
import textwrap
import threading

import numpy as np

import brdfbake


def test_a_device_is_opened_once_per_process(tmp_path):
    # In a fresh interpreter: every call, whatever spelling names the default device, reuses it.
    code = textwrap.dedent("""
        import sys
        import brdfbake
        from brdfbake import _brdfbake
        assert _brdfbake.opened_backends() == 0
        default = [d for d in brdfbake.devices() if d["default"]][0]
        brdfbake.lut(size=4)
        brdfbake.fresnel("dielectric", ior=1.5, size=4, device=default["selector"])
        brdfbake.tabulate({"model": "lambert"}, layout="albedo", res=4, device=default["type"])
        brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": "charlie", "size": 4}]}, sys.argv[1])
        assert _brdfbake.opened_backends() == 1, _brdfbake.opened_backends()
        brdfbake.lut(size=4, device="reference")
        assert _brdfbake.opened_backends() == 2
        print("ok")
    """)
    got = subprocess.run([sys.executable, "-c", code, str(tmp_path / "out")], capture_output=True, text=True,
                         timeout=300)
    assert got.returncode == 0 and "ok" in got.stdout, got.stderr[-2000:]


def test_the_gil_is_released_during_device_work():
    # The main thread counts while another thread bakes; the progress callback (which takes the GIL
    # at each step) records the count. Had the bake held the GIL, the count could not move between
    # its steps.
    count = [0]
    seen = []
    done = threading.Event()

    def progress(fraction, step):
        seen.append(count[0])

    def work():
        try:
            brdfbake.prefilter("builtin:studio", size=64, min_size=4, progress=progress)
        finally:
            done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        count[0] += 1
    t.join()
    assert len(seen) >= 3, seen
    assert seen[-1] > seen[0], seen


def test_threads_share_a_device_and_get_what_one_thread_gets(red):
    want_lut = brdfbake.lut(kind="ggx", size=16).array
    want_merl = brdfbake.tabulate(red, layout="merl").array
    got, errors = {}, []

    def work(i):
        try:
            got[i] = (brdfbake.lut(kind="ggx", size=16).array, brdfbake.tabulate(red, layout="merl").array)
        except Exception as e:  # reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for a, b in got.values():
        np.testing.assert_array_equal(a, want_lut)
        np.testing.assert_array_equal(b, want_merl)
