"""The public functions of brdfbake, built from the table schemas of the library.

One function per table family (``lut``, ``fresnel``, ``thin_film``, ``prefilter``, ``irradiance``,
``eval``, ``tabulate``) is generated at import time from the family registry: its keyword arguments
are the job fields of the family's kinds, with their types, ranges, defaults and help, so that
Python, the command line and jobs take exactly the same parameters (tests/python/test_schema.py
holds them to it). Values are checked by the library's own validation, the messages naming the
field as ``<function>.<field>``.
"""

from __future__ import annotations

import difflib
import inspect
import json
import math
import numbers
import os
import warnings
from typing import Any, Callable, Dict, List, Optional, Sequence

import numpy as np

from . import _brdfbake as _core
from ._errors import ArgumentError, BakeWarning, InputError

# Every kind's schema as ``brdfbake kinds --json`` prints it: one serialisation, the library's.
_KINDS_JSON = {k["kind"]: k for k in json.loads(_core.kinds_json())["kinds"]}


def _schema_of(kind: str) -> List[Dict[str, Any]]:
    if kind not in _KINDS_JSON:
        _core.validate(kind, [], {}, "schema")  # raises the library's message naming the kinds
    return json.loads(json.dumps(_KINDS_JSON[kind]["parameters"]))  # a copy the caller may change


# ---- Results -------------------------------------------------------------------------------------


