#!/usr/bin/env python3
"""Fetches Babylon.js 8.46.2 as the PyPI wheel gradio==6.31.0 ships it and lays out what the harness
page (harness.html) imports: the static ES-module chunks of Babylon.js that the render needs, found
by following their imports from the chunks named in ROLES, and a stub for gradio's app entry.

    python3 tests/engines/babylon/setup_babylon.py            # prints the folder it prepared

Idempotent: a second run with the same wheel does nothing. The cache folder is
$BRDFBAKE_ENGINES_CACHE, else build/engines/ in the repository. The wheel comes from
`pip download --no-deps gradio==6.31.0` into CACHE/wheels/ (network: PyPI only), unless
$BRDFBAKE_GRADIO_WHEEL names an already downloaded copy; either way its SHA-256 must be WHEEL_SHA256.

Layout: CACHE/babylon-8.46.2/assets/*.js (the chunks, unchanged, plus the stub module in place of
gradio's `index-*.js`), CACHE/babylon-8.46.2/chunks.json (ROLES: which chunk and which export
is each class the harness uses, and the Babylon.js version) and a stamp file.

Why a stub: Babylon.js's chunks import two bundler helpers from gradio's app entry (`gn`, vite's
__vitePreload(load, deps, importer), which the stub makes `load()`; `bn`, the bundler's
__exportAll(getters) that builds a module namespace object). The app itself is not needed."""

import hashlib
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import zipfile

REPO = pathlib.Path(__file__).resolve().parents[3]
GRADIO = "gradio==6.31.0"
WHEEL_NAME = "gradio-6.31.0-py3-none-any.whl"
WHEEL_SHA256 = "7b50b9b6a2d23cd02851ad4c8b1c8312c88d8b911d1f29c93f9761c98348a64a"
BABYLON_VERSION = "8.46.2"
ASSETS = "gradio/templates/frontend/assets/"
APP_ENTRY = "index-DphvyggB.js"  # gradio's app entry: replaced by STUB

# Each class or function the harness uses: the chunk that exports it and the (minified) export name,
# read from gradio 6.31.0's chunks. harness.js checks each against its getClassName() or its kind.
ROLES = {
    "Engine": ["engine-C02FCZbl.js", "t"],
    "Scene": ["scene-st5sWpa6.js", "t"],
    "ImageProcessingConfiguration": ["scene-st5sWpa6.js", "o"],
    "PBRMaterial": ["pbrMaterial-BaVaB1qy.js", "PBRMaterial"],
    "StandardMaterial": ["standardMaterial-BRIgb55F.js", "t"],  # the scene's default material (a side effect)
    "CubeTexture": ["cubeTexture-DfuETeLB.js", "t"],
    "HDRCubeTexture": ["hdrCubeTexture-C6F_rpiQ.js", "HDRCubeTexture"],  # Babylon.js's own equirect -> cube
    "Mesh": ["mesh-DplWMzLh.js", "t"],
    "VertexData": ["abstractMesh-DFvAWZQT.js", "r"],
    "RenderTargetTexture": ["renderTargetTexture-D0QgiwTB.js", "t"],
    "TargetCamera": ["lazy-C7yeuR_e.js", "s"],
    "Vector3": ["math.vector-Bp1Ze-Mf.js", "a"],
    "Matrix": ["math.vector-Bp1Ze-Mf.js", "t"],
    "Color3": ["math.color-JN-C52SF.js", "t"],
    "Color4": ["math.color-JN-C52SF.js", "n"],
    "LoadAssetContainerAsync": ["sceneLoader-Drj_iws4.js", "n"],  # (source, scene, options)
    "GLTFFileLoader": ["glTFLoader-14BlYlbM.js", "GLTFFileLoader"],
    "EXT_lights_image_based": ["EXT_lights_image_based-5NA-x9G1.js", "EXT_lights_image_based"],
    "KHR_materials_ior": ["KHR_materials_ior-BK7bTVEn.js", "KHR_materials_ior"],
    "KHR_materials_specular": ["KHR_materials_specular-DtoXmZ4K.js", "KHR_materials_specular"],
}

STUB = """// brdfbake: stub for gradio's app entry (tests/engines/babylon/setup_babylon.py). Babylon.js's
// chunks import bundler helpers from it; nothing else of gradio is loaded.
const dp = Object.defineProperty;
export const gn = (load) => load();                       // vite's __vitePreload(load, deps, importer)
export const bn = (getters, noTag) => {                   // __exportAll(getters): a namespace object
  const r = {};
  for (const k in getters) dp(r, k, { get: getters[k], enumerable: true });
  if (!noTag) dp(r, Symbol.toStringTag, { value: "Module" });
  return r;
};
export const yn = (cb, mod) => () => (mod || (cb((mod = { exports: {} }).exports, mod), cb = null), mod.exports);
export const Sn = (m) => m;
export const xn = (x) => { throw new Error("require() is not available in the harness: " + x); };
"""


