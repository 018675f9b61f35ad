#!/usr/bin/env python3
"""Babylon.js as a test oracle (issue 33, "engine truth"): renders brdfbake's preview grid with
Babylon.js 8.46.2 itself — the chunks of the PyPI wheel gradio==6.31.0, laid out by setup_babylon.py —
in Debian's chromium, headless, WebGL2 on SwiftShader, and compares it with the preview's split-sum
image.

    python3 babylon_render.py --bake DIR --preview-json P.json --mode env|gltf -o out.npy [--compare]
    python3 babylon_render.py probe --cli build/host/cli/brdfbake --target babylon|gltf [--work DIR]

render(bake_dir, preview_json, mode, options) returns float32 H x W x 3 linear radiance, row 0 at the
top, in the preview's pixel grid and frame (pixel (i, j) shaded at its centre (i + 0.5, j + 0.5)).

- mode "env": scene.environmentTexture = CubeTexture.CreateFromPrefilteredData("NAME.env"), one
  PBRMaterial per sphere (albedoColor = baseColor, metallic, roughness; ior, specular and
  specular_color when the sphere has them), spheres as VertexData.CreateSphere meshes.
- mode "gltf": a glTF written to a temporary folder — the bake's NAME.gltf (its
  EXT_lights_image_based light and images) plus one mesh node per sphere with a pbrMetallicRoughness
  material — loaded with Babylon.js's glTF loader (AppendSceneAsync), which makes the materials and
  the environment as it does for users.
- mode "hdr" (diagnosis): bake_dir names an equirect .hdr, which Babylon.js turns into a cube itself
  (HDRCubeTexture, 256 per face, not prefiltered: mirrors only): the frame Babylon.js gives a panorama.
- options (None keeps Babylon.js's own default): "mix_ibl" (PBRBRDFConfiguration
  mixIblRadianceWithIrradiance), "legacy_energy" (useLegacySpecularEnergyConservation),
  "specular_aa" (enableSpecularAntiAliasing), "gamma_space" (the environment cube's gammaSpace),
  "irradiance_in_fragment" (forceIrradianceInFragment), "right_handed" (scene.useRightHandedSystem,
  default False: Babylon.js's left-handed default), "segments" (the sphere mesh's, default 64),
  "distance" (the camera's, in pixels, default 1e7), "read_cube_levels" (list: read the loaded
  cube back at these levels, into the result's "cube").

Frames: the env scene's world is the environment's frame; a left-handed camera sees it mirrored in
x, so the render is flipped back. In gltf mode the loader puts glTF (x, y, z) at (-x, y, z) in a
left-handed scene; the camera is placed in the glTF's frame there, and nothing is flipped.

Every server and browser this module starts stops by itself: the HTTP server (127.0.0.1, an
ephemeral port) and chromium end when the session ends, and a watchdog kills chromedriver's process
group (chromium with it) after the session's time limit (TIME_LIMIT_S)."""

import argparse
import base64
import contextlib
import functools
import http.server
import json
import math
import os
import pathlib
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import setup_babylon  # noqa: E402

TIME_LIMIT_S = 240  # a session's wall-clock limit: the watchdog kills the browser after it
CHROMIUM_ARGS = ("--headless=new", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
                 "--disable-dev-shm-usage", "--no-first-run", "--disable-extensions",
                 "--disable-background-networking", "--disable-component-update", "--mute-audio",
                 "--window-size=256,256")


class Unavailable(RuntimeError):
    """What the harness needs is missing (chromium, chromedriver, selenium, the wheel)."""


def _find(*names):
    for n in names:
        path = shutil.which(n) or (f"/usr/bin/{n}" if os.access(f"/usr/bin/{n}", os.X_OK) else None)
        if path:
            return path
    return None