class Result:
    """What a baking call returns.

    ``array`` holds the data as float32 NumPy (read-only views of the result's own buffers where the
    layout allows: tables and cube levels are not copied):

    - tables (DFG, Fresnel, thin film, tabulate grid/albedo/slice): shape (height, width, channels),
      row 0 first (``axes`` gives the coordinates and channel names);
    - prefilter: a list of levels, each of shape (6, size, size, 3): faces +X, -X, +Y, -Y, +Z, -Z;
    - irradiance: the SH coefficients of E / pi, shape (order**2, 3) (``sh`` has them in float64,
      ``cube`` the irradiance cube when one was baked);
    - tabulate layout merl: shape (90, 90, 180, 3): theta_h, theta_d, phi_d bins, then r, g, b; f
      itself (not divided by MERL's channel scales), -1 in bins below the horizon;
    - eval: shape (n, 3), f (without the cosine) at each pair.
    - preview: shape (height, width, 3): the split-sum render, linear radiance, row 0 at the top;
      ``.preview`` holds both renders, the error image and every number.

    ``meta`` is the metadata the file would carry, as a dict of strings, with its error figure under
    its name (``error_name``; ``error`` and ``errors`` give it too) as a number (None where the family
    measures none) and its definition. ``save(path)`` writes the
    result with the command-line tool's writers (atomically: no partial file, ever).
    """

    __slots__ = ("_core", "_array", "__weakref__")

    def __init__(self, core: "_core.Result"):
        self._core = core
        self._array = None

    # -- what was baked
    @property
    def kind(self) -> str:
        """The table kind, e.g. ``"ggx"``."""
        return self._core.kind

    @property
    def parameters(self) -> Dict[str, Any]:
        """Every parameter as baked, resolved defaults included (e.g. the DFG sample count)."""
        return self._core.parameters

    @property
    def request(self) -> Dict[str, Any]:
        """The validated request: kind, parameters as given with defaults, precision, device, ..."""
        return self._core.request

    @property
    def summary(self) -> str:
        """One line for people: what was baked, how well, how fast (the CLI prints the same)."""
        return self._core.summary

    @property
    def device(self) -> str:
        """The device's name, or ``"reference"``."""
        return self._core.device

    @property
    def seconds(self) -> float:
        """Wall time of the bake."""
        return self._core.seconds

    @property
    def device_seconds(self) -> float:
        """Kernel time of the bake (0 on the reference)."""
        return self._core.device_seconds

    @property
    def error(self) -> Optional[float]:
        """The result's error figure, the number named :attr:`error_name` (None where the family
        measures none): the result's own, the integration bound (what a file adds is in
        :attr:`files`)."""
        return self._core.error

    @property
    def errors(self) -> Dict[str, Optional[float]]:
        """The error figure by its name, as the manifest and the files key it:
        ``{error_name: error}``, e.g. ``{"error_bound_mixed": 1.8e-05}``."""
        return {self.error_name: self.error}

    @property
    def error_bound(self) -> Optional[float]:
        """Deprecated (a name that did not say which figure): :attr:`error`, named by
        :attr:`error_name`, or :attr:`errors`. Warns with :class:`DeprecationWarning`."""
        warnings.warn("Result.error_bound is deprecated: use Result.error (the figure Result.error_name names) "
                      "or Result.errors (by its name)", DeprecationWarning, stacklevel=2)
        return self.error

    @property
    def error_name(self) -> str:
        """What :attr:`error` is, by the name the manifest, the files, the summary and the server give
        it (docs/CONVENTIONS.md, "Error figures"): ``error_bound_mixed``, ``error_bound_rel``,
        ``error_rms_rel`` or ``error_rms_rel_bound``."""
        return self._core.error_name

    @property
    def error_definition(self) -> str:
        """The one definition of :attr:`error_name` for this kind."""
        return self._core.error_definition

    @property
    def warnings(self) -> List[str]:
        """What was changed on the way to the files written from this result (``output=`` and every
        ``save()``), e.g. values clamped by ``clamp_f16``; each was also emitted as a
        :class:`brdfbake.BakeWarning`."""
        return self._core.warnings

    @property
    def files(self) -> List[Dict[str, Any]]:
        """The files written from this result, in order: ``path``, ``error_name`` and the figure under
        that name (what the file records: the integration bound plus ``storage_error``, what its
        ``encoding`` adds), ``storage_error``, ``encoding`` and ``warnings``."""
        files = []
        for f in self._core.files:
            f = dict(f)
            value = f.pop("error", None)
            f["error_name"] = self.error_name
            f[self.error_name] = value
            files.append(f)
        return files

    @property
    def details(self) -> Dict[str, str]:
        """What else the family reports (channels, levels, error against exact, ...)."""
        return self._core.details

    # -- the data
    @property
    def array(self):
        """The data as float32 NumPy (see the class documentation for each kind's shape)."""
        if self._array is None:
            artifact = self._core.artifact
            if artifact == "table":
                self._array = self._core.table_array()
            elif artifact == "cube":
                self._array = self._core.cube_levels()
            elif artifact == "preview":
                self._array = self._core.preview()["splitsum"]
            elif artifact == "irradiance":
                a = self._core.sh()["irradiance_over_pi"].astype(np.float32)
                a.flags.writeable = False
                self._array = a
            else:  # merl, eval: float64 in the library, converted once
                self._array = self._core.converted_array()
        return self._array

    @property
    def axes(self) -> Optional[Dict[str, Any]]:
        """Tables: ``channels``, ``x_name``, ``x`` (one value a column), ``y_name``, ``y`` (a row)."""
        return self._core.table_axes()

    @property
    def levels(self):
        """prefilter: the levels, each (6, size, size, 3); irradiance: the cube's one level, or None."""
        return self._core.cube_levels()

    @property
    def cube(self):
        """irradiance: the irradiance cube (E / pi) as (6, size, size, 3), or None without one."""
        levels = self._core.cube_levels()
        return levels[0] if levels else None

    @property
    def sh(self):
        """irradiance: the SH coefficients of E / pi in float64, shape (order**2, 3) (``array`` holds
        them in float32); read-only. What they mean is in ``meta``: ``order``, ``basis``,
        ``irradiance_definition``, ``window``, ``window_weights``. None for other kinds."""
        return self._sh_array("irradiance_over_pi")

    @property
    def sh_radiance(self):
        """irradiance: the SH coefficients of the radiance itself, L_lm (float64, (order**2, 3),
        read-only; ``meta["radiance_definition"]``), before the cosine lobe and the window."""
        return self._sh_array("radiance")

    def _sh_array(self, key: str):
        core = self._core.sh()
        if core is None:
            return None
        a = np.asarray(core[key], dtype=np.float64)
        a.flags.writeable = False
        return a

    @property
    def preview(self) -> Optional[Dict[str, Any]]:
        """preview: the two renders and every number of NAME.json (docs/PREVIEW.md), or None.

        ``splitsum`` and ``reference`` (float32 (height, width, 3), linear radiance, row 0 at the top;
        ``reference`` None with ``reference=False``), ``error`` (float32 (height, width): per pixel
        |split-sum - reference| / |reference| of the RGB triples' norms, NaN off the spheres), and
        ``spheres``: per sphere its material (``name``, ``base_color``, ``metallic``, ``roughness``,
        ``f0``, ``diffuse_color``), ``row``, ``column``, ``centre`` (x, y) and ``radius`` in pixels,
        ``pixels``, ``linear`` and ``srgb8`` (``rms``, ``p99``, ``max``) and ``reference_bound``
        (``rms``, ``max``, ``pixels``, ``refinement``: the refinement the sphere was integrated
        at); ``camera`` (``view_direction``, ``up``, ``right`` in the environment's frame),
        ``target``, ``brdf``, ``multiscatter``, ``exposure``, ``bake``,
        ``shading`` (each step of the target's shader) and ``times``. With the error's shares
        (``shares=True``, the default with the reference): ``ideal`` (float32 (height, width, 3), the
        target's shader rendered from the ideal bake), per sphere ``engine_share`` (|ideal -
        reference| / |reference|) and ``bake_share`` (|split-sum - ideal| / |reference|), each
        ``rms``, ``p99``, ``max`` (the difference images add up exactly, their RMS do not),
        ``ideal_bake`` (what it holds) and ``share_groups`` (per group ``name``, ``spheres``,
        ``error``, ``engine_share``, ``bake_share``: ``median`` and ``worst`` sphere RMS); otherwise
        ``ideal`` is None.
        """
        doc = self._core.preview()
        if doc is None:
            return None
        ref = doc["reference"]
        if ref is None:
            doc["error"] = None
            return doc
        split = doc["splitsum"]
        h, w = split.shape[:2]
        error = np.full((h, w), np.nan, dtype=np.float32)
        ys, xs = np.mgrid[0:h, 0:w]
        norm_s = np.linalg.norm(split.astype(np.float64) - ref, axis=2)
        norm_r = np.linalg.norm(ref.astype(np.float64), axis=2)
        for sphere in doc["spheres"]:
            cx, cy = sphere["centre"]
            inside = (xs + 0.5 - cx) ** 2 + (ys + 0.5 - cy) ** 2 < sphere["radius"] ** 2
            with np.errstate(divide="ignore", invalid="ignore"):
                error[inside] = (norm_s[inside] / norm_r[inside]).astype(np.float32)
        error.flags.writeable = False
        doc["error"] = error
        return doc

    @property
    def meta(self) -> Dict[str, Any]:
        """The metadata the file carries, with its error figure (``error_name``) as a number (or None)."""
        if self._core.artifact == "irradiance":
            doc = json.loads(self._core.sh_json())
            meta: Dict[str, Any] = {k: v for k, v in doc.items() if k not in ("radiance", "irradiance_over_pi")}
            cube = self._core.metadata
            if cube:
                meta["cube"] = cube
        else:
            meta = dict(self._core.metadata)
        meta.setdefault("kind", self.kind)
        # the error figure under its kind's name, as the files record it (never the legacy error_bound)
        meta.pop("error_bound", None)
        meta.pop("error_bound_definition", None)
        meta["error_name"] = self.error_name
        meta[self.error_name] = self._core.error
        meta["error_definition"] = self.error_definition
        meta["error_measurement"] = self._core.error_measurement
        return meta

    def save(self, path: "os.PathLike[str] | str", *, format: Optional[str] = None, pixel: Optional[str] = None,
             **output_params: Any) -> str:
        """Writes the result to ``path`` with the command-line tool's writers, atomically.

        The extension picks the format as on the command line (tables: .exr .png .hdr .ktx2 .csv .h;
        prefilter: .ktx2 .ktx .dds or a folder; irradiance: .json, or a cube container when baked
        with ``irradiance_size``; merl: .binary with a .json beside it; eval: CSV, or float32 for .f32
        .bin .raw). ``format`` and ``pixel`` (``"f16"`` or ``"f32"``; a prefilter chain's .ktx2 also
        ``"astc4x4"`` or ``"astc6x6"``, ASTC HDR with its measured error) and the family's output
        parameters (``symbol``, ``layout``, ``image_format``, ``sh_json``) are those of the CLI.
        Returns the path.
        """
        path = _text_path(path, "save.path")
        params = [(k, _param_value(k, v, "save")) for k, v in output_params.items() if v is not None]
        _warn(self._core.save(path, format or "", pixel or "", params))
        return path

    def __repr__(self) -> str:
        a = self.array
        shape = [x.shape for x in a] if isinstance(a, list) else a.shape
        return f"<brdfbake.Result {self.kind}: {shape}, {self.error_name} {self.error}>"


