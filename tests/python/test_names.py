"""One name per meaning (issue 34, docs/SCENES.md): from Python, every alias (an option's old name)
gives what its canonical name gives, both together are refused with one line, and what the package
returns names only the canonical names."""

import inspect
import json
import subprocess

import numpy as np
import pytest

import brdfbake

# bake_scene's options: (canonical, alias, a value that changes the plan)
BAKE = [("chain_size", "cube_size", 64), ("chain_max_error", "prefilter_max_error", 0.02), ("sh_order", "sh", 5)]

# the table functions' parameters: (kind, canonical, alias, value)
TABLE = [
    ("prefilter", "chain_size", "size", 32),
    ("prefilter", "chain_max_error", "max_error", 0.05),
    ("irradiance", "irradiance_size", "cube_size", 4),
    ("irradiance", "irradiance_size", "cube", 4),
    ("irradiance", "sh_order", "sh", 5),
]


def test_every_alias_is_covered():
    """A new alias of a bake option or of a table parameter needs its row above (or its own test)."""
    bake = {(o["name"], a[2:].replace("-", "_")) for o in brdfbake.plan_options() for a in o.get("aliases", [])}
    assert bake - {("environment", "env")} == {(n, a) for n, a, _ in BAKE}
    table = {(k["name"], d["name"], a[2:].replace("-", "_"))
             for k in brdfbake.kinds() for d in brdfbake.schema(k["name"]) for a in d.get("aliases", [])}
    assert table == {(k, n, a) for k, n, a, _ in TABLE} | {("preview", "material", "materials")}


@pytest.mark.parametrize("name,alias,value", BAKE)
def test_bake_scene_takes_an_alias_as_its_name(name, alias, value, cli):
    by_name = brdfbake.bake_scene(dry_run=True, **{name: value})
    assert brdfbake.bake_scene(dry_run=True, **{alias: value}) == by_name
    assert by_name != brdfbake.bake_scene(dry_run=True)  # the value is seen, or this proves nothing
    assert f'"{alias}"' not in json.dumps(by_name)
    # the command line, by the canonical name: the same tables
    out = subprocess.run([cli, "bake", "--dry-run", "--json", "--" + name.replace("_", "-"), str(value)],
                         check=True, capture_output=True, text=True).stdout
    assert json.loads(out)["tables"] == by_name["tables"]
    with pytest.raises(brdfbake.InputError) as e:
        brdfbake.bake_scene(dry_run=True, **{name: value, alias: value})
    assert str(e.value) == f"bake_scene.{name}: given together with its alias {alias} (the same option): give one"


@pytest.mark.parametrize("kind,name,alias,value", TABLE)
def test_table_keywords_take_an_alias_as_its_name(kind, name, alias, value):
    by_name = brdfbake.validate(kind, **{name: value})
    assert brdfbake.validate(kind, **{alias: value}) == by_name
    assert by_name["parameters"][name] == value and alias not in by_name["parameters"]
    # the generated function's signature names the canonical name only; the alias is still a keyword
    assert name in inspect.signature(brdfbake.function_of(kind)).parameters
    assert alias not in inspect.signature(brdfbake.function_of(kind)).parameters
    with pytest.raises(brdfbake.ArgumentError) as e:
        brdfbake.function_of(kind)("builtin:sun", **{name: value, alias: value})
    assert str(e.value) == f"{kind}.{name}: given together with its alias {alias} (the same option): give one"
    with pytest.raises(brdfbake.InputError) as e:
        brdfbake.validate(kind, **{name: value, alias: value})
    assert str(e.value) == f"{kind}.{name}: given together with its alias {alias} (the same option): give one"


def test_the_old_names_bake_what_the_new_ones_bake():
    a = brdfbake.prefilter("builtin:sun", chain_size=8, min_size=4)
    b = brdfbake.prefilter("builtin:sun", size=8, min_size=4)
    assert len(a.array) == len(b.array) == 2
    for x, y in zip(a.array, b.array):
        np.testing.assert_array_equal(x, y)
    c = brdfbake.irradiance("builtin:sun", irradiance_size=4, source_size=8)
    d = brdfbake.irradiance("builtin:sun", cube_size=4, source_size=8)
    assert c.cube.shape == (6, 4, 4, 3)
    np.testing.assert_array_equal(c.cube, d.cube)


def test_the_preview_takes_its_material_file_by_its_old_name(red_file):
    """preview's material file is `material`, as eval and tabulate name theirs (a table's `materials`
    is the informative list of the materials that asked for it); `materials` is its alias."""
    by_name = brdfbake.validate("preview", material=str(red_file))
    assert brdfbake.validate("preview", materials=str(red_file)) == by_name
    assert by_name["parameters"]["material"] == str(red_file) and "materials" not in by_name["parameters"]
    assert "material" in inspect.signature(brdfbake.preview).parameters
    assert inspect.signature(brdfbake.preview).parameters["material"].kind == inspect.Parameter.KEYWORD_ONLY
    with pytest.raises(brdfbake.ArgumentError) as e:
        brdfbake.preview("builtin:sun", material=str(red_file), materials=str(red_file))
    assert str(e.value) == "preview.material: given together with its alias materials (the same option): give one"
