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
