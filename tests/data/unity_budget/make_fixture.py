"""Writes the `scatterlab budget` test project (tests/data/unity_budget/
project): 24 HDRP diffusion profiles over 40 materials, laid out as a
Unity project (`Assets/` with a `.meta` beside every asset).

Independent of scatterlab's Rust code: the profile assets are HDRP's own
SkinDiffusionProfile.asset (tests/data/hdrp, m_Version 2) with the fields
replaced; the materials are HDRP Lit materials whose `_DiffusionProfileAsset`
holds the profile's GUID packed as HDRP's HDUtils.ConvertGUIDToVector4 does
(the 16 bytes in order, read as four little-endian floats) and whose
`_DiffusionProfileHash` is the profile's hash as a float, the hash computed
as HDRP's DiffusionProfileHashTable.GetDiffusionProfileHash does
(MonoStringHash of the GUID, mantissa only, exponent of 2.0). One material
is a LayeredLit with two layers' profiles, one a Shader Graph material
(`DiffusionProfile_<id>` and `DiffusionProfile_<id>_Asset`); two profiles
are used by no material. GUIDs are MD5 hashes of the paths.

Usage: python make_fixture.py   (rewrites project/ beside this script)
"""

import hashlib
import math
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "project")
TEMPLATE = open(os.path.join(HERE, "..", "hdrp", "SkinDiffusionProfile.asset")).read()

# name, folder, scattering distance (mm, per channel), tint, texturing (0
# pre-and-post, 1 post), transmission (0 thick, 1 thin), materials using it
PROFILES = [
    ("Skin_Hero", "Characters/Hero", (0.76, 0.32, 0.20), (0.76, 0.32, 0.20), 0, 0, 5),
    ("Skin_Hero_Face", "Characters/Hero", (0.80, 0.34, 0.21), (0.76, 0.32, 0.20), 0, 0, 2),
    ("Skin_Villager_A", "Characters/Villagers", (0.70, 0.30, 0.19), (0.75, 0.33, 0.21), 0, 0, 4),
    ("Skin_Villager_B", "Characters/Villagers", (0.72, 0.29, 0.18), (0.76, 0.32, 0.20), 0, 0, 3),
    ("Skin_Villager_C", "Characters/Villagers", (0.90, 0.40, 0.25), (0.78, 0.35, 0.22), 0, 0, 2),
    ("Skin_Elder", "Characters/Villagers", (0.60, 0.25, 0.16), (0.72, 0.30, 0.20), 0, 0, 2),
    ("Skin_Child", "Characters/Villagers", (1.00, 0.45, 0.28), (0.80, 0.36, 0.22), 0, 0, 1),
    ("Skin_Dark", "Characters/Villagers", (0.55, 0.26, 0.18), (0.60, 0.28, 0.18), 0, 0, 2),
    ("Skin_Zombie", "Characters/Enemies", (0.40, 0.30, 0.28), (0.50, 0.55, 0.40), 1, 0, 1),
    ("Skin_Troll", "Characters/Enemies", (1.80, 1.10, 0.70), (0.50, 0.70, 0.40), 0, 0, 1),
    ("Ears", "Characters/Hero", (1.10, 0.45, 0.28), (0.90, 0.35, 0.22), 0, 1, 1),
    ("Lips", "Characters/Hero", (0.85, 0.30, 0.22), (0.85, 0.30, 0.22), 0, 0, 1),
    ("Sclera", "Characters/Eyes", (2.50, 2.30, 2.10), (1.00, 0.85, 0.80), 1, 0, 2),
    ("Sclera_Bloodshot", "Characters/Eyes", (2.40, 2.00, 1.80), (1.00, 0.60, 0.55), 1, 0, 1),
    ("Teeth", "Characters/Mouth", (0.30, 0.28, 0.25), (1.00, 0.95, 0.85), 1, 0, 1),
    ("Gums", "Characters/Mouth", (0.70, 0.25, 0.18), (0.90, 0.30, 0.25), 0, 0, 1),
    ("Leaf", "Environment/Foliage", (4.00, 6.00, 2.00), (0.45, 0.80, 0.20), 0, 1, 4),
    ("Grass", "Environment/Foliage", (3.50, 5.50, 1.80), (0.50, 0.85, 0.25), 0, 1, 2),
    ("Fern", "Environment/Foliage", (4.50, 6.50, 2.20), (0.40, 0.75, 0.20), 0, 1, 1),
    ("Candle_Wax", "Environment/Props", (6.00, 4.50, 2.50), (1.00, 0.80, 0.50), 0, 0, 1),
    ("Marble_Statue", "Environment/Props", (8.00, 7.50, 7.00), (1.00, 0.97, 0.92), 1, 0, 1),
    ("Jade_Idol", "Environment/Props", (3.00, 6.00, 4.00), (0.55, 0.90, 0.65), 1, 0, 1),
    ("Old_Skin_Test", "Characters/Archive", (0.75, 0.31, 0.20), (0.76, 0.32, 0.20), 0, 0, 0),
    ("Unused_Wax_Test", "Environment/Archive", (5.50, 4.00, 2.30), (1.00, 0.80, 0.50), 0, 0, 0),
]


def guid_of(rel):
    # A GUID whose four floats are all finite (a NaN or infinite pattern
    # would not survive a float's text; Unity's random GUIDs hit one in
    # about 64): salted until so.
    salt = 0
    while True:
        g = hashlib.md5(("scatterlab-budget-fixture/%s/%d" % (rel, salt)).encode()).hexdigest()
        if all(math.isfinite(x) for x in struct.unpack("<4f", bytes.fromhex(g))):
            return g
        salt += 1


