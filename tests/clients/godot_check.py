"""Checks scatterlab's Godot 4 export (.tres StandardMaterial3D) with a
text-resource parser that is not ours (PyPI godot-parser) and with Godot's
own kernel numbers, typed here from Godot's source.

Usage: python godot_check.py EXPECT.json
EXPECT: {"tres": path, "profile_exr": path, "albedo": [A, A, A] (optional),
         "total": [t, t, t] or null (the look's total reflectance; null:
         integrate the EXR's r*R(r), which holds 0.997 of a Dirac-free look)}

Godot 4 is in no package registry this project can install from, so the
renderer itself cannot run; what it would do is rebuilt from its source:

- Property names and ranges: scene/resources/material.cpp (Godot 4.2.2)
  lines 2820-2831; `subsurf_scatter_strength` 0-1,
  `subsurf_scatter_transmittance_depth` 0.001-8, `_boost` 0-1.
- The blur kernel: servers/rendering/renderer_rd/shaders/effects/
  subsurface_scattering.glsl, `skin_kernel` (25 taps) copied below. It is
  the Jimenez demo's `SeparableSSS::calculateKernel` (iryoku/separable-sss)
  with strength (0.48, 0.41, 0.28), falloff (1, 0.37, 0.3); the check
  rebuilds it here from the demo's profile() formula first, so the profile
  used below is the one Godot's table samples.
- Width: one kernel unit spans scale*strength/3 in UV with
  scale = mix(sss_scale, unit_size/depth, sss_depth_scale) and
  unit_size = P[0][0] (ss_effects.cpp, sub_surface_scattering), i.e.
  2*depth_scale*strength/3 scene units (metres) when the screen term is
  left out. The depth scale is read from the file's comment.
- A neighbour with strength < 0.001 stops the blur (`do_filter`).
- Colours with `source_color` are sRGB-decoded by Godot
  (material_storage.cpp, `_fill_std140_ubo_value`: c.srgb_to_linear()),
  with Color::srgb_to_linear's formula (core/math/color.h).

The checks: the file parses; every property is one BaseMaterial3D has and
within its range; the albedo decodes to the look's A; the stated error of
r*R(r) per channel is what Godot's profile at the written strength gives
against the profile EXR's r*R(r) (energy-normalised, relative L2), within
0.03; and no nearby width would do better (a 10 % step either way), unless
the width sits at Godot's 0.001 strength floor.
"""

import json
import math
import re
import sys

import numpy as np
import OpenEXR
import godot_parser

# material.cpp lines 2820-2831 (and the common ones this export writes:
# resource_name from Resource, albedo_color line 2751, roughness).
PROPERTIES = {
    "resource_name": None,
    "albedo_color": None,
    "roughness": (0.0, 1.0),
    "subsurf_scatter_enabled": None,
    "subsurf_scatter_strength": (0.0, 1.0),
    "subsurf_scatter_skin_mode": None,
    "subsurf_scatter_texture": None,
    "subsurf_scatter_transmittance_enabled": None,
    "subsurf_scatter_transmittance_color": None,
    "subsurf_scatter_transmittance_texture": None,
    "subsurf_scatter_transmittance_depth": (0.001, 8.0),
    "subsurf_scatter_transmittance_boost": (0.0, 1.0),
}

# subsurface_scattering.glsl, USE_25_SAMPLES `skin_kernel` (r, g, b, offset).
GODOT_SKIN_KERNEL_25 = [
    (0.530605, 0.613514, 0.739601, 0),
    (0.0211412, 0.0459286, 0.0378196, 0.0208333),
    (0.0402784, 0.0657244, 0.04631, 0.0833333),
    (0.0493588, 0.0367726, 0.0219485, 0.1875),
    (0.0410172, 0.0199899, 0.0118481, 0.333333),
    (0.0263642, 0.0119715, 0.00684598, 0.520833),
    (0.017924, 0.00711691, 0.00347194, 0.75),
    (0.0128496, 0.00356329, 0.00132016, 1.02083),
    (0.0094389, 0.00139119, 0.000416598, 1.33333),
    (0.00700976, 0.00049366, 0.000151938, 1.6875),
    (0.00500364, 0.00020094, 5.28848e-005, 2.08333),
    (0.00333804, 7.85443e-005, 1.2945e-005, 2.52083),
    (0.000973794, 1.11862e-005, 9.43437e-007, 3),
]

