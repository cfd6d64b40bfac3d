"""Renders a whole head in Blender's Cycles with a scatterlab Blender export
and compares its scattering effect with scatterlab's ground truth's, by
region.

Usage: python blender_head.py SNIPPET.py STATS.json MESH.obj OURS_NONE.exr
           OURS_REFERENCE.exr OUT_DIR [--samples S] [--seeds 1,2]
           [--random-walk] [--box 5]

SNIPPET.py is `scatterlab export --format blender`; STATS.json, MESH.obj
and the two EXRs come from `scatterlab render --method none|reference
--stats STATS.json --scene-obj MESH.obj --out X.exr` of the same view.
Prints one JSON line of figures and writes OUT_DIR/cycles_*.exr (Blender's
renders, read back with the OpenEXR bindings) and OUT_DIR/regions.png and
OUT_DIR/effects.png (the region map; the two scattering effects side by
side) for a person to look at.

The scene is rebuilt from the files alone: the OBJ's triangles in metres
(scatterlab's y-up frame turned to Blender's z-up one, (x, y, z) ->
(x, -z, y)) with its per-vertex normals as custom normals, the skin group
with the snippet's material, eyes and teeth a plain diffuse; a pinhole
camera at the recorded eye looking at the recorded target with the
recorded vertical field of view; a sun (angle 0) towards the recorded
light direction with strength = the recorded irradiance (W/m^2); a black
world. Specular is off (Specular IOR Level 0), so each pixel is the
diffuse radiance alone, as scatterlab's with --ior 1. Paths are direct
light only (max_bounces 0; the subsurface step is not a bounce).

Renders, all with a pixel filter of 0.01 px (every sample through the
pixel's centre, as a rasteriser samples):
- no_sss: Subsurface Weight 0 (a Lambertian Base Color);
- passes: the skin's ambient occlusion (5 mm) and N.L drawn as colours
  (`render_passes`), which define the regions;
- burley_seedN: the snippet's Christensen-Burley, one per seed;
- random_walk_seedN (--random-walk): the same material with Subsurface
  Method Random Walk.

The effects compared are Cycles' burley - no_sss and scatterlab's
reference - none, each box-filtered (--box pixels, over skin pixels only).
Regions, in this order of precedence, from Cycles' passes: `rim` (skin
within 2 px of anything else), `crease` (AO within 5 mm under 0.75: closed
lids and lips, the ear's hollows, the nostrils), `shadow` (no_sss under 2 %
of the lit level: attached and cast shadow), `terminator` (lit, N.L under
0.3) and `lit`. Each figure is a share of the lit level: Base Color x
E / pi (averaged over the channels), the radiance of skin facing the sun. The seeds' noise is the RMS of the
difference of two seeds' effects over 2: the noise of their mean.
"""

import argparse
import json
import math
import os
import sys

import numpy as np
import OpenEXR

from cycles_setup import unbiased_cpu_cycles

REGIONS = ["rim", "crease", "shadow", "terminator", "lit"]


def to_blender(p):
    """scatterlab's y-up frame to Blender's z-up one."""
    return (p[0], -p[2], p[1])


def read_obj(path):
    verts, normals, groups = [], [], {}
    current = "skin"
    with open(path, encoding="utf-8") as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append(to_blender([float(x) for x in w[1:4]]))
            elif w[0] == "vn":
                normals.append(to_blender([float(x) for x in w[1:4]]))
            elif w[0] == "g":
                current = w[1]
            elif w[0] == "f":
                if len(w) != 4:
                    raise SystemExit(f"{path}: a face of {len(w) - 1} corners; `scatterlab render "
                                     "--scene-obj` writes triangles")
                groups.setdefault(current, []).append(
                    [int(c.split("/")[0]) - 1 for c in w[1:4]])
    if len(normals) != len(verts):
        raise SystemExit(f"{path}: {len(verts)} vertices and {len(normals)} normals (vn); "
                         "`scatterlab render --scene-obj` writes one normal a vertex")
    return verts, normals, groups


