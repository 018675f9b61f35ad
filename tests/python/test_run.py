"""brdfbake.run: jobs from dicts, files and JSON text; the manifest as a dict."""

import json

import brdfbake


def test_run_a_job_dict_returns_the_manifest(tmp_path):
    events = []
    job = {"brdfbake_job": 1, "tables": [
        {"kind": "ggx", "size": 16},
        {"kind": "fresnel", "model": "dielectric", "ior": 1.5, "size": 8, "output": "glass.csv"},
        {"kind": "irradiance"},
    ]}
    m = brdfbake.run(job, tmp_path / "out", progress=events.append)
    assert m["bakes"] == 3
    paths = [f["path"] for f in m["files"]]
    assert paths == ["dfg_ggx_16.exr", "glass.csv", "irradiance_sh3.json"]
    for p in paths:
        assert (tmp_path / "out" / p).stat().st_size > 0
    on_disk = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert on_disk["files"] == m["files"]
    assert m["files"][0]["error_bound_mixed"] == brdfbake.lut(kind="ggx", size=16).error
    assert {e["bake"] for e in events} == {0, 1, 2} and all(e["bakes"] == 3 for e in events)


def test_run_a_job_file_and_json_text(tmp_path):
    job = {"brdfbake_job": 1, "output_dir": str(tmp_path / "own"), "tables": [{"kind": "charlie", "size": 8}]}
    path = tmp_path / "job.json"
    path.write_text(json.dumps(job))
    m = brdfbake.run(path)  # the job's own output_dir
    assert (tmp_path / "own" / m["files"][0]["path"]).exists()
    m = brdfbake.run(json.dumps(job), tmp_path / "text")
    assert (tmp_path / "text" / "manifest.json").exists()
