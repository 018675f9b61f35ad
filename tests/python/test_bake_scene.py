"""brdfbake.bake_scene: the scene planner of `brdfbake bake`, engine targets included, from Python.
The files are the command's, byte for byte; the plan is a job that brdfbake.run bakes the same."""

import filecmp
import subprocess

import pytest

import brdfbake

# Small sizes: the whole standard set with a glTF engine file set bakes in well under a second.
SMALL = {"cube_size": 16, "lut_size": 16, "fresnel_size": 16, "thin_film_size": 16}  # cube_size: chain_size's alias
SMALL_CLI = ["--chain-size", "16", "--lut-size", "16", "--fresnel-size", "16", "--thin-film-size", "16"]


def assert_same_folders(a, b):
    """Every file of `a` is in `b` with the same bytes, once the folder's own name (which names the
    engine files: a.gltf, a_specular_0_px.png) is read as the other's."""
    names_a = sorted(p.name for p in a.iterdir() if p.name != "manifest.json")
    names_b = sorted(p.name.replace(b.name, a.name) for p in b.iterdir() if p.name != "manifest.json")
    assert names_a == names_b
    for name in names_a:
        other = b / name.replace(a.name, b.name)
        if name.endswith(".gltf"):  # it names its images after the folder
            assert (a / name).read_text().replace(a.name, "FOLDER") == other.read_text().replace(b.name, "FOLDER"), name
        else:
            assert filecmp.cmp(a / name, other, shallow=False), name


def test_the_standard_set_with_an_engine_target_is_the_commands(tmp_path, cli):
    py, cmd = tmp_path / "from_python", tmp_path / "from_cli"
    manifest = brdfbake.bake_scene(None, py, target="gltf", **SMALL)
    subprocess.run([cli, "bake", "--target", "gltf", *SMALL_CLI, "-o", str(cmd), "--quiet"], check=True)
    assert_same_folders(py, cmd)
    assert manifest["engine"]["target"] == "gltf"
    assert "from_python.gltf" in manifest["engine"]["files"]
    kinds = {f["kind"] for f in manifest["files"]}
    assert {"ggx-multiscatter", "prefilter", "irradiance"} <= kinds


def test_the_plan_is_a_job_that_run_bakes_the_same(tmp_path):
    plan = brdfbake.bake_scene(dry_run=True, target="filament", **SMALL)
    assert plan["target"] == "filament"
    assert plan["plan"]["rules_fired"]
    brdfbake.run(plan, tmp_path / "by_run")
    brdfbake.bake_scene(None, tmp_path / "by_bake_scene", target="filament", **SMALL)
    assert_same_folders(tmp_path / "by_run", tmp_path / "by_bake_scene")


def test_a_scene_plans_what_its_materials_call_for(shared_dir):
    if shared_dir is None or not (shared_dir / "scenes" / "SheenChair.gltf").exists():
        pytest.skip("../shared/scenes/SheenChair.gltf is absent (set BRDFBAKE_SHARED_DIR)")
    plan = brdfbake.bake_scene(shared_dir / "scenes" / "SheenChair.gltf", dry_run=True, **SMALL)
    kinds = {t["kind"] for t in plan["tables"]}
    assert "charlie" in kinds, kinds  # KHR_materials_sheen asks for the Charlie DFG table
    assert plan["plan"]["materials"]


def test_plan_options_are_the_commands(cli):
    help_text = subprocess.run([cli, "bake", "--help"], capture_output=True, text=True).stdout
    options = brdfbake.plan_options()
    assert {"target", "chain_size", "lut_size", "table_format"} <= {o["name"] for o in options}
    assert "cube_size" not in {o["name"] for o in options}  # an alias of chain_size (issue 34)
    for o in options:
        flag = o["option"] if not (o["type"] == "flag" and o.get("default") is True) else "--no-" + o["option"][2:]
        assert flag in help_text, flag


@pytest.mark.parametrize("call, message", [
    (dict(target="unity"), "bake_scene.target: must be one of generic, filament"),
    (dict(cube_sizee=16), "bake_scene: cube_sizee: unknown option (expected energy_compensation"),
    (dict(chain_size=float("nan")), "bake_scene.chain_size: must be an integer"),
    (dict(cube_size="16"), "bake_scene.chain_size"),  # by its old name (an alias): named canonically
    (dict(precision="fp128"), "bake_scene.precision"),
    (dict(scene="/nonexistent/scene.gltf"), "/nonexistent/scene.gltf"),
])
def test_bad_plan_input_raises_one_line(call, message):
    with pytest.raises(brdfbake.InputError) as e:
        brdfbake.bake_scene(dry_run=True, **call)
    assert message in str(e.value)
    assert "\n" not in str(e.value)


