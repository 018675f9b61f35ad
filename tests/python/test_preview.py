"""brdfbake.preview(...) through Python (docs/PREVIEW.md): both renders as NumPy arrays, the error
image and every number per sphere, consistent with each other and with the files `save` writes."""

import json

import numpy as np
import pytest

import brdfbake

# The target for the reference at default settings: relative RMS per sphere.
REFERENCE_TARGET = 5e-3


@pytest.fixture(scope="module")
def small():
    # The registry's example: builtin:sun, 96 x 48 (the default grid of 72 spheres, radius 1.84 px).
    return brdfbake.preview("builtin:sun", target="filament", width=96, height=48, bound_stride=64)


def test_the_renders_are_views_with_the_layout(small):
    p = small.preview
    assert small.kind == "preview"
    for name in ("splitsum", "reference"):
        a = p[name]
        assert a.shape == (48, 96, 3) and a.dtype == np.float32 and not a.flags.writeable
        assert np.isfinite(a).all()
    assert small.array.shape == (48, 96, 3)
    np.testing.assert_array_equal(small.array, p["splitsum"])
    assert (p["reference"] >= 0).all()
    assert len(p["spheres"]) == 72 and p["target"] == "filament"
    assert p["camera"]["view_direction"] == pytest.approx((0.0, 0.0, -1.0))
    first = p["spheres"][0]
    assert first["roughness"] == 0.0 and first["metallic"] == 0.0 and first["row"] == 0 and first["column"] == 0
    gold = [s for s in p["spheres"] if s["metallic"] == 1.0 and s["base_color"][2] < 0.4]
    assert len(gold) == 12 and gold[0]["f0"] == pytest.approx(gold[0]["base_color"])  # a metal's F0 is its colour


def test_the_error_image_gives_the_numbers_per_sphere(small):
    p = small.preview
    error = p["error"]
    assert error.shape == (48, 96) and error.dtype == np.float32
    h, w = error.shape
    ys, xs = np.mgrid[0:h, 0:w]
    covered = np.zeros((h, w), dtype=bool)
    for s in p["spheres"]:
        cx, cy = s["centre"]
        inside = (xs + 0.5 - cx) ** 2 + (ys + 0.5 - cy) ** 2 < s["radius"] ** 2
        covered |= inside
        e = error[inside].astype(np.float64)
        assert inside.sum() == s["pixels"], s["name"]
        # the library's statistics in double over the same pixels; the image is float32 (2^-24)
        assert np.sqrt(np.mean(e * e)) == pytest.approx(s["linear"]["rms"], rel=1e-5, abs=1e-7), s["name"]
        assert e.max() == pytest.approx(s["linear"]["max"], rel=1e-5, abs=1e-7), s["name"]
        assert 0 < s["reference_bound"]["rms"] <= REFERENCE_TARGET, s["name"]
        assert 0 <= s["srgb8"]["p99"] <= s["srgb8"]["max"] <= 255
    assert np.isnan(error[~covered]).all()


def test_save_writes_the_same_numbers(small, tmp_path):
    small.save(tmp_path / "p.png")
    for f in ("p.png", "p_splitsum.exr", "p_reference.exr", "p.json"):
        assert (tmp_path / f).is_file(), f
    doc = json.loads((tmp_path / "p.json").read_text())
    for s, d in zip(small.preview["spheres"], doc["spheres"]):
        assert d["error"]["linear"]["rms"] == pytest.approx(s["linear"]["rms"], rel=1e-6)
        assert d["centre"] == pytest.approx(list(s["centre"]))


def test_the_shares_add_up_and_match_the_json(small, tmp_path):
    # the error's shares (docs/PREVIEW.md): the ideal bake's render, per sphere engine_share |ideal -
    # reference| / |reference| and bake_share |split-sum - ideal| / |reference|, per group medians
    p = small.preview
    ideal = p["ideal"]
    assert ideal.shape == (48, 96, 3) and ideal.dtype == np.float32 and np.isfinite(ideal).all()
    s64, i64, r64 = (p[k].astype(np.float64) for k in ("splitsum", "ideal", "reference"))
    h, w, _ = s64.shape
    ys, xs = np.mgrid[0:h, 0:w]
    for s in p["spheres"]:
        cx, cy = s["centre"]
        inside = (xs + 0.5 - cx) ** 2 + (ys + 0.5 - cy) ** 2 < s["radius"] ** 2
        n = np.linalg.norm(r64[inside], axis=1)
        engine = np.linalg.norm(i64[inside] - r64[inside], axis=1) / n
        bake = np.linalg.norm(s64[inside] - i64[inside], axis=1) / n
        assert np.sqrt(np.mean(engine ** 2)) == pytest.approx(s["engine_share"]["rms"], rel=1e-6, abs=1e-9), s["name"]
        assert np.sqrt(np.mean(bake ** 2)) == pytest.approx(s["bake_share"]["rms"], rel=1e-6, abs=1e-9), s["name"]
        # the difference images add up; their RMS obey the triangle inequality
        e, b, t = s["engine_share"]["rms"], s["bake_share"]["rms"], s["linear"]["rms"]
        assert abs(e - b) - 1e-6 <= t <= e + b + 1e-6, s["name"]
    groups = p["share_groups"]
    assert [g["name"] for g in groups] == ["white", "grey", "dark", "gold", "copper", "silver"]
    assert all(len(g["spheres"]) == 12 for g in groups)
    gold = groups[3]
    worst = max(p["spheres"][k]["bake_share"]["rms"] for k in gold["spheres"])
    assert gold["bake_share"]["worst"] == worst
    assert p["times"]["ideal"] > 0 and "specular" in p["ideal_bake"]
    small.save(tmp_path / "q.png")
    doc = json.loads((tmp_path / "q.json").read_text())
    assert doc["shares"]["groups"][3]["bake_share"]["worst"] == pytest.approx(worst, rel=1e-12)
    assert doc["spheres"][0]["engine_share"]["rms"] == pytest.approx(p["spheres"][0]["engine_share"]["rms"])


def test_no_shares_without_them():
    r = brdfbake.preview("builtin:sun", target="generic", width=96, height=48, bound_stride=64, shares=False)
    p = r.preview
    assert p["ideal"] is None and "share_groups" not in p and "engine_share" not in p["spheres"][0]


def test_without_the_reference_and_with_a_material_file(red_file):
    r = brdfbake.preview("builtin:sun", target="generic", width=64, height=64, reference=False,
                         materials=red_file)
    p = r.preview
    assert p["reference"] is None and p["error"] is None
    assert len(p["spheres"]) == 1
    s = p["spheres"][0]
    assert s["name"] == "red" and s["base_color"] == pytest.approx((0.8, 0.1, 0.1))
    assert s["metallic"] == 0.2 and s["roughness"] == 0.4 and "linear" not in s
    # F0 = mix(0.04, baseColor, metallic)
    assert s["f0"] == pytest.approx(tuple(0.04 + 0.2 * (c - 0.04) for c in (0.8, 0.1, 0.1)))


def test_other_results_have_no_preview():
    assert brdfbake.lut(kind="ggx", size=8).preview is None
