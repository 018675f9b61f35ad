"""examples/merl_sweep.py with a small N: through Dask and in a single process, as .npy shards and
MERL binaries, the same tables."""

import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

pytest.importorskip("distributed", reason="dask.distributed is not installed")
SCRIPT = str(REPO / "examples" / "merl_sweep.py")


def run(*args):
    got = subprocess.run([sys.executable, SCRIPT, *args, "--json"], capture_output=True, text=True, timeout=600)
    assert got.returncode == 0, got.stderr[-3000:]
    return json.loads(got.stdout.strip().splitlines()[-1])


def test_merl_sweep_dask_and_single_process_agree(tmp_path):
    dask = run("--count", "5", "--output", str(tmp_path / "dask"), "--npy-shards", "2", "--workers", "2")
    single = run("--count", "5", "--output", str(tmp_path / "single"), "--npy-shards", "2", "--single-process")
    assert dask["baked"] == single["baked"] == 5 and dask["tables_per_second"] > 0
    for shard, size in (("shard-00000", 2), ("shard-00001", 2), ("shard-00002", 1)):
        a = np.load(tmp_path / "dask" / f"{shard}.npy")
        b = np.load(tmp_path / "single" / f"{shard}.npy")
        assert a.shape == (size, 90, 90, 180, 3) and a.dtype == np.float32
        np.testing.assert_array_equal(a, b)
        index = json.loads((tmp_path / "dask" / f"{shard}.json").read_text())["items"]
        names = [i["name"] for i in index]
        assert names == [i["name"] for i in json.loads((tmp_path / "single" / f"{shard}.json").read_text())["items"]]
        assert all(json.loads(i["meta"]["materials"])[0]["name"] == i["name"] for i in index)
    # MERL binaries, single process: one file and its metadata per material.
    run("--count", "2", "--output", str(tmp_path / "merl"), "--single-process")
    assert sorted(p.name for p in (tmp_path / "merl").iterdir()) == [
        "sweep-00000.binary", "sweep-00000.binary.json", "sweep-00001.binary", "sweep-00001.binary.json"]
