"""Filament itself renders a bake's `--target filament` files: the engine truth for what
`brdfbake preview --target filament` (its split-sum image) computes.

Filament is the one linked into open3d-cpu 0.20.0 (PyPI; Filament 1.76), driven through
`open3d.visualization.rendering.OffscreenRenderer` on Filament's Vulkan backend, on Mesa's lavapipe
(software Vulkan: no GPU, no display; VK_ICD_FILENAMES names lavapipe's ICD, DISPLAY and
WAYLAND_DISPLAY are dropped, and Open3D falls back to its headless window system by itself).
setup_open3d.py makes the virtual environment this module runs in; tests/python/
test_engine_filament.py runs it as a subprocess. The light is `Scene.set_indirect_light(PREFIX)`:
Open3D reads PREFIX_ibl.ktx (reflections, and the `sh` key as IndirectLight irradiance(3, sh)) and,
if present, PREFIX_skybox.ktx (hidden here; a folder without it renders the same, with a warning).

The scene is the preview's exactly (docs/PREVIEW.md, "The scene"; the preview's NAME.json): an
orthographic camera looking along the JSON's view_direction with its up and right, one pixel one
world unit, each pixel shaded once at its centre (post-processing, MSAA, SSAO, shadows and the sun
off). Each sphere is a flat mesh whose vertices sit on the pixel centres (x + 0.5, y + 0.5) of the
sphere's disc, each with the preview's normal n = d.x right - d.y up + sqrt(1 - |d|^2) v,
d = ((x + 0.5 - cx), (y + 0.5 - cy)) / radius: every sample point is a vertex, so the normal Filament
interpolates is the preview's at every pixel (an orthographic view needs no depth for the shading:
Filament's view vector is the camera's backward direction for every fragment). Open3D's defaultLit
reads a normal map: it gets a float texture of (0.5, 0.5, 1), the tangent-space normal (0, 0, 1)
exactly (Open3D's default one is 8-bit, 128/255, which tilts normals by 0.3 degrees), and explicit
UVs (0, 0) (Open3D otherwise leaves them uninitialised, and the garbage makes lavapipe's anisotropic
filtering take seconds a frame).

Materials: glTF metallic-roughness as the JSON gives them: baseColor (linear), metallic,
roughness, and Filament's reflectance = sqrt(F0_dielectric / 0.16) (0.5 for F0 0.04).

Radiance from 8-bit frames: Open3D reads back RGBA8 only. With post-processing off Filament writes
the shaded colour times the camera exposure (1/38400 for the default camera: f/16, 1/125 s,
ISO 100) into a UNORM8 target, linearly, so an indirect light of intensity 38400 k gives
q = round(255 k L). A reading q brackets L in [(q - 0.5), (q + 0.5)] / (255 k) (q = 255: at least
254.5/(255 k); q = 0: at most 0.5/(255 k)); readings at many k (2^(1/steps_per_octave) apart, an
irrational ratio, so the 8-bit grids never line up) narrow each pixel's bracket, and the radiance is
its midpoint (`capture`: a coarse ladder finds each sphere's range, then each sphere is drawn only
in the frames that read it between low_q and 255). An empty intersection would mean the rounding
model is wrong: it is counted (`inconsistent_pixels`; 0 in every capture so far), as are pixels
never bracketed (`unbounded_pixels`, `zero_pixels`).
"""

from __future__ import annotations

import argparse
import glob
import importlib.util
import json
import math
import os
import pathlib
import signal
import sys
import time
import types

import numpy as np

LAVAPIPE_ICDS = ("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json", "/usr/share/vulkan/icd.d/lvp_icd.json")
FILAMENT_DEFAULT_EXPOSURE = 1.0 / 38400.0  # 1 / (1.2 * 2^EV100), EV100 = log2(16^2 * 125 * 100 / 100)
DIELECTRIC_F0_PER_REFLECTANCE = 0.16       # Filament: f0 = 0.16 reflectance^2 (1 - metallic) + baseColor metallic


def force_lavapipe(environ=os.environ):
    """Vulkan through Mesa's lavapipe only, and no window system: called before open3d is imported
    (the Vulkan loader reads VK_ICD_FILENAMES once). Returns the ICD file used (or None)."""
    icd = environ.get("BRDFBAKE_VK_ICD") or next((p for p in LAVAPIPE_ICDS if os.path.exists(p)), None)
    if icd:
        environ["VK_ICD_FILENAMES"] = icd          # older loaders
        environ["VK_DRIVER_FILES"] = icd           # loader >= 1.3.234
    for var in ("DISPLAY", "WAYLAND_DISPLAY"):
        environ.pop(var, None)                     # Open3D falls back to headless without them
    return icd


