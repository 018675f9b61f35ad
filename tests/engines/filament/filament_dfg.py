"""Filament's built-in DFG table (the `light_iblDFG` texture every Filament material samples), two ways:

1. `compute_table(size, dtype)`: a NumPy re-implementation of what Filament's build runs
   (filament/CMakeLists.txt: `cmgen --quiet --size=128 --ibl-dfg-multiscatter --ibl-dfg-cloth
   --ibl-dfg=generated/data/dfg.inc`), i.e. google/filament libs/ibl/src/CubemapIBL.cpp
   `CubemapIBL::DFG` with `DFV_Multiscatter` (1024 GGX importance samples) and
   `DFV_Charlie_Uniform` (4096 uniform samples), Hammersley points from libs/ibl/include/ibl/
   utilities.h `hammersley`, written by tools/cmgen/src/cmgen.cpp `iblLutDfg` in "GL order"
   (image row size-1-t becomes texture row t).
2. `extract_from_library(path)`: the RGB16F table as shipped, out of a binary that links Filament
   statically (open3d-cpu's libOpen3D.so): Filament >= 1.5x keeps it as a Zstd-compressed resource
   (filament/src/DFG.cpp `DFG::init`, `generated/resources/dfg.h`), the only Zstd frame whose
   content size is 128*128*3*2 bytes.

Layout of the table (both): float array [t][s][c], t the texture row (texture coordinate
v = (t + 0.5)/size), s the column (u = (s + 0.5)/size); the shader samples it bilinearly with
clamp to edge at vec2(NoV, perceptualRoughness) (shaders/src/surface_light_indirect.fs /
light_indirect.fs `prefilteredDFG`). Column s holds NoV = (s + 0.5)/size; row t holds
perceptualRoughness = min(1, (t + 1.5)/size) -- one texel above its centre, from cmgen's
`coord = saturate((h - y + 0.5) / h)` for image row y = size - 1 - t. Channels:
  c=0: DFV.x = 4/N sum Fc V NoL VoH/NoH  (Fc = (1 - VoH)^5)    = integral of D V Fc n.l
  c=1: DFV.y = 4/N sum    V NoL VoH/NoH                        = integral of D V n.l (albedo at F0=F90=1)
  c=2: Charlie sheen albedo with Ashikhmin's V = 1/(4 (NoL + NoV - NoL NoV)), uniform sampling.
Filament's shader: specularDFG = mix(dfg.xxx, dfg.yyy, f0); energy compensation 1 + f0 (1/dfg.y - 1).

Run as a script to write /tmp/filament_dfg/ (or the folder given): the computed tables
(float64 and float32 arithmetic), the extracted one if a library is given, as .npy, and a note.
"""

import argparse
import json
import pathlib
import subprocess
import sys

import numpy as np

LUT_SIZE = 128
GGX_SAMPLES = 1024
CHARLIE_SAMPLES = 4096


def hammersley(n, dtype):
    """libs/ibl/include/ibl/utilities.h `hammersley(i, iN)`: (i * iN, radicalInverse(i)), both
    computed in float (iN = 1.0f / n, tof = 0.5f / 0x80000000)."""
    i = np.arange(n, dtype=np.uint32)
    bits = i.copy()
    bits = (bits << np.uint32(16)) | (bits >> np.uint32(16))
    bits = ((bits & np.uint32(0x55555555)) << np.uint32(1)) | ((bits & np.uint32(0xAAAAAAAA)) >> np.uint32(1))
    bits = ((bits & np.uint32(0x33333333)) << np.uint32(2)) | ((bits & np.uint32(0xCCCCCCCC)) >> np.uint32(2))
    bits = ((bits & np.uint32(0x0F0F0F0F)) << np.uint32(4)) | ((bits & np.uint32(0xF0F0F0F0)) >> np.uint32(4))
    bits = ((bits & np.uint32(0x00FF00FF)) << np.uint32(8)) | ((bits & np.uint32(0xFF00FF00)) >> np.uint32(8))
    i_n = np.float32(1.0) / np.float32(n)
    tof = np.float32(0.5) / np.float32(0x80000000)
    ux = (i.astype(np.float32) * i_n).astype(dtype)
    uy = (bits.astype(np.float32) * tof).astype(dtype)
    return ux, uy


