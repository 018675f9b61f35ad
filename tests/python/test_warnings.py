"""What a write changes on the way to the file reaches Python users: each warning the command line
prints after ``warning:`` is emitted as a brdfbake.BakeWarning and listed on the result, with the
bound the file records."""

import json
import warnings

import pytest

import brdfbake

# A Phong lobe of shininess 1e6 sampled 1e-4 rad from its peak: 152 098, beyond binary16's 65504.
SHARP = {"name": "a", "model": "phong", "shininess": 1000000, "specularColor": [1, 1, 1]}


def test_output_warns_about_clamped_values(tmp_path):
    out = tmp_path / "t.h"
    with pytest.warns(brdfbake.BakeWarning) as record:
        r = brdfbake.tabulate(SHARP, layout="slice", res=64, pixel="f16", clamp_f16=True, output=out)
    messages = [str(w.message) for w in record if issubclass(w.category, brdfbake.BakeWarning)]
    assert len(messages) == 1, messages
    assert messages[0].startswith(f"'{out}': ") and "clamped to 65504" in messages[0]
    assert r.warnings == messages
    assert "f16_clamped" in out.read_text()
    assert [f["path"] for f in r.files] == [str(out)] and r.files[0]["warnings"] == messages


def test_save_warns_about_clamped_values(tmp_path):
    r = brdfbake.tabulate(SHARP, layout="slice", res=64)
    assert r.warnings == [] and r.files == []
    with pytest.raises(brdfbake.InputError, match="clamp_f16"):
        r.save(tmp_path / "refused.ktx2", pixel="f16")
    assert not (tmp_path / "refused.ktx2").exists()
    with pytest.warns(brdfbake.BakeWarning, match="clamped to 65504"):
        r.save(tmp_path / "t.ktx2", pixel="f16", clamp_f16=True)
    assert len(r.warnings) == 1 and str(tmp_path / "t.ktx2") in r.warnings[0]
    # float32 holds the peak: nothing to warn about.
    with warnings.catch_warnings():
        warnings.simplefilter("error", brdfbake.BakeWarning)
        r.save(tmp_path / "t32.ktx2", pixel="f32")
    assert len(r.warnings) == 1 and len(r.files) == 2 and r.files[1]["warnings"] == []


def test_files_record_the_delivered_bound(tmp_path):
    # binary16 adds its rounding to the integration bound: the file's bound is the sum, as the
    # manifest and the command line report it; float32 EXR adds nothing.
    r = brdfbake.lut(kind="ggx", size=16)
    r.save(tmp_path / "dfg.ktx2", pixel="f16")
    r.save(tmp_path / "dfg.exr")
    f16, f32 = r.files
    assert f16["encoding"].startswith("binary16") and f16["storage_error"] > 2 ** -13
    assert r.error_name == "error_bound_mixed" and f16["error_name"] == r.error_name
    assert f16["error_bound_mixed"] == pytest.approx(r.error + f16["storage_error"], rel=1e-12)
    assert f32["storage_error"] == 0 and f32["error_bound_mixed"] == r.error


def test_job_warns_as_the_command_line_prints(tmp_path):
    material = tmp_path / "sharp.json"
    material.write_text(json.dumps({"materials": [SHARP]}))
    job = {"brdfbake_job": 1, "tables": [{"kind": "tabulate", "material": str(material), "layout": "slice", "res": 64,
                                          "pixel": "f16", "clamp_f16": True, "output": "t.h"}]}
    with pytest.warns(brdfbake.BakeWarning, match="clamped to 65504") as record:
        manifest = brdfbake.run(job, tmp_path / "out")
    messages = [str(w.message) for w in record if issubclass(w.category, brdfbake.BakeWarning)]
    assert messages == manifest["warnings"] and str(tmp_path / "out" / "t.h") in messages[0]


def test_save_writes_where_asked_or_nowhere(tmp_path, monkeypatch):
    # save("") is refused; it never falls back to the default name validation gives a request.
    monkeypatch.chdir(tmp_path)
    r = brdfbake.lut(size=4)
    with pytest.raises(brdfbake.Error):
        r.save("")
    assert list(tmp_path.iterdir()) == [] and r.files == []