def import_open3d():
    """open3d's package __init__ imports its plotly/dash helpers (draw_plotly), which rendering
    never calls; where they are not installed, empty stand-ins keep the import to numpy alone."""
    if "plotly" not in sys.modules and importlib.util.find_spec("plotly") is None:
        plotly = types.ModuleType("plotly")
        plotly.__path__ = []
        go = types.ModuleType("plotly.graph_objects")
        plotly.graph_objects = go
        sys.modules.setdefault("plotly", plotly)
        sys.modules.setdefault("plotly.graph_objects", go)
    if "dash" not in sys.modules and importlib.util.find_spec("dash") is None:
        dash = types.ModuleType("dash")
        dash.html = dash.dcc = dash.Dash = None
        sys.modules.setdefault("dash", dash)
    import open3d  # noqa: PLC0415
    import open3d.visualization.rendering as rendering  # noqa: PLC0415
    return open3d, rendering


# --------------------------------------------------------------------------------------------------
# The scene of the preview's JSON


def load_preview_json(preview_json):
    if isinstance(preview_json, dict):
        return preview_json
    return json.loads(pathlib.Path(preview_json).read_text())


def camera_frame(meta):
    cam = meta["camera"]
    if cam.get("projection", "orthographic") != "orthographic":
        raise ValueError(f"only the orthographic preview camera is supported, not {cam['projection']}")
    view = np.asarray(cam["view_direction"], float)
    up = np.asarray(cam["up"], float)
    right = np.asarray(cam["right"], float)
    return right, up, -view


def sphere_normal(d_x, d_y, right, up, v):
    """The preview's normal (docs/PREVIEW.md, "The scene"), d clamped onto the disc."""
    r2 = d_x * d_x + d_y * d_y
    scale = np.where(r2 > 1.0, 1.0 / np.sqrt(np.maximum(r2, 1e-30)), 1.0)
    d_x, d_y = d_x * scale, d_y * scale
    nz = np.sqrt(np.maximum(0.0, 1.0 - (d_x * d_x + d_y * d_y)))
    return d_x[..., None] * right - d_y[..., None] * up + nz[..., None] * v


def sphere_mesh(sphere, right, up, v):
    """Vertices on the pixel centres of the sphere's disc (plus a ring of 2 pixels, normals clamped
    to the horizon), each with the preview's normal; two counter-clockwise triangles per square of
    four centres. World position = (x + 0.5) right - (y + 0.5) up (pixel units, the view plane)."""
    cx, cy = sphere["centre"]
    rad = float(sphere["radius"])
    x0, x1 = int(math.floor(cx - rad)) - 2, int(math.ceil(cx + rad)) + 2
    y0, y1 = int(math.floor(cy - rad)) - 2, int(math.ceil(cy + rad)) + 2
    xs = np.arange(x0, x1 + 1) + 0.5
    ys = np.arange(y0, y1 + 1) + 0.5
    px, py = np.meshgrid(xs, ys)                       # [row, col]
    dx, dy = (px - cx) / rad, (py - cy) / rad
    keep = dx * dx + dy * dy <= (1.0 + 2.0 / rad) ** 2
    index = -np.ones(px.shape, np.int64)
    index[keep] = np.arange(int(keep.sum()))
    pos = px[keep][:, None] * right - py[keep][:, None] * up
    nrm = sphere_normal(dx[keep], dy[keep], right, up, v)
    a, b = index[:-1, :-1], index[:-1, 1:]             # (x, y), (x + 1, y)
    c, d = index[1:, :-1], index[1:, 1:]               # (x, y + 1), (x + 1, y + 1)
    ok = (a >= 0) & (b >= 0) & (c >= 0) & (d >= 0)
    # screen y grows downwards: (a, d, b) and (a, c, d) are counter-clockwise seen from v
    tris = np.concatenate([np.stack([a[ok], d[ok], b[ok]], 1), np.stack([a[ok], c[ok], d[ok]], 1)])
    return pos, nrm, tris