def add_part(bpy, name, verts, normals, faces, index):
    used = sorted({i for f in faces for i in f})
    remap = {old: new for new, old in enumerate(used)}
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([verts[i] for i in used], [], [[remap[i] for i in f] for f in faces])
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = True
    # scatterlab's own smooth normals, so both renderers shade the same
    # surface (Blender's would weight the faces differently).
    mesh.normals_split_custom_set_from_vertices([normals[i] for i in used])
    obj = bpy.data.objects.new(name, mesh)
    obj.pass_index = index
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build_scene(bpy, args, camera):
    from mathutils import Vector

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    verts, normals, groups = read_obj(args.mesh)
    if "skin" not in groups:
        raise SystemExit(f"{args.mesh}: no group 'skin'")
    skin = add_part(bpy, "skin", verts, normals, groups["skin"], 1)
    for k, name in enumerate(n for n in groups if n != "skin"):
        part = add_part(bpy, name, verts, normals, groups[name], 2 + k)
        mat = bpy.data.materials.new(name)
        bsdf = mat.node_tree.nodes.get("Principled BSDF") if mat.node_tree else None
        if bsdf is not None:
            bsdf.inputs["Specular IOR Level"].default_value = 0.0
        part.data.materials.append(mat)
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    bpy.context.view_layer.objects.active = skin
    skin.select_set(True)

    if camera.get("unrecorded"):
        raise SystemExit(
            f"{args.stats}: camera.unrecorded: the frame also has {camera['unrecorded']}, which "
            "this script does not set up: render it with --ior 1 --transmission off "
            "--environment-intensity 0 and without --fill-light or --rim-light"
        )
    if [float(c) for c in camera["up"]] != [0.0, 1.0, 0.0]:
        raise SystemExit(f"{args.stats}: camera.up is {camera['up']}; this script knows y up only")
    if camera.get("point_light_m") is not None:
        raise SystemExit(f"{args.stats}: a point light; this script sets up a sun only")
    irr = camera["light_irradiance"]
    sun_data = bpy.data.lights.new("Sun", "SUN")
    sun_data.energy = max(irr)
    sun_data.color = tuple(c / max(max(irr), 1e-9) for c in irr)
    sun_data.angle = 0.0
    sun = bpy.data.objects.new("Sun", sun_data)
    toward = Vector(to_blender(camera["toward_light"])).normalized()
    # A sun shines along its local -Z.
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = toward.to_track_quat("Z", "Y")
    scene.collection.objects.link(sun)

    world = bpy.data.worlds.new("Black")
    world.color = (0, 0, 0)
    scene.world = world
    if world.node_tree is not None:
        for n in world.node_tree.nodes:
            if n.type == "BACKGROUND":
                n.inputs["Strength"].default_value = 0.0
    world.light_settings.distance = 0.005  # the AO pass's reach: 5 mm

    cam_data = bpy.data.cameras.new("Cam")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(camera["fov_y_deg"])
    distance = (Vector(camera["target_m"]) - Vector(camera["eye_m"])).length
    cam_data.clip_start = 0.01 * distance
    cam_data.clip_end = 100.0 * distance
    cam = bpy.data.objects.new("Cam", cam_data)
    eye = Vector(to_blender(camera["eye_m"]))
    target = Vector(to_blender(camera["target_m"]))
    cam.location = eye
    cam.rotation_mode = "QUATERNION"
    # The camera looks along its local -Z with +Y up; scatterlab's up is y,
    # Blender's z.
    cam.rotation_quaternion = (target - eye).to_track_quat("-Z", "Y")
    scene.collection.objects.link(cam)
    scene.camera = cam

    r, c = unbiased_cpu_cycles(scene, camera["width"], camera["height"], args.samples)
    r.film_transparent = True
    # Direct light only. Cycles' subsurface step is not a bounce: with
    # max_bounces 0 the disk or walk still runs and its exit point is lit
    # directly (measured here: 16 spp on the scan, the skin's mean radiance
    # 0.1595 with subsurface and 0.1580 without at 0 bounces, each +0.0063
    # with one diffuse bounce), and nothing is lit indirectly, as in
    # scatterlab.
    c.max_bounces = 0
    c.diffuse_bounces = 0
    c.glossy_bounces = 0
    c.transmission_bounces = 0
    c.volume_bounces = 0
    c.transparent_max_bounces = 0
    if bpy.app.version >= (5, 0, 0):
        r.image_settings.media_type = "MULTI_LAYER_IMAGE"  # 5.0's way to ask for it
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "32"
    return skin