def _warn(messages: List[str]) -> None:
    """Emits what a write changed on the way to the file, at the caller of the public function."""
    for m in messages:
        warnings.warn(m, BakeWarning, stacklevel=3)


# ---- Environments --------------------------------------------------------------------------------


class Environment:
    """A loaded environment map (equirect or cube, linear RGB float), reusable across bakes."""

    __slots__ = ("_core",)

    def __init__(self, core: "_core.Environment"):
        self._core = core

    layout = property(lambda self: self._core.layout, doc='"equirect" or "cube"')
    width = property(lambda self: self._core.width, doc="width in pixels (a cube: the face size)")
    height = property(lambda self: self._core.height, doc="height in pixels (a cube: the face size)")
    source = property(lambda self: self._core.source, doc="the file, builtin or array it came from")
    description = property(lambda self: self._core.description, doc="what was read")
    sanitized = property(lambda self: self._core.sanitized, doc="counts of replaced NaN/inf/negative values")

    def __repr__(self) -> str:
        return f"<brdfbake.Environment {self.source!r}: {self.description}>"


def load_environment(env: Any, *, sanitize: bool = False) -> Environment:
    """Loads an environment once, to bake several tables from it.

    ``env`` is a path (.hdr, .exr: equirect 2:1 or a cross; .ktx2 cube; six comma-separated faces or a
    path with ``{face}``), ``"builtin:studio"`` / ``"builtin:sun"``, or a NumPy array of shape
    (height, width = 2 height, 3) holding a linear RGB equirect (any floating dtype; converted to
    float32). NaN, infinite and negative values are refused unless ``sanitize=True`` replaces them.

    >>> env = brdfbake.load_environment("builtin:studio")
    >>> chain = brdfbake.prefilter(env, chain_size=64)
    """
    return _environment(env, bool(sanitize), "load_environment")


def _environment(env: Any, sanitize: bool, where: str) -> Environment:
    if isinstance(env, Environment):
        return env
    try:
        if isinstance(env, np.ndarray):
            return Environment(_core.Environment.from_array(_equirect_array(env, where), sanitize,
                                                            f"array {env.shape[1]}x{env.shape[0]}"))
        if isinstance(env, (str, os.PathLike)):
            return Environment(_core.Environment.load(os.fspath(env), sanitize))
    except InputError as e:  # the library's message names the CLI's option
        raise InputError(str(e).replace("pass --sanitize", "pass sanitize=True")) from None
    raise InputError(f"{where}.env: expected a path, 'builtin:studio', a brdfbake.Environment or a NumPy array "
                     f"of shape (height, 2 height, 3) (got {type(env).__name__})")


