"""Bad input from Python raises a brdfbake.Error subclass with a clear one-line message, and never
crashes the interpreter."""

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import brdfbake


def raises(fn, cls, *words):
    with pytest.raises(cls) as e:
        fn()
    message = str(e.value)
    assert "\n" not in message, message
    for w in words:
        assert w in message, message
    return e.value


def test_the_exception_classes():
    assert issubclass(brdfbake.InputError, brdfbake.Error) and issubclass(brdfbake.InputError, ValueError)
    assert issubclass(brdfbake.ArgumentError, brdfbake.InputError) and issubclass(brdfbake.ArgumentError, TypeError)
    assert issubclass(brdfbake.DeviceError, brdfbake.Error) and issubclass(brdfbake.DeviceError, RuntimeError)
    assert brdfbake.InputError.exit_code == 2 and brdfbake.DeviceError.exit_code == 1


def test_parameters_out_of_range_name_the_field_as_the_cli_does(cli):
    e = raises(lambda: brdfbake.lut(size=-8), brdfbake.InputError, "lut.size", "must be an integer in 1..")
    # The message after the field is the command-line tool's.
    got = subprocess.run([cli, "lut", "--size", "-8", "-o", "/tmp/never.exr"], capture_output=True, text=True)
    assert got.returncode == e.exit_code
    assert str(e).split("lut.size", 1)[1] in got.stderr


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, np.float32("nan")])
def test_nan_and_infinite_parameters(value):
    raises(lambda: brdfbake.lut(size=value), brdfbake.InputError, "lut.size")
    raises(lambda: brdfbake.fresnel("dielectric", ior=value), brdfbake.InputError, "fresnel.ior")
    raises(lambda: brdfbake.fresnel("dielectric", ior=[1.5, value, 1.5]), brdfbake.InputError, "fresnel.ior")
    raises(lambda: brdfbake.tabulate({"roughness": value}, layout="merl"), brdfbake.InputError, "tabulate.material")
    raises(lambda: brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": value}]}, "/tmp/never"),
           brdfbake.InputError)


def test_unknown_kinds_arguments_and_choices():
    raises(lambda: brdfbake.lut(kind="fresnel"), brdfbake.InputError, "lut.kind", "ggx, ggx-multiscatter, charlie")
    raises(lambda: brdfbake.bake("nonesuch"), brdfbake.InputError, "unknown table kind 'nonesuch'")
    raises(lambda: brdfbake.validate("nonesuch"), brdfbake.InputError, "unknown table kind")
    raises(lambda: brdfbake.schema("nonesuch"), brdfbake.InputError, "unknown table kind")
    raises(lambda: brdfbake.lut(sise=3), brdfbake.ArgumentError, "lut.sise", "did you mean size")
    raises(lambda: brdfbake.tabulate({"model": "gltf"}), brdfbake.ArgumentError, "layout")
    raises(lambda: brdfbake.lut(estimator="magic"), brdfbake.InputError, "lut.estimator", "quadrature")
    raises(lambda: brdfbake.lut(kind="ggx", sheen_visibility="neubelt"), brdfbake.InputError, "sheen_visibility")
    raises(lambda: brdfbake.lut(size=8, samples=64, max_error=1e-3), brdfbake.InputError, "not both")
    raises(lambda: brdfbake.lut(size="big"), brdfbake.InputError, "lut.size")
    raises(lambda: brdfbake.lut(size={"a": 1}), brdfbake.InputError, "lut.size")
    raises(lambda: brdfbake.lut(size=1 + 2j), brdfbake.InputError, "lut.size")
    raises(lambda: brdfbake.lut(size=np.ones((2, 2))), brdfbake.InputError, "lut.size")
    raises(lambda: brdfbake.lut(precision="fp16"), brdfbake.InputError, "precision")
    raises(lambda: brdfbake.lut(size=8, device="no such device"), brdfbake.InputError, "no OpenCL device matches")
    raises(lambda: brdfbake.lut(size=8, progress=3), brdfbake.InputError, "progress")


