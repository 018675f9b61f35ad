"""brdfbake.dask on a 2-worker LocalCluster (separate processes, one device each): jobs, materials
and environments baked across workers, failures reported per item without losing the others."""

import json
import os

import numpy as np
import pytest

import brdfbake
from tolerances import ENV_FURNACE

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed (pip install dask[distributed])")
import brdfbake.dask as bdask  # noqa: E402


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as cluster, distributed.Client(cluster) as c:
        c.register_plugin(bdask.DevicePlugin())
        yield c


def csv_values(path):
    rows = [l for l in open(path) if not l.startswith("#")][1:]
    return np.array([[float(x) for x in r.split(",")] for r in rows])


def test_eight_jobs_one_failing(client, tmp_path):
    jobs = [{"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": 8 + i, "output": "dfg.csv"}]} for i in range(7)]
    # The failure happens on a worker, at bake time: its environment does not exist.
    jobs.insert(5, {"brdfbake_job": 1, "environment": str(tmp_path / "missing.hdr"), "tables": [{"kind": "irradiance"}]})
    batch = bdask.bake(client, jobs, output_root=tmp_path / "out")
    assert len(batch) == 8
    assert [o.name for o in batch.failed] == ["job-00005"]
    failed = batch.failed[0]
    assert failed.error_type == "InputError" and "missing.hdr" in failed.error
    assert not (tmp_path / "out" / "job-00005").exists()  # all or nothing
    assert len(batch.succeeded) == 7
    workers = set()
    for o in batch.succeeded:
        size = o.value["files"][0]["parameters"]["size"]
        folder = tmp_path / "out" / o.name
        assert json.loads((folder / "manifest.json").read_text()) == o.value
        got = csv_values(folder / "dfg.csv")[:, 2:].astype(np.float32).reshape(size, size, 3)
        # Correct: the very table this process bakes itself (same kernels, same device kind).
        np.testing.assert_array_equal(got, brdfbake.lut(kind="ggx", size=size).array)
        workers.add(o.worker)
    assert len(workers) == 2  # both workers took part
    with pytest.raises(brdfbake.Error, match="1 of 8 items failed: job-00005"):
        batch.raise_for_failures()


def test_materials_come_back_as_arrays(client):
    mats = [{"name": f"m{i}", "model": "gltf", "baseColor": [0.9, 0.5, 0.1], "roughness": 0.2 + 0.3 * i}
            for i in range(3)]
    batch = bdask.bake(client, mats, kind="tabulate", layout="merl")
    assert [o.name for o in batch] == ["m0", "m1", "m2"] and not batch.failed
    for m, o in zip(mats, batch):
        np.testing.assert_array_equal(o.value["array"], brdfbake.tabulate(m, layout="merl").array)
        assert o.value["meta"]["layout"] == "merl"


def test_npy_shards_with_a_bad_material(client, tmp_path):
    mats = [{"name": f"m{i}", "model": "disney", "roughness": 0.1 * i} for i in range(5)]
    mats[2]["roughness"] = 2.0  # out of range: this one fails, its shard keeps the other
    batch = bdask.bake(client, mats, kind="tabulate", layout="merl", output_root=tmp_path, output_format="npy",
                       shard_size=2)
    assert [o.name for o in batch.failed] == ["m2"] and "roughness" in batch.failed[0].error
    shards = sorted(p.name for p in tmp_path.iterdir())
    assert shards == ["shard-00000.json", "shard-00000.npy", "shard-00001.json", "shard-00001.npy",
                      "shard-00002.json", "shard-00002.npy"]
    s1 = np.load(tmp_path / "shard-00001.npy")
    assert s1.shape == (1, 90, 90, 180, 3) and s1.dtype == np.float32
    index = json.loads((tmp_path / "shard-00001.json").read_text())["items"]
    assert [i["name"] for i in index] == ["m3"]
    np.testing.assert_array_equal(s1[0], brdfbake.tabulate(mats[3], layout="merl").array)
    assert batch.by_name()["m4"].value == {"path": str(tmp_path / "shard-00002.npy"), "index": 0,
                                           "meta": batch.by_name()["m4"].value["meta"]}


def test_environments_written_under_the_output_root(client, tmp_path):
    white = np.ones((16, 32, 3), np.float32)
    batch = bdask.bake(client, [white, "builtin:studio", str(tmp_path / "nope.exr")], kind="irradiance",
                       names=["white", "studio", "nope"], output_root=tmp_path, sh_order=5)
    assert [o.name for o in batch.failed] == ["nope"]
    sh = json.loads((tmp_path / "white.json").read_text())
    assert sh["order"] == 5
    np.testing.assert_allclose(sh["irradiance_over_pi"][0], 2 * np.sqrt(np.pi), rtol=ENV_FURNACE)
    assert batch.by_name()["studio"].value["path"] == str(tmp_path / "studio.json")
    assert sorted(os.listdir(tmp_path)) == ["studio.json", "white.json"]  # nothing partial