def test_no_output_dir_without_dry_run_raises():
    with pytest.raises(brdfbake.InputError, match="bake_scene.output_dir: missing"):
        brdfbake.bake_scene()


def test_run_takes_a_jobs_engine_target(tmp_path):
    job = {"brdfbake_job": 1, "target": "gltf",
           "tables": [{"kind": "prefilter", "size": 16}, {"kind": "irradiance", "sh_order": 3}]}
    manifest = brdfbake.run(job, tmp_path / "out")
    assert manifest["engine"]["target"] == "gltf"
    for name in manifest["engine"]["files"]:
        assert (tmp_path / "out" / name).is_file(), name


def _key_values(data: bytes, ktx2: bool) -> dict:
    """The key/value data of a KTX 1.1 file (bytesOfKeyValueData at byte 60, the entries from byte 64)
    or of a KTX 2.0 file (kvdByteOffset, kvdByteLength at bytes 56, 60); values without their NUL."""
    import struct

    begin, length = struct.unpack_from("<II", data, 56) if ktx2 else (64, struct.unpack_from("<I", data, 60)[0])
    out, at = {}, begin
    while at < begin + length:
        n = struct.unpack_from("<I", data, at)[0]
        key, value = data[at + 4:at + 4 + n].split(b"\0", 1)
        out[key.decode()] = value.rstrip(b"\0").decode()
        at += 4 + ((n + 3) & ~3)
    return out


def _recorded(text: str, value: float) -> None:
    """A figure as files record it: rounded up to three significant digits, never below the measured."""
    import re

    recorded = float(text)
    assert value <= recorded <= value * (1 + 1e-2) + 1e-300, (text, value)
    assert len(re.sub(r"e.*$", "", text).replace("0.", "").lstrip("0").replace(".", "")) <= 3, text


@pytest.mark.parametrize("target", ["filament", "khronos-viewer", "babylon", "gltf"])
def test_each_engine_file_carries_its_manifest_entry(tmp_path, target):
    """The files users ship carry their error (issue 35): each engine file's own metadata (KTX1/KTX2
    key/values, the .env's manifest, a .gltf's image extras for its PNG faces) holds the delivered
    figures manifest.json's engine.file_entries records for it, under their names."""
    import json

    folder = tmp_path / "out"
    brdfbake.bake_scene(None, folder, target=target, **SMALL)
    manifest = json.loads((folder / "manifest.json").read_text())
    entries = {e["path"]: e for e in manifest["engine"]["file_entries"]}
    images = {}
    carried = 0
    for path, e in entries.items():
        data = (folder / path).read_bytes()
        assert e["bytes"] == len(data), path
        if path.endswith(".gltf"):
            images = {i["uri"]: i.get("extras", {}).get("brdfbake") for i in json.loads(data)["images"]}
        if e["error_rms_rel"] is None:
            continue
        if path.endswith((".ktx", ".ktx2")):
            kv = {k[len("brdfbake:"):]: v for k, v in _key_values(data, path.endswith(".ktx2")).items()
                  if k.startswith("brdfbake:")}
        elif path.endswith(".env"):
            kv = json.loads(data[8:data.index(b"\0", 8)])["brdfbake"]
        else:
            continue  # a PNG face: its figures are in the .gltf (below)
        carried += 1
        assert kv["error_name"] == "error_rms_rel", path
        for name in ("error_rms_rel", "error_max_rel"):
            _recorded(kv[name], e[name])
            levels = kv[name + "_per_level"].split(" ")
            assert len(levels) == len(e[name + "_per_level"]), path
            for text, value in zip(levels, e[name + "_per_level"]):
                _recorded(text, value)
        assert "decoded as the engine decodes it" in kv["error_definition"]
    for uri, kv in images.items():
        assert kv is not None and kv["error_name"] == "error_rms_rel", uri
        _recorded(kv["error_rms_rel"], entries[uri]["error_rms_rel"])
        _recorded(kv["error_max_rel"], entries[uri]["error_max_rel"])
        carried += 1
    assert carried >= {"filament": 2, "khronos-viewer": 2, "babylon": 1, "gltf": 6}[target]
