"""Renders a scatterlab Blender export with Blender's own Cycles and recovers
Burley's scattering distance d per channel from a shadow edge.

Usage: python blender_edge.py SNIPPET.py OUT_DIR
           [--existing-material principled|diffuse] [--unit-scale M]
           [--width-mm W] [--pixels N] [--samples S] [--no-render]

Prints one JSON line: {"d_mm": [r, g, b], "amplitude": [...], "rms": [...],
"inputs": {...}} and writes OUT_DIR/edge.exr (the render, read back with the
OpenEXR bindings, not Blender) and OUT_DIR/edge_fit.csv (x, data, fit).

The scene: a large plane at z = 0 in metres, the snippet's material on it;
a sun straight down (angle 0, so the shadow edge is sharp) with a
shadow-only occluder over x > 0; an orthographic camera looking down. The
world is black and the Principled BSDF's specular is off (Specular IOR
Level 0), so each pixel's radiance is the Burley-scattered irradiance alone.

The fit is written independently of scatterlab. Cycles' Burley profile
(intern/cycles/kernel/closure/bssrdf.h, Blender 5.0, `bssrdf_burley_eval`,
lines 129-148) is R(r) = A (e^{-r/d} + e^{-r/3d}) / (8 pi d r), a mix
1/4 f_d + 3/4 f_3d of normalised 2D kernels f_l(r) = e^{-r/l}/(2 pi l r).
Integrating f_l over y gives the marginal K0(|x|/l)/(pi l) (Abramowitz &
Stegun 9.6.23 / Gradshteyn 3.754), so the share of a kernel centred at
distance x > 0 inside the lit half-plane is Ki1(x/l)/pi, with the Bickley
function Ki1(z) = int_z^inf K0 = pi/2 - int_0^z K0 (scipy.special.iti0k0).
Cycles truncates the profile at 16 d (BURLEY_TRUNCATE, bssrdf.h line 99);
the mass beyond it is 0.36 %, far below the 10 % tolerance, so it is
ignored. The radiance across the edge is then
    L(x) = L_lit * [ 1/4 S(x/d) + 3/4 S(x/3d) ],
    S(u) = 1 - Ki1(u)/pi for u <= 0 (lit), Ki1(u)/pi for u > 0 (shadow)
and each channel's (L_lit, d) is a least-squares fit of the pixel row
averages, with the model averaged over each pixel's width.
"""

import argparse
import json
import math
import os
import sys

import numpy as np
import OpenEXR
from scipy.optimize import least_squares
from scipy.special import iti0k0

from cycles_setup import unbiased_cpu_cycles


def ki1(z):
    """Bickley function Ki1(z) = int_z^inf K0(t) dt for z >= 0."""
    return math.pi / 2.0 - iti0k0(z)[1]


def lit_share(x_mm, d_mm):
    """Share of the Burley kernel centred at x inside the lit half x <= 0."""
    out = np.empty_like(x_mm)
    for i, x in enumerate(x_mm):
        s = 0.0
        for w, l in ((0.25, d_mm), (0.75, 3.0 * d_mm)):
            t = ki1(abs(x) / l) / math.pi
            s += w * (t if x > 0 else 1.0 - t)
        out[i] = s
    return out


def model(params, x_mm, pixel_mm):
    amp, d = params
    # Average over the pixel's width (5-point Gauss-Legendre).
    nodes, weights = np.polynomial.legendre.leggauss(5)
    acc = np.zeros_like(x_mm)
    for n, w in zip(nodes, weights):
        acc += 0.5 * w * lit_share(x_mm + 0.5 * n * pixel_mm, d)
    return amp * acc


