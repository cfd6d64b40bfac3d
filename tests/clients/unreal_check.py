"""Runs a scatterlab Unreal .py against the stub `unreal` module (unreal_stub/)
and converts what it set back to Burley's d with Unreal's own formulas,
typed here from UE 5.1.1's source:
- SubsurfaceProfile.cpp line 473: DMFP_mm = GetDiffuseMeanFreePathFromMeanFreePath(
  SurfaceAlbedo, MeanFreePathColor * MeanFreePathDistance) * 10 / 0.6;
- BurleyNormalizedSSS.cpp lines 70-74, 101-104, 119-122:
  S_perp(A) = 1.85 - A + 7|A - 0.8|^3, S_dmfp(A) = 3.5 + 100 (A - 0.33)^4,
  DMFP = MFP * S_dmfp / S_perp;
- the shader's Burley shape is S_dmfp(A)/DMFP, so d = DMFP / S_dmfp, in
  profile mm, and a world centimetre is 10 * WorldUnitScale / 0.1 profile mm
  (BurleyNormalizedSSS.cpp), so the physical d is d * 0.1 / WorldUnitScale.

The Substrate material the script builds is read back too: one Slab on the
Front Material, type MSS_DIFFUSION, its Diffuse Albedo, and either the
created SubsurfaceProfile on the Slab and on the material or, with
--substrate-diffusion, SSS MFP (cm) and SSS MFP Scale, turned back into d
by the SubsurfaceProfile formulas above (d_from_ue at WorldUnitScale 0.1:
d = MFP * 10 / (0.6 S_perp(A)) mm), the conversion Substrate's per-pixel
path is assumed to share (UE 5.8's Substrate.ush passes SSS MFP x SSS MFP
Scale on unscaled; its GetBurleyParameters could not be read).

Usage: python unreal_check.py SCRIPT.py STRUCT.txt
Prints JSON {"d_mm": [...], "albedo": [...], "lobe_mix": ..., "substrate": {...}}.
"""

import json
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "unreal_stub"))
import unreal  # noqa: E402  (the stub)


def s_perp(a):
    return 1.85 - a + 7 * abs(a - 0.8) ** 3


def s_dmfp(a):
    return 3.5 + 100 * (a - 0.33) ** 4


def d_from_ue(albedo, color, dist_cm, wus):
    d = []
    for c in range(3):
        mfp_cm = color[c] * dist_cm
        dmfp_mm = mfp_cm * s_dmfp(albedo[c]) / s_perp(albedo[c]) * 10 / 0.6
        d.append(dmfp_mm / s_dmfp(albedo[c]) * 0.1 / wus)
    return d


def rgb(c):
    return [c.r, c.g, c.b]


def main():
    script, struct = sys.argv[1], sys.argv[2]
    code = open(script, encoding="utf-8").read()
    exec(compile(code, script, "exec"), {"__name__": "__main__"})
    profiles = [a for a in unreal.CREATED if isinstance(a, unreal.SubsurfaceProfile)]
    if len(profiles) != 1 or profiles[0] not in unreal.EditorAssetLibrary.saved:
        print("FAIL: the script did not create and save one SubsurfaceProfile")
        sys.exit(1)
    v = profiles[0].settings.values
    substrate = read_substrate(profiles[0])
    for flag in ("enable_burley", "enable_mean_free_path"):
        if v.get(flag) is not True:
            print("FAIL: %s is not set" % flag)
            sys.exit(1)
    albedo = rgb(v["surface_albedo"])
    color = rgb(v["mean_free_path_color"])
    d = d_from_ue(albedo, color, v["mean_free_path_distance"], v["world_unit_scale"])
    # The copy-paste struct must say the same as the script.
    text = open(struct, encoding="utf-8").read()
    def scalar(key):
        return float(re.search(r"[(,]%s=([-0-9.eE+]+)" % key, text).group(1))
    def color3(key):
        m = re.search(r"%s=\(R=([^,]+),G=([^,]+),B=([^,]+)," % key, text)
        return [float(x) for x in m.groups()]
    pairs = [
        (scalar("MeanFreePathDistance"), v["mean_free_path_distance"]),
        (scalar("WorldUnitScale"), v["world_unit_scale"]),
        (scalar("LobeMix"), v["lobe_mix"]),
        (scalar("Roughness0"), v["roughness0"]),
        (scalar("Roughness1"), v["roughness1"]),
        (scalar("IOR"), v["ior"]),
    ] + list(zip(color3("MeanFreePathColor"), color)) + list(zip(color3("SurfaceAlbedo"), albedo))
    for a, b in pairs:
        if abs(a - b) > 1e-5 * max(1.0, abs(b)):
            print("FAIL: struct text %r differs from the script's %r" % (a, b))
            sys.exit(1)
    print(json.dumps({
        "d_mm": d,
        "albedo": albedo,
        "mean_free_path_distance_cm": v["mean_free_path_distance"],
        "lobe_mix": v["lobe_mix"],
        "roughness0": v["roughness0"],
        "roughness1": v["roughness1"],
        "substrate": substrate,
    }))


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read_substrate(profile):
    materials = [a for a in unreal.CREATED if isinstance(a, unreal.Material)]
    if not hasattr(unreal, "MaterialExpressionSubstrateSlabBSDF"):
        if materials or not unreal.WARNINGS:
            fail("without Substrate the script must only warn")
        return None
    if len(materials) != 1 or materials[0] not in unreal.EditorAssetLibrary.saved:
        fail("the script did not create and save one material")
    m = materials[0]
    slabs = [e for e in m.expressions if isinstance(e, unreal.MaterialExpressionSubstrateSlabBSDF)]
    if len(slabs) != 1 or m.front_material is not slabs[0] or not m.compiled:
        fail("the material is not one compiled Slab on the Front Material")
    slab = slabs[0]
    if slab.values.get("sub_surface_type") != unreal.MaterialSubSurfaceType.MSS_DIFFUSION:
        fail("the Slab is not of type Diffusion")

    def constant_of(pin):
        node = slab.inputs.get(pin, (None,))[0]
        if node is None:
            return None
        if isinstance(node, unreal.MaterialExpressionConstant3Vector):
            return rgb(node.values["constant"])
        return node.values["r"]

    albedo = constant_of("Diffuse Albedo")
    out = {"albedo": albedo, "roughness": constant_of("Roughness"), "f0": constant_of("F0")}
    mfp = constant_of("SSS MFP")
    if mfp is None:
        if slab.values.get("subsurface_profile") is not profile or \
                m.values.get("subsurface_profile") is not profile:
            fail("the profile is not set on both the Slab and the material")
        out["uses_profile"] = True
    else:
        if slab.values.get("subsurface_profile") is not None:
            fail("a Slab with its own MFP must not carry a profile")
        scale = constant_of("SSS MFP Scale")
        out["uses_profile"] = False
        out["mfp_cm"] = mfp
        out["d_mm"] = d_from_ue(albedo, [m * scale for m in mfp], 1.0, 0.1)
    return out


if __name__ == "__main__":
    main()
