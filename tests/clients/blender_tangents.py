"""Compares scatterlab's vertex tangents with Blender's MikkTSpace.

Usage: python blender_tangents.py MESH.obj OURS.json

MESH.obj is a triangulated mesh written by the test (v/vt/vn per corner,
UVs with V up as OBJ has them); OURS.json holds our per-vertex tangents,
[[x, y, z, w], ...], in the OBJ's vertex order. Blender's OBJ importer keeps
that order and sets the OBJ normals as custom normals; `Mesh.calc_tangents`
is Blender's MikkTSpace (Mikkelsen 2008, the reference code), on those
corner normals and the UV map. For every face corner the tangent and the
bitangent sign are compared with ours at its vertex.

Prints one JSON line: corners, the fraction whose tangent is within 1
degree of ours, the fraction with the same sign, and the worst angle.
"""

import json
import math
import sys

import bpy


def main():
    obj_path, ours_path = sys.argv[1], sys.argv[2]
    ours = json.load(open(ours_path))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=obj_path)
    ob = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    me = ob.data
    if len(me.vertices) != len(ours):
        print(json.dumps({"error": f"Blender has {len(me.vertices)} vertices, we have {len(ours)}"}))
        return
    me.calc_tangents(uvmap=me.uv_layers.active.name)
    n = within = same_sign = 0
    worst = 0.0
    for loop in me.loops:
        t = loop.tangent
        o = ours[loop.vertex_index]
        dot = t[0] * o[0] + t[1] * o[1] + t[2] * o[2]
        nt = math.sqrt(sum(x * x for x in t)) * math.sqrt(sum(x * x for x in o[:3]))
        angle = math.degrees(math.acos(max(-1.0, min(1.0, dot / nt)))) if nt > 0 else 180.0
        n += 1
        within += angle < 1.0
        same_sign += (loop.bitangent_sign > 0) == (o[3] > 0)
        worst = max(worst, angle)
    print(json.dumps({
        "corners": n,
        "within_1deg": within / n,
        "same_sign": same_sign / n,
        "worst_deg": worst,
        "blender": bpy.app.version_string,
    }))


if __name__ == "__main__":
    main()
