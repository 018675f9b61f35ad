"""Every table family through Python: shapes, zero-copy views, metadata, and values against closed
forms and the double reference."""

import json
import math
import pathlib

import numpy as np
import pytest

import brdfbake
from tolerances import BRDF_ALBEDO, BRDF_FP32, ENV_FURNACE, FRESNEL_FP32, MERL_READBACK, PREFILTER_FURNACE


def test_lut_is_a_view_of_the_result_with_its_metadata():
    r = brdfbake.lut(kind="ggx", size=32, height=16)
    a = r.array
    assert a.shape == (16, 32, 3) and a.dtype == np.float32
    # No copy: the array's memory belongs to the C++ result, which the array keeps alive.
    assert not a.flags.owndata and a.base is not None and not a.flags.writeable
    assert r.array is a
    axes = r.axes
    assert axes["channels"] == ["scale", "bias", "diffuse"]
    np.testing.assert_allclose(axes["x"], (np.arange(32) + 0.5) / 32)  # cell centres (docs/CONVENTIONS.md)
    np.testing.assert_allclose(axes["y"], (np.arange(16) + 0.5) / 16)
    meta = r.meta
    assert meta["kind"] == "ggx" and meta["channels"] == "scale,bias,diffuse"
    assert meta["error_name"] == r.error_name == "error_bound_mixed" and "error_bound" not in meta
    assert isinstance(meta["error_bound_mixed"], float) and 0 < meta["error_bound_mixed"] <= 1e-4
    assert meta["error_bound_mixed"] == r.error
    assert r.parameters["samples"] > 0 and r.parameters["size"] == 32
    # Split-sum sanity at the smoothest row and normal incidence: scale + bias is the directional
    # albedo of a white specular GGX lobe, at most 1 and near 1 for a smooth surface.
    assert 0.9 < a[0, -1, 0] + a[0, -1, 1] <= 1.0 + 1e-6


@pytest.mark.parametrize("call,name", [
    (lambda: brdfbake.lut(kind="ggx", size=16), "error_bound_mixed"),
    (lambda: brdfbake.prefilter("builtin:sun", chain_size=16, min_size=4), "error_bound_rel"),
    (lambda: brdfbake.irradiance("builtin:sun"), "error_rms_rel"),
])
def test_the_error_figure_by_its_name_and_the_deprecated_error_bound(call, name, recwarn):
    """Result.error is the figure Result.error_name names, Result.errors keys it by that name, as the
    metadata does (docs/CONVENTIONS.md, "Error figures"); error_bound is a deprecated alias that warns."""
    r = call()
    assert r.error_name == name and r.meta["error_name"] == name
    assert isinstance(r.error, float) and r.error > 0
    assert r.errors == {name: r.error}
    assert r.meta[name] == r.error
    assert not [w for w in recwarn if issubclass(w.category, DeprecationWarning)]
    with pytest.warns(DeprecationWarning, match=r"Result\.error_bound is deprecated: use Result\.error"):
        assert r.error_bound == r.error


def test_array_outlives_the_result():
    a = brdfbake.lut(kind="charlie", size=8).array  # the Result itself is gone at once
    import gc

    gc.collect()
    assert np.isfinite(a).all() and a.shape == (8, 8, 1)


def test_fresnel_dielectric_matches_the_closed_form():
    # endpoints: cos_theta = i / (N - 1), so the last cell is normal incidence and the first grazing.
    r = brdfbake.fresnel("dielectric", ior=1.5, size=16, endpoints=True)
    a = r.array
    assert a.shape == (1, 16, 3)
    assert abs(a[0, -1, 0] - 0.04) < FRESNEL_FP32  # ((1.5 - 1) / (1.5 + 1))^2
    assert abs(a[0, 0, 0] - 1.0) < FRESNEL_FP32  # grazing: total reflection
    # Fresnel's error bound is measured against the double reference at every cell as it is baked.
    assert r.error is not None and r.error < FRESNEL_FP32


def test_eval_lambert_is_albedo_over_pi_and_zero_below_the_horizon():
    m = {"model": "lambert", "baseColor": [0.5, 0.25, 1.0]}
    wi = np.array([[0, 0, 1], [0.3, 0.4, 0.5], [0, 0, -1]], dtype=np.float32)
    r = brdfbake.eval(m, wi, [0, 0.6, 0.8])  # wo broadcast against wi
    a = r.array
    assert a.shape == (3, 3) and a.dtype == np.float32
    np.testing.assert_allclose(a[:2], np.array([[0.5, 0.25, 1.0]] * 2) / math.pi, rtol=BRDF_FP32)
    assert (a[2] == 0).all()
    assert r.meta["model"] == "lambert"


def test_eval_on_the_device_matches_the_reference(red):
    rng = np.random.default_rng(7)
    wi = rng.normal(size=(500, 3))
    wo = rng.normal(size=(500, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]) + 0.05, np.abs(wo[:, 2]) + 0.05
    got = brdfbake.eval(red, wi, wo).array
    want = brdfbake.eval(red, wi, wo, device="reference").array
    err = np.abs(got - want) / np.maximum(1.0, np.abs(want))
    assert err.max() < BRDF_FP32 + 1e-7  # + the float32 rounding of the reference's own array