def _equirect_array(a: np.ndarray, where: str) -> np.ndarray:
    if a.dtype.kind != "f":
        raise InputError(f"{where}.env: expected a floating-point array of linear RGB (got dtype {a.dtype}); "
                         "convert 8-bit sRGB images to linear float first")
    if a.ndim != 3 or a.shape[2] != 3:
        raise InputError(f"{where}.env: expected an equirect array of shape (height, width, 3) "
                         f"(got shape {a.shape})")
    h, w = a.shape[0], a.shape[1]
    if h < 1 or w != 2 * h:
        raise InputError(f"{where}.env: an equirect array must be twice as wide as it is high "
                         f"(got {w}x{h}, shape {a.shape})")
    # The pixel limit and the memory budget, on the shape: before the array (perhaps a broadcast view
    # of one value, which takes no memory yet) is converted and copied.
    _core.check_environment_size(w, h, f"{where}.env: array {w}x{h}")
    with np.errstate(over="ignore"):  # float64 beyond float32's range becomes inf: refused (or sanitized) as such
        return np.ascontiguousarray(a, dtype=np.float32)


# ---- Parameter values ------------------------------------------------------------------------------


def _json_default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, os.PathLike):
        return os.fspath(o)
    raise TypeError(f"{type(o).__name__} is not JSON")


def _to_json(doc: Any, field: str) -> str:
    try:
        return json.dumps(doc, allow_nan=False, default=_json_default)
    except ValueError:
        raise InputError(f"{field}: NaN and infinite values are not valid (JSON has none)") from None
    except TypeError as e:
        raise InputError(f"{field}: {e}") from None


def _material_text(material: Any, field: str) -> str:
    """A material parameter as the library reads it: a file path, or the JSON document itself."""
    if isinstance(material, (str, os.PathLike)):
        text = os.fspath(material)
        if not text:
            raise InputError(f"{field}: must not be empty")
        return text
    if isinstance(material, dict):
        doc = material if "materials" in material else {"materials": [material]}
        return _to_json(doc, field)
    if isinstance(material, (list, tuple)) and all(isinstance(m, dict) for m in material):
        return _to_json({"materials": list(material)}, field)
    raise InputError(f"{field}: expected a material file, a material dict, a list of them or "
                     f"{{'materials': [...]}} (got {type(material).__name__})")


def _text_path(p: Any, field: str) -> str:
    if isinstance(p, (str, os.PathLike)):
        return os.fspath(p)
    raise InputError(f"{field}: expected a path (got {type(p).__name__})")


def _number(v: Any, field: str) -> Any:
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        return float(v)
    if isinstance(v, numbers.Complex):
        raise InputError(f"{field}: must be a real number (got {v!r})")
    return v  # the library names what it expected


def _param_value(name: str, v: Any, where: str) -> Any:
    """A Python value as the extension takes it: bool, int, float, str or a list of numbers."""
    field = f"{where}.{name}"
    if isinstance(v, np.ndarray):
        if v.ndim > 1:
            raise InputError(f"{field}: expected a number or a list of numbers (got an array of shape {v.shape})")
        v = v.tolist()
    if isinstance(v, (list, tuple)):
        return [_number(x, field) for x in v]
    if isinstance(v, (str, os.PathLike)):
        return os.fspath(v)
    return _number(v, field)


# ---- The generated functions ---------------------------------------------------------------------

# Arguments every baking function takes beside its kinds' parameters (the table fields jobs share).
_COMMON = [
    ("precision", "fp32", '"fp32" or "fp64": the precision of the kernels'),
    ("device", None, 'the device: None (the default: $BRDFBAKE_DEVICE, else the first GPU, else the first '
                     'CPU), "P:D", "cpu", "gpu", a name, or "reference" (the scalar double reference)'),
    ("output", None, "also write the result to this file as it is baked (the format from its extension)"),
    ("format", None, "with output: the format when the extension cannot say"),
    ("pixel", None, 'with output: "f16" or "f32" texels (.ktx2, .h, cube containers)'),
    ("progress", None, "a callable(fraction, step) called as the bake goes (Ctrl-C stops a bake at these points)"),
]

# Parameters of a kind that a Python function takes in another form; the schema test checks that
# every schema parameter is either an argument or listed here with its replacement.
REPLACED = {
    "eval": {
        "input": "the pairs come as the arrays wi and wo",
        "binary": "results come back as an array (save() picks CSV or float32 from the file name)",
    },
}

_EXAMPLES = {
    "lut": """    >>> dfg = brdfbake.lut(kind="ggx", size=128)
    >>> dfg.array.shape              # (roughness, n_dot_v, channels): scale, bias, diffuse
    (128, 128, 3)
    >>> dfg.meta["error_bound_mixed"]
    1.7e-05
    >>> dfg.save("dfg.ktx2", pixel="f16")""",
    "fresnel": """    >>> f = brdfbake.fresnel("conductor", material="gold", size=64)
    >>> f.array.shape                 # (1, cos_theta, rgb)
    (1, 64, 3)
    >>> glass = brdfbake.fresnel("dielectric", ior=1.5, table="2d", size=32)""",
    "thin_film": """    >>> film = brdfbake.thin_film(base_ior=1.5, film_ior=1.3, size=64)
    >>> film.array.shape              # (thickness, cos_theta, rgb)
    (64, 64, 3)""",
    "prefilter": """    >>> chain = brdfbake.prefilter("builtin:studio", chain_size=64, min_size=8)
    >>> [level.shape for level in chain.array]      # levels -> (face, y, x, rgb)
    [(6, 64, 64, 3), (6, 32, 32, 3), (6, 16, 16, 3), (6, 8, 8, 3)]
    >>> chain.save("studio_ggx.ktx2")
    >>> hdr = np.zeros((256, 512, 3), np.float32); hdr[:128] = 1.0   # an equirect array
    >>> sky = brdfbake.prefilter(hdr, chain_size=32)""",
    "irradiance": """    >>> sh = brdfbake.irradiance("builtin:studio")
    >>> sh.array.shape                # SH coefficients of E / pi
    (9, 3)
    >>> cube = brdfbake.irradiance("builtin:studio", irradiance_size=32).cube   # (6, 32, 32, 3)""",
    "eval": """    >>> wi = np.array([[0.0, 0.0, 1.0], [0.3, 0.0, 0.95]])
    >>> wo = np.array([0.0, 0.2, 0.98])                         # broadcast against wi
    >>> f = brdfbake.eval({"model": "gltf", "baseColor": [0.9, 0.6, 0.2], "roughness": 0.3}, wi, wo)
    >>> f.array.shape
    (2, 3)""",
    "tabulate": """    >>> gold = {"name": "gold", "model": "disney", "baseColor": [1.0, 0.78, 0.34],
    ...         "metallic": 1.0, "roughness": 0.3}
    >>> merl = brdfbake.tabulate(gold, layout="merl")
    >>> merl.array.shape              # theta_h, theta_d, phi_d, rgb
    (90, 90, 180, 3)
    >>> merl.save("gold.binary")      # MERL's binary, with gold.binary.json beside it
    >>> albedo = brdfbake.tabulate("materials.json", layout="albedo", res=64)""",
}


