"""Opens `scatterlab render --out FILE.exr` with the OpenEXR Python bindings
(the Academy Software Foundation's reader, not the `exr` crate that wrote
it) and checks its layers against the PNG the renderer wrote for the same
frame and against each other.

Usage: python render_exr_check.py METHOD.exr METHOD.png NONE.exr

METHOD.exr/.png: one frame of a scattering method, as EXR and as PNG;
NONE.exr: the same frame with `--method none`. Checks:
- the channels: R, G, B, A (the radiance before exposure and tone
  mapping, alpha the coverage) and the layers scattered.*, unscattered.*,
  albedo.* (RGBA) and specular.* (RGB), all 32-bit float and finite;
- the PNG is sRGB(ACES(exposure x RGB)) on the mesh, to 8-bit rounding:
  ACES by Narkowicz's 2015 fit, x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)
  clamped to [0, 1] (K. Narkowicz, "ACES Filmic Tone Mapping Curve",
  2016-01-06), the sRGB transfer function of IEC 61966-2-1; the exposure
  from the header; the PNG decoded here with zlib (PNG spec, ISO/IEC
  15948, filters 0-4);
- RGB = scattered x albedo + specular on the mesh, 0 off it;
- a method that scatters nothing gives back the unscattered frame: in
  NONE.exr, scattered = unscattered on every pixel;
- both files saw the same scene pass: their unscattered layers agree;
- the method did scatter: over its inner SSS pixels the scattered
  layer's total variation is under 0.95 of the unscattered one's.
Prints one JSON line of the figures.
"""

import json
import struct
import sys
import zlib

import numpy as np
import OpenEXR


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def read_exr(path):
    with OpenEXR.File(path) as f:
        header = f.header()
        exposure = float(header.get("exposure", float("nan")))
        method = str(header.get("method", ""))
        layers = {}
        for name, ch in f.channels().items():
            px = np.asarray(ch.pixels)
            if px.dtype != np.float32:
                fail("%s: %s is %s, not 32-bit float" % (path, name, px.dtype))
            layers[name] = px.astype(np.float64)
    return exposure, method, layers


def read_png(path):
    """8-bit RGB or RGBA, non-interlaced: the chunks, zlib, the filters."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("%s: not a PNG" % path)
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                fail("%s: depth %d colour %d interlace %d" % (path, depth, colour, interlace))
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride = w * bpp
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, dtype=np.int32)
        for x in range(stride):
            a = cur[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if ft == 0:
                p = 0
            elif ft == 1:
                p = a
            elif ft == 2:
                p = b
            elif ft == 3:
                p = (a + b) // 2
            elif ft == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            else:
                fail("%s: filter %d" % (path, ft))
            cur[x] = (line[x] + p) & 0xFF
        out[y] = cur
        prev = cur
    return out.reshape(h, w, bpp)[..., :3] / 255.0


def aces(x):
    return np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)


def srgb(x):
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(np.maximum(x, 0.0), 1.0 / 2.4) - 0.055)


def main():
    exposure, method, a = read_exr(sys.argv[1])
    png = read_png(sys.argv[2])
    _, none_method, n = read_exr(sys.argv[3])
    want = {"RGBA": 4, "scattered": 4, "unscattered": 4, "albedo": 4, "specular": 3}
    for layers, path in ((a, sys.argv[1]), (n, sys.argv[3])):
        if sorted(layers) != sorted(want):
            fail("%s: channels %s, expected %s" % (path, sorted(layers), sorted(want)))
        for k, c in want.items():
            if layers[k].shape[-1] != c or not np.all(np.isfinite(layers[k])):
                fail("%s: %s has shape %r or non-finite values" % (path, k, layers[k].shape))
    if none_method != "none":
        fail("%s: method %r, expected none" % (sys.argv[3], none_method))
    if not exposure > 0:
        fail("exposure %r in the header" % exposure)
    rgba = a["RGBA"]
    mesh = rgba[..., 3] > 0
    if png.shape[:2] != mesh.shape or mesh.sum() < 100:
        fail("PNG %r against EXR %r, %d pixels on the mesh" % (png.shape, mesh.shape, mesh.sum()))

    # The PNG from the EXR, by the published curve and transfer function.
    predicted = srgb(aces(exposure * rgba[..., :3]))
    png_error = np.abs(predicted - png)[mesh]
    png_max = float(png_error.max() * 255)
    if png_max > 1.0:
        fail("sRGB(ACES(exposure x RGB)) is %.2f/255 from the PNG at worst" % png_max)

    # The radiance is the composite of the layers.
    composite = a["scattered"][..., :3] * a["albedo"][..., :3] + a["specular"]
    comp_err = float(np.abs(composite - rgba[..., :3])[mesh].max() / max(rgba[..., :3][mesh].max(), 1e-9))
    if comp_err > 1e-6:
        fail("RGB differs from scattered x albedo + specular by %.2e (relative)" % comp_err)
    if np.abs(rgba[~mesh]).max() > 0:
        fail("radiance off the mesh")

    # No scattering: the unscattered frame back, bit for bit.
    none_err = float(np.abs(n["scattered"][..., :3] - n["unscattered"][..., :3]).max())
    if none_err != 0.0:
        fail("none: scattered differs from unscattered by %g" % none_err)
    # The same scene pass under both methods.
    scene_err = float(np.abs(a["unscattered"] - n["unscattered"]).max())
    if scene_err > 1e-6:
        fail("the unscattered layers differ by %g between the methods" % scene_err)
    # The method scattered light on its SSS pixels, and scattering
    # smooths: a convolution with a normalised positive kernel never
    # raises the total variation (|grad (k * f)|_1 <= |k|_1 |grad f|_1), so
    # over the SSS pixels whose four neighbours are SSS pixels too it must
    # fall (the screen-space methods' depth weights make it approximate:
    # a 5 % margin).
    sss = a["unscattered"][..., 3] > 0.5
    inner = sss[1:-1, 1:-1] & sss[2:, 1:-1] & sss[:-2, 1:-1] & sss[1:-1, 2:] & sss[1:-1, :-2]

    def total_variation(x):
        gx = np.abs(x[1:-1, 2:] - x[1:-1, :-2])
        gy = np.abs(x[2:, 1:-1] - x[:-2, 1:-1])
        return float((gx + gy)[inner].sum())

    relative = total_variation(a["scattered"][..., :3]) / max(total_variation(a["unscattered"][..., :3]), 1e-9)
    if inner.sum() < 100 or relative > 0.95:
        fail("%s on %d inner SSS pixels: total variation x%.3f (scattering must smooth)" % (method, inner.sum(), relative))

    print(json.dumps({
        "method": method, "exposure": exposure, "mesh_pixels": int(mesh.sum()),
        "sss_pixels": int(sss.sum()), "png_max_255": png_max,
        "png_mean_255": float(png_error.mean() * 255), "composite_rel": comp_err,
        "scene_diff": scene_err, "total_variation_ratio": relative,
    }))


main()
