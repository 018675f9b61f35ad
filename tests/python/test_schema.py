"""Python, the command line and jobs cannot drift: every schema parameter of every kind is an
argument of the Python function of its kind (or is listed with what replaces it), every argument of
a function is a schema parameter or one of the fields every table shares, and both are accepted."""

import inspect
import json
import math
import subprocess

import pytest

import brdfbake
from brdfbake import _api

COMMON = {name for name, _, _ in _api._COMMON}
INPUTS = {"env", "sanitize", "wi", "wo", "kind"}

ALL_KINDS = [k["name"] for k in brdfbake.kinds()]


def test_every_kind_has_a_function():
    assert set(ALL_KINDS) == {"ggx", "ggx-multiscatter", "charlie", "fresnel", "thin-film", "prefilter",
                              "irradiance", "eval", "tabulate", "preview"}
    for k in brdfbake.kinds():
        f = brdfbake.function_of(k["name"])
        assert f.__name__ == k["command"].replace("-", "_")
        assert getattr(brdfbake, f.__name__) is f
        assert f.__doc__ and k["summary"] in f.__doc__


@pytest.mark.parametrize("kind", ALL_KINDS)
def test_schema_and_signature_agree(kind):
    f = brdfbake.function_of(kind)
    arguments = set(inspect.signature(f).parameters)
    schema = {d["name"]: d for d in brdfbake.schema(kind)}
    replaced = _api.REPLACED.get(kind, {})
    # Every schema parameter: an argument, or replaced (with a reason).
    for name in schema:
        assert name in arguments or name in replaced, f"{kind}.{name} is not an argument of {f.__name__}()"
        assert not (name in arguments and name in replaced)
        if name in arguments:
            assert name in f.__doc__
    for name, why in replaced.items():
        assert name in schema and why
    # Every argument: a parameter of one of the function's kinds, or a common field or input.
    family_params = set()
    for k in _api.FAMILIES[brdfbake.kinds()[ALL_KINDS.index(kind)]["command"]].kinds:
        family_params |= {d["name"] for d in brdfbake.schema(k)}
    for name in arguments:
        assert name in family_params or name in COMMON or name in INPUTS, f"{f.__name__}({name}=) is in no schema"
    # The defaults shown are the schema's.
    sig = inspect.signature(f)
    for name, d in schema.items():
        if name in sig.parameters and not d["required"]:
            assert sig.parameters[name].default == d.get("default"), name


def example_value(d):
    """A valid value of a parameter: its default, else one taken from its range or choices."""
    if d.get("default") is not None:
        return d["default"]
    if d.get("choices"):
        return d["choices"][0]
    t, lo, hi = d["type"], d.get("min", -math.inf), d.get("max", math.inf)
    if t == "flag":
        return True
    if t in ("integer", "integers"):
        return int(max(lo, 1)) if t == "integer" else [int(max(lo, 1))]
    if t in ("number", "rgb"):
        return min(max(lo, 0.5), hi) if not d.get("min_exclusive") else min(lo + 0.5, hi)
    if t == "range":
        return [lo, hi] if hi < 1e300 else [lo, lo + 1]
    return None  # paths and free names depend on the kind