def _visibility(nov, nol, a, dtype):
    # Heitz 2014, height-correlated Smith GGX, V = G / (4 NoL NoV) (CubemapIBL.cpp `Visibility`)
    a2 = a * a
    ggxl = nov * np.sqrt((nol - nol * a2) * nol + a2)
    ggxv = nol * np.sqrt((nov - nov * a2) * nov + a2)
    return dtype(0.5) / (ggxv + ggxl)


def dfv_multiscatter(nov, a, dtype=np.float64, n=GGX_SAMPLES):
    """CubemapIBL.cpp `DFV_Multiscatter`: returns (x, y) = 4/N sum (Fc v, v) over GGX samples,
    v = V NoL VoH / NoH. `nov` is an array (one row of the table), `a` the linear roughness."""
    dt = dtype
    nov = np.asarray(nov, dt)[:, None]
    a = dt(a)
    ux, uy = hammersley(n, dt)
    phi = dt(2.0) * dt(np.pi) * ux
    cos2 = (dt(1) - uy) / (dt(1) + (a + dt(1)) * ((a - dt(1)) * uy))   # hemisphereImportanceSampleDggx
    cos_t = np.sqrt(cos2)
    sin_t = np.sqrt(dt(1) - cos2)
    hx, hz = sin_t * np.cos(phi), cos_t                                 # H.y drops out: V.y = 0
    vx = np.sqrt(dt(1) - nov * nov)
    voh_raw = vx * hx + nov * hz                                         # V = (sqrt(1-NoV^2), 0, NoV)
    lz = dt(2) * voh_raw * hz - nov
    voh = np.clip(voh_raw, 0, 1)
    nol = np.clip(lz, 0, 1)
    noh = np.clip(hz, 0, 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = _visibility(nov, nol, a, dt) * nol * (voh / noh)
        fc = (dt(1) - voh) ** 2
        fc = fc * fc * (dt(1) - voh)
    mask = nol > 0
    v = np.where(mask, v, dt(0))
    fc = np.where(mask, fc, dt(0))
    # sequential accumulation, as the C++ loop does (cumsum is sequential; sum is pairwise)
    rx = np.cumsum(v * fc, axis=1, dtype=dt)[:, -1]
    ry = np.cumsum(v, axis=1, dtype=dt)[:, -1]
    scale = dt(4.0) / dt(n)
    return rx * scale, ry * scale


def dfv_charlie_uniform(nov, a, dtype=np.float64, n=CHARLIE_SAMPLES):
    """CubemapIBL.cpp `DFV_Charlie_Uniform`: uniform hemisphere samples of h, D_Charlie (Estevez and
    Kulla 2017), V_Ashikhmin (Neubelt and Pettineo 2013), r += V D NoL VoH; r * 4 * 2 pi / N."""
    dt = dtype
    nov = np.asarray(nov, dt)[:, None]
    a = dt(a)
    ux, uy = hammersley(n, dt)
    phi = dt(2.0) * dt(np.pi) * ux
    cos_t = dt(1) - uy
    sin_t = np.sqrt(dt(1) - cos_t * cos_t)
    hx, hz = sin_t * np.cos(phi), cos_t                                 # H.y drops out: V.y = 0
    vx = np.sqrt(dt(1) - nov * nov)
    voh_raw = vx * hx + nov * hz
    lz = dt(2) * voh_raw * hz - nov
    voh = np.clip(voh_raw, 0, 1)
    nol = np.clip(lz, 0, 1)
    noh = np.clip(hz, 0, 1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        vis = dt(1) / (dt(4) * (nol + nov - nol * nov))
        inv_a = dt(1) / a
        sin2h = dt(1) - noh * noh
        d = (dt(2) + inv_a) * np.power(sin2h, inv_a * dt(0.5)) / (dt(2) * dt(np.pi))
        term = vis * d * nol * voh
    term = np.where(nol > 0, term, dt(0))
    r = np.cumsum(term, axis=1, dtype=dt)[:, -1]
    return r * (dt(4.0) * dt(2.0) * dt(np.pi) / dt(n))


def compute_table(size=LUT_SIZE, dtype=np.float64, cloth=True):
    """The table in texture order [t][s][c] (row t = texture coordinate (t + 0.5)/size), before the
    conversion to half floats. dtype float64 is cmgen 1.9.x (double), float32 the later cmgen."""
    dt = dtype
    out = np.zeros((size, size, 3), np.float64)
    h = dt(size)
    nov = np.clip((np.arange(size, dtype=dt) + dt(0.5)) / dt(size), 0, 1)
    for y in range(size):                       # image row y (cmgen's), texture row size-1-y
        coord = min(max((h - dt(y) + dt(0.5)) / h, dt(0)), dt(1))
        a = dt(coord * coord)
        x, yv = dfv_multiscatter(nov, a, dt)
        t = size - 1 - y
        out[t, :, 0] = x
        out[t, :, 1] = yv
        if cloth:
            out[t, :, 2] = dfv_charlie_uniform(nov, a, dt)
    return out


def to_half(table):
    return np.asarray(table, np.float32).astype(np.float16)


def extract_from_library(path, size=LUT_SIZE):
    """The shipped table out of a library with Filament linked in (setup_open3d.extract_dfg_raw: the Zstd
    frame whose declared content size is 128*128*3*2 bytes, decompressed with `zstd`). Returns float16
    [t][s][3] or None."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    import setup_open3d  # noqa: PLC0415

    assert size == LUT_SIZE, "Filament's table is 128 x 128"
    raw = setup_open3d.extract_dfg_raw(path)
    return None if raw is None else np.frombuffer(raw, "<f2").reshape(size, size, 3)


# --------------------------------------------------------------------------------------------------
# What the `filament` preview would show with another DFG table (no C++ change needed): Filament's
# evaluateIBL is, per pixel and channel,
#   P = S T(dfg) + c_d Irr(n) (1 - E(dfg)),  E = mix(x, y, f0),  T = E (1 + f0 (1/y - 1)),
# S the prefiltered radiance (independent of the table), Irr the SH irradiance (sh.txt), so a split-sum
# image made with table A becomes the one table B gives: S = (P - c_d Irr (1 - E_A)) / T_A.


def lookup(table, nov, pr):
    """Bilinear, clamp to edge, texel centres: table [row][col][c] at u = nov (columns), v = pr (rows)."""
    h, w = table.shape[:2]
    u = np.clip(np.asarray(nov, np.float64) * w - 0.5, 0, w - 1)
    v = np.clip(np.asarray(pr, np.float64) * h - 0.5, 0, h - 1)
    i0 = np.minimum(np.floor(u).astype(int), w - 2)
    j0 = np.minimum(np.floor(v).astype(int), h - 2)
    fu, fv = (u - i0)[..., None], (v - j0)[..., None]
    t = np.asarray(table, np.float64)
    return ((t[j0, i0] * (1 - fu) + t[j0, i0 + 1] * fu) * (1 - fv)
            + (t[j0 + 1, i0] * (1 - fu) + t[j0 + 1, i0 + 1] * fu) * fv)


def read_sh_txt(path):
    """cmgen's sh.txt: 9 lines '( r, g, b); // Llm ...' -> float64 [9][3]."""
    import re  # noqa: PLC0415
    rows = [[float(x) for x in re.findall(r"[-+0-9.eE]+", line.split(")")[0])]
            for line in pathlib.Path(path).read_text().splitlines() if line.strip().startswith("(")]
    return np.array(rows[:9], np.float64)


def irradiance_sh(sh, n):
    """Filament's Irradiance_SphericalHarmonics(n) (surface_light_indirect.fs): max(sum sh_k poly_k, 0)."""
    x, y, z = n[..., 0:1], n[..., 1:2], n[..., 2:3]
    e = (sh[0] + sh[1] * y + sh[2] * z + sh[3] * x + sh[4] * (y * x) + sh[5] * (y * z)
         + sh[6] * (3 * z * z - 1) + sh[7] * (z * x) + sh[8] * (x * x - y * y))
    return np.maximum(e, 0.0)


def swap_dfg(splitsum, meta, sh, table_from, table_to, limit=1.0):
    """The `filament` split-sum image re-made with table_to in place of table_from (both [row][col][>=2]
    sampled at (NoV, perceptualRoughness) as Filament does). Pixels off the spheres are kept."""
    out = np.array(splitsum, np.float64)
    cam = meta["camera"]
    right, up, v = (np.asarray(cam["right"], float), np.asarray(cam["up"], float),
                    -np.asarray(cam["view_direction"], float))
    h, w = out.shape[:2]
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    for sp in meta["spheres"]:
        cx, cy = sp["centre"]
        rad = sp["radius"]
        dx, dy = (xs - cx) / rad, (ys - cy) / rad
        m = dx * dx + dy * dy <= limit * limit
        if not m.any():
            continue
        ddx, ddy = dx[m], dy[m]
        n = ddx[:, None] * right - ddy[:, None] * up + np.sqrt(np.maximum(0, 1 - ddx ** 2 - ddy ** 2))[:, None] * v
        nov = np.maximum(n @ v, 1e-4)                                   # clampNoV
        mat = sp["material"]
        pr = np.clip(float(mat["roughness"]), 0.045, 1.0)               # MIN_PERCEPTUAL_ROUGHNESS
        f0 = np.asarray(mat["F0"], float)[None, :]
        cd = np.asarray(mat.get("diffuse_color", [0, 0, 0]), float)[None, :]
        irr = irradiance_sh(sh, n)

        def terms(table):
            d = lookup(table, nov, np.full_like(nov, pr))
            x, y = d[:, 0:1], d[:, 1:2]
            e = x + (y - x) * f0
            return e * (1 + f0 * (1 / y - 1)), e

        t_a, e_a = terms(table_from)
        t_b, e_b = terms(table_to)
        p = out[m]
        s = (p - cd * irr * (1 - e_a)) / t_a
        out[m] = s * t_b + cd * irr * (1 - e_b)
    return out.astype(np.float32)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--out", default="/tmp/filament_dfg")
    ap.add_argument("--library", help="libOpen3D.so (or another binary with Filament) to extract the shipped table from")
    ap.add_argument("--cmgen-inc", help="a dfg.inc written by cmgen --ibl-dfg=X.inc --ibl-dfg-multiscatter --ibl-dfg-cloth, to compare")
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tables = {}
    for name, dt in (("computed_f64", np.float64), ("computed_f32", np.float32)):
        t = compute_table(LUT_SIZE, dt)
        np.save(out / f"dfg_{name}.npy", t.astype(np.float32))
        tables[name] = to_half(t)
    if args.library:
        shipped = extract_from_library(args.library)
        if shipped is not None:
            np.save(out / "dfg_filament_shipped_f16.npy", shipped)
            np.save(out / "dfg_filament_shipped.npy", shipped.astype(np.float32))
            tables["shipped"] = shipped
    if args.cmgen_inc:
        import re  # noqa: PLC0415
        vals = [int(h, 16) for h in re.findall(r"0x([0-9a-f]{4})", pathlib.Path(args.cmgen_inc).read_text())]
        tables["cmgen_inc"] = np.array(vals, "<u2").view(np.float16).reshape(LUT_SIZE, LUT_SIZE, 3)
    report = {}
    names = list(tables)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ua = tables[a].view(np.uint16).astype(np.int32)
            ub = tables[b].view(np.uint16).astype(np.int32)
            ulps = np.abs(ua - ub)
            fa, fb = tables[a].astype(np.float64), tables[b].astype(np.float64)
            rel = np.abs(fa - fb) / np.maximum(np.abs(fb), 1e-4)
            report[f"{a} vs {b}"] = {
                "identical_half_values_per_channel": [float((ulps[..., c] == 0).mean()) for c in range(3)],
                "max_half_ulps_per_channel": [int(ulps[..., c].max()) for c in range(3)],
                "max_rel_diff_per_channel": [float(rel[..., c].max()) for c in range(3)],
            }
    (out / "compare.json").write_text(json.dumps(report, indent=1))
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    sys.exit(main())