def filament_reflectance(material):
    """Filament's `reflectance` for the JSON's material: f0 = 0.16 r^2 (1 - m) + baseColor m, so
    r = sqrt(F0_dielectric / 0.16), F0_dielectric the non-metallic part of the JSON's F0 (one value:
    Filament's reflectance is a scalar; a coloured dielectric F0 is averaged)."""
    m = float(material.get("metallic", 0.0))
    base = np.asarray(material.get("baseColor", [1, 1, 1]), float)
    f0 = np.asarray(material.get("F0", [0.04, 0.04, 0.04]), float)
    if m >= 1.0:
        return 0.5
    f0_d = (f0 - base * m) / (1.0 - m)
    return float(math.sqrt(max(float(np.mean(f0_d)), 0.0) / DIELECTRIC_F0_PER_REFLECTANCE))


# --------------------------------------------------------------------------------------------------
# The renderer


class FilamentRenderer:
    """One OffscreenRenderer (one Filament engine) per process; `render` may be called repeatedly."""

    def __init__(self, width, height, verbose=False):
        force_lavapipe()
        self.o3d, self.rendering = import_open3d()
        if not verbose:
            self.o3d.utility.set_verbosity_level(self.o3d.utility.VerbosityLevel.Error)
        self.width, self.height = int(width), int(height)
        self.renderer = self.rendering.OffscreenRenderer(self.width, self.height)
        self.scene = self.renderer.scene
        view = self.scene.view
        view.set_post_processing(False)     # no tone mapping, dithering, FXAA, colour grading
        view.set_antialiasing(False)        # no MSAA: one sample at the pixel centre
        view.set_ambient_occlusion(False)
        view.set_shadowing(False)
        self.scene.set_background([0.0, 0.0, 0.0, 1.0])
        self.scene.show_skybox(False)
        self.scene.scene.enable_sun_light(False)
        self.ibl_prefix = None

    def set_bake(self, ibl_prefix):
        if not os.path.exists(ibl_prefix + "_ibl.ktx"):
            raise FileNotFoundError(ibl_prefix + "_ibl.ktx")
        if not self.scene.scene.set_indirect_light(ibl_prefix):
            raise RuntimeError(f"Filament refused {ibl_prefix}_ibl.ktx")
        self.scene.scene.enable_indirect_light(True)
        self.scene.show_skybox(False)
        self.ibl_prefix = ibl_prefix

    def set_spheres(self, meta, spheres=None):
        o3d, rendering = self.o3d, self.rendering
        self.scene.clear_geometry()
        self.unsupported = []
        right, up, v = camera_frame(meta)
        flat = np.zeros((4, 4, 3), np.float32)
        flat[...] = (0.5, 0.5, 1.0)                      # tangent-space (0, 0, 1) exactly, as float
        normal_img = o3d.geometry.Image(flat)
        chosen = meta["spheres"] if spheres is None else [meta["spheres"][i] for i in spheres]
        for i, sp in enumerate(chosen):
            pos, nrm, tris = sphere_mesh(sp, right, up, v)
            mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(pos), o3d.utility.Vector3iVector(tris))
            mesh.vertex_normals = o3d.utility.Vector3dVector(nrm)
            mesh.vertex_colors = o3d.utility.Vector3dVector(np.ones_like(pos))
            # explicit UVs: without them Open3D leaves the vertex buffer's uv uninitialised
            # (TriangleMeshBuffers.cpp CreateColoredBuffers), and the garbage coordinates make
            # lavapipe's anisotropic texture filtering take seconds a frame; every texture
            # this material samples is constant, so (0, 0) everywhere changes no value
            mesh.triangle_uvs = o3d.utility.Vector2dVector(np.zeros((3 * len(tris), 2)))
            mat = sp["material"]
            rec = rendering.MaterialRecord()
            rec.shader = "defaultLit"
            rec.base_color = [*map(float, mat["baseColor"]), 1.0]
            rec.base_metallic = float(mat.get("metallic", 0.0))
            rec.base_roughness = float(mat.get("roughness", 0.0))
            rec.base_reflectance = filament_reflectance(mat)
            rec.normal_img = normal_img
            # beyond Open3D's defaultLit or this flat-mesh set-up: a clear coat would be shaded with
            # the flat mesh's geometric normal (Filament's coat ignores the normal map), sheen and
            # iridescence have no parameter; such spheres render without them, and say so
            for key in ("clearcoat", "sheen_color", "iridescence"):
                if key in mat and np.any(np.asarray(mat[key], float) > 0):
                    self.unsupported.append(f"{sp.get('name', i)}: {key} not rendered")
            self.scene.add_geometry(f"sphere{i}", mesh, rec, False)
        self.count = len(chosen)
        self.shown = {i: True for i in range(self.count)}
        w, h = self.width, self.height
        cam = self.scene.camera
        # camera space: x along right, y along up; the view plane holds pixel (x, y) at
        # (x, -y) in those units, so the frustum [0, W] x [-H, 0] maps pixels 1:1
        cam.set_projection(rendering.Camera.Projection.Ortho, 0.0, float(w), -float(h), 0.0, 1.0, 1000.0)
        eye = (500.0 * v).astype(np.float32)              # 500 pixels in front of the view plane, along v
        cam.look_at(np.zeros(3, np.float32), eye, up.astype(np.float32))

    def frame(self, k):
        """One 8-bit frame at IBL intensity 38400 k: uint8 HxWx3, row 0 at the top."""
        self.scene.scene.set_indirect_light_intensity(float(k) / FILAMENT_DEFAULT_EXPOSURE)
        img = np.asarray(self.renderer.render_to_image())
        return img[..., :3].copy()

    def show(self, visible):
        """Shows the spheres whose index is in `visible` (a set), hides the others."""
        for i in range(self.count):
            want = i in visible
            if self.shown.get(i) != want:
                self.scene.show_geometry(f"sphere{i}", want)
                self.shown[i] = want