def test_environment_arrays_of_the_wrong_dtype_or_shape():
    raises(lambda: brdfbake.prefilter(np.zeros((8, 16, 3), np.uint8)), brdfbake.InputError, "dtype uint8")
    raises(lambda: brdfbake.prefilter(np.zeros((8, 16, 3), np.complex64)), brdfbake.InputError, "dtype complex64")
    raises(lambda: brdfbake.prefilter(np.zeros((8, 16, 4), np.float32)), brdfbake.InputError, "(height, width, 3)")
    raises(lambda: brdfbake.prefilter(np.zeros((16, 3), np.float32)), brdfbake.InputError, "(height, width, 3)")
    raises(lambda: brdfbake.prefilter(np.zeros((8, 15, 3), np.float32)), brdfbake.InputError, "twice as wide")
    raises(lambda: brdfbake.prefilter(np.zeros((0, 0, 3), np.float32)), brdfbake.InputError, "twice as wide")
    raises(lambda: brdfbake.irradiance([[1, 2, 3]]), brdfbake.InputError, "irradiance.env")
    raises(lambda: brdfbake.irradiance("/nonexistent/sky.hdr"), brdfbake.InputError, "/nonexistent/sky.hdr")
    bad = np.ones((8, 16, 3), np.float32)
    bad[2, 3, 1] = np.nan
    bad[4, 4, 0] = -1
    raises(lambda: brdfbake.irradiance(bad), brdfbake.InputError, "1 NaN", "1 negative", "sanitize=True")
    r = brdfbake.irradiance(bad, sanitize=True)  # replaced, not refused
    assert np.isfinite(r.array).all()
    # A strided (non-contiguous) float64 view is accepted and converted.
    big = np.ones((8, 32, 3))[:, ::2]
    assert brdfbake.irradiance(big).array.shape == (9, 3)


def test_eval_directions():
    m = {"model": "lambert"}
    raises(lambda: brdfbake.eval(m, [0, 0, 0], [0, 0, 1]), brdfbake.InputError, "wi is the zero vector")
    raises(lambda: brdfbake.eval(m, [[0, 0, 1], [0, 0, 1]], [[0, 0, 1], [0, 0, 0]]), brdfbake.InputError,
           "pair 1", "wo is the zero vector")
    raises(lambda: brdfbake.eval(m, [0, np.inf, 1], [0, 0, 1]), brdfbake.InputError, "not finite")
    raises(lambda: brdfbake.eval(m, [0, 0, 1, 0], [0, 0, 1]), brdfbake.InputError, "shape (n, 3)")
    raises(lambda: brdfbake.eval(m, np.zeros((2, 3)) + [0, 0, 1], np.zeros((3, 3)) + 1), brdfbake.InputError,
           "do not broadcast")
    raises(lambda: brdfbake.eval(m, ["a", "b", "c"], [0, 0, 1]), brdfbake.InputError, "real numbers")
    raises(lambda: brdfbake.eval(m, [[0, 0, 1], [0, 1]], [0, 0, 1]), brdfbake.InputError, "wi")
    raises(lambda: brdfbake.eval(42, [0, 0, 1], [0, 0, 1]), brdfbake.InputError, "eval.material")
    raises(lambda: brdfbake.eval({"model": "gltf", "roughnes": 0.5}, [0, 0, 1], [0, 0, 1]), brdfbake.InputError,
           "roughnes")
    raises(lambda: brdfbake.eval("/nonexistent.json", [0, 0, 1], [0, 0, 1]), brdfbake.InputError, "/nonexistent.json")


def test_save_refuses_what_the_result_cannot_be(tmp_path):
    sh = brdfbake.irradiance("builtin:studio")
    raises(lambda: sh.save(tmp_path / "x.ktx2"), brdfbake.InputError, "irradiance_size")
    raises(lambda: brdfbake.lut(size=4).save(tmp_path / "x.jpg"), brdfbake.InputError, "unknown output format")
    raises(lambda: brdfbake.lut(size=4).save(tmp_path / "x.exr", size=8), brdfbake.InputError, "not an output parameter")
    raises(lambda: brdfbake.lut(size=4).save(tmp_path / "no" / "such" / "folder" / "x.exr", pixel="f64"),
           brdfbake.InputError, "pixel")
    raises(lambda: brdfbake.lut(size=4).save(42), brdfbake.InputError, "save.path")
    assert list(tmp_path.iterdir()) == []