def test_prefilter_of_a_constant_environment_is_constant():
    white = np.full((32, 64, 3), 2.0, dtype=np.float64)  # any float dtype; converted to float32
    r = brdfbake.prefilter(white, size=16, min_size=4)
    levels = r.array
    assert [l.shape for l in levels] == [(6, 16, 16, 3), (6, 8, 8, 3), (6, 4, 4, 3)]
    assert all(not l.flags.owndata and not l.flags.writeable for l in levels)
    for l in levels:
        assert np.abs(l - 2.0).max() < 2.0 * PREFILTER_FURNACE
    assert r.meta["levels"] == "3"
    assert r.request["environment"] == "array 64x32"


def test_prefilter_saves_as_astc_hdr_with_its_bound(tmp_path):
    # pixel astc4x4 / astc6x6 (issue 24 item 9): the chain as ASTC HDR KTX2 (VK_FORMAT_ASTC_4x4_SFLOAT_BLOCK
    # = 1000066000, 6x6 = 1000066004 at byte 12 of the header), its measured storage error in the
    # metadata and in the error bound; the chain records its integration bound (item 7) as well.
    r = brdfbake.prefilter("builtin:sun", size=16, min_size=4)
    assert r.error is not None and r.error > 0
    for pixel, vk_format in (("astc4x4", 1000066000), ("astc6x6", 1000066004)):
        out = tmp_path / f"{pixel}.ktx2"
        r.save(out, pixel=pixel)
        data = out.read_bytes()
        assert int.from_bytes(data[12:16], "little") == vk_format
        assert b"brdfbake:astc_rms_rel_error_per_level" in data and b"brdfbake:storage_error" in data
    with pytest.raises(brdfbake.InputError, match="pixel"):
        r.save(tmp_path / "x.dds", pixel="astc4x4")
    with pytest.raises(brdfbake.InputError, match="pixel"):
        brdfbake.lut(size=4).save(tmp_path / "x.ktx2", pixel="astc4x4")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["astc4x4.ktx2", "astc6x6.ktx2"]


def test_sh_is_float64_coefficients_as_python_md_says(tmp_path):
    # docs/PYTHON.md: `.array` the SH coefficients of E/pi, (order^2, 3) float32; `.sh` the same
    # coefficients in float64; what they mean beside them in `.meta`. Held to the JSON file the CLI's
    # writer makes of the same result (nlohmann writes doubles so that they read back exactly).
    for order in (3, 5):
        r = brdfbake.irradiance("builtin:sun", sh_order=order)
        assert isinstance(r.sh, np.ndarray) and r.sh.dtype == np.float64 and r.sh.shape == (order * order, 3)
        assert not r.sh.flags.writeable
        np.testing.assert_array_equal(r.array, r.sh.astype(np.float32))
        doc = json.loads(pathlib.Path(r.save(tmp_path / f"sh{order}.json")).read_text())
        np.testing.assert_array_equal(r.sh, np.array(doc["irradiance_over_pi"]))
        np.testing.assert_array_equal(r.sh_radiance, np.array(doc["radiance"]))
        assert r.meta["order"] == order and r.meta["window"] == doc["window"] and "basis" in r.meta
    assert brdfbake.lut(kind="ggx", size=4).sh is None


def test_irradiance_of_a_white_environment_is_pi_in_l00_only():
    # Furnace: radiance 1 everywhere gives E = pi, E / pi = 1 = c00 Y00 with Y00 = 1 / (2 sqrt(pi)).
    white = np.ones((32, 64, 3), dtype=np.float32)
    r = brdfbake.irradiance(white, cube_size=8)
    sh = r.sh
    assert r.meta["order"] == 3 and sh.shape == (9, 3)
    np.testing.assert_allclose(sh[0], 2 * math.sqrt(math.pi), rtol=ENV_FURNACE)
    assert np.abs(sh[1:]).max() < ENV_FURNACE
    assert r.array.dtype == np.float32 and r.array.shape == (9, 3)
    assert r.cube.shape == (6, 8, 8, 3)
    np.testing.assert_allclose(r.cube, 1.0, rtol=10 * ENV_FURNACE)
    assert "basis" in r.meta and r.meta["error_name"] == "error_rms_rel" and r.meta["error_rms_rel"] is None


def test_tabulate_merl_layout(red, tmp_path):
    r = brdfbake.tabulate(red, layout="merl")
    a = r.array
    assert a.shape == (90, 90, 180, 3) and a.dtype == np.float32
    assert (a[a < 0] == -1).all()  # below the horizon: MERL's -1
    assert np.isfinite(a).all() and (a >= 0).sum() > 0.5 * a.size
    assert json.loads(r.meta["materials"])[0]["name"] == "red"
    # The file: MERL's binary, f divided by the channel scales (docs/CONVENTIONS.md).
    path = tmp_path / "red.binary"
    assert r.save(path) == str(path)
    raw = path.read_bytes()
    dims = np.frombuffer(raw[:12], dtype="<i4")
    assert dims.tolist() == [90, 90, 180]
    stored = np.frombuffer(raw[12:], dtype="<f8").reshape(3, 90, 90, 180)
    scales = np.array([1 / 1500, 1.15 / 1500, 1.66 / 1500])
    above = a[..., 0] >= 0
    for c in range(3):
        back = (stored[c] * scales[c])[above]
        np.testing.assert_allclose(a[..., c][above], back, rtol=MERL_READBACK, atol=0)
    assert (path.parent / "red.binary.json").exists()


