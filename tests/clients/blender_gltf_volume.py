"""Imports a scatterlab glTF export with Blender's own glTF importer and
prints what it made of the look's material: the Principled BSDF's
subsurface and the Volume Absorption node's colour and density (Blender
turns KHR_materials_volume into absorption).

Usage: python blender_gltf_volume.py FILE.gltf MATERIAL_NAME
Prints one JSON line: {"version", "subsurface_weight", "base_color",
"absorption_color", "absorption_density"}.
"""

import json
import sys

import bpy


def main():
    path, name = sys.argv[1], sys.argv[2]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    m = bpy.data.materials[name]
    bsdf = next(n for n in m.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    vol = [n for n in m.node_tree.nodes if n.bl_idname == "ShaderNodeVolumeAbsorption"]
    out = {
        "version": bpy.app.version_string,
        "subsurface_weight": bsdf.inputs["Subsurface Weight"].default_value,
        "base_color": list(bsdf.inputs["Base Color"].default_value)[:3],
        "absorption_color": list(vol[0].inputs["Color"].default_value)[:3] if vol else None,
        "absorption_density": vol[0].inputs["Density"].default_value if vol else None,
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