def test_bad_batches_fail_before_submission(client, tmp_path):
    with pytest.raises(brdfbake.InputError, match="output_root"):
        bdask.bake(client, [{"brdfbake_job": 1, "tables": []}])
    with pytest.raises(brdfbake.InputError, match="two items are named"):
        bdask.bake(client, [{"name": "a"}, {"name": "a"}], kind="tabulate", layout="merl")
    with pytest.raises(brdfbake.InputError, match="tabulate.layout"):
        bdask.bake(client, [{"name": "a"}], kind="tabulate", layout="nonesuch")
    with pytest.raises(brdfbake.InputError, match="unknown table kind"):
        bdask.bake(client, [{}], kind="nonesuch")


def test_without_a_client_the_same_tasks_run_in_this_process(tmp_path):
    mats = [{"name": "a", "model": "lambert"}, {"name": "b", "model": "lambert", "baseColor": [2, 0, 0]}]
    batch = bdask.bake(None, mats, kind="tabulate", layout="albedo", res=8, output_root=tmp_path, suffix=".csv")
    assert [o.name for o in batch.succeeded] == ["a"] and "baseColor" in batch.failed[0].error
    assert batch[0].value["path"] == str(tmp_path / "a.csv") and sorted(os.listdir(tmp_path)) == ["a.csv"]
    assert batch[0].worker.endswith(":" + str(os.getpid()))


# MERL batches are large (33 MiB a table: the docs' 64 write 2.1 GiB, 1000 write 33 GiB): the batch
# says how much before baking, and one that cannot fit the free space is refused before anything
# is written (issue 24, a new user's item 10).
MERL_BINARY_BYTES = 90 * 90 * 180 * 3 * 8 + 12  # MERL's header: three int32 dimensions


def merl_materials(n):
    return [{"name": f"m{k}", "model": "gltf", "roughness": 0.2 + 0.1 * k} for k in range(n)]


def test_a_large_batch_is_announced_before_it_bakes(tmp_path, monkeypatch):
    monkeypatch.setattr(bdask, "LARGE_OUTPUT_BYTES", MERL_BINARY_BYTES)  # two tables are "large" here
    with pytest.warns(brdfbake.BakeWarning, match=r"2 tables of 33 MiB, about 67 MiB under .*GiB free\)"):
        batch = bdask.bake(None, merl_materials(2), kind="tabulate", layout="merl", output_root=tmp_path / "m")
    assert not batch.failed
    assert sum(os.path.getsize(o.value["path"]) for o in batch) == 2 * MERL_BINARY_BYTES  # the estimate is exact


def test_a_batch_larger_than_the_free_space_is_refused_before_baking(tmp_path, monkeypatch):
    import shutil

    free = 3 * MERL_BINARY_BYTES  # room for three tables, not for four
    monkeypatch.setattr(bdask.shutil, "disk_usage", lambda path: shutil._ntuple_diskusage(10 * free, 9 * free, free))
    with pytest.raises(brdfbake.InputError, match=r"4 tables of 33 MiB, about 133 MiB under .* but only 100 MiB is "
                                                  r"free there: bake fewer items"):
        bdask.bake(None, merl_materials(4), kind="tabulate", layout="merl", output_root=tmp_path / "m")
    assert os.listdir(tmp_path / "m") == []
    # npy halves it: four float32 tables fit.
    batch = bdask.bake(None, merl_materials(4)[:1], kind="tabulate", layout="merl", output_root=tmp_path / "n",
                       output_format="npy")
    assert not batch.failed