def cache_dir():
    return pathlib.Path(os.environ.get("BRDFBAKE_ENGINES_CACHE") or (REPO / "build" / "engines"))


def target_dir():
    return cache_dir() / f"babylon-{BABYLON_VERSION}"


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


class MissingWheel(RuntimeError):
    """The wheel is not here and downloading was not allowed."""


def fetch_wheel(download=True):
    """The pinned wheel's path: $BRDFBAKE_GRADIO_WHEEL, else CACHE/wheels/, downloaded there by pip
    (unless download is False: then MissingWheel)."""
    given = os.environ.get("BRDFBAKE_GRADIO_WHEEL")
    if given:
        wheel = pathlib.Path(given)
        if not wheel.is_file():
            raise MissingWheel(f"BRDFBAKE_GRADIO_WHEEL={given}: no such file")
    else:
        folder = cache_dir() / "wheels"
        wheel = folder / WHEEL_NAME
        if not wheel.is_file():
            if not download:
                raise MissingWheel(f"{wheel} is not downloaded (run {pathlib.Path(__file__).name}: "
                                   f"pip download --no-deps {GRADIO}, 31 MB from PyPI)")
            folder.mkdir(parents=True, exist_ok=True)
            cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:",
                   "--disable-pip-version-check", "-d", str(folder), GRADIO]
            r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900)
            if r.returncode != 0 or not wheel.is_file():
                raise RuntimeError(f"`{' '.join(cmd)}` failed ({r.returncode}):\n{r.stdout[-2000:]}")
    digest = _sha256(wheel)
    if digest != WHEEL_SHA256:
        raise RuntimeError(f"{wheel}: SHA-256 {digest}, expected {WHEEL_SHA256} (the pinned {GRADIO})")
    return wheel


_IMPORT_RES = (
    re.compile(r'from\s*"\./([^"]+\.js)"'),
    re.compile(r'import\s*"\./([^"]+\.js)"'),
    re.compile(r'import\(\s*"\./([^"]+\.js)"\s*\)'),
    re.compile(r'import\(\s*`\./([^`]+\.js)`\s*\)'),
)


def _imports(text):
    """Every chunk a chunk imports, statically, dynamically or through vite's preload list."""
    out = set()
    for rx in _IMPORT_RES:
        out |= set(rx.findall(text))
    m = re.search(r"m\.f=\[([^\]]*)\]", text)  # __vite__mapDeps's list
    if m:
        out |= set(re.findall(r'"\./([^"]+\.js)"', m.group(1)))
    return out


def closure(read, seeds):
    """The chunks reachable from seeds (read(name) -> text), without gradio's app entry."""
    seen, stack = set(), list(seeds)
    while stack:
        name = stack.pop()
        if name in seen or name == APP_ENTRY:
            continue
        seen.add(name)
        stack.extend(_imports(read(name)))
    return sorted(seen)


def prepared():
    """Whether target_dir() is laid out for this script's pins."""
    try:
        return json.loads((target_dir() / "stamp.json").read_text()) == _stamp()
    except (OSError, ValueError):
        return False


def _stamp():
    return {"wheel_sha256": WHEEL_SHA256, "roles": ROLES, "stub": hashlib.sha256(STUB.encode()).hexdigest()}


def setup(quiet=False, download=True):
    """Prepares target_dir() (if not already done) and returns it; download=False raises MissingWheel
    instead of running pip when the wheel is not here."""
    out = target_dir()
    if prepared():
        return out
    want = _stamp()
    wheel = fetch_wheel(download)
    tmp = out.with_name(out.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    (tmp / "assets").mkdir(parents=True)
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())

        def read(name):
            path = ASSETS + name
            if path not in names:
                raise RuntimeError(f"{wheel.name} has no {path}")
            return z.read(path).decode("utf-8")

        files = closure(read, sorted({f for f, _ in ROLES.values()}))
        for name in files:
            (tmp / "assets" / name).write_bytes(z.read(ASSETS + name))
        version = re.search(r"static get Version\(\)\{return`([0-9.]+)`\}", read("tools.functions-VA-Es30k.js"))
    if not version or version.group(1) != BABYLON_VERSION:
        raise RuntimeError(f"the wheel's Babylon.js is {version and version.group(1)}, expected {BABYLON_VERSION}")
    (tmp / "assets" / APP_ENTRY).write_text(STUB)
    (tmp / "chunks.json").write_text(json.dumps({"babylon_version": BABYLON_VERSION, "source": GRADIO,
                                                 "roles": ROLES, "files": len(files)}, indent=1) + "\n")
    (tmp / "stamp.json").write_text(json.dumps(want, indent=1) + "\n")
    shutil.rmtree(out, ignore_errors=True)
    tmp.rename(out)
    if not quiet:
        print(f"{out}: {len(files)} chunks of Babylon.js {BABYLON_VERSION} from {wheel.name}", file=sys.stderr)
    return out


if __name__ == "__main__":
    print(setup())