class Brackets:
    """Per pixel and channel the interval [lo, hi] that every 8-bit reading so far allows:
    q = round(255 k L) gives (q - 0.5) / (255 k) <= L <= (q + 0.5) / (255 k); q = 255 only the lower
    bound (254.5 / (255 k)), q = 0 only the upper one."""

    def __init__(self, shape):
        self.lo = np.zeros(shape, np.float64)
        self.hi = np.full(shape, np.inf)

    def add(self, q, k, where):
        q = q[where].astype(np.float64)
        scale = 255.0 * k
        lo = np.where(q > 0, (q - 0.5) / scale, 0.0)
        hi = np.where(q < 255, (q + 0.5) / scale, np.inf)
        self.lo[where] = np.maximum(self.lo[where], lo)
        self.hi[where] = np.minimum(self.hi[where], hi)

    def estimate(self):
        bounded = np.isfinite(self.hi)
        return np.where(bounded, 0.5 * (self.lo + self.hi), self.lo)


def capture(r, masks, steps_per_octave=8, coarse_octaves=3, k_range=(2.0 ** -24, 2.0 ** 14),
            low_q=32.0, margin=2.0):
    """Linear radiance of the spheres from 8-bit frames (the module's notes). masks: [(index, HxW
    bool)] of each sphere's disc. A coarse ladder (one frame every `coarse_octaves` octaves over
    k_range, all spheres) estimates each sphere's darkest and brightest pixel; then each sphere is
    shown only in the frames of the fine ladder (2^(1/steps_per_octave) apart) that read its pixels
    between `low_q` and 255 (widened by `margin` on both sides). Returns (HxWx3 float32, info)."""
    h, w = r.height, r.width
    t0 = time.time()
    union = np.zeros((h, w), bool)
    for _, m in masks:
        union |= m
    r.show({i for i, _ in masks})
    coarse = Brackets((h, w, 3))
    n_coarse = int(math.floor(math.log2(k_range[1] / k_range[0]) / coarse_octaves)) + 1
    for j in range(n_coarse):
        k = k_range[0] * 2.0 ** (j * coarse_octaves)
        coarse.add(r.frame(k), k, union)
    rough = coarse.estimate()
    # each sphere's k interval: its brightest pixel read at >= low_q / margin, its darkest at <= 255 margin
    spans = {}
    for i, m in masks:
        vals = rough[m]
        vals = vals[vals > 0]
        if vals.size == 0:
            spans[i] = (k_range[0], k_range[1])
            continue
        spans[i] = (low_q / (255.0 * float(vals.max()) * margin), margin / float(vals.min()))
    k_lo = min(a for a, _ in spans.values())
    k_hi = max(b for _, b in spans.values())
    n = int(math.ceil(math.log2(k_hi / k_lo) * steps_per_octave)) + 1
    fine = Brackets((h, w, 3))
    shaded = 0
    frames = 0
    for j in range(n):
        k = k_lo * 2.0 ** (j / steps_per_octave)   # irrational ratios: the 8-bit grids never line up
        visible = {i for i, (a, b) in spans.items() if a <= k <= b}
        if not visible:
            continue
        r.show(visible)
        where = np.zeros((h, w), bool)
        for i, m in masks:
            if i in visible:
                where |= m
        fine.add(r.frame(k), k, where)
        frames += 1
        shaded += int(where.sum())
    r.show({i for i, _ in masks})
    est = fine.estimate()
    bad = fine.lo > fine.hi
    unbounded = ~np.isfinite(fine.hi)
    est[bad] = 0.5 * (fine.lo + fine.hi)[bad]
    width = np.where(~unbounded & ~bad, (fine.hi - fine.lo) / np.maximum(est, 1e-30), np.nan)[union]
    info = {
        "coarse_frames": n_coarse, "fine_frames": frames, "ladder_k": [k_lo, k_hi],
        "steps_per_octave": steps_per_octave, "shaded_pixels": shaded, "seconds": time.time() - t0,
        "pixels": int(union.sum()),
        "inconsistent_pixels": int(bad[union].any(axis=-1).sum()),
        "unbounded_pixels": int(unbounded[union].any(axis=-1).sum()),
        "zero_pixels": int((fine.lo[union] <= 0).any(axis=-1).sum()),
        "bracket_rel_width_median": float(np.nanmedian(width)),
        "bracket_rel_width_p95": float(np.nanpercentile(width, 95)),
        "bracket_rel_width_max": float(np.nanmax(width)),
    }
    out = est.astype(np.float32)
    out[~union] = 0.0
    return out, info


