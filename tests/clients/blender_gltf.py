"""Writes the default head as a glTF with Blender's own exporter, as an
artist's file would come: centimetre units, an external colour map.

Usage: python blender_gltf.py HEAD.obj MAP.png OUT_DIR

Imports HEAD.obj (decimetres; Blender's OBJ importer), scales it ×10 so one
unit is a centimetre and applies the scale, gives every face one material
whose Base Color is MAP.png (an Image Texture node), and exports OUT_DIR/
head_cm.gltf with Blender's glTF 2.0 exporter ('GLTF_SEPARATE': .gltf,
.bin and the image beside them). Prints one JSON line with the exported
height in units and Blender's version.
"""

import json
import os
import sys

import bpy


def main():
    obj_path, map_path, out_dir = sys.argv[1], sys.argv[2], sys.argv[3]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=obj_path)
    obs = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    bpy.ops.object.select_all(action="DESELECT")
    for o in obs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = obs[0]
    if len(obs) > 1:
        bpy.ops.object.join()
    ob = bpy.context.view_layer.objects.active
    ob.scale = (10.0, 10.0, 10.0)
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    mat = bpy.data.materials.new("Skin")
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = next(n for n in nodes if n.type == "BSDF_PRINCIPLED")
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(map_path)
    links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    ob.data.materials.clear()
    ob.data.materials.append(mat)
    for p in ob.data.polygons:
        p.material_index = 0
    out = os.path.join(out_dir, "head_cm.gltf")
    bpy.ops.export_scene.gltf(filepath=out, export_format="GLTF_SEPARATE", use_selection=False)
    zs = [v.co.z for v in ob.data.vertices]
    print(json.dumps({"gltf": out, "height_units": max(zs) - min(zs), "blender": bpy.app.version_string}))


if __name__ == "__main__":
    main()
