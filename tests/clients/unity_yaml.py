"""Reads a scatterlab Unity export as HDRP would and checks it against HDRP's
conventions, written down here from HDRP's own source (Unity-Technologies/
Graphics, com.unity.render-pipelines.high-definition, HDRP 15-17):

- Runtime/Material/DiffusionProfile/DiffusionProfileSettings.cs: the
  serialised fields of DiffusionProfile in order (lines 54-77), the enums
  TexturingMode {PreAndPostScatter = 0, PostScatter = 1} (lines 33-41) and
  TransmissionMode {Regular = 0, ThinObject = 1} (lines 43-51), worldScale
  "size of the world unit in meters" (line 69), m_Version 2 =
  SplitScatteringDistance (DiffusionProfileSettings.Migration.cs lines 13-18),
  script GUID b2686e09ec7aef44bad2843e4416f057 (DiffusionProfileSettings.cs.meta).
- HDUtils.ConvertHDRColorToLDR: the colour's largest channel is 191/255 and
  colour x multiplier is the scattering distance (mm at world scale 1).
- Runtime/Material/Lit/Lit.hlsl EvaluateBSDF (dual lobe):
    roughnessL = PerceptualSmoothnessToRoughness(saturate(lobeA - rho*lobeA))
    roughnessH = PerceptualSmoothnessToRoughness(saturate(lobeB - rho*lobeB))
    DV = lerp(DV(roughnessL), DV(roughnessH), lobeMix)
  with lobeA = smoothnessMultipliers.x, lobeB = .y (UpdateCache, line 389),
  so lobeMix is the weight of the .y lobe and each lobe's perceptual
  roughness is 1 - m (1 - rho).

Usage: python unity_yaml.py ASSET.asset EXPECT.json
EXPECT holds the look as scatterlab's viewport draws it: d_mm, file stem,
base roughness rho, lobe roughness multipliers m0, m1 and lobe_mix (the
weight of lobe 1, as D = mix(D(rho m0), D(rho m1), lobe_mix) in
shaders/scene.wgsl, like Unreal's lerp).
"""

import json
import math
import sys

import yaml

HDRP_FIELDS = [
    "scatteringDistance",
    "scatteringDistanceMultiplier",
    "transmissionTint",
    "texturingMode",
    "smoothnessMultipliers",
    "lobeMix",
    "diffuseShadingPower",
    "transmissionMode",
    "thicknessRemap",
    "worldScale",
    "ior",
    "hash",
]


class UnityLoader(yaml.SafeLoader):
    pass


def _unity_tag(loader, suffix, node):
    return loader.construct_mapping(node, deep=True)


UnityLoader.add_multi_constructor("tag:unity3d.com,2011:", _unity_tag)


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def main():
    path, expect_path = sys.argv[1], sys.argv[2]
    expect = json.load(open(expect_path))
    text = open(path, encoding="utf-8").read()
    doc = yaml.load(text, Loader=UnityLoader)
    mb = doc["MonoBehaviour"]
    if mb["m_Script"]["guid"] != "b2686e09ec7aef44bad2843e4416f057":
        fail("m_Script guid %r is not DiffusionProfileSettings" % mb["m_Script"]["guid"])
    if mb["m_Version"] != 2:
        fail("m_Version %r" % mb["m_Version"])
    if str(mb["m_Name"]) != expect["file_stem"]:
        fail("m_Name %r differs from the file name %r" % (mb["m_Name"], expect["file_stem"]))
    prof = mb["profile"]
    if list(prof.keys()) != HDRP_FIELDS:
        fail("fields %r, HDRP has %r" % (list(prof.keys()), HDRP_FIELDS))
    if prof["texturingMode"] not in (0, 1) or prof["transmissionMode"] not in (0, 1):
        fail("enum out of range")
    col = [prof["scatteringDistance"][k] for k in "rgb"]
    mult = prof["scatteringDistanceMultiplier"]
    if abs(max(col) - 191.0 / 255.0) > 1e-6:
        fail("largest colour channel %r, HDRP splits at 191/255" % max(col))
    world = prof["worldScale"]
    d = [c * mult for c in col]
    for c in range(3):
        want = expect["d_mm"][c]
        if abs(d[c] - want) > 1e-6 * max(want, 1.0):
            fail("channel %d: colour x multiplier = %r mm, look has %r mm" % (c, d[c], want))
    if abs(world - expect["world_scale_m_per_unit"]) > 1e-12:
        fail("worldScale %r" % world)

    # Specular: pair HDRP's lobes with the viewport's, smoother with smoother.
    rho = expect["roughness"]
    x, y = prof["smoothnessMultipliers"]["x"], prof["smoothnessMultipliers"]["y"]
    mix = prof["lobeMix"]
    if not (0 <= x <= 1 <= y <= 2 and 0 <= mix <= 1):
        fail("dual lobe outside HDRP's ranges: x %r y %r lobeMix %r" % (x, y, mix))
    hdrp = sorted(
        [(1 - min(1, x * (1 - rho)), 1 - mix), (1 - min(1, y * (1 - rho)), mix)]
    )  # (perceptual roughness, weight), smoother first
    ours = sorted(
        [
            (min(1, rho * expect["m0"]), 1 - expect["lobe_mix"]),
            (min(1, rho * expect["m1"]), expect["lobe_mix"]),
        ]
    )
    for (hr, hw), (orr, ow) in zip(hdrp, ours):
        if abs(hw - ow) > 1e-9:
            fail("lobe of roughness %.4f: HDRP weight %.4f, viewport %.4f" % (orr, hw, ow))
        if abs(hr - orr) > 1e-6:
            fail("lobe roughness: HDRP %.6f, viewport %.6f" % (hr, orr))
    print(json.dumps({"d_mm": d, "hdrp_lobes": hdrp, "viewport_lobes": ours}))


if __name__ == "__main__":
    main()