def sphere_masks(meta, limit=1.0, spheres=None):
    """[(index, HxW bool)]: each sphere's pixels whose centre has |d| <= limit."""
    w, h = meta["image"]["width"], meta["image"]["height"]
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    out = []
    for i, sp in enumerate(meta["spheres"]):
        if spheres is not None and i not in spheres:
            continue
        cx, cy = sp["centre"]
        rad = sp["radius"]
        out.append((i, ((xs - cx) ** 2 + (ys - cy) ** 2) <= (limit * rad) ** 2))
    return out


def find_prefix(bake_dir, name=None):
    bake_dir = pathlib.Path(bake_dir)
    if name:
        return str(bake_dir / name)
    hits = sorted(glob.glob(str(bake_dir / "*_ibl.ktx")))
    if len(hits) != 1:
        raise FileNotFoundError(f"expected one *_ibl.ktx in {bake_dir}, found {len(hits)}; give the name")
    return hits[0][: -len("_ibl.ktx")]


def render(bake_dir, name, preview_json, *, steps_per_octave=8, spheres=None, renderer=None, info=None,
           low_q=32.0, margin=2.0):
    """Filament's render of the preview's scene from BAKE_DIR/NAME_ibl.ktx (NAME None: the folder's
    one *_ibl.ktx): float32 HxWx3 linear radiance, row 0 at the top, 0 off the spheres. `spheres`
    (indices) renders those only; `info` (a dict) receives the capture's statistics."""
    meta = load_preview_json(preview_json)
    w, h = meta["image"]["width"], meta["image"]["height"]
    r = renderer or FilamentRenderer(w, h)
    r.set_bake(find_prefix(bake_dir, name))
    r.set_spheres(meta, spheres)
    masks = sphere_masks(meta, 1.0, spheres)
    # set_spheres numbers the geometries 0.. in the order of `spheres`
    masks = [(j, m) for j, (_, m) in enumerate(masks)]
    img, stats = capture(r, masks, steps_per_octave, low_q=low_q, margin=margin)
    stats["unsupported"] = list(r.unsupported)
    if info is not None:
        info.update(stats)
    return img


# --------------------------------------------------------------------------------------------------
# The comparison, the preview's files and the orientation probe: the Babylon.js harness's (one
# definition for every engine's test): `compare` is per sphere the median and 95th percentile of
# |engine - preview| / preview of the Rec. 709 luminance (channel="rgb": every channel pooled) over
# the pixels with |d| <= 0.9, and the same pooled over all spheres, roughness >= 0.1 and < 0.1.

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "babylon"))
from babylon_render import (SPOTS, SPOT_TOLERANCE_DEG, compare, load_preview, orientation_map,  # noqa: E402,F401
                            probe_preview, read_exr, seen_directions, splitsum_of, summary)


