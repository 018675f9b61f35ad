"""The same table through Python, the command-line tool and a job is identical, byte for byte."""

import json
import subprocess

import numpy as np

import brdfbake


def without_capture_date(exr: bytes) -> bytes:
    """An OpenEXR file with its capDate attribute (the time it was written) blanked."""
    key = b"capDate\x00string\x00"
    at = exr.find(key)
    if at < 0:
        return exr
    start = at + len(key) + 4
    size = int.from_bytes(exr[at + len(key):start], "little")
    return exr[:start] + b"?" * size + exr[start + size:]


def read_csv_table(path):
    rows = [l for l in open(path) if not l.startswith("#")]
    header = rows[0].strip().split(",")
    values = np.array([[float(x) for x in r.split(",")] for r in rows[1:]], dtype=np.float64)
    return header, values


def test_dfg_table_python_cli_and_job_identical(cli, tmp_path):
    r = brdfbake.lut(kind="ggx", size=32)
    r.save(tmp_path / "py.csv")
    r.save(tmp_path / "py.exr")
    subprocess.run([cli, "lut", "--kind", "ggx", "--size", "32", "-o", str(tmp_path / "cli.csv"), "--quiet"], check=True)
    subprocess.run([cli, "lut", "--kind", "ggx", "--size", "32", "-o", str(tmp_path / "cli.exr"), "--quiet"], check=True)
    job = {"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": 32, "output": "job.csv"},
                                         {"kind": "ggx", "size": 32, "output": "job.exr"}]}
    manifest = brdfbake.run(job, tmp_path / "job")
    for ext in ("csv", "exr"):
        py = without_capture_date((tmp_path / f"py.{ext}").read_bytes())
        assert py == without_capture_date((tmp_path / f"cli.{ext}").read_bytes()), ext
        assert py == without_capture_date((tmp_path / "job" / f"job.{ext}").read_bytes()), ext
    # And the array is exactly what the files hold (CSV prints float32 with 9 digits: exact).
    header, values = read_csv_table(tmp_path / "cli.csv")
    assert header == ["n_dot_v", "roughness", "scale", "bias", "diffuse"]
    np.testing.assert_array_equal(values[:, 2:].astype(np.float32).reshape(32, 32, 3), r.array)
    # The manifest records what .meta does.
    f = manifest["files"][0]
    assert f["error_name"] == r.error_name
    assert f[r.error_name] == r.meta[r.error_name] and f["parameters"] == r.parameters


def test_merl_table_python_cli_and_job_identical(cli, red, red_file, tmp_path):
    r = brdfbake.tabulate(red, layout="merl")
    r.save(tmp_path / "py.binary")
    subprocess.run([cli, "tabulate", "--material", str(red_file), "--layout", "merl", "-o",
                    str(tmp_path / "cli.binary"), "--quiet"], check=True)
    job = {"brdfbake_job": 1, "tables": [{"kind": "tabulate", "material": str(red_file), "layout": "merl",
                                          "output": "job.binary"}]}
    brdfbake.run(job, tmp_path / "job")
    py = (tmp_path / "py.binary").read_bytes()
    assert py == (tmp_path / "cli.binary").read_bytes()
    assert py == (tmp_path / "job" / "job.binary").read_bytes()
    # Python given the file itself gives the same array as Python given the dict.
    np.testing.assert_array_equal(brdfbake.tabulate(red_file, layout="merl").array, r.array)


def test_fresnel_and_prefilter_python_and_cli_identical(cli, tmp_path):
    brdfbake.fresnel("conductor", material="gold", size=64).save(tmp_path / "py.csv")
    subprocess.run([cli, "fresnel", "--model", "conductor", "--material", "gold", "--size", "64", "-o",
                    str(tmp_path / "cli.csv"), "--quiet"], check=True)
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    brdfbake.prefilter("builtin:studio", size=16, min_size=4).save(tmp_path / "py.ktx2", pixel="f32")
    subprocess.run([cli, "prefilter", "--env", "builtin:studio", "--size", "16", "--min-size", "4", "--pixel", "f32",
                    "-o", str(tmp_path / "cli.ktx2"), "--quiet"], check=True)
    assert (tmp_path / "py.ktx2").read_bytes() == (tmp_path / "cli.ktx2").read_bytes()


def test_eval_python_and_cli_identical(cli, red_file, tmp_path):
    rng = np.random.default_rng(3)
    pairs = rng.normal(size=(200, 6))
    pairs[:, 2] = np.abs(pairs[:, 2])
    pairs[:, 5] = np.abs(pairs[:, 5])
    pairs = pairs.astype(np.float32).astype(np.float64)  # what a float32 binary input holds
    pairs.astype("<f4").tofile(tmp_path / "pairs.f32")
    subprocess.run([cli, "eval", "--material", str(red_file), "--binary", "-i", str(tmp_path / "pairs.f32"), "-o",
                    str(tmp_path / "cli.f32"), "--quiet"], check=True)
    r = brdfbake.eval(red_file, pairs[:, :3], pairs[:, 3:])
    r.save(tmp_path / "py.f32")
    assert (tmp_path / "py.f32").read_bytes() == (tmp_path / "cli.f32").read_bytes()
    np.testing.assert_array_equal(np.fromfile(tmp_path / "cli.f32", dtype="<f4").reshape(-1, 3), r.array)
