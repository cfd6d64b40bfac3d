"""A side-lit sphere's scattered radiance by quadrature, against scatterlab's
ground truth and Cycles' Christensen-Burley (issue 53, item 3: which of the
two is right where they differ on a head).

Usage (tools/cycles_sphere.sh runs it): python sphere_quadrature.py DIR RADIUS_MM

DIR holds what tools/cycles_sphere.sh wrote: sphere.obj's render by
`scatterlab render` (none.exr, reference.exr, none.json with the camera)
and tests/clients/blender_head.py's Cycles renders (cycles_no_sss.exr,
cycles_burley_seed1.exr, cycles_burley_seed2.exr).

The quadrature is independent of both renderers. On a sphere of radius
rho centred at the origin, lit by a sun of irradiance I towards L (no cast
shadows on a sphere), the radiance leaving x is
    A * int R(|x - y|) E(y) dA(y),   E(y) = I / pi * max(0, n(y).L),
with Burley's normalised profile R(r) = (e^{-r/d} + e^{-r/3d}) / (8 pi d r)
(Christensen & Burley 2015) and the look's d and A, read from the Blender
snippet's comment (DIR/snippet.py). y is
taken in polar coordinates about x on the sphere: geodesic angle alpha and
azimuth beta, dA = rho^2 sin(alpha) dalpha dbeta, |x - y| = 2 rho
sin(alpha / 2); alpha = alpha_max u^2 with 300 Gauss-Legendre nodes in u
(the 1/r core is then smooth), 96 azimuths, out to 25 d. On a uniformly
lit sphere the integral is 1 (the area of a cap within chord r is pi r^2,
Archimedes), which the script prints as its own check.

Prints, for the visible sphere away from its outline (2 px), and its lit,
terminator and shadowed parts: reference / quadrature and Cycles /
quadrature, per channel, as sums over the pixels.
"""

import json
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "clients"))
import blender_head as bh  # noqa: E402  (its EXR reader and mask helpers)

def look(snippet):
    """Burley's d (mm) and the albedo from the Blender snippet's comment
    line `# ... d = (r, g, b) mm,` and the next, `# albedo (r, g, b).`"""
    text = open(snippet, encoding="utf-8").read()
    d = re.search(r"d = \(([^)]*)\) mm", text)
    a = re.search(r"albedo \(([^)]*)\)", text)
    if not d or not a:
        raise SystemExit(f"{snippet}: no `d = (...) mm` and `albedo (...)` comment to read the look from")
    return (np.array([float(v) for v in d.group(1).split(",")]),
            np.array([float(v) for v in a.group(1).split(",")]))


def profile(r, d):
    return (np.exp(-r / d) + np.exp(-r / (3 * d))) / (8 * math.pi * d * r)


def visible_points(cam, rho):
    """The sphere's point seen through each pixel's centre (mm), and the mask."""
    w, h = cam["width"], cam["height"]
    eye = np.array(cam["eye_m"]) * 1000
    target = np.array(cam["target_m"]) * 1000
    f = target - eye
    f /= np.linalg.norm(f)
    right = np.cross(f, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, f)
    t = math.tan(math.radians(cam["fov_y_deg"]) / 2)
    j, i = np.mgrid[0:h, 0:w]
    dx = (2 * (i + 0.5) / w - 1) * t * w / h
    dy = (1 - 2 * (j + 0.5) / h) * t
    d = f[None, None] + dx[..., None] * right + dy[..., None] * up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    b = d @ eye
    disc = b * b - (eye @ eye - rho * rho)
    hit = disc > 0
    s = -b - np.sqrt(np.maximum(disc, 0))
    return eye + s[..., None] * d, hit


def main():
    out, rho = sys.argv[1], float(sys.argv[2])
    D_MM, ALBEDO = look(os.path.join(out, "snippet.py"))
    cam = json.load(open(os.path.join(out, "none.json")))["camera"]
    toward = np.array(cam["toward_light"])
    x, hit = visible_points(cam, rho)
    n = x[hit] / rho
    g, gw = np.polynomial.legendre.leggauss(300)
    u, uw = 0.5 * (g + 1), 0.5 * gw
    nb = 96
    beta = (np.arange(nb) + 0.5) * 2 * math.pi / nb
    exact = np.zeros((len(n), 3))
    for k in range(3):
        a_max = min(math.pi, 2 * math.asin(min(1.0, 25 * D_MM[k] / (2 * rho))))
        alpha = a_max * u**2
        w_alpha = profile(2 * rho * np.sin(alpha / 2), D_MM[k]) * rho**2 * np.sin(alpha) * a_max * 2 * u * uw
        if k == 0:
            print(f"uniform light (Archimedes: 1, less what lies beyond the sphere): {w_alpha.sum() * 2 * math.pi:.5f}")
        for p in range(len(n)):
            xp = n[p]
            t = np.cross(xp, [0, 1, 0] if abs(xp[1]) < 0.9 else [1, 0, 0])
            t /= np.linalg.norm(t)
            b = np.cross(xp, t)
            dirs = np.cos(beta)[:, None] * t + np.sin(beta)[:, None] * b
            ny = np.cos(alpha)[:, None, None] * xp + np.sin(alpha)[:, None, None] * dirs[None]
            e = cam["light_irradiance"][k] / math.pi * np.maximum(ny @ toward, 0)
            exact[p, k] = (w_alpha[:, None] * e).sum() * 2 * math.pi / nb
    img = np.zeros(hit.shape + (3,))
    img[hit] = exact * ALBEDO

    ours = bh.read_layers(os.path.join(out, "none.exr"))
    reference = bh.read_layers(os.path.join(out, "reference.exr"))["RGBA"][..., :3]
    no_sss = bh.read_layers(os.path.join(out, "cycles_no_sss.exr"))["Combined"][..., :3]
    burley = sum(
        bh.read_layers(os.path.join(out, f"cycles_burley_seed{s}.exr"))["Combined"][..., :3] for s in (1, 2)
    ) / 2
    skin = hit & (ours["scattered"][..., 3] > 0.5)
    inner = skin & ~bh.dilate(~skin, 2)
    lum = no_sss.mean(-1)
    parts = {
        "visible": inner,
        "lit": inner & (lum > 0.3 * lum.max()),
        "terminator": inner & (lum > 0) & (lum <= 0.3 * lum.max()),
        "shadow": inner & (lum == 0),
    }
    print(f"sphere {rho} mm, d = {D_MM} mm")
    for name, m in parts.items():
        r = reference[m].sum(0) / img[m].sum(0)
        c = burley[m].sum(0) / img[m].sum(0)
        print(f"{name:10s} {m.sum():5d} px  reference/quadrature {np.round(r, 4)}  Cycles C-B/quadrature {np.round(c, 4)}")


if __name__ == "__main__":
    main()