def test_tabulate_albedo_of_several_materials(tmp_path):
    mats = [{"name": "a", "model": "lambert", "baseColor": 0.5}, {"name": "b", "model": "lambert", "baseColor": 1.0}]
    mats = [{"name": m["name"], "model": m["model"], "baseColor": [m["baseColor"]] * 3} for m in mats]
    r = brdfbake.tabulate(mats, layout="albedo", res=16)
    a = r.array
    assert a.shape == (2, 16, 3)  # one row per material
    # Lambert's directional albedo is its albedo at every angle.
    np.testing.assert_allclose(a[0], 0.5, rtol=BRDF_ALBEDO)
    np.testing.assert_allclose(a[1], 1.0, rtol=BRDF_ALBEDO)


@pytest.mark.parametrize("fmt", [".exr", ".csv", ".ktx2", ".h"])
def test_save_writes_every_table_format(tmp_path, fmt):
    r = brdfbake.lut(kind="ggx-multiscatter", size=8)
    path = r.save(tmp_path / ("dfg" + fmt))
    assert (tmp_path / ("dfg" + fmt)).stat().st_size > 0
    assert [p.name for p in tmp_path.iterdir()] == ["dfg" + fmt]  # nothing else: no temporary left
    assert path.endswith(fmt)


def test_output_argument_writes_as_it_bakes(tmp_path):
    out = tmp_path / "chain.ktx2"
    r = brdfbake.prefilter("builtin:studio", size=8, min_size=8, output=out)
    assert out.stat().st_size > 0 and r.array[0].shape == (6, 8, 8, 3)


def test_environment_loaded_once_serves_several_bakes():
    env = brdfbake.load_environment("builtin:sun")
    assert env.layout == "equirect" and env.width == 2 * env.height
    a = brdfbake.irradiance(env).array
    b = brdfbake.irradiance("builtin:sun").array
    np.testing.assert_array_equal(a, b)


def test_real_hdr_from_shared(shared_dir):
    if shared_dir is None:
        pytest.skip("../shared is absent: no real HDR maps to load")
    hdrs = sorted(shared_dir.rglob("*.hdr"))
    if not hdrs:
        pytest.skip(f"no .hdr file under {shared_dir}")
    r = brdfbake.irradiance(hdrs[0])
    assert np.isfinite(r.array).all() and r.array[0].min() > 0  # L00 of a real sky is positive


def test_devices_and_generic_bake():
    ds = brdfbake.devices()
    assert all({"selector", "name", "type", "default"} <= set(d) for d in ds)
    r = brdfbake.bake("thin-film", base_ior=1.5, size=8)
    assert r.kind == "thin-film" and r.array.shape[1] == 8
    assert brdfbake.function_of("charlie") is brdfbake.lut


def _white_png(path, width, height):
    """An 8-bit RGB PNG, every texel 255 (1.0 with or without an sRGB decode), written by hand."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    rows = b"".join(b"\x00" + b"\xff" * (3 * width) for _ in range(height))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def test_a_png_environment_goes_through_the_installed_openimageio_module(tmp_path):
    # PNG is read by the OpenImageIO module the package installs beside the extension and names.
    import os
    module = os.environ.get("BRDFBAKE_OIIO_MODULE", "")
    assert os.path.dirname(module) == os.path.dirname(brdfbake.__file__) and os.path.isfile(module)
    _white_png(tmp_path / "white.png", 64, 32)
    env = brdfbake.load_environment(tmp_path / "white.png")
    assert (env.width, env.height) == (64, 32)
    r = brdfbake.irradiance(env, sh_order=3)
    np.testing.assert_allclose(r.sh[0], 2 * math.sqrt(math.pi), rtol=ENV_FURNACE)


def test_kernel_shape_from_python():
    """The kernels' work shape (docs/DEVICES.md): devices() says each device's; set_kernel_shape
    chooses it for the devices opened afterwards (a process of its own here: it is process-wide);
    another name is an InputError (a ValueError) and changes nothing."""
    import os
    import subprocess
    import sys

    if not os.environ.get("BRDFBAKE_KERNEL_SHAPE"):
        for d in brdfbake.devices():
            assert d["kernel_shape"] == ("cpu" if d["type"] == "cpu" else "gpu"), d
    with pytest.raises(ValueError, match="auto, cpu or gpu"):
        brdfbake.set_kernel_shape("warp")
    code = ("import brdfbake, json; brdfbake.set_kernel_shape('gpu'); "
            "print(json.dumps([d['kernel_shape'] for d in brdfbake.devices()]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    shapes = json.loads(out.stdout)
    assert shapes and all(s == "gpu" for s in shapes), shapes