STRENGTH = (0.48, 0.41, 0.28)
FALLOFF = (1.0, 0.37, 0.3)
# SeparableSSS::profile: d'Eon's red Gaussians without the first (variance mm^2, weight).
DEMO_GAUSSIANS = [(0.0484, 0.100), (0.187, 0.118), (0.567, 0.113), (1.99, 0.358), (7.41, 0.078)]


def demo_profile(r, falloff):
    rr = r / (0.001 + falloff)
    return sum(w * math.exp(-rr * rr / (2 * v)) / (2 * 3.14 * v) for v, w in DEMO_GAUSSIANS)


def demo_kernel(n):
    """calculateKernel, positive half, centre first (the demo's code)."""
    rng = 3.0 if n > 20 else 2.0
    step = 2 * rng / (n - 1)
    o = [-rng + i * step for i in range(n)]
    off = [rng * math.copysign(1, x) * abs(x) ** 2 / rng**2 for x in o]
    out = []
    for c in range(3):
        k = []
        for i in range(n):
            w0 = abs(off[i] - off[i - 1]) if i > 0 else 0
            w1 = abs(off[i] - off[i + 1]) if i < n - 1 else 0
            k.append((w0 + w1) / 2 * demo_profile(off[i], FALLOFF[c]))
        s = sum(k)
        k = [x / s * STRENGTH[c] for x in k]
        k[n // 2] += 1 - STRENGTH[c]
        out.append(k[n // 2 :])
    return [(out[0][i], out[1][i], out[2][i], off[n // 2 + i]) for i in range(n // 2 + 1)]


def godot_rr(r, width_mm, skin):
    """r*R(r) (1/mm) of Godot's blur at this width: the radial profile
    whose separable kernel is the table above (Jimenez et al. 2015 sec. 4,
    the pre-integrated kernel). The table samples the demo's 2D Gaussian
    formula w*exp(-x^2/2v)/(2 pi v) along a line, so each term's share of
    the 1D kernel is w/sqrt(2 pi v), not w: 2D Gaussians with variance
    v*((0.001+falloff)*width)^2 and weights strength*(w/sqrt v)/sum(w/sqrt v)
    (falloff scales every v of a channel alike). The 1 - strength Dirac
    has r*R = 0."""
    sw = sum(w / math.sqrt(v) for v, w in DEMO_GAUSSIANS)
    out = []
    for c in range(3):
        f = FALLOFF[c if skin else 0]
        s = STRENGTH[c if skin else 0]
        acc = np.zeros_like(r)
        for v, w in DEMO_GAUSSIANS:
            var = v * ((0.001 + f) * width_mm) ** 2
            acc += s * w / math.sqrt(v) / sw * np.exp(-r * r / (2 * var)) / (2 * math.pi * var)
        out.append(r * acc)
    return out


def srgb_to_linear(x):
    return x / 12.92 if x < 0.04045 else ((x + 0.055) / 1.055) ** 2.4


def main():
    expect = json.load(open(sys.argv[1]))
    text = open(expect["tres"]).read()
    fails = []

    # Godot's loader skips ';' comments (variant_parser.cpp 212-223,
    # 1628-1639); godot-parser 0.1.7 does not, so whole-line comments are
    # taken out here and nothing else may carry one.
    comments = [l for l in text.splitlines() if l.startswith(";")]
    body = "\n".join(l for l in text.splitlines() if not l.startswith(";"))
    if ";" in body.replace('";"', ""):
        fails.append("a ';' outside a whole-line comment")
    res = godot_parser.parse(body)
    sections = list(res.get_sections())
    head = text.splitlines()[0]
    if not head.startswith('[gd_resource type="StandardMaterial3D" format=3'):
        fails.append(f"header {head!r}")
    props = dict(sections[-1].properties) if sections else {}
    if not sections or sections[-1].header.name != "resource":
        fails.append("no [resource] section")
    for k, v in props.items():
        if k not in PROPERTIES:
            fails.append(f"{k}: not a BaseMaterial3D property")
        elif PROPERTIES[k] and not (PROPERTIES[k][0] <= float(v) <= PROPERTIES[k][1]):
            fails.append(f"{k} = {v} outside {PROPERTIES[k]}")

    # Our kernel formula is Godot's table.
    for mine, godot in zip(demo_kernel(25), GODOT_SKIN_KERNEL_25):
        for c in range(4):
            if abs(mine[c] - godot[c]) > 2e-5 * max(abs(godot[c]), 1e-3):
                fails.append(f"kernel tap {godot}: rebuilt {mine}")
                break

    strength = float(props["subsurf_scatter_strength"])
    skin = bool(props["subsurf_scatter_skin_mode"])
    if strength < 0.001:
        fails.append(f"strength {strength} < 0.001: Godot's blur would stop at once")
    joined = " ".join(comments)
    m = re.search(r"Depth Scale to ([0-9.]+)", joined)
    depth_scale = float(m.group(1))
    width_mm = 2 * depth_scale * strength / 3 * 1000

    albedo = props["albedo_color"]
    a = [srgb_to_linear(float(albedo.r)), srgb_to_linear(float(albedo.g)), srgb_to_linear(float(albedo.b))]
    for c in range(3 if expect.get("albedo") else 0):
        if abs(a[c] - expect["albedo"][c]) > 1e-5:
            fails.append(f"albedo channel {c}: {a[c]} decoded vs {expect['albedo'][c]}")

    # The look's r*R(r) from the profile EXR.
    with OpenEXR.File(expect["profile_exr"]) as f:
        note = str(f.header().get("comments", ""))
        ch = f.channels()
        px = np.asarray(ch["RGB"].pixels, dtype=np.float64).reshape(-1, 3)
    r_max = float(re.search(r"\* ([0-9.eE+-]+) mm", note).group(1))
    n = px.shape[0]
    r = (np.arange(n) + 0.5) / n * r_max

    def errors(w):
        g = godot_rr(r, w, skin)
        out = []
        for c in range(3):
            t = px[:, c]
            total = expect["total"][c] if expect.get("total") else 2 * math.pi * t.sum() * r_max / n
            t = t / total
            out.append(math.sqrt(((g[c] - t) ** 2).sum() / (t**2).sum()))
        return out

    got = errors(width_mm)
    m = re.search(r"\(R ([0-9.]+), G ([0-9.]+), B ([0-9.]+)\)", joined)
    stated = [float(x) for x in m.groups()]
    for c in range(3):
        if abs(got[c] - stated[c]) > 0.03:
            fails.append(f"channel {c}: Godot's profile at {width_mm:.4f} mm/unit gives error {got[c]:.4f}, the file states {stated[c]:.4f}")
    at_floor = strength <= 0.001 * (1 + 1e-6)
    here = sum(e * e for e in got)
    for step in (1.1, 1 / 1.1):
        if at_floor and step < 1:
            continue
        there = sum(e * e for e in errors(width_mm * step))
        if there < here - 1e-3:
            fails.append(f"width x{step:.3f} fits better ({there:.4f} < {here:.4f})")

    if props.get("subsurf_scatter_transmittance_enabled"):
        tc = props["subsurf_scatter_transmittance_color"]
        if float(tc.a) != 1.0:
            fails.append(f"transmittance alpha {tc.a}: Godot scales it by the strength; 1 keeps what can be kept")
        if f"{strength:.4f}" not in joined and "no material field can undo" not in joined:
            fails.append("the comments do not say that Godot scales transmittance by the strength")
        for x in (tc.r, tc.g, tc.b):
            if not 0 <= float(x) <= 1:
                fails.append(f"transmittance colour {tc}")

    print(json.dumps({"fails": fails, "errors": got, "stated": stated, "width_mm": width_mm, "skin": skin}))


if __name__ == "__main__":
    main()