class _Family:
    """A generated function's description: its command, kinds and merged schema."""

    def __init__(self, command: str, kinds: List[Dict[str, Any]]):
        self.command = command
        self.function = command.replace("-", "_")
        self.kinds = [k["name"] for k in kinds]
        self.summaries = {k["name"]: k["summary"] for k in kinds}
        self.uses_environment = kinds[0]["uses_environment"]
        self.schemas = {k: _schema_of(k) for k in self.kinds}
        merged: Dict[str, Dict[str, Any]] = {}
        for k in self.kinds:
            for d in self.schemas[k]:
                merged.setdefault(d["name"], dict(d, kinds=[]))["kinds"].append(k)
        replaced = set()
        for k in self.kinds:
            replaced |= set(REPLACED.get(k, {}))
        self.params = [d for name, d in merged.items() if name not in replaced]
        # eval and tabulate: a material (a file, a dict, a list), positional; preview's material is
        # an optional file, a keyword like its other parameters
        self.takes_material = any(d["name"] == "material" and d["type"] == "path" and d["required"]
                                  for d in self.params)
        self.is_eval = "eval" in self.kinds
        # Other spellings of a parameter (its old names: cube_size for irradiance_size), as keywords.
        self.aliases = {a[2:].replace("-", "_"): d["name"] for d in self.params for a in d.get("aliases", [])}

    def canonical(self, kwargs: Dict[str, Any]) -> Dict[str, Any]:
        """The keywords with every alias under its parameter's name; both together are refused."""
        out = dict(kwargs)
        for alias, name in self.aliases.items():
            if alias not in out:
                continue
            if name in out:
                raise ArgumentError(f"{self.function}.{name}: given together with its alias {alias} "
                                    "(the same option): give one")
            other = [a for a, n in self.aliases.items() if n == name and a != alias and a in out]
            if other:
                raise ArgumentError(f"{self.function}.{name}: given as both {alias} and {other[0]} "
                                    "(the same option): give one")
            out[name] = out.pop(alias)
        return out

    def positional(self) -> List[str]:
        names = []
        if self.uses_environment:
            names.append("env")
        if self.takes_material:
            names.append("material")
        if self.is_eval:
            names += ["wi", "wo"]
        if not names and any(d["name"] == "model" and d["required"] for d in self.params):
            names.append("model")  # fresnel("dielectric", ior=1.5)
        return names

    def signature(self) -> inspect.Signature:
        P = inspect.Parameter
        out = []
        positional = self.positional()
        for name in positional:
            out.append(P(name, P.POSITIONAL_OR_KEYWORD))
        if len(self.kinds) > 1:
            out.append(P("kind", P.KEYWORD_ONLY, default=self.kinds[0]))
        for d in self.params:
            if d["name"] in positional:
                continue
            default = P.empty if d["required"] else d.get("default")
            out.append(P(d["name"], P.KEYWORD_ONLY, default=default))
        if self.uses_environment:
            out.append(P("sanitize", P.KEYWORD_ONLY, default=False))
        for name, default, _ in _COMMON:
            out.append(P(name, P.KEYWORD_ONLY, default=default))
        return inspect.Signature(out)

    def docstring(self) -> str:
        lines = []
        if len(self.kinds) > 1:
            lines.append(f"Bakes a table of kind {', '.join(self.kinds)} (``brdfbake {self.command}``).")
            lines.append("")
            for k in self.kinds:
                lines.append(f"- {k}: {self.summaries[k]}")
        else:
            lines.append(f"Bakes {self.summaries[self.kinds[0]]} (``brdfbake {self.command}``).")
        lines += ["", "The arguments are the job fields of the kind (docs/SCENES.md) and the options of the",
                  f"command `brdfbake {self.command}`, with the same ranges and defaults.", "", "Arguments:"]
        if self.uses_environment:
            lines += ["  env: a path (.hdr .exr equirect or cross, .ktx2 cube, six faces), 'builtin:studio',",
                      "      'builtin:sun', a brdfbake.Environment, or a float NumPy array (height, 2 height, 3)",
                      "      holding a linear RGB equirect"]
        if self.is_eval:
            lines += ["  wi, wo: directions towards the light and the viewer in tangent space (normal +z), float",
                      "      arrays of shape (n, 3) or (3,), broadcast against each other; any length but not zero"]
        if len(self.kinds) > 1:
            lines.append(f"  kind: {' | '.join(self.kinds)} (default {self.kinds[0]})")
        for d in self.params:
            what = d["expects"]
            if d.get("default") is not None:
                what += f", default {d['default']!r}"
            elif d.get("default_text"):
                what += f", default {d['default_text']}"
            if d["required"]:
                what += ", required"
            only = "" if len(d["kinds"]) == len(self.kinds) else f" ({', '.join(d['kinds'])} only)"
            lines.append(f"  {d['name']}: {d['help']}{only}")
            lines.append(f"      {what}")
            if d["name"] == "material" and self.takes_material:
                lines.append("      (also a material dict, a list of them, or {'materials': [...]}: see docs/CONVENTIONS.md)")
        if self.uses_environment:
            lines.append("  sanitize: replace NaN, infinite and negative environment pixels instead of refusing them")
        for name, default, text in _COMMON:
            lines.append(f"  {name}: {text}")
        lines += ["", "Returns a brdfbake.Result (.array, .meta, .save(path)). Raises brdfbake.InputError for bad",
                  "input, brdfbake.DeviceError when the device fails."]
        if self.function in _EXAMPLES:
            lines += ["", "Example::", "", _EXAMPLES[self.function]]
        return "\n".join(lines)