def mono_string_hash(s):
    def i32(x):
        x &= 0xFFFFFFFF
        return x - (1 << 32) if x & 0x80000000 else x
    h1 = h2 = 5381
    i = 0
    while i < len(s):
        h1 = i32(i32(h1 << 5) + h1) ^ ord(s[i])
        if i + 1 >= len(s):
            break
        h2 = i32(i32(h2 << 5) + h2) ^ ord(s[i + 1])
        i += 2
    return i32(h1 + i32(h2 * 1566083941))


def profile_hash(guid):
    return (0b10000000 << 23) | ((mono_string_hash(guid) & 0xFFFFFFFF) & 0x7FFFFF)


def vector4(guid):
    return struct.unpack("<4f", bytes.fromhex(guid))


def f32(x):
    """The shortest text of x as a 32-bit float that reads back to it, as
    Unity's YAML writer prints floats (e.g. 1.0959463e-38)."""
    bits = struct.pack("<f", x)
    for p in range(1, 10):
        t = "%.*g" % (p, struct.unpack("<f", bits)[0])
        if struct.pack("<f", float(t)) == bits:
            return t
    return "%.9g" % struct.unpack("<f", bits)[0]


def write(rel, text):
    path = os.path.join(OUT, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write(text)


def meta(guid, main_object):
    return ("fileFormatVersion: 2\nguid: %s\nNativeFormatImporter:\n  externalObjects: {}\n"
            "  mainObjectFileID: %d\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
            % (guid, main_object))


def profile_asset(name, d, tint, texturing, transmission, guid):
    m = max(d)
    text = TEMPLATE
    text = text.replace("m_Name: SkinDiffusionProfile", "m_Name: " + name)
    text = text.replace("scatteringDistance: {r: 0.7490196, g: 0.32156864, b: 0.2, a: 1}",
                        "scatteringDistance: {r: %s, g: %s, b: %s, a: 1}" % tuple(f32(x / m) for x in d))
    text = text.replace("scatteringDistanceMultiplier: 1.0104712", "scatteringDistanceMultiplier: %s" % f32(m))
    text = text.replace("transmissionTint: {r: 0.7568628, g: 0.32156864, b: 0.20000002, a: 1}",
                        "transmissionTint: {r: %s, g: %s, b: %s, a: 1}" % tuple(f32(x) for x in tint))
    text = text.replace("texturingMode: 0", "texturingMode: %d" % texturing)
    text = text.replace("transmissionMode: 0", "transmissionMode: %d" % transmission)
    text = text.replace("hash: 1075477546", "hash: %d" % profile_hash(guid))
    return text


def material(name, refs):
    """refs: [(asset property, hash property, guid)]"""
    floats = "".join("    - %s: %s\n" % (h, f32(struct.unpack("<f", struct.pack("<I", profile_hash(g)))[0]))
                     for _, h, g in refs)
    colors = "".join("    - %s: {r: %s, g: %s, b: %s, a: %s}\n" % ((a,) + tuple(f32(x) for x in vector4(g)))
                     for a, _, g in refs)
    return ("%%YAML 1.1\n%%TAG !u! tag:unity3d.com,2011:\n--- !u!21 &2100000\nMaterial:\n"
            "  serializedVersion: 8\n  m_ObjectHideFlags: 0\n  m_Name: %s\n"
            "  m_Shader: {fileID: 4800000, guid: 6e4ae4064600d784cac1e41a9e6f2e59, type: 3}\n"
            "  m_SavedProperties:\n    serializedVersion: 3\n    m_Floats:\n%s    - _MaterialID: 0\n"
            "    m_Colors:\n    - _BaseColor: {r: 1, g: 1, b: 1, a: 1}\n%s" % (name, floats, colors))


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    guids = {}
    for name, folder, d, tint, tex, trans, _ in PROFILES:
        rel = "Assets/%s/%s.asset" % (folder, name)
        g = guid_of(rel)
        guids[name] = g
        write(rel, profile_asset(name, d, tint, tex, trans, g))
        write(rel + ".meta", meta(g, 11400000))
    count = 0
    lit = ("_DiffusionProfileAsset", "_DiffusionProfileHash")
    for name, folder, _, _, _, _, uses in PROFILES:
        for k in range(uses):
            mat = "%s_%d" % (name, k + 1)
            refs = [lit + (guids[name],)]
            if name == "Skin_Hero" and k == 0:
                # A LayeredLit: layer 0 skin, layer 1 the face's profile.
                mat = "Hero_Layered"
                refs = [("_DiffusionProfileAsset0", "_DiffusionProfileHash0", guids["Skin_Hero"]),
                        ("_DiffusionProfileAsset1", "_DiffusionProfileHash1", guids["Skin_Hero_Face"])]
            if name == "Leaf" and k == 0:
                # A Shader Graph material's diffusion profile property.
                prop = "DiffusionProfile_6b1f0c2d3e4a5b6c7d8e9f0a1b2c3d4e"
                mat = "Leaf_ShaderGraph"
                refs = [(prop + "_Asset", prop, guids["Leaf"])]
            rel = "Assets/%s/Materials/%s.mat" % (folder, mat)
            write(rel, material(mat, refs))
            write(rel + ".meta", meta(guid_of(rel), 2100000))
            count += 1
    write("Assets/README.txt", "A test project for scatterlab budget: 24 diffusion profiles, %d materials.\n" % count)
    write("ProjectSettings/ProjectVersion.txt", "m_EditorVersion: 6000.0.23f1\n")
    print("%d profiles, %d materials" % (len(PROFILES), count))


if __name__ == "__main__":
    main()