def principled(skin):
    return next(n for n in skin.active_material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")


def render(bpy, path, seed):
    scene = bpy.context.scene
    scene.cycles.seed = seed
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def render_passes(bpy, path, toward, samples=32):
    """The regions' inputs as one render of emission: on skin R = ambient
    occlusion within 5 mm (Cycles' AO node), G = (N.L + 1) / 2 with the
    shading normal, B = 1; elsewhere black. (The render passes of
    bpy 5.0.1's view layer did not reach its multilayer EXR here, so the
    passes are drawn as colours.)"""
    scene = bpy.context.scene
    kept = {}
    for obj in scene.objects:
        if obj.type != "MESH":
            continue
        kept[obj.name] = list(obj.data.materials)
        mat = bpy.data.materials.new(f"pass_{obj.name}")
        nt = mat.node_tree
        for n in list(nt.nodes):
            nt.nodes.remove(n)
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        emit = nt.nodes.new("ShaderNodeEmission")
        emit.inputs["Strength"].default_value = 1.0
        nt.links.new(emit.outputs["Emission"], out.inputs["Surface"])
        if obj.pass_index == 1:
            ao = nt.nodes.new("ShaderNodeAmbientOcclusion")
            ao.samples = 16
            ao.inputs["Distance"].default_value = 0.005
            geo = nt.nodes.new("ShaderNodeNewGeometry")
            dot = nt.nodes.new("ShaderNodeVectorMath")
            dot.operation = "DOT_PRODUCT"
            dot.inputs[1].default_value = toward
            nt.links.new(geo.outputs["Normal"], dot.inputs[0])
            half = nt.nodes.new("ShaderNodeMath")
            half.operation = "MULTIPLY_ADD"
            half.inputs[1].default_value = 0.5
            half.inputs[2].default_value = 0.5
            nt.links.new(dot.outputs["Value"], half.inputs[0])
            rgb = nt.nodes.new("ShaderNodeCombineColor")
            nt.links.new(ao.outputs["AO"], rgb.inputs["Red"])
            nt.links.new(half.outputs["Value"], rgb.inputs["Green"])
            rgb.inputs["Blue"].default_value = 1.0
            nt.links.new(rgb.outputs["Color"], emit.inputs["Color"])
        else:
            emit.inputs["Color"].default_value = (0, 0, 0, 1)
        obj.data.materials.clear()
        obj.data.materials.append(mat)
    keep_samples = scene.cycles.samples
    scene.cycles.samples = samples
    render(bpy, path, 1)
    scene.cycles.samples = keep_samples
    for obj in scene.objects:
        if obj.name in kept:
            obj.data.materials.clear()
            for m in kept[obj.name]:
                obj.data.materials.append(m)


def read_layers(path, need=(), size=None):
    """{layer name: (h, w, k) array}: scatterlab's (RGBA, scattered, ...)
    or Blender's multilayer (ViewLayer.Combined as Combined); refuses a
    file without the layers in `need`, or of another (width, height)."""
    with OpenEXR.File(path) as f:
        layers = {
            name.split(".")[-1]: np.asarray(ch.pixels, dtype=np.float64)
            for name, ch in f.channels().items()
        }
    missing = [n for n in need if n not in layers]
    if missing:
        raise SystemExit(f"{path}: no layer {missing} (it has {sorted(layers)})")
    for name, px in layers.items():
        if size is not None and (px.shape[1], px.shape[0]) != tuple(size):
            raise SystemExit(f"{path}: layer {name} is {px.shape[1]}x{px.shape[0]}, the stats' "
                             f"camera is {size[0]}x{size[1]}")
    return layers


def box(img, mask, n):
    """Mean over an n x n box of the masked pixels (per channel)."""
    if n <= 1:
        return img * mask[..., None]
    k = n // 2
    m = mask.astype(np.float64)
    pad = lambda a: np.pad(a, [(k, k), (k, k)] + [(0, 0)] * (a.ndim - 2))
    ip, mp = pad(img * m[..., None]), pad(m)
    acc = np.zeros_like(img)
    cnt = np.zeros_like(m)
    h, w = m.shape
    for dy in range(n):
        for dx in range(n):
            acc += ip[dy:dy + h, dx:dx + w]
            cnt += mp[dy:dy + h, dx:dx + w]
    return np.where(mask[..., None], acc / np.maximum(cnt, 1.0)[..., None], 0.0)


def dilate(mask, n):
    out = mask.copy()
    h, w = mask.shape
    p = np.pad(mask, n)
    for dy in range(-n, n + 1):
        for dx in range(-n, n + 1):
            out |= p[n + dy:n + dy + h, n + dx:n + dx + w]
    return out


def regions(skin, nl, ao, no_sss, lit_level):
    """An int map: -1 off skin, else an index into REGIONS."""
    rim = skin & dilate(~skin, 2)
    crease = skin & (ao < 0.75)
    shadow = skin & (no_sss.mean(axis=-1) < 0.02 * lit_level)
    terminator = skin & (nl < 0.3)
    out = np.full(skin.shape, -1, dtype=np.int32)
    out[skin] = 4
    for k, m in reversed(list(enumerate([rim, crease, shadow, terminator]))):
        out[m] = k
    return out


def save_png(path, rgb):
    import bpy  # Blender writes the PNG: no imaging module in its Python

    h, w, _ = rgb.shape
    img = bpy.data.images.new(os.path.basename(path), w, h, alpha=True, float_buffer=True)
    rgba = np.concatenate([np.clip(rgb, 0, 1), np.ones((h, w, 1))], axis=-1)
    img.pixels.foreach_set(rgba[::-1].astype(np.float32).ravel())
    img.filepath_raw = path
    img.file_format = "PNG"
    img.save()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("snippet")
    ap.add_argument("stats")
    ap.add_argument("mesh")
    ap.add_argument("ours_none")
    ap.add_argument("ours_reference")
    ap.add_argument("out_dir")
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--random-walk", action="store_true")
    ap.add_argument("--box", type=int, default=5)
    ap.add_argument(
        "--random-walk-reflectance",
        default="1,1,1",
        help="R,G,B: Random Walk's radiance over the no-subsurface render on a flat, "
        "uniformly lit plane (this script's `random_walk_over_no_sss` there); the "
        "Random Walk renders are divided by it for the *_flat figures",
    )
    args = ap.parse_args()
    import bpy

    if args.box < 1 or args.box % 2 == 0:
        raise SystemExit(f"--box {args.box}: an odd number of pixels (the box is centred)")
    stats = json.load(open(args.stats, encoding="utf-8"))
    if "camera" not in stats:
        raise SystemExit(f"{args.stats}: no `camera`: write it with this version's "
                         "`scatterlab render --stats`")
    camera = stats["camera"]
    skin_obj = build_scene(bpy, args, camera)
    code = open(args.snippet, encoding="utf-8").read()
    exec(compile(code, args.snippet, "exec"), {"__name__": "__main__"})
    bsdf = principled(skin_obj)
    bsdf.inputs["Specular IOR Level"].default_value = 0.0
    base = np.asarray(bsdf.inputs["Base Color"].default_value[:3])
    os.makedirs(args.out_dir, exist_ok=True)
    out = lambda n: os.path.join(args.out_dir, n)
    seeds = [int(s) for s in args.seeds.split(",")]

    bsdf.inputs["Subsurface Weight"].default_value = 0.0
    render(bpy, out("cycles_no_sss.exr"), 1)
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    for s in seeds:
        render(bpy, out(f"cycles_burley_seed{s}.exr"), s)
    if args.random_walk:
        bsdf.subsurface_method = "RANDOM_WALK"
        for s in seeds:
            render(bpy, out(f"cycles_random_walk_seed{s}.exr"), s)
    toward = to_blender(camera["toward_light"])
    render_passes(bpy, out("cycles_passes.exr"), toward)

    no = read_layers(out("cycles_no_sss.exr"))
    no_sss = no["Combined"][..., :3]
    passes = read_layers(out("cycles_passes.exr"))["Combined"]
    size = (camera["width"], camera["height"])
    ours_none_l = read_layers(args.ours_none, ("RGBA", "scattered"), size)
    ours_ref_l = read_layers(args.ours_reference, ("RGBA",), size)
    ours_none, ours_ref = ours_none_l["RGBA"][..., :3], ours_ref_l["RGBA"][..., :3]
    ours_skin = ours_none_l["scattered"][..., 3] > 0.5
    cycles_skin = (passes[..., 2] > 0.5) & (passes[..., 3] > 0.999)
    skin = cycles_skin & ours_skin
    union = cycles_skin | ours_skin
    ao = passes[..., 0]
    nl = 2.0 * passes[..., 1] - 1.0
    irr = np.asarray(camera["light_irradiance"])
    lit_level = float((base * irr / math.pi).mean())
    reg = regions(skin, nl, ao, no_sss, lit_level)

    # Every figure is a share of the lit level: A E / pi, the radiance of
    # skin facing the sun, averaged over the channels (a scale that does not
    # vanish on a back-lit view, as the skin's mean does).
    scale = lit_level
    f = lambda img: box(img, skin, args.box)
    burley = [read_layers(out(f"cycles_burley_seed{s}.exr"))["Combined"][..., :3] for s in seeds]
    eff_c = [f(b - no_sss) for b in burley]
    eff_cycles = sum(eff_c) / len(eff_c)
    burley_mean = sum(burley) / len(burley)
    eff_ours = f(ours_ref - ours_none)
    eff_rw = None
    if args.random_walk:
        rw = [
            read_layers(out(f"cycles_random_walk_seed{s}.exr"))["Combined"][..., :3] for s in seeds
        ]
        eff_r = [f(x - no_sss) for x in rw]
        eff_rw = sum(eff_r) / len(eff_r)
        # Random Walk's diffuse reflectance is not Base Color (with the
        # snippet's IOR, internal reflection at the boundary: on a plane
        # 0.98, 0.85, 0.83 of it): divided by what it gives on a plane, what
        # is left is the spread and the curvature, not the albedo.
        flat = np.asarray([float(v) for v in args.random_walk_reflectance.split(",")])
        rw_mean = sum(rw) / len(rw)
        eff_rw_flat = f(rw_mean / flat - no_sss)
        interior_skin = skin & ~dilate(~skin, 2)
        random_walk_over_no_sss = (
            (rw_mean[interior_skin].sum(axis=0) / no_sss[interior_skin].sum(axis=0)).tolist()
            if interior_skin.any()
            else None
        )

    def rms(a, m):
        return float(np.sqrt(np.mean(a[m] ** 2))) / scale if m.any() else 0.0

    def mean(a, m):
        return float(a[m].mean()) / scale if m.any() else 0.0

    # The unscattered frames first: they must agree for the rest to mean
    # anything (camera, mesh, light, shadow).
    interior = skin & (reg != 0)
    result = {
        "pixels": {"skin": int(skin.sum()), "mask_iou": float(skin.sum() / max(union.sum(), 1))},
        "scale": scale,
        "unscattered": {
            "rms_none_vs_no_sss": rms(ours_none - no_sss, interior),
            "mean_none": mean(ours_none, interior),
            "mean_no_sss": mean(no_sss, interior),
        },
        "regions": {},
    }
    two = len(eff_c) >= 2
    for k, name in enumerate(["skin"] + REGIONS):
        m = skin if name == "skin" else (reg == k - 1)
        row = {
            "pixels": int(m.sum()),
            "effect_cycles": mean(eff_cycles, m),
            "effect_reference": mean(eff_ours, m),
            "rms_cycles": rms(eff_cycles, m),
            "rms_reference_minus_cycles": rms(eff_ours - eff_cycles, m),
            "noise": rms(eff_c[0] - eff_c[1], m) / 2.0 if two else None,
            # The effects' difference is these two's: where the unscattered
            # frames differ (shadow-map edges), the effects differ by it.
            "none_minus_no_sss": mean(ours_none - no_sss, m),
            "reference_minus_burley": mean(ours_ref - burley_mean, m),
        }
        if eff_rw is not None:
            row["effect_random_walk"] = mean(eff_rw, m)
            row["rms_random_walk_minus_burley"] = rms(eff_rw - eff_cycles, m)
            row["rms_random_walk"] = rms(eff_rw, m)
            row["effect_random_walk_flat"] = mean(eff_rw_flat, m)
            row["rms_random_walk_flat_minus_burley"] = rms(eff_rw_flat - eff_cycles, m)
        result["regions"][name] = row

    if eff_rw is not None:
        result["random_walk_over_no_sss"] = random_walk_over_no_sss
    # For eyes: the regions, and the two effects side by side (x8).
    palette = np.array([[1, 0.2, 0.2], [1, 0.8, 0], [0.2, 0.3, 1], [0.6, 0.2, 1], [0.2, 0.8, 0.3]])
    rmap = np.zeros(reg.shape + (3,))
    for k in range(len(REGIONS)):
        rmap[reg == k] = palette[k]
    save_png(out("regions.png"), rmap)
    side = [eff_ours, eff_cycles] + ([eff_rw] if eff_rw is not None else [])
    save_png(out("effects.png"), np.concatenate([0.5 + 8.0 * e for e in side], axis=1))
    print(json.dumps(result))


if __name__ == "__main__":
    sys.exit(main())
