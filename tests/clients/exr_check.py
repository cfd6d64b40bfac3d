"""Opens scatterlab's EXR exports with the OpenEXR Python bindings (the
Academy Software Foundation's reader, not the `exr` crate that wrote them)
and checks their contents against closed forms and physical limits.

Usage: python exr_check.py EXPECT.json
EXPECT: {"profile": path, "transmittance": path, "lut": path, "shadow": path,
         "albedo": [A], "d_mm": [d], "thickness_max_mm": t}
for a Burley look. Checks:
- profile: 256x1 RGB float; the header's comments give r_max, and texel i
  holds r*R(r) at r = (i + 1/2)/256 r_max with Burley's
  R(r) = A (e^{-r/d} + e^{-r/3d}) / (8 pi d r) (Christensen & Burley 2015
  eq. 2), so r*R(r) = A (e^{-r/d} + e^{-r/3d}) / (8 pi d);
- transmittance: 64x1; T(t) = A/4 (e^{-t/d} + 3 e^{-t/3d}) (the share of
  Burley's profile beyond radius t, times A);
- lut: 256x256, finite, and its top row (curvature radius 100 mm, far
  wider than d) is the flat-skin limit D = max(N.L, 0) within 0.02;
- shadow: 64x64 in [0, 1], and its top row (a 100 mm penumbra) keeps the
  unscattered shadow value x within 0.02.
"""

import json
import math
import re
import sys

import numpy as np
import OpenEXR


def read(path):
    with OpenEXR.File(path) as f:
        # Copy what is needed while the file is open: the header's values
        # are views into it.
        header = {"comments": str(f.header().get("comments", ""))}
        ch = f.channels()
        if "RGB" in ch:
            px = np.asarray(ch["RGB"].pixels, dtype=np.float64)
        else:
            px = np.stack([np.asarray(ch[k].pixels, dtype=np.float64) for k in "RGB"], axis=-1)
    return header, px


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def check_shape(name, px, w, h):
    if px.shape != (h, w, 3):
        fail("%s: shape %r, expected (%d, %d, 3)" % (name, px.shape, h, w))
    if not np.all(np.isfinite(px)):
        fail("%s: non-finite texels" % name)


def main():
    e = json.load(open(sys.argv[1]))
    A, d = e["albedo"], e["d_mm"]
    worst = {}

    header, px = read(e["profile"])
    check_shape("profile", px, 256, 1)
    comments = header["comments"]
    m = re.search(r"\* ([0-9.eE+-]+) mm", comments)
    if not m:
        fail("profile: no r_max in the comments attribute: %r" % comments)
    r_max = float(m.group(1))
    r = (np.arange(256) + 0.5) / 256 * r_max
    for c in range(3):
        want = A[c] * (np.exp(-r / d[c]) + np.exp(-r / (3 * d[c]))) / (8 * math.pi * d[c])
        err = np.max(np.abs(px[0, :, c] - want) / np.max(want))
        worst["profile_%d" % c] = float(err)
        if err > 1e-5:
            fail("profile channel %d: max error %.3g of the peak" % (c, err))

    header, px = read(e["transmittance"])
    check_shape("transmittance", px, 64, 1)
    t = (np.arange(64) + 0.5) / 64 * e["thickness_max_mm"]
    for c in range(3):
        want = A[c] / 4 * (np.exp(-t / d[c]) + 3 * np.exp(-t / (3 * d[c])))
        err = np.max(np.abs(px[0, :, c] - want))
        worst["transmittance_%d" % c] = float(err)
        if err > 1e-5:
            fail("transmittance channel %d: max error %.3g" % (c, err))

    header, px = read(e["lut"])
    check_shape("lut", px, 256, 256)
    nl = -1 + (np.arange(256) + 0.5) / 256 * 2
    flat = np.maximum(nl, 0)
    err = float(np.max(np.abs(px[0, :, :] - flat[:, None])))
    worst["lut_flat_row"] = err
    if err > 0.02:
        fail("lut: the 100 mm row differs from max(N.L, 0) by %.4f" % err)

    header, px = read(e["shadow"])
    check_shape("shadow", px, 64, 64)
    if px.min() < -1e-6 or px.max() > 1 + 1e-6:
        fail("shadow: values outside [0, 1]: %r..%r" % (px.min(), px.max()))
    x = (np.arange(64) + 0.5) / 64
    err = float(np.max(np.abs(px[0, :, :] - x[:, None])))
    worst["shadow_wide_row"] = err
    if err > 0.02:
        fail("shadow: the 100 mm row differs from the unscattered value by %.4f" % err)
    print(json.dumps(worst))


if __name__ == "__main__":
    main()
