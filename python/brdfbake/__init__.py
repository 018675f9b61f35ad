"""brdfbake: physically based BRDF tables on OpenCL devices, as NumPy arrays.

One function per table family, each taking the job fields of its kinds (docs/SCENES.md) with the
same ranges and defaults as the command line and jobs, returning a :class:`Result` with ``.array``
(float32 NumPy), ``.meta`` (the file's metadata, error bound included) and ``.save(path)`` (the
command-line tool's writers, atomic):

>>> import brdfbake
>>> dfg = brdfbake.lut(kind="ggx", size=32)
>>> dfg.array.shape
(32, 32, 3)
>>> chain = brdfbake.prefilter("builtin:studio", chain_size=64)
>>> merl = brdfbake.tabulate({"model": "disney", "roughness": 0.3}, layout="merl")
>>> manifest = brdfbake.run("job.json", "out")
>>> manifest = brdfbake.bake_scene("scene.glb", "out", target="filament")

Batches across a Dask cluster: :mod:`brdfbake.dask`. The guide with examples: docs/PYTHON.md.

A device is opened once per process, on first use, and reused by every later call; device work runs
without the GIL (calls from several threads share a device one call at a time). Errors raise
:class:`Error` subclasses carrying the command-line tool's one-line message.
"""

import os as _os

# The OpenImageIO module installed beside the extension (TIFF, JPEG, PFM... environments): named
# explicitly (the library, inside the extension, would look in this folder too, and nowhere else).
_oiio = _os.path.join(_os.path.dirname(__file__), "brdfbake_oiio.so")
if _os.path.isfile(_oiio):
    _os.environ.setdefault("BRDFBAKE_OIIO_MODULE", _oiio)
del _oiio

from ._errors import ArgumentError, BakeWarning, DeviceError, Error, InputError, NotAvailableError
from . import _brdfbake
from ._api import (
    Environment,
    Result,
    bake,
    bake_scene,
    devices,
    set_kernel_shape,
    function_of,
    kinds,
    load_environment,
    plan_options,
    run,
    schema,
    validate,
)
from ._api import FUNCTIONS as _FUNCTIONS

__version__ = _brdfbake.version

# lut, fresnel, thin_film, prefilter, irradiance, eval, tabulate: generated from the schemas.
globals().update(_FUNCTIONS)

# `eval` stays out of the star-import, which would shadow the builtin: use brdfbake.eval.
__all__ = [
    "ArgumentError", "BakeWarning", "DeviceError", "Environment", "Error", "InputError", "NotAvailableError", "Result",
    "bake", "bake_scene", "devices", "function_of", "kinds", "load_environment", "plan_options", "run", "schema", "set_kernel_shape", "validate",
    *sorted(name for name in _FUNCTIONS if name != "eval"),
]