def test_a_failed_job_writes_nothing(tmp_path):
    job = {"brdfbake_job": 1, "environment": str(tmp_path / "missing.hdr"),
           "tables": [{"kind": "ggx", "size": 8}, {"kind": "irradiance"}]}
    raises(lambda: brdfbake.run(job, tmp_path / "out"), brdfbake.InputError, "missing.hdr")
    assert list(tmp_path.iterdir()) == []
    raises(lambda: brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": "ggx", "sise": 8}]}, tmp_path / "o"),
           brdfbake.InputError, "tables[0].sise", "unknown field")
    raises(lambda: brdfbake.run(42, tmp_path), brdfbake.InputError, "run.job")
    raises(lambda: brdfbake.run(str(tmp_path / "no_job.json"), tmp_path / "o"), brdfbake.InputError, "no_job.json")


def test_a_python_exception_in_progress_stops_the_bake():
    def stop(fraction, step):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        brdfbake.prefilter("builtin:studio", size=16, progress=stop)
    assert brdfbake.lut(size=4).array.shape == (4, 4, 3)  # and the device still works


def test_no_bad_input_crashes_the_interpreter():
    # A battery of hostile inputs in a child interpreter: it must get to the end and exit 0 (a crash
    # would be a signal, not an exception).
    code = textwrap.dedent(r"""
        import math, numpy as np, brdfbake
        cases = [
            lambda: brdfbake.lut(size=2**70),
            lambda: brdfbake.lut(size=-(2**70)),
            lambda: brdfbake.lut(size=10**400),
            lambda: brdfbake.lut(height=[1, 2, 3]),
            lambda: brdfbake.fresnel("dielectric", ior=[]),
            lambda: brdfbake.fresnel("dielectric", ior=[1.5] * 1000),
            lambda: brdfbake.fresnel("x" * 100000),
            lambda: brdfbake.fresnel("dielectric\0", ior=1.5),
            lambda: brdfbake.tabulate("\0", layout="merl"),
            lambda: brdfbake.tabulate("{" * 5000, layout="merl"),
            lambda: brdfbake.tabulate({"materials": 5}, layout="merl"),
            lambda: brdfbake.tabulate({"model": "disney"}, layout="grid", res=[0]),
            lambda: brdfbake.tabulate({"model": "disney"}, layout="grid", res=[10**9]),
            lambda: brdfbake.prefilter(np.zeros((1, 2, 3), np.float32), size=10**9),
            lambda: brdfbake.prefilter(np.empty((0, 0, 3), np.float32)),
            lambda: brdfbake.prefilter(np.full((4, 8, 3), 1e39)),
            lambda: brdfbake.prefilter(np.zeros((4, 8, 3), object)),
            lambda: brdfbake.irradiance(np.zeros((4, 8, 3), np.float32), sh_order=4),
            lambda: brdfbake.eval({"model": "gltf"}, np.zeros((0, 3)), np.zeros((0, 3))).array.shape,
            lambda: brdfbake.eval({"model": "gltf"}, np.array([[1e308, 1e308, 1e308]]), [0, 0, 1]).array,
            lambda: brdfbake.eval({"model": "gltf"}, np.array([[1e-320, 0, 0]]), [0, 0, 1]).array,
            lambda: brdfbake.run("{not json", "/tmp/never"),
            lambda: brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": None}]}, "/tmp/never"),
            lambda: brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": "ggx", "output": "../x.exr"}]}, "/tmp/never"),
            lambda: brdfbake.lut(size=4).save("/proc/forbidden/x.exr"),
            lambda: brdfbake.lut(size=4).save(""),
        ]
        for i, case in enumerate(cases):
            try:
                case()
            except brdfbake.Error as e:
                assert "\n" not in str(e), (i, str(e))
        print("survived", len(cases))
    """)
    got = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert got.returncode == 0, got.stderr[-2000:]
    assert "survived 26" in got.stdout