# The base request of a kind, and for parameters that apply only with others (each family's rules
# across fields), the context in which each one is valid.
MINIMAL = {
    "fresnel": {"model": "dielectric", "ior": 1.5},
    "thin-film": {"base_ior": 1.5},
    "tabulate": {"layout": "albedo"},
}
_LUT_SYMBOL = {"symbol": {"symbol": "dfg", "output": "dfg.h"}}
CONTEXT = {
    "ggx": _LUT_SYMBOL, "ggx-multiscatter": _LUT_SYMBOL, "charlie": _LUT_SYMBOL,
    "fresnel": {
        "model": {"model": "schlick-ior", "ior": 1.5},
        "material": {"model": "conductor", "material": "gold"},
        "f0": {"model": "schlick", "f0": 0.04}, "f90": {"model": "schlick", "f0": 0.04, "f90": 0.9},
        "f82": {"model": "f82-tint", "f0": 0.9, "f82": 0.8},
        "base_color": {"model": "schlick-metallic", "base_color": 0.5, "metallic": 1.0},
        "metallic": {"model": "schlick-metallic", "base_color": 0.5, "metallic": 1.0},
        "dielectric_f0": {"model": "schlick-metallic", "base_color": 0.5, "metallic": 0.5, "dielectric_f0": 0.05},
        "n": {"model": "conductor", "n": 0.2, "k": 3.0}, "k": {"model": "conductor", "n": 0.2, "k": 3.0},
        "bias": {"model": "empirical", "bias": 0.0, "scale": 1.0, "power": 5.0},
        "scale": {"model": "empirical", "bias": 0.0, "scale": 1.0, "power": 5.0},
        "power": {"model": "empirical", "bias": 0.0, "scale": 1.0, "power": 5.0},
        "range": {"model": "schlick", "table": "2d", "range": [0.0, 1.0]},
        "symbol": {"model": "dielectric", "ior": 1.5, "symbol": "fresnel_table", "output": "f.h"},
    },
    "thin-film": {"base_f0": {"base_f0": 0.9}, "symbol": {"base_ior": 1.5, "symbol": "film", "output": "t.h"}},
    "prefilter": {"samples": {"estimator": "sampling", "samples": 64}},
    "irradiance": {"sh_json": {"cube_size": 8, "sh_json": "sh.json", "output": "i.ktx2"}},
    "eval": {"name": {"name": "red"}},
    "tabulate": {"name": {"layout": "merl", "name": "red"}, "phi_d": {"layout": "slice", "phi_d": 1.0},
                 "symbol": {"layout": "albedo", "symbol": "albedo", "output": "a.h"}},
    # preview reads its files when validated: a material file (RED_FILE) and a bake folder (BAKE_DIR,
    # one holding a manifest.json), put in by request()
    "preview": {"material": {"material": "RED_FILE"}, "scene": {"scene": "RED_FILE"}, "bake": {"bake": "BAKE_DIR"},
                "keep_bake": {"keep_bake": "NEW_DIR"}},
}


@pytest.mark.parametrize("kind", ALL_KINDS)
def test_every_parameter_is_accepted_by_validation(kind, red_file, tmp_path):
    bake_dir = tmp_path / "bake"
    bake_dir.mkdir()
    (bake_dir / "manifest.json").write_text("{}")

    def request(args):
        if kind in ("eval", "tabulate"):
            args = dict(args, material=str(red_file))
        args = {k: str(red_file) if v == "RED_FILE" else str(bake_dir) if v == "BAKE_DIR"
                else str(tmp_path / "kept") if v == "NEW_DIR" else v for k, v in args.items()}
        return brdfbake.validate(kind, **args)

    base = MINIMAL.get(kind, {})
    request(base)
    for d in brdfbake.schema(kind):
        name = d["name"]
        if name in _api.REPLACED.get(kind, {}) or (kind in ("eval", "tabulate") and name == "material"):
            continue
        if name in CONTEXT.get(kind, {}):
            args = CONTEXT[kind][name]
        else:
            assert example_value(d) is not None, f"{kind}.{name}: give it a context in CONTEXT"
            args = dict(base, **{name: example_value(d)})
        resolved = request(args)
        if not d["output_only"]:
            assert name in resolved["parameters"], (kind, name)


@pytest.mark.parametrize("kind", ["ggx", "fresnel", "prefilter", "irradiance", "tabulate"])
def test_cli_options_are_the_schema(cli, kind):
    # The command's --help lists an option for every parameter (the CLI is generated from the same
    # schema), so a parameter reachable from Python is reachable from the CLI.
    command = brdfbake.kinds()[ALL_KINDS.index(kind)]["command"]
    help_text = subprocess.run([cli, command, "--help"], capture_output=True, text=True).stdout
    for d in brdfbake.schema(kind):
        flag = d["option"] if not (d["type"] == "flag" and d.get("default") is True) else "--no-" + d["option"][2:]
        assert flag in help_text, (kind, flag)


def test_schema_is_the_command_lines_serialisation(cli):
    # One serialisation of the schemas (the library's): `brdfbake kinds --json` and brdfbake.schema()
    # give the same objects, with the same type names.
    doc = json.loads(subprocess.run([cli, "kinds", "--json"], capture_output=True, text=True, check=True).stdout)
    for k in doc["kinds"]:
        assert brdfbake.schema(k["kind"]) == k["parameters"], k["kind"]
    types = {d["type"] for k in doc["kinds"] for d in k["parameters"]}
    assert types <= {"integer", "number", "name", "path", "flag", "rgb", "range", "integers"}, types
    assert {"integer", "rgb"} <= types
    size = next(d for d in brdfbake.schema("ggx") if d["name"] == "size")
    assert size["type"] == "integer" and size["default"] == 128 and isinstance(size["default"], int)
    assert size["min"] == 1 and size["option"] == "--size"