def _families() -> Dict[str, _Family]:
    by_command: Dict[str, List[Dict[str, Any]]] = {}
    for k in _core.kinds():
        by_command.setdefault(k["command"], []).append(k)
    return {c: _Family(c, ks) for c, ks in by_command.items()}


FAMILIES = _families()
_FAMILY_OF_KIND = {k: f for f in FAMILIES.values() for k in f.kinds}


def _pairs(wi: Any, wo: Any, where: str) -> np.ndarray:
    arrays = []
    for name, v in (("wi", wi), ("wo", wo)):
        try:
            a = np.asarray(v)
        except Exception as e:  # ragged lists and the like
            raise InputError(f"{where}.{name}: not an array of directions ({e})") from None
        if a.dtype.kind not in "fiu":
            raise InputError(f"{where}.{name}: expected real numbers (got dtype {a.dtype})")
        if a.ndim not in (1, 2) or a.shape[-1] != 3:
            raise InputError(f"{where}.{name}: expected shape (n, 3) or (3,) (got {a.shape})")
        arrays.append(a)
    try:
        shape = np.broadcast_shapes(np.atleast_2d(arrays[0]).shape, np.atleast_2d(arrays[1]).shape)
    except ValueError:
        raise InputError(f"{where}: wi {arrays[0].shape} and wo {arrays[1].shape} do not broadcast") from None
    # The memory the pairs and their values take, on the broadcast shape: before a view (perhaps of
    # one direction against a broadcast of billions) is converted and joined.
    need = shape[0] * (6 * 8 + 3 * 8)
    budget = _core.default_memory_budget()
    if need > budget:
        raise InputError(f"{where}: {shape[0]} pairs need {need / 2**30:.1f} GiB (float64 pairs and their values), "
                         f"above the memory budget of {budget / 2**30:.1f} GiB (half the memory this process may "
                         "use); evaluate them in parts")
    arrays = [a.astype(np.float64, copy=False) for a in arrays]
    wi64, wo64 = np.broadcast_arrays(np.atleast_2d(arrays[0]), np.atleast_2d(arrays[1]))
    pairs = np.ascontiguousarray(np.concatenate([wi64, wo64], axis=1))
    bad = ~np.isfinite(pairs).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"{where}: pair {i}: wi or wo is not finite ({pairs[i, :3].tolist()}, {pairs[i, 3:].tolist()})")
    for name, half in (("wi", pairs[:, :3]), ("wo", pairs[:, 3:])):
        zero = ~half.any(axis=1)
        if zero.any():
            raise InputError(f"{where}: pair {int(np.argmax(zero))}: {name} is the zero vector")
    return pairs


def _bind(family: _Family, sig: inspect.Signature, args: Sequence[Any], kwargs: Dict[str, Any]) -> Dict[str, Any]:
    try:
        return dict(sig.bind(*args, **kwargs).arguments)
    except TypeError as e:
        message = f"{family.function}(): {e}"
        unknown = [k for k in kwargs if k not in sig.parameters]
        if unknown:
            close = difflib.get_close_matches(unknown[0], list(sig.parameters), n=1)
            message = (f"{family.function}.{unknown[0]}: unknown argument" +
                       (f" (did you mean {close[0]}?)" if close else "") +
                       f"; {family.function}() takes {', '.join(sig.parameters)}")
        raise ArgumentError(message) from None