def build_scene(args):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    # Scene units of --unit-scale metres (0.01: a scene in centimetres).
    u = 1.0 / args.unit_scale
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = args.unit_scale
    # The plane: 0.4 m wide, so every Burley probe (16 d) lands on it.
    half = 0.2 * u
    mesh = bpy.data.meshes.new("plane")
    mesh.from_pydata(
        [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)],
        [],
        [(0, 1, 2, 3)],
    )
    plane = bpy.data.objects.new("Plane", mesh)
    scene.collection.objects.link(plane)
    if args.existing_material:
        # An artist's object with a material already on it: a Principled
        # BSDF whose values the snippet must replace, or a Diffuse BSDF
        # only, for which it must add and connect a Principled BSDF.
        mat = bpy.data.materials.new("ArtistSkin")
        if bpy.app.version < (5, 0, 0):
            # Before 5.0 a new material has no node tree until use_nodes
            # is on; an artist's material in 4.x has it on.
            mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        for n in list(nodes):
            if n.type != "OUTPUT_MATERIAL":
                nodes.remove(n)
        out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL"), None)
        if out is None:
            out = nodes.new("ShaderNodeOutputMaterial")
        if args.existing_material == "principled":
            bsdf = nodes.new("ShaderNodeBsdfPrincipled")
            bsdf.subsurface_method = "RANDOM_WALK"
            bsdf.inputs["Base Color"].default_value = (0.2, 0.9, 0.1, 1.0)
            bsdf.inputs["Subsurface Weight"].default_value = 0.3
            bsdf.inputs["Subsurface Radius"].default_value = (5.0, 5.0, 5.0)
            bsdf.inputs["Subsurface Scale"].default_value = 0.3
        else:
            bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
        mesh.materials.append(mat)
    bpy.context.view_layer.objects.active = plane
    plane.select_set(True)

    # The occluder: casts shadows only, over x > 0, 5 mm above the plane.
    occ_mesh = bpy.data.meshes.new("occluder")
    occ_mesh.from_pydata(
        [(0, -u, 0.005 * u), (u, -u, 0.005 * u), (u, u, 0.005 * u), (0, u, 0.005 * u)],
        [],
        [(0, 1, 2, 3)],
    )
    occ = bpy.data.objects.new("Occluder", occ_mesh)
    scene.collection.objects.link(occ)
    for attr in ("visible_camera", "visible_diffuse", "visible_glossy",
                 "visible_transmission", "visible_volume_scatter"):
        setattr(occ, attr, False)

    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = 3.0
    sun_data.angle = 0.0
    sun = bpy.data.objects.new("Sun", sun_data)
    scene.collection.objects.link(sun)  # default rotation: pointing down -Z

    world = bpy.data.worlds.new("Black")
    world.color = (0, 0, 0)
    scene.world = world
    if world.node_tree is not None:
        for n in world.node_tree.nodes:
            if n.type == "BACKGROUND":
                n.inputs["Strength"].default_value = 0.0

    cam_data = bpy.data.cameras.new("Cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = args.width_mm / 1000.0 * u
    cam_data.clip_start = 0.001 * u
    cam_data.clip_end = 10.0 * u
    cam = bpy.data.objects.new("Cam", cam_data)
    cam.location = (0, 0, 1.0 * u)
    scene.collection.objects.link(cam)
    scene.camera = cam

    r, c = unbiased_cpu_cycles(scene, args.pixels, args.rows, args.samples)
    c.max_bounces = 1
    c.diffuse_bounces = 1
    c.glossy_bounces = 0
    c.transmission_bounces = 0
    c.transparent_max_bounces = 0
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    return plane


def principled_values(plane):
    mat = plane.active_material
    bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    inp = bsdf.inputs
    return {
        "material": mat.name,
        "subsurface_method": bsdf.subsurface_method,
        "base_color": list(inp["Base Color"].default_value)[:3],
        "subsurface_weight": inp["Subsurface Weight"].default_value,
        "subsurface_radius": list(inp["Subsurface Radius"].default_value),
        "subsurface_scale": inp["Subsurface Scale"].default_value,
        "ior": inp["IOR"].default_value,
        "linked_to_output": any(
            l.from_node == bsdf and l.to_node.type == "OUTPUT_MATERIAL"
            for l in mat.node_tree.links
        ),
        "materials_on_object": len(plane.data.materials),
    }


def read_exr_rgb(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        if "RGB" in ch:
            px = np.asarray(ch["RGB"].pixels, dtype=np.float64)
        elif "RGBA" in ch:
            px = np.asarray(ch["RGBA"].pixels, dtype=np.float64)[..., :3]
        else:
            px = np.stack([np.asarray(ch[k].pixels, dtype=np.float64) for k in "RGB"], axis=-1)
    return px


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("snippet")
    ap.add_argument("out_dir")
    ap.add_argument("--existing-material", choices=["principled", "diffuse"])
    ap.add_argument("--unit-scale", type=float, default=1.0)
    ap.add_argument("--width-mm", type=float, default=8.0)
    ap.add_argument("--pixels", type=int, default=160)
    ap.add_argument("--rows", type=int, default=16)
    ap.add_argument("--samples", type=int, default=512)
    ap.add_argument("--no-render", action="store_true")
    args = ap.parse_args()

    import bpy

    plane = build_scene(args)
    code = open(args.snippet, encoding="utf-8").read()
    exec(compile(code, args.snippet, "exec"), {"__name__": "__main__"})
    values = principled_values(plane)
    result = {"inputs": values}
    if args.no_render:
        print(json.dumps(result))
        return
    # Specular off, so the pixel is the scattered diffuse alone (the
    # snippet's IOR is kept and reported above; the Specular IOR Level
    # socket scales F0 to 0, Cycles svm/closure.h lines 411-456).
    bsdf = next(n for n in plane.active_material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    bsdf.inputs["Specular IOR Level"].default_value = 0.0

    os.makedirs(args.out_dir, exist_ok=True)
    exr = os.path.join(args.out_dir, "edge.exr")
    bpy.context.scene.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    img = read_exr_rgb(exr)  # (rows, pixels, 3), top row first
    profile = img.mean(axis=0)
    pixel_mm = args.width_mm / args.pixels
    x_mm = (np.arange(args.pixels) + 0.5) * pixel_mm - 0.5 * args.width_mm

    fit_d, amps, rms = [], [], []
    columns = [x_mm]
    for c in range(3):
        y = profile[:, c]
        lit = float(np.median(y[: args.pixels // 8]))
        f = least_squares(
            lambda p: model(p, x_mm, pixel_mm) - y,
            x0=[lit, 0.3],
            bounds=([0.0, 1e-3], [np.inf, 100.0]),
            x_scale=[max(lit, 1e-6), 0.3],
        )
        fit_d.append(float(f.x[1]))
        amps.append(float(f.x[0]))
        rms.append(float(np.sqrt(np.mean(f.fun**2)) / max(f.x[0], 1e-12)))
        columns += [y, model(f.x, x_mm, pixel_mm)]
    np.savetxt(
        os.path.join(args.out_dir, "edge_fit.csv"),
        np.stack(columns, axis=1),
        delimiter=",",
        header="x_mm,r,r_fit,g,g_fit,b,b_fit",
        comments="",
    )
    result.update({"d_mm": fit_d, "amplitude": amps, "rms": rms, "pixel_mm": pixel_mm})
    print(json.dumps(result))


if __name__ == "__main__":
    sys.exit(main())