def test_a_sweep_of_settings_over_two_environments(client, shared_dir, tmp_path):
    """brdfbake.dask.sweep: 2 environments x 2 settings, one task per environment; each row's
    numbers are those of the same bake made and previewed here directly."""
    import time

    tiny = None if shared_dir is None else shared_dir / "envmaps" / "derived" / "venice_sunset_256x128_derived.hdr"
    if tiny is None or not tiny.exists():
        pytest.skip("../shared/envmaps/derived/venice_sunset_256x128_derived.hdr is not there")
    envs = ["builtin:sun", str(tiny)]
    t0 = time.perf_counter()
    rows = bdask.sweep(client, envs, [{}, {"cube_size": 32}], width=96, height=48)
    assert time.perf_counter() - t0 < 240  # 4 bakes of about a second and 2 small references
    assert [(r["env"], r["setting"]) for r in rows] == [
        ("builtin:sun", "default"), ("builtin:sun", "chain_size=32"),  # cube_size: an alias, named canonically
        ("venice_sunset_256x128_derived", "default"), ("venice_sunset_256x128_derived", "chain_size=32")]
    groups = ("white", "grey", "dark", "gold", "copper", "silver")
    for r in rows:
        assert "failed" not in r, r.get("failed")
        assert r["seconds"] > 0 and r["bytes"] == sum(r["file_sizes"].values()) and "manifest.json" in r["file_sizes"]
        assert len(r["spheres"]) == 72 and 0 < r["error"] < 10
        for figure in ("error", "engine_share", "bake_share"):
            assert set(k for k in r if k.startswith(figure + "_")) == {f"{figure}_{g}" for g in groups}
        # the shares (the default: each setting's preview renders its reference and its ideal bake)
        assert 0 < r["engine_share"] < 10 and 0 < r["bake_share"] < 10 and "reference_seconds" in r
    assert rows[0]["error"] != rows[2]["error"]  # the two maps differ
    # The 32^2 chain is smaller and, against the same reference, further from it.
    assert rows[1]["bytes"] < rows[0]["bytes"] and rows[1]["error"] > rows[0]["error"]

    # One row made here: the same bake (its files' sizes; the manifest holds times and paths) and a
    # direct preview of it, whose per-sphere errors are the row's (the library sums in double in
    # pixel order, NumPy pairwise: equal to rounding).
    folder = tmp_path / "tiny32"
    brdfbake.bake_scene(None, folder, env=str(tiny), cube_size=32)
    sizes = {str(p.relative_to(folder)): p.stat().st_size for p in folder.rglob("*") if p.is_file()}
    row = rows[3]
    assert sizes.keys() == row["file_sizes"].keys()
    assert {k: v for k, v in sizes.items() if k != "manifest.json"} == \
           {k: v for k, v in row["file_sizes"].items() if k != "manifest.json"}
    direct = brdfbake.preview(str(tiny), target="generic", bake=str(folder), width=96, height=48).preview
    for want, got in zip(direct["spheres"], row["spheres"]):
        assert got["name"] == want["name"]
        for stat in ("rms", "p99", "max"):
            assert got[stat] == pytest.approx(want["linear"][stat], rel=1e-9, abs=1e-12), (want["name"], stat)
            # the shares are the preview's own (its JSON's spheres[k].engine_share, .bake_share)
            for share in ("engine_share", "bake_share"):
                assert got[share][stat] == pytest.approx(want[share][stat], rel=1e-9, abs=1e-12), (want["name"], share)
    for share in ("engine_share", "bake_share"):
        assert row[share] == pytest.approx(float(np.median([s[share]["rms"] for s in direct["spheres"]])), rel=1e-9)
        gold = [s[share]["rms"] for s in direct["spheres"] if s["name"].startswith("gold")]
        assert row[share + "_gold"] == pytest.approx(float(np.median(gold)), rel=1e-9)


def test_a_sweep_splits_its_error_into_the_engines_share_and_the_bakes():
    """Each row's shares: per sphere the triangle inequality |engine - bake| <= error <= engine + bake
    (the difference images add up exactly: docs/PREVIEW.md), the row's error measured here against
    the preview's reference; a coarser chain (16^2) has the larger bake share (its level count moves
    the engine's too: the ideal bake has the files' levels); shares=False leaves them out and renders
    the reference once."""
    rows = bdask.sweep(None, "builtin:sun", [{}, {"chain_size": 16}], width=96, height=48)
    for r in rows:
        assert "failed" not in r, r.get("failed")
        for s in r["spheres"]:
            e, b = s["engine_share"]["rms"], s["bake_share"]["rms"]
            assert abs(e - b) * (1 - 1e-6) - 1e-9 <= s["rms"] <= (e + b) * (1 + 1e-6) + 1e-9, s
    default, coarse = rows
    assert coarse["bake_share"] > default["bake_share"]
    without = bdask.sweep(None, "builtin:sun", [{}, {"chain_size": 16}], width=96, height=48, shares=False)
    for r, w in zip(rows, without):
        assert not any(k.startswith(("engine_share", "bake_share")) for k in w)
        assert "engine_share" not in w["spheres"][0]
        assert w["error"] == pytest.approx(r["error"], rel=1e-9)  # the same reference
    assert "reference_seconds" in without[0] and "reference_seconds" not in without[1]


def test_a_sweep_without_a_cluster_and_a_failing_setting():
    rows = bdask.sweep(None, ["builtin:sun"], {"small": {"cube_size": 16}, "bad": {"cube_size": 0}},
                       width=96, height=48)
    assert [r["setting"] for r in rows] == ["small", "bad"]
    assert "failed" not in rows[0] and rows[0]["bytes"] > 0
    assert "chain_size" in rows[1]["failed"] and "error" not in rows[1]  # cube_size: its alias
    with pytest.raises(brdfbake.InputError, match="sweep.envs"):
        bdask.sweep(None, [], [{}])


def test_a_sweep_refuses_its_own_arguments_as_settings_and_takes_one_env_string():
    # issue 34, class 7: a setting naming target or scene aborted every row; a string was one
    # environment a character
    for name in ("target", "scene"):
        with pytest.raises(brdfbake.InputError, match=rf"sweep.settings\['x'\].{name}: not a setting"):
            bdask.sweep(None, ["builtin:sun"], {"x": {name: "filament"}}, width=96, height=48)
    rows = bdask.sweep(None, "builtin:sun", [{"cube_size": 16}], width=96, height=48)
    assert [r["env"] for r in rows] == ["builtin:sun"]
    assert "failed" not in rows[0]