def requirements():
    """(chromium, chromedriver) or raises Unavailable saying what is missing."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        raise Unavailable("selenium is not installed (python/requirements-test.txt)")
    chromium = _find("chromium", "chromium-browser")
    driver = _find("chromedriver")
    if not chromium or not driver:
        raise Unavailable("chromium and chromium-driver are not installed (scripts/deps.sh installs them)")
    return chromium, driver


# ---------------------------------------------------------------------------------------------------
# Files: the preview's EXR and JSON

def read_exr(path):
    """An uncompressed scanline OpenEXR's R, G, B (FLOAT or HALF) as float32 H x W x 3, row 0 at the
    top (brdfbake writes the preview's EXRs uncompressed, docs/PREVIEW.md)."""
    data = pathlib.Path(path).read_bytes()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    pos, header = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        kind = data[end + 1:end2].decode()
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        header[name] = (kind, data[end2 + 5:end2 + 5 + size])
        pos = end2 + 5 + size
    pos += 1
    if header["compression"][1][0] != 0:
        raise ValueError(f"{path}: compressed EXR (only NO_COMPRESSION is read here)")
    chl, channels, p = header["channels"][1], [], 0
    while chl[p] != 0:
        end = chl.index(b"\0", p)
        ptype = struct.unpack_from("<i", chl, end + 1)[0]
        channels.append((chl[p:end].decode(), ptype))
        p = end + 17
    x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    offsets = np.frombuffer(data, "<u8", h, pos)
    dtypes = {1: np.dtype("<f2"), 2: np.dtype("<f4")}
    planes = {c: np.zeros((h, w), np.float32) for c, _ in channels}
    for off in offsets:
        y = struct.unpack_from("<i", data, int(off))[0] - y0
        q = int(off) + 8
        for c, ptype in channels:
            dt = dtypes[ptype]
            planes[c][y] = np.frombuffer(data, dt, w, q)
            q += w * dt.itemsize
    return np.stack([planes["R"], planes["G"], planes["B"]], axis=-1)


def load_preview(preview_json):
    p = pathlib.Path(preview_json)
    doc = json.loads(p.read_text())
    doc["_path"] = str(p)
    return doc


def splitsum_of(preview):
    """The split-sum image beside a preview JSON."""
    base = pathlib.Path(preview["_path"]).parent
    return read_exr(base / preview["files"]["splitsum"])


def write_hdr(path, rgb):
    """Radiance RGBE (.hdr), uncompressed scanlines, row 0 at the top."""
    rgb = np.asarray(rgb, np.float64)
    h, w, _ = rgb.shape
    m = rgb.max(axis=-1)
    e = np.zeros(m.shape, np.int32)
    mant = np.zeros(m.shape)
    ok = m > 1e-32
    mant[ok], e[ok] = np.frexp(m[ok])
    scale = np.where(ok, mant * 256.0 / np.where(ok, m, 1.0), 0.0)
    out = np.zeros((h, w, 4), np.uint8)
    out[..., :3] = np.clip(np.floor(rgb * scale[..., None]), 0, 255).astype(np.uint8)
    out[..., 3] = np.where(ok, e + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode())
        f.write(out.tobytes())


# ---------------------------------------------------------------------------------------------------
# The glTF document of mode "gltf"

def _sphere_geometry(segments):
    """A UV sphere of radius 1 (positions = normals), as glTF wants it: counter-clockwise front faces."""
    rings, sectors = segments, 2 * segments
    th = np.linspace(0.0, math.pi, rings + 1)
    ph = np.linspace(0.0, 2.0 * math.pi, sectors + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    pos = np.stack([np.sin(t) * np.sin(p), np.cos(t), np.sin(t) * np.cos(p)], axis=-1).reshape(-1, 3)
    idx = []
    for i in range(rings):
        for j in range(sectors):
            a, b = i * (sectors + 1) + j, (i + 1) * (sectors + 1) + j
            if i > 0:
                idx.append((a, b, a + 1))
            if i < rings - 1:
                idx.append((a + 1, b, b + 1))
    return pos.astype(np.float32), np.asarray(idx, np.uint32).reshape(-1)


def write_combined_gltf(bake_dir, preview, folder, segments=64):
    """folder/scene.gltf: the bake's NAME.gltf (its light; its images linked into folder: Babylon.js's
    loader refuses URIs with '..') plus one node a sphere (position in the preview's frame, radius in
    pixels) with its material. Returns the path."""
    bake_dir = pathlib.Path(bake_dir).resolve()
    found = sorted(bake_dir.glob("*.gltf"))
    if len(found) != 1:
        raise ValueError(f"{bake_dir}: expected one .gltf (a --target gltf bake), found {[f.name for f in found]}")
    doc = json.loads(found[0].read_text())
    for img in doc.get("images", []):
        if "uri" in img and not img["uri"].startswith("data:"):
            link = pathlib.Path(folder) / img["uri"]
            link.parent.mkdir(parents=True, exist_ok=True)
            link.symlink_to(bake_dir / img["uri"])
    pos, idx = _sphere_geometry(segments)
    blob = pos.tobytes() + idx.tobytes()
    (pathlib.Path(folder) / "spheres.bin").write_bytes(blob)
    buffers = doc.setdefault("buffers", [])
    views = doc.setdefault("bufferViews", [])
    accessors = doc.setdefault("accessors", [])
    buf = len(buffers)
    buffers.append({"uri": "spheres.bin", "byteLength": len(blob)})
    views.append({"buffer": buf, "byteOffset": 0, "byteLength": pos.nbytes, "target": 34962})
    views.append({"buffer": buf, "byteOffset": pos.nbytes, "byteLength": idx.nbytes, "target": 34963})
    a_pos = len(accessors)
    accessors.append({"bufferView": len(views) - 2, "componentType": 5126, "count": len(pos), "type": "VEC3",
                      "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0]})
    accessors.append({"bufferView": len(views) - 2, "componentType": 5126, "count": len(pos), "type": "VEC3"})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"})
    materials = doc.setdefault("materials", [])
    meshes = doc.setdefault("meshes", [])
    nodes = doc.setdefault("nodes", [])
    scene = doc["scenes"][doc.get("scene", 0)]
    scene_nodes = scene.setdefault("nodes", [])
    used = set(doc.get("extensionsUsed", []))
    cam = preview["camera"]
    right, up = np.array(cam["right"]), np.array(cam["up"])
    w, h = preview["image"]["width"], preview["image"]["height"]
    for k, s in enumerate(preview["spheres"]):
        m = s["material"]
        mat = {"name": f"m{k}_{s.get('name', '')}",
               "pbrMetallicRoughness": {"baseColorFactor": list(m["baseColor"]) + [1.0],
                                        "metallicFactor": m["metallic"], "roughnessFactor": m["roughness"]}}
        ext = {}
        if "ior" in m:
            ext["KHR_materials_ior"] = {"ior": m["ior"]}
        if "specular" in m:
            ext["KHR_materials_specular"] = {"specularFactor": m["specular"],
                                             "specularColorFactor": m.get("specular_color", [1, 1, 1])}
        if ext:
            mat["extensions"] = ext
            used |= set(ext)
        materials.append(mat)
        meshes.append({"name": f"s{k}", "primitives": [{"attributes": {"POSITION": a_pos, "NORMAL": a_pos + 1},
                                                       "indices": a_pos + 2, "material": len(materials) - 1}]})
        dx, dy = s["centre"][0] - w / 2.0, s["centre"][1] - h / 2.0
        t = dx * right - dy * up
        nodes.append({"name": f"s{k}", "mesh": len(meshes) - 1, "translation": [float(x) for x in t],
                      "scale": [s["radius"]] * 3})
        scene_nodes.append(len(nodes) - 1)
    doc["extensionsUsed"] = sorted(used)
    out = pathlib.Path(folder) / "scene.gltf"
    out.write_text(json.dumps(doc))
    return out


# ---------------------------------------------------------------------------------------------------
# The session: a loopback HTTP server and one headless chromium

class _Quiet(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".js": "text/javascript",
                      ".mjs": "text/javascript", ".env": "application/octet-stream", ".gltf": "model/gltf+json",
                      ".json": "application/json", ".bin": "application/octet-stream"}

    def log_message(self, *args):
        pass

    def end_headers(self):
        self.send_header("Cache-Control", "no-store")
        super().end_headers()


class _Server(http.server.ThreadingHTTPServer):
    daemon_threads = True

    def handle_error(self, request, client_address):
        if not isinstance(sys.exc_info()[1], (BrokenPipeError, ConnectionResetError)):  # the browser hung up
            super().handle_error(request, client_address)


class Session:
    """One HTTP server on 127.0.0.1 (ephemeral port) serving a temporary root (harness/, babylon/,
    the bakes) and one headless chromium driven by Selenium; render() as often as needed, then
    close() (or use it as a context manager). A watchdog kills the browser after time_limit_s."""

    def __init__(self, time_limit_s=TIME_LIMIT_S):
        chromium, driver = requirements()
        self.assets = setup_babylon.setup(quiet=True)
        self.root = pathlib.Path(tempfile.mkdtemp(prefix="brdfbake-babylon-"))
        (self.root / "harness").symlink_to(HERE)
        (self.root / "babylon").symlink_to(self.assets)
        self._bakes = {}
        handler = functools.partial(_Quiet, directory=str(self.root))
        self.httpd = _Server(("127.0.0.1", 0), handler)
        self._serve = threading.Thread(target=self.httpd.serve_forever, daemon=True)
        self._serve.start()
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}"
        self.driver = None
        self._service = None
        self._timer = None
        self._closed = False
        try:
            self._start_browser(chromium, driver, time_limit_s)
        except BaseException:
            self.close()
            raise

    def _start_browser(self, chromium, driver, time_limit_s):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for a in CHROMIUM_ARGS + (f"--user-data-dir={self.root / 'profile'}",):
            options.add_argument(a)
        if os.geteuid() == 0:
            options.add_argument("--no-sandbox")  # chromium refuses to run as root with its sandbox
        # chromedriver in a session of its own: the watchdog kills its whole process group (chromium's too).
        self._service = Service(executable_path=driver, popen_kw={"start_new_session": True})
        self._deadline = time.monotonic() + time_limit_s
        self._timer = threading.Timer(time_limit_s, self._kill)
        self._timer.daemon = True
        self._timer.start()
        self.driver = webdriver.Chrome(options=options, service=self._service)
        left = max(5, int(self._deadline - time.monotonic()))
        self.driver.set_page_load_timeout(left)
        self.driver.set_script_timeout(left)
        self.driver.get(self.url + "/harness/harness.html")
        t0 = time.monotonic()
        while not self.driver.execute_script("return window.brdfbakeReady === true"):
            if time.monotonic() - t0 > 30:
                raise RuntimeError("the harness page did not load: " + self._console())
            time.sleep(0.02)
        caps = self.driver.capabilities
        self.browser_version = caps.get("browserVersion")

    def _console(self):
        try:
            return "; ".join(e.get("message", "") for e in self.driver.get_log("browser"))
        except Exception:  # noqa: BLE001 - only for a message
            return "(no console log)"

    def _browser_pids(self):
        """The processes of this session's chromium: those whose command line names its own profile
        folder (chromium's children outlive chromedriver and leave its process group)."""
        marker = f"--user-data-dir={self.root / 'profile'}".encode()
        pids = []
        for entry in os.listdir("/proc"):
            if entry.isdigit():
                try:
                    with open(f"/proc/{entry}/cmdline", "rb") as f:
                        if marker in f.read():
                            pids.append(int(entry))
                except OSError:
                    pass
        return pids

    def _kill(self):
        """chromedriver's process group, then every process of this session's chromium, by id."""
        proc = getattr(self._service, "process", None)
        if proc is not None and proc.poll() is None:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        for pid in self._browser_pids():
            try:
                os.kill(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass

    def _serve_bake(self, bake_dir):
        bake_dir = str(pathlib.Path(bake_dir).resolve())
        if bake_dir not in self._bakes:
            name = f"bake{len(self._bakes)}"
            (self.root / name).symlink_to(bake_dir)
            self._bakes[bake_dir] = name
        return self._bakes[bake_dir]

    def render_raw(self, bake_dir, preview, mode="env", options=None):
        """The harness's whole answer: image (H x W x 3 float32, row 0 at the top, the preview's frame),
        alpha (H x W: 1 where a sphere was drawn), info (Babylon.js's state: defines of every material,
        the environment texture, the renderer) and, with read_cube_levels, cube[level] = 6 faces."""
        if isinstance(preview, (str, pathlib.Path)):
            preview = load_preview(preview)
        o = dict(options or {})
        if mode not in ("env", "gltf", "hdr"):
            raise ValueError(f"mode {mode!r}: env, gltf or hdr")
        if mode == "hdr":  # bake_dir is an equirect .hdr: Babylon.js's own HDRCubeTexture of it
            hdr = pathlib.Path(bake_dir).resolve()
            bake_dir = hdr.parent
        bake = self._serve_bake(bake_dir)
        w, h = preview["image"]["width"], preview["image"]["height"]
        cfg = {"mode": mode, "width": w, "height": h, "camera": preview["camera"],
               "spheres": [{"name": s.get("name", ""), "centre": s["centre"], "radius": s["radius"],
                            "material": s["material"]} for s in preview["spheres"]],
               "rightHanded": bool(o.get("right_handed", False)), "segments": int(o.get("segments", 64)),
               "distance": float(o.get("distance", 1e7)), "readCubeLevels": o.get("read_cube_levels"),
               "options": {"mixIbl": o.get("mix_ibl"), "legacyEnergy": o.get("legacy_energy"),
                           "specularAA": o.get("specular_aa"), "gammaSpace": o.get("gamma_space"),
                           "irradianceInFragment": o.get("irradiance_in_fragment")}}
        if mode == "hdr":
            cfg["hdrUrl"] = f"../{bake}/{hdr.name}"
            cfg["hdrSize"] = int(o.get("hdr_size", 256))
        elif mode == "env":
            envs = sorted(pathlib.Path(bake_dir).glob("*.env"))
            if len(envs) != 1:
                raise ValueError(f"{bake_dir}: expected one .env (a --target babylon bake), found {len(envs)}")
            cfg["envUrl"] = f"../{bake}/{envs[0].name}"
        else:
            work = pathlib.Path(tempfile.mkdtemp(prefix="gltf", dir=self.root))
            write_combined_gltf(bake_dir, preview, work, segments=int(o.get("segments", 64)))
            cfg["gltfUrl"] = f"../{work.name}/scene.gltf"
        left = self._deadline - time.monotonic()
        if left < 5:
            raise TimeoutError("the session's time limit is spent")
        self.driver.set_script_timeout(int(left))
        r = self.driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "window.brdfbakeRender(arguments[0]).then(done, e => done({error: String(e && e.stack || e)}));", cfg)
        if "error" in r:
            raise RuntimeError("Babylon.js harness: " + r["error"] + " | console: " + self._console())
        raw = np.frombuffer(base64.b64decode(r["pixels"]), np.float32).reshape(h, w, 4)
        rgba = raw[::-1]  # readPixels: row 0 at the bottom
        if r["info"]["mirrored"]:
            rgba = rgba[:, ::-1]
        out = {"image": np.ascontiguousarray(rgba[..., :3]), "alpha": np.ascontiguousarray(rgba[..., 3]),
               "info": r["info"], "browser": self.browser_version}
        if r.get("cube"):
            out["cube"] = [_decode_level(level) for level in r["cube"]]
        return out

    def render(self, bake_dir, preview, mode="env", options=None):
        return self.render_raw(bake_dir, preview, mode, options)["image"]

    def close(self):
        if self._closed:
            return
        self._closed = True
        try:
            if self.driver is not None:
                self.driver.quit()
        except Exception:  # noqa: BLE001 - the kill below ends it anyway
            pass
        t0 = time.monotonic()  # chromium's helpers end within a second or two of quit(); then killed
        while self._browser_pids() and time.monotonic() - t0 < 5:
            time.sleep(0.1)
        self._kill()
        if self._timer is not None:
            self._timer.cancel()
        self.httpd.shutdown()
        self.httpd.server_close()
        shutil.rmtree(self.root, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _decode_level(level):
    n = level["size"]
    faces = []
    for f in level["faces"]:
        raw = base64.b64decode(f["data"])
        if f["dtype"] == "float16":
            a = np.frombuffer(raw, np.float16).astype(np.float32)
        elif f["dtype"] == "uint8":
            a = np.frombuffer(raw, np.uint8).astype(np.float32) / 255.0
        else:
            a = np.frombuffer(raw, np.float32)
        faces.append(a.reshape(n, n, 4))  # row 0 = GL's first row (t = 0), as stored on the GPU
    return {"level": level["level"], "size": n, "faces": faces}


def render(bake_dir, preview_json, mode="env", options=None):
    """Babylon.js's render of the preview's grid from bake_dir's files: float32 H x W x 3 linear
    radiance, row 0 at the top, in the preview's frame (one browser session)."""
    with Session() as s:
        return s.render(bake_dir, preview_json, mode, options)


# ---------------------------------------------------------------------------------------------------
# The comparison

LUMA = np.array([0.2126, 0.7152, 0.0722], np.float64)


def sphere_interior(preview, sphere, rim=0.9):
    """The pixel indices (ys, xs) of a sphere whose centre has |d| <= rim, d as the preview defines it."""
    cx, cy = sphere["centre"]
    r = sphere["radius"]
    h, w = preview["image"]["height"], preview["image"]["width"]
    x0, x1 = max(0, int(math.floor(cx - r))), min(w, int(math.ceil(cx + r)) + 1)
    y0, y1 = max(0, int(math.floor(cy - r))), min(h, int(math.ceil(cy + r)) + 1)
    ys, xs = np.mgrid[y0:y1, x0:x1]
    dx, dy = (xs + 0.5 - cx) / r, (ys + 0.5 - cy) / r
    keep = dx * dx + dy * dy <= rim * rim
    return ys[keep], xs[keep]


def compare(engine_img, splitsum_img, preview_json, rim=0.9, channel="luminance"):
    """Per sphere the median and 95th percentile of the per-pixel relative error |engine - preview| /
    preview over the sphere's interior (pixels with |d| <= rim), on the luminance (Rec. 709 weights
    of the linear RGB; channel="luminance") or on every channel's value pooled (channel="rgb").
    Returns {"spheres": [{name, roughness, metallic, median, p95, pixels}], "all": {median, p95},
    "rough": {median, p95} (spheres of roughness >= 0.1), "mirrors": (roughness < 0.1)}; pooled
    figures are over the pixels of those spheres together."""
    preview = load_preview(preview_json) if isinstance(preview_json, (str, pathlib.Path)) else preview_json
    e = np.asarray(engine_img, np.float64)
    p = np.asarray(splitsum_img, np.float64)
    if e.shape != p.shape:
        raise ValueError(f"engine image {e.shape}, split-sum image {p.shape}")
    out, pools = [], {"all": [], "rough": [], "mirrors": []}
    for s in preview["spheres"]:
        ys, xs = sphere_interior(preview, s, rim)
        if channel == "luminance":
            a, b = e[ys, xs] @ LUMA, p[ys, xs] @ LUMA
        else:
            a, b = e[ys, xs].reshape(-1), p[ys, xs].reshape(-1)
        rel = np.abs(a - b) / np.maximum(np.abs(b), 1e-30)
        m = s["material"]
        out.append({"name": s.get("name", ""), "roughness": m["roughness"], "metallic": m["metallic"],
                    "median": float(np.median(rel)), "p95": float(np.percentile(rel, 95)), "pixels": int(rel.size),
                    "ratio_median": float(np.median(a / np.maximum(b, 1e-30)))})
        pools["all"].append(rel)
        pools["rough" if m["roughness"] >= 0.1 else "mirrors"].append(rel)
    res = {"spheres": out, "rim": rim, "channel": channel}
    for k, v in pools.items():
        if v:
            cat = np.concatenate(v)
            res[k] = {"median": float(np.median(cat)), "p95": float(np.percentile(cat, 95)), "spheres": len(v)}
    return res


def summary(res):
    """One line of the pooled figures, then one line per material row (the default grid's 12 columns)."""
    def pct(x):
        return f"{100 * x:.3g} %"
    lines = [f"all: median {pct(res['all']['median'])}, p95 {pct(res['all']['p95'])}"
             + (f"; roughness >= 0.1: median {pct(res['rough']['median'])}, p95 {pct(res['rough']['p95'])}"
                if "rough" in res else "")
             + (f"; roughness < 0.1: median {pct(res['mirrors']['median'])}, p95 {pct(res['mirrors']['p95'])}"
                if "mirrors" in res else "")]
    for s in res["spheres"]:
        lines.append(f"  {s['name']:<24} r {s['roughness']:.2f} m {s['metallic']:.0f}: median {pct(s['median'])}, "
                     f"p95 {pct(s['p95'])}, engine/preview {s['ratio_median']:.4f}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------------
# Modified copies of a bake (diagnosis: row order)

def _png_chunks(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, chunks = 8, []
    while pos < len(data):
        n = struct.unpack(">I", data[pos:pos + 4])[0]
        chunks.append((data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]))
        pos += 12 + n
    return chunks


def png_decode(data):
    """An 8-bit RGB or RGBA PNG (no interlace) as uint8 H x W x C, row 0 at the top."""
    import zlib
    chunks = _png_chunks(data)
    w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    if depth != 8 or colour not in (2, 6) or interlace:
        raise ValueError(f"PNG depth {depth} colour {colour} interlace {interlace}: not handled")
    bpp = 4 if colour == 6 else 3
    raw = zlib.decompress(b"".join(c for t, c in chunks if t == b"IDAT"))
    stride = w * bpp
    img = np.zeros((h, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 255
        else:  # Sub, Average, Paeth: byte by byte
            cur = np.zeros(stride, np.int32)
            for i in range(stride):
                left = cur[i - bpp] if i >= bpp else 0
                up_ = prev[i]
                ul = prev[i - bpp] if i >= bpp else 0
                if f == 1:
                    pred = left
                elif f == 3:
                    pred = (left + up_) >> 1
                else:
                    pa, pb, pc = abs(up_ - ul), abs(left - ul), abs(left + up_ - 2 * ul)
                    pred = left if pa <= pb and pa <= pc else (up_ if pb <= pc else ul)
                cur[i] = (line[i] + pred) & 255
        img[y] = cur.astype(np.uint8)
        prev = cur
    return img.reshape(h, w, bpp)


def png_encode(img, keep_from=None):
    """uint8 H x W x 3|4 as a PNG (filter 0); keep_from: a PNG whose ancillary chunks are copied."""
    import zlib
    img = np.ascontiguousarray(img, np.uint8)
    h, w, c = img.shape
    body = b"".join(b"\0" + img[y].tobytes() for y in range(h))

    def chunk(t, data):
        return struct.pack(">I", len(data)) + t + data + struct.pack(">I", zlib.crc32(t + data) & 0xFFFFFFFF)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6 if c == 4 else 2, 0, 0, 0))
    for t, data in (_png_chunks(keep_from)[1:] if keep_from else []):
        if t not in (b"IDAT", b"IEND"):
            out += chunk(t, data)
    return out + chunk(b"IDAT", zlib.compress(body, 6)) + chunk(b"IEND", b"")


def _png_flip_rows(data):
    """A PNG's rows reversed."""
    return png_encode(png_decode(data)[::-1], keep_from=data)


def rgbd_decode(img):
    """Babylon.js's fromRGBD of 8-bit RGBD texels: rgb = (rgb'/255)^2.2 / (a/255) (helperFunctions.fx)."""
    f = img.astype(np.float64) / 255.0
    return (f[..., :3] ** 2.2) / np.maximum(f[..., 3:4], 1.0 / 255.0)


def env_faces(path, level=0):
    """The six decoded PNGs of one level of a .env (uint8 RGBD, rows as stored)."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"\0", 8)
    manifest = json.loads(data[8:end].decode())
    base = end + 1
    mips = manifest["specular"]["mipmaps"][6 * level:6 * level + 6]
    return [png_decode(data[base + m["position"]:base + m["position"] + m["length"]]) for m in mips]


def gpu_row_order(session, bake_dir, preview, mode="env", level=0):
    """Babylon.js's cube read back at one level against the file's own faces at that level: for each face
    'same' when the GPU's row 0 (t = 0, the +Y edge of a side face in OpenGL's cube) holds the PNG's
    row 0, 'reversed' when it holds its last row, with the relative RMS of the better match."""
    r = session.render_raw(bake_dir, preview, mode, {"read_cube_levels": [level]})
    gpu = r["cube"][0]["faces"]
    bake_dir = pathlib.Path(bake_dir)
    if mode == "env":
        files = env_faces(next(bake_dir.glob("*.env")), level)
    else:
        files = [png_decode(p.read_bytes()) for p in
                 (next(bake_dir.glob(f"*_specular_{level}_{f}.png")) for f in ("px", "nx", "py", "ny", "pz", "nz"))]
    out = []
    for g, f in zip(gpu, files):
        ref = rgbd_decode(f)
        g = g[..., :3].astype(np.float64)
        scale = np.sqrt(np.mean(ref ** 2)) + 1e-30
        same = float(np.sqrt(np.mean((g - ref) ** 2)) / scale)
        rev = float(np.sqrt(np.mean((g - ref[::-1]) ** 2)) / scale)
        out.append({"rows": "same" if same < rev else "reversed", "rms_same": same, "rms_reversed": rev})
    return out


def flip_env_rows(src, dst):
    """A copy of a .env with every face PNG's rows reversed (the manifest's positions rewritten)."""
    data = pathlib.Path(src).read_bytes()
    end = data.index(b"\0", 8)
    manifest = json.loads(data[8:end].decode())
    base = end + 1
    blobs = []
    for mip in manifest["specular"]["mipmaps"]:
        blobs.append(_png_flip_rows(data[base + mip["position"]:base + mip["position"] + mip["length"]]))
    pos = 0
    for mip, b in zip(manifest["specular"]["mipmaps"], blobs):
        mip["position"], mip["length"] = pos, len(b)
        pos += len(b)
    pathlib.Path(dst).write_bytes(data[:8] + json.dumps(manifest).encode() + b"\0" + b"".join(blobs))


def flipped_bake(src_dir, dst_dir):
    """A copy of a bake folder with every .env face and every glTF face PNG upside down."""
    src_dir, dst_dir = pathlib.Path(src_dir), pathlib.Path(dst_dir)
    dst_dir.mkdir(parents=True, exist_ok=True)
    for f in src_dir.iterdir():
        if f.suffix == ".env":
            flip_env_rows(f, dst_dir / f.name)
        elif f.suffix == ".png" and "_specular_" in f.name:
            (dst_dir / f.name).write_bytes(_png_flip_rows(f.read_bytes()))
        elif f.is_file():
            shutil.copy(f, dst_dir / f.name)
    return dst_dir


_FACES = ("px", "nx", "py", "ny", "pz", "nz")


def mirrored_gltf_x(src_dir, dst_dir):
    """A copy of a --target gltf bake whose light is the environment mirrored in x, (x, y, z) -> (-x, y, z):
    the +X and -X faces swapped and every face's columns reversed (row order does not matter), and the
    irradiance coefficients odd in x (l11, l2-2, l21: indices 3, 4, 7) negated."""
    src_dir, dst_dir = pathlib.Path(src_dir), pathlib.Path(dst_dir)
    dst_dir.mkdir(parents=True, exist_ok=True)
    swap = {"px": "nx", "nx": "px"}
    for f in src_dir.iterdir():
        if f.suffix == ".png" and "_specular_" in f.name:
            stem, face = f.stem.rsplit("_", 1)
            img = png_decode(f.read_bytes())[:, ::-1]
            (dst_dir / f"{stem}_{swap.get(face, face)}.png").write_bytes(png_encode(img, keep_from=f.read_bytes()))
        elif f.suffix == ".gltf":
            doc = json.loads(f.read_text())
            for light in doc["extensions"]["EXT_lights_image_based"]["lights"]:
                c = light["irradianceCoefficients"]
                for k in (3, 4, 7):
                    c[k] = [-x for x in c[k]]
            (dst_dir / f.name).write_text(json.dumps(doc))
        elif f.is_file():
            shutil.copy(f, dst_dir / f.name)
    return dst_dir


# ---------------------------------------------------------------------------------------------------
# The orientation probe

def _spot(axis, sign):
    """A spot's direction: the axis, tilted towards the next two axes (0.30 and 0.15), so that it lies
    off its face's centre in both face coordinates: a face stored upside down or mirrored moves it."""
    d = np.zeros(3)
    d[axis] = sign
    d[(axis + 1) % 3] = 0.30
    d[(axis + 2) % 3] = 0.15
    return tuple(float(x) for x in d / np.linalg.norm(d))


SPOTS = {  # name -> (direction in the environment's frame, colour)
    "+X": (_spot(0, 1), (1.0, 0.0, 0.0)), "-X": (_spot(0, -1), (0.0, 1.0, 1.0)),
    "+Y": (_spot(1, 1), (0.0, 1.0, 0.0)), "-Y": (_spot(1, -1), (1.0, 0.0, 1.0)),
    "+Z": (_spot(2, 1), (0.0, 0.0, 1.0)), "-Z": (_spot(2, -1), (1.0, 1.0, 0.0)),
}
SPOT_TOLERANCE_DEG = 4.0  # a spot seen further than this from its direction is "not where it is"


def orientation_map(path, width=512, spot_deg=10.0, level=8.0, background=0.05):
    """A synthetic equirect (OpenEXR LatLong convention, docs/CONVENTIONS.md) with a coloured spot
    of spot_deg degrees around each direction of SPOTS (one per face of the cube, off the face's
    centre), written as Radiance .hdr."""
    h = width // 2
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(h) + 0.5) / h
    phi = 2 * math.pi * (0.5 - u)[None, :]
    theta = math.pi * (0.5 - v)[:, None]
    d = np.stack(np.broadcast_arrays(np.sin(phi) * np.cos(theta), np.sin(theta), np.cos(phi) * np.cos(theta)), -1)
    img = np.full((h, width, 3), background)
    cos_r = math.cos(math.radians(spot_deg))
    for direction, colour in SPOTS.values():
        inside = d @ np.array(direction) >= cos_r
        img[inside] = np.array(colour) * level
    write_hdr(path, img)
    return path


def probe_preview(size=128, view=(0.0, 0.0, -1.0)):
    """A preview-like description of one mirror sphere (silver metal, roughness 0) filling a size² image,
    the camera looking along view (the preview's own default is (0, 0, -1), up +Y)."""
    vd = np.array(view, float)
    vd /= np.linalg.norm(vd)
    up0 = np.array([0.0, 1.0, 0.0])
    right = np.cross(vd, up0)
    right /= np.linalg.norm(right)
    up = np.cross(right, vd)
    return {"image": {"width": size, "height": size}, "_path": "",
            "camera": {"view_direction": vd.tolist(), "up": up.tolist(), "right": right.tolist()},
            "spheres": [{"name": "mirror", "centre": [size / 2, size / 2], "radius": size * 0.47,
                         "material": {"baseColor": [1.0, 1.0, 1.0], "metallic": 1.0, "roughness": 0.0}}]}


def seen_directions(img, preview, min_level=1.0):
    """For each spot colour seen on the probe's sphere: where, in the preview's frame, the pixels of
    that colour look (the mirror's reflect(-v, n) at their centres, averaged), their count, and the
    nearest axis."""
    s = preview["spheres"][0]
    ys, xs = sphere_interior(preview, s, rim=0.995)
    cam = preview["camera"]
    right, up, v = np.array(cam["right"]), np.array(cam["up"]), -np.array(cam["view_direction"])
    dx = (xs + 0.5 - s["centre"][0]) / s["radius"]
    dy = (ys + 0.5 - s["centre"][1]) / s["radius"]
    n = dx[:, None] * right - dy[:, None] * up + np.sqrt(np.maximum(0, 1 - dx * dx - dy * dy))[:, None] * v
    r = 2 * (n @ v)[:, None] * n - v
    rgb = img[ys, xs].astype(np.float64)
    bright = rgb.max(axis=1) >= min_level
    cols = {k: np.array(c) for k, (_, c) in SPOTS.items()}
    out = {}
    for name, c in cols.items():
        unit = rgb / np.maximum(np.linalg.norm(rgb, axis=1, keepdims=True), 1e-9)
        match = bright & (unit @ (c / np.linalg.norm(c)) > 0.97)
        if match.sum() == 0:
            out[name] = {"pixels": 0}
            continue
        mean = r[match].mean(axis=0)
        mean /= np.linalg.norm(mean)
        nearest = max(SPOTS, key=lambda k: float(mean @ np.array(SPOTS[k][0])))
        off = math.degrees(math.acos(min(1.0, float(mean @ np.array(SPOTS[name][0])))))
        out[name] = {"pixels": int(match.sum()), "direction": [round(float(x), 3) for x in mean],
                     "expected": [round(x, 3) for x in SPOTS[name][0]], "degrees_off": round(off, 2),
                     "nearest_spot": nearest}
    return out


def orientation_probe(session, bake_dir, mode, options=None, size=128):
    """Renders the mirror sphere from both sides (looking down -Z, the preview's default, and down +Z)
    and reports, per spot, the direction in the preview's frame where it is seen (from the view
    that sees more of it) and whether that is where the map put it."""
    best = {}
    for view in ((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)):
        pv = probe_preview(size, view)
        img = session.render(bake_dir, pv, mode, options)
        for name, got in seen_directions(img, pv).items():
            if got["pixels"] > best.get(name, {"pixels": 0})["pixels"]:
                best[name] = got
    for name in SPOTS:
        got = best.setdefault(name, {"pixels": 0})
        got["as_expected"] = got["pixels"] > 0 and got["degrees_off"] <= SPOT_TOLERANCE_DEG
    return best


# ---------------------------------------------------------------------------------------------------
# Command line

def _options(args):
    def tri(x):
        return None if x is None else x == "on"
    return {"mix_ibl": tri(args.mix_ibl), "legacy_energy": tri(args.legacy_energy), "specular_aa": tri(args.specular_aa),
            "gamma_space": tri(args.gamma_space), "irradiance_in_fragment": tri(args.irradiance_in_fragment),
            "right_handed": args.right_handed, "segments": args.segments}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command")
    pr = sub.add_parser("probe", help="the orientation probe: bake a map of coloured spots, see where Babylon.js shows them")
    pr.add_argument("--cli", default=os.environ.get("BRDFBAKE_CLI", str(setup_babylon.REPO / "build/host/cli/brdfbake")))
    pr.add_argument("--target", choices=("babylon", "gltf"), action="append")
    pr.add_argument("--work", help="folder for the map and the bakes (default: a temporary one)")
    pr.add_argument("--map", help="an equirect to bake instead of the synthetic spots (e.g. OrientationLatLong.exr)")
    for p in (ap, pr):
        p.add_argument("--mix-ibl", choices=("on", "off"))
        p.add_argument("--legacy-energy", choices=("on", "off"))
        p.add_argument("--specular-aa", choices=("on", "off"))
        p.add_argument("--gamma-space", choices=("on", "off"))
        p.add_argument("--irradiance-in-fragment", choices=("on", "off"))
        p.add_argument("--right-handed", action="store_true")
        p.add_argument("--segments", type=int, default=64)
    ap.add_argument("--bake", help="the bake folder (NAME.env for --mode env, NAME.gltf for --mode gltf)")
    ap.add_argument("--preview-json", help="the preview's NAME.json (its NAME_splitsum.exr beside it for --compare)")
    ap.add_argument("--mode", choices=("env", "gltf", "hdr"), default="env",
                    help="env: the bake's NAME.env; gltf: its NAME.gltf through the glTF loader; hdr: --bake names "
                         "an equirect .hdr that Babylon.js converts itself (HDRCubeTexture, 256, not prefiltered)")
    ap.add_argument("-o", "--output", help="the engine's render as .npy (float32 H x W x 3, row 0 at the top)")
    ap.add_argument("--compare", action="store_true", help="print the comparison with the preview's split-sum image")
    ap.add_argument("--rim", type=float, default=0.9)
    ap.add_argument("--channel", choices=("luminance", "rgb"), default="luminance")
    ap.add_argument("--json", help="write the comparison and Babylon.js's state (defines, texture) here")
    args = ap.parse_args(argv)
    try:
        if args.command == "probe":
            return _probe_main(args)
        if not args.bake or not args.preview_json:
            ap.error("--bake and --preview-json are required")
        t0 = time.monotonic()
        with Session() as s:
            r = s.render_raw(args.bake, args.preview_json, args.mode, _options(args))
        print(f"rendered {r['image'].shape[1]}x{r['image'].shape[0]} in {time.monotonic() - t0:.1f} s "
              f"(Babylon.js {r['info']['babylon']}, chromium {r['browser']}, {r['info']['renderer']})", file=sys.stderr)
        if args.output:
            np.save(args.output, r["image"])
        res = None
        if args.compare:
            preview = load_preview(args.preview_json)
            res = compare(r["image"], splitsum_of(preview), preview, args.rim, args.channel)
            print(summary(res))
        if args.json:
            pathlib.Path(args.json).write_text(json.dumps({"comparison": res, "info": r["info"]}, indent=1))
    except Unavailable as e:
        print(f"babylon_render: {e}", file=sys.stderr)
        return 77
    return 0


def _probe_main(args):
    work = pathlib.Path(args.work or tempfile.mkdtemp(prefix="brdfbake-probe-"))
    work.mkdir(parents=True, exist_ok=True)
    env = args.map or str(orientation_map(work / "spots.hdr"))
    targets = args.target or ["babylon", "gltf"]
    results = {}
    with Session() as s:
        for t in targets:
            out = work / f"bake_{t}"
            if not out.exists():
                subprocess.run([args.cli, "bake", "--env", env, "--target", t, "-o", str(out)], check=True,
                               stdout=subprocess.DEVNULL, timeout=600)
            results[t] = orientation_probe(s, out, "env" if t == "babylon" else "gltf", _options(args))
    for t, res in results.items():
        print(f"{t}:")
        for name, got in res.items():
            print(f"  spot {name} at {got.get('expected', SPOTS[name][0])}: "
                  + (f"seen towards {got['direction']}, {got['degrees_off']} degrees off (nearest spot "
                     f"{got['nearest_spot']}, {got['pixels']} px){'' if got['as_expected'] else '  <-- not where it is'}"
                     if got["pixels"] else "not seen"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