def orientation_probe(bake_dir, name=None, size=128, renderer=None):
    """A roughness-0 silver sphere filling a size^2 image, looked at down -Z (the preview's default)
    and down +Z: per spot of the probe map (babylon_render.SPOTS) the direction, in the preview's
    frame, where Filament shows it (the mirror direction reflect(-v, n) of its pixels, from the view
    that sees more of it), and whether that is within SPOT_TOLERANCE_DEG of where the map put it."""
    best = {}
    r = renderer or FilamentRenderer(size, size)
    r.set_bake(find_prefix(bake_dir, name))
    for view in ((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)):
        pv = probe_preview(size, view)
        pv["spheres"][0]["material"]["F0"] = [1.0, 1.0, 1.0]
        r.set_spheres(pv)
        img, _ = capture(r, [(0, sphere_masks(pv)[0][1])], steps_per_octave=1)
        for spot, got in seen_directions(img, pv).items():
            if got["pixels"] > best.get(spot, {"pixels": 0})["pixels"]:
                best[spot] = got
    for spot in SPOTS:
        got = best.setdefault(spot, {"pixels": 0})
        got["as_expected"] = got["pixels"] > 0 and got["degrees_off"] <= SPOT_TOLERANCE_DEG
    return best


TIME_LIMIT_S = 300  # the command line's wall-clock limit: SIGALRM ends the process (Filament's threads too)


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    probe = bool(argv) and argv[0] == "probe"
    ap = argparse.ArgumentParser(
        prog="filament_render.py" + (" probe" if probe else ""),
        description="Filament 1.76 (open3d-cpu 0.20.0, Vulkan on lavapipe) renders a brdfbake preview's scene from a "
                    "--target filament bake" + (": the orientation probe" if probe else ""))
    ap.add_argument("--bake", required=True, help="the bake folder (brdfbake bake --target filament -o DIR)")
    ap.add_argument("--name", help="NAME of NAME_ibl.ktx (default: the folder's one *_ibl.ktx)")
    ap.add_argument("--json", help="write the statistics (and the comparison or the probe's spots) here")
    ap.add_argument("--time-limit", type=float, default=TIME_LIMIT_S, help="seconds before the process ends itself")
    if probe:
        ap.add_argument("--size", type=int, default=128)
    else:
        ap.add_argument("--preview-json", required=True, help="the preview's NAME.json (brdfbake preview --target filament)")
        ap.add_argument("--steps-per-octave", type=int, default=8, help="frames an octave of exposure (default 8)")
        ap.add_argument("--low-q", type=float, default=32.0, help="the darkest 8-bit reading of a sphere's brightest pixel (default 32)")
        ap.add_argument("--margin", type=float, default=2.0, help="each sphere's exposure range widened by this factor both ways (default 2)")
        ap.add_argument("--spheres", help="comma-separated sphere indices (default: all)")
        ap.add_argument("-o", "--output", help="float32 HxWx3 .npy of linear radiance, row 0 at the top")
        ap.add_argument("--compare", action="store_true", help="compare with the preview's split-sum image and print it")
        ap.add_argument("--channel", default="luminance", choices=("luminance", "rgb"))
    args = ap.parse_args(argv[1:] if probe else argv)
    if args.time_limit > 0:
        signal.alarm(int(math.ceil(args.time_limit)))
    t0 = time.time()
    out = {}
    if probe:
        out["spots"] = orientation_probe(args.bake, args.name, args.size)
        for k, v in out["spots"].items():
            print(f"spot {k}: expected {v.get('expected')}, seen {v.get('direction')} ({v.get('degrees_off')} degrees off, "
                  f"nearest spot {v.get('nearest_spot')}, {v['pixels']} px){'' if v['as_expected'] else '  <-- NOT AS EXPECTED'}")
    else:
        meta = load_preview(args.preview_json)
        spheres = [int(x) for x in args.spheres.split(",")] if args.spheres else None
        info = {}
        img = render(args.bake, args.name, meta, steps_per_octave=args.steps_per_octave, spheres=spheres, info=info,
                     low_q=args.low_q, margin=args.margin)
        out["capture"] = info
        if args.output:
            np.save(args.output, img)
        if args.compare:
            sub = dict(meta)
            if spheres is not None:
                sub["spheres"] = [meta["spheres"][i] for i in spheres]
            res = compare(img, splitsum_of(meta), sub, channel=args.channel)
            out["comparison"] = res
            print(summary(res))
        print(json.dumps(info))
    out["seconds"] = time.time() - t0
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