def _prepare(family: _Family, given: Dict[str, Any]):
    """Splits bound arguments into the kind, its parameters, the common fields and the inputs."""
    where = family.function
    kind = given.pop("kind", family.kinds[0])
    if not isinstance(kind, str) or kind not in family.kinds:
        raise InputError(f"{where}.kind: must be one of {', '.join(family.kinds)} (got {kind!r})")
    common = {}
    for name, _, _ in _COMMON:
        if name in given:
            v = given.pop(name)
            if name == "progress":
                if v is not None and not callable(v):
                    raise InputError(f"{where}.progress: must be callable (got {type(v).__name__})")
                common[name] = v
            elif v is not None:
                common[name] = os.fspath(v) if isinstance(v, os.PathLike) else v
    inputs: Dict[str, Any] = {}
    for name in ("env", "sanitize", "wi", "wo"):
        if name in given:
            inputs[name] = given.pop(name)
    params = []
    for name, v in given.items():
        if v is None:
            continue  # None: the default (absent), as when the argument is not given
        if name == "material" and family.takes_material:
            params.append((name, _material_text(v, f"{where}.material")))
        else:
            params.append((name, _param_value(name, v, where)))
    return kind, params, common, inputs


def _make_function(family: _Family) -> Callable[..., Result]:
    sig = family.signature()

    def bake(*args: Any, **kwargs: Any) -> Result:
        given = _bind(family, sig, args, family.canonical(kwargs))
        kind, params, common, inputs = _prepare(family, given)
        where = family.function
        progress = common.pop("progress", None)
        env = None
        if family.uses_environment:
            env = _environment(inputs["env"], bool(inputs.get("sanitize", False)), where)
            common["environment"] = env.source
            env = env._core
        pairs = None
        if family.is_eval:
            pairs = _pairs(inputs["wi"], inputs["wo"], where)
            params.append(("input", f"array of {len(pairs)} pairs"))
        result = Result(_core.bake(kind, params, common, where, env, pairs, progress))
        _warn(result.warnings)
        return result

    bake.__name__ = bake.__qualname__ = family.function
    bake.__signature__ = sig  # type: ignore[attr-defined]
    bake.__doc__ = family.docstring()
    bake.__module__ = "brdfbake"
    return bake


FUNCTIONS = {f.function: _make_function(f) for f in FAMILIES.values()}


def function_of(kind: str) -> Callable[..., Result]:
    """The function that bakes ``kind`` (``"ggx"`` -> ``brdfbake.lut``)."""
    if kind not in _FAMILY_OF_KIND:
        raise InputError(f"unknown table kind {kind!r} (known: {', '.join(_FAMILY_OF_KIND)})")
    return FUNCTIONS[_FAMILY_OF_KIND[kind].function]


def bake(kind: str, *args: Any, **params: Any) -> Result:
    """Bakes a table of any kind by name: ``bake("ggx", size=64)`` is ``lut(kind="ggx", size=64)``.

    The arguments are those of the kind's function (``brdfbake.function_of(kind)``)."""
    if not isinstance(kind, str):
        raise InputError(f"bake.kind: must be a table kind name (got {type(kind).__name__})")
    f = function_of(kind)
    family = _FAMILY_OF_KIND[kind]
    if len(family.kinds) > 1:
        if "kind" in params:
            raise ArgumentError("bake(): give the kind once")
        params["kind"] = kind
    return f(*args, **params)


def validate(kind: str, **params: Any) -> Dict[str, Any]:
    """Checks a table request as a job would, without baking: returns the request with every default
    filled in (``brdfbake run --dry-run`` prints the same), or raises brdfbake.InputError.

    >>> brdfbake.validate("ggx", size=64)["parameters"]
    {'size': 64, 'height': 64, 'estimator': 'quadrature'}
    """
    if not isinstance(kind, str) or kind not in _FAMILY_OF_KIND:
        raise InputError(f"validate.kind: unknown table kind {kind!r} (known: {', '.join(_FAMILY_OF_KIND)})")
    family = _FAMILY_OF_KIND[kind]
    where = family.function
    common = {}
    plist = []
    for name, v in params.items():
        if name in ("precision", "device", "output", "format", "pixel", "environment"):
            if v is not None:
                common[name] = os.fspath(v) if isinstance(v, os.PathLike) else v
        elif v is None:
            continue
        elif name == "material" and family.takes_material:
            plist.append((name, _material_text(v, f"{where}.material")))
        else:
            plist.append((name, _param_value(name, v, where)))
    if family.is_eval and not any(n == "input" for n, _ in plist):
        plist.append(("input", "-"))
    if family.uses_environment and "environment" not in common:
        common["environment"] = "builtin:studio"
    return _core.validate(kind, plist, common, where)


# ---- Jobs, devices, schemas ----------------------------------------------------------------------


def run(job: Any, output_dir: "os.PathLike[str] | str | None" = None, *, sanitize: bool = False,
        progress: Optional[Callable[[Dict[str, Any]], None]] = None) -> Dict[str, Any]:
    """Runs a job (docs/SCENES.md, "Jobs") as ``brdfbake run`` does and returns its manifest as a dict.

    ``job`` is a dict, a path to a job file, or the JSON text. ``output_dir`` overrides the job's own.
    Every file and manifest.json are written into a temporary folder beside ``output_dir`` and moved
    in at the end: a failure leaves the folder as it was. ``progress``, if given, is called with
    ``{"bake", "bakes", "what", "fraction"}``. What the writes changed on request (``clamp_f16``) is
    emitted as :class:`brdfbake.BakeWarning`, as ``brdfbake run`` prints it, and is in the
    manifest's ``"warnings"``.

    >>> manifest = brdfbake.run({"brdfbake_job": 1, "tables": [{"kind": "ggx", "size": 64}]}, "out")
    >>> manifest["files"][0]["path"], manifest["files"][0]["error_bound_mixed"]
    ('dfg_ggx_64.exr', 1.7e-05)
    """
    if progress is not None and not callable(progress):
        raise InputError(f"run.progress: must be callable (got {type(progress).__name__})")
    out = "" if output_dir is None else _text_path(output_dir, "run.output_dir")
    if isinstance(job, dict):
        text, is_path, origin = _to_json(job, "run.job"), False, "job"
    elif isinstance(job, (str, os.PathLike)):
        text = os.fspath(job)
        is_path = not text.lstrip().startswith("{")
        origin = "job"
    else:
        raise InputError(f"run.job: expected a job dict, a job file or JSON text (got {type(job).__name__})")
    manifest, warned = _core.run(text, is_path, origin, out, bool(sanitize), progress)
    _warn(warned)
    return json.loads(manifest)


