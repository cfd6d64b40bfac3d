"""Runs the scatterlab Blender add-on (tools/blender/scatterlab_looks) in
Blender's own Python: writes a material's Principled BSDF subsurface as a
look in a centimetre scene, applies that look to a new material in a metre
scene, applies a shipped scatterlab preset, and refuses a look that has no
Cycles form.

Usage: python blender_addon.py OUT_DIR PRESETS_DIR
Prints one JSON line with the material's inputs, the file written, and the
Principled inputs each application set.
"""

import json
import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "blender"))
import scatterlab_looks  # noqa: E402


def fresh_material(name):
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    obj = bpy.context.object
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    obj.active_material = mat
    return mat


def inputs(mat):
    b = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    return {
        "base_color": list(b.inputs["Base Color"].default_value[:3]),
        "radius": list(b.inputs["Subsurface Radius"].default_value),
        "scale": b.inputs["Subsurface Scale"].default_value,
        "ior": b.inputs["IOR"].default_value,
        "method": b.subsurface_method,
        "weight": b.inputs["Subsurface Weight"].default_value,
        "unit_scale": bpy.context.scene.unit_settings.scale_length,
    }


def main():
    out_dir, presets = sys.argv[1], sys.argv[2]
    os.makedirs(out_dir, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scatterlab_looks.register()
    bpy.ops.mesh.primitive_cube_add()
    scene = bpy.context.scene
    scene.unit_settings.scale_length = 0.01  # a centimetre scene

    mat = fresh_material("Wax")
    b = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    b.inputs["Base Color"].default_value = (0.8, 0.5, 0.4, 1.0)
    b.inputs["Subsurface Radius"].default_value = (1.0, 0.45, 0.25)
    b.inputs["Subsurface Scale"].default_value = 0.3
    b.inputs["IOR"].default_value = 1.38
    b.inputs["Subsurface Weight"].default_value = 1.0
    b.subsurface_method = "BURLEY"
    written = os.path.join(out_dir, "wax.ron")
    r = bpy.ops.scatterlab.export_look(filepath=written)
    source = inputs(mat)

    # The same look in a metre scene, on a new material.
    scene.unit_settings.scale_length = 1.0
    back = fresh_material("WaxBack")
    r2 = bpy.ops.scatterlab.apply_look(filepath=written)
    round_trip = inputs(back)

    skin = fresh_material("Skin")
    r3 = bpy.ops.scatterlab.apply_look(filepath=os.path.join(presets, "skin_default.ron"))
    applied_skin = inputs(skin)

    gauss = fresh_material("Gaussians")
    try:
        r4 = bpy.ops.scatterlab.apply_look(filepath=os.path.join(presets, "skin_deon_six_gaussians.ron"))
    except RuntimeError as e:  # an operator's ERROR report raises in bpy
        r4 = {"ERROR: " + str(e).strip().splitlines()[-1]}
    scatterlab_looks.unregister()
    print(
        json.dumps(
            {
                "blender": bpy.app.version_string,
                "export": sorted(r),
                "source": source,
                "written": written,
                "apply": sorted(r2),
                "round_trip": round_trip,
                "apply_skin": sorted(r3),
                "skin": applied_skin,
                "gaussians": sorted(r4),
            }
        )
    )


if __name__ == "__main__":
    main()