def bake_scene(scene: "os.PathLike[str] | str | None" = None, output_dir: "os.PathLike[str] | str | None" = None,
               *, env: "os.PathLike[str] | str" = "builtin:studio", sanitize: bool = False, target: str = "generic",
               device: Optional[str] = None, precision: str = "fp32", pixel: Optional[str] = None,
               dry_run: bool = False, progress: Optional[Callable[[Dict[str, Any]], None]] = None,
               **options: Any) -> Dict[str, Any]:
    """Bakes what a glTF scene's materials call for, as ``brdfbake bake`` does (docs/SCENES.md), and
    returns the manifest as a dict; with ``dry_run=True`` bakes nothing and returns the plan: the job
    document (``brdfbake.run`` accepts it) with its ``"plan"`` section (the rules that fired, and
    for each material why).

    ``scene`` is a .gltf or .glb path; ``None`` plans the standard set for metallic-roughness
    materials. ``env`` is an environment path or ``builtin:NAME``. ``target`` adds an engine's file
    set (docs/ENGINES.md: ``"filament"``, ``"gltf"``, ``"babylon"``, ``"khronos-viewer"``) with its
    schedule, sizes and SH window. ``options`` are the planner's other options, the command's long
    options with ``_`` for ``-`` (:func:`plan_options` lists them): ``lut_size``, ``chain_size``,
    ``min_size``, ``schedule``, ``chain_max_error``, ``fresnel_size``, ``thin_film_size``,
    ``sh_order``, ``sheen_visibility``, ``energy_compensation``, ``table_format``, ``cube_format``.
    The old names (``cube_size``, ``prefilter_max_error``) are aliases: taken, never written.

    >>> plan = brdfbake.bake_scene("scene.glb", dry_run=True, target="filament")
    >>> manifest = brdfbake.bake_scene("scene.glb", "out", target="filament", chain_size=128)
    """
    scene_path = "" if scene is None else _text_path(scene, "bake_scene.scene")
    env_text = _text_path(env, "bake_scene.env")
    opts = [("target", target)] + [(name, _number(v, "bake_scene." + name)) for name, v in options.items()]
    for name, v in (("device", device), ("pixel", pixel)):
        if v is not None and not isinstance(v, str):
            raise InputError(f"bake_scene.{name}: must be a string (got {type(v).__name__})")
    if not isinstance(precision, str):
        raise InputError(f"bake_scene.precision: must be a string (got {type(precision).__name__})")
    job = json.loads(_core.plan(scene_path, opts, env_text, bool(sanitize), pixel or "", precision, device or ""))
    if dry_run:
        return job
    if output_dir is None:
        raise InputError("bake_scene.output_dir: missing (give the folder to bake into, or dry_run=True)")
    return run(job, output_dir, progress=progress)


def plan_options() -> List[Dict[str, Any]]:
    """The options of :func:`bake_scene` (the planner's, those of ``brdfbake bake``), described as
    :func:`schema` describes a kind's parameters."""
    return json.loads(_core.plan_schema_json())


def devices() -> List[Dict[str, Any]]:
    """The OpenCL devices: selector ("P:D"), name, type, vendor, platform, versions, compute units,
    memory, fp64, which is the default, and the kernel shape it opens in (``kernel_shape``: "cpu"
    or "gpu", docs/DEVICES.md). ``device="reference"`` (the scalar double reference) is always there
    too. An empty list when there is no OpenCL platform."""
    return _core.devices()


def set_kernel_shape(shape: str) -> None:
    """The kernels' work shape for the devices opened from now on: "auto" (the device's type),
    "cpu" or "gpu" (docs/DEVICES.md, "Kernel shapes"); as ``--kernel-shape`` of the command line,
    and ahead of ``BRDFBAKE_KERNEL_SHAPE``. A device already opened (by an earlier call) keeps its
    shape. Raises ValueError for another name."""
    _core.set_kernel_shape(shape)


def kinds() -> List[Dict[str, Any]]:
    """Every table kind: name, command, summary, whether it reads an environment, availability."""
    return _core.kinds()


def schema(kind: str) -> List[Dict[str, Any]]:
    """The parameters of a kind as the library declares them, spelled as ``brdfbake kinds --json``
    spells them: ``name``, ``option`` (the command line's), ``type`` (``integer``, ``number``,
    ``name``, ``path``, ``flag``, ``rgb``, ``range``, ``integers``), ``expects`` (in words),
    ``required``, ``output_only``, ``help``, and where they apply ``choices``, ``default``,
    ``default_text``, ``min``, ``min_exclusive``, ``max``, ``max_items``."""
    if not isinstance(kind, str):
        raise InputError(f"schema.kind: must be a table kind name (got {type(kind).__name__})")
    return _schema_of(kind)
