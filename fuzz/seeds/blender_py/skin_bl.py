# Blender Principled BSDF subsurface for "Skin (default)": written by scatterlab 0.1.0 from "Skin (default)" (presets/skin_default.ron).
# exact Burley parameters.
# Cycles (Blender 3.0+, kernel/closure/bssrdf.h bssrdf_setup_radius) uses
# Burley's d = Subsurface Radius x Subsurface Scale / (4 pi) in scene units,
# with Base Color as the albedo. This look: d = (0.756863, 0.321569, 0.200000) mm,
# albedo (0.910580, 0.338275, 0.271800).
# Needs Blender 4.0 or later (Principled BSDF v2 socket names); checked with
# Blender 4.5.15 and 5.0.1. EEVEE approximates Burley with its own screen-space blur.
# Select a mesh object and run this in Blender's Python console or Text Editor.
import bpy

NAME = "SSS_Skin__default"
SUBSURFACE_RADIUS = (1, 0.4248704520819362, 0.26424868549491404)
SUBSURFACE_SCALE_M = 0.009511018449021602  # metres; divided by the scene's Unit Scale below
BASE_COLOR = (0.91058, 0.338275, 0.2718, 1.0)
IOR = 1.4

if bpy.app.version < (4, 0, 0):
    raise RuntimeError("This snippet needs Blender 4.0 or later (Principled BSDF v2).")
obj = bpy.context.object
if obj is None or obj.type != "MESH":
    raise RuntimeError("Select a mesh object first.")
mat = obj.active_material
if mat is None:
    mat = bpy.data.materials.new(NAME)
    if obj.material_slots:
        obj.active_material = mat
    else:
        obj.data.materials.append(mat)
if bpy.app.version < (5, 0, 0):
    mat.use_nodes = True  # Blender 5.0 deprecates it: every material has nodes.
nodes, links = mat.node_tree.nodes, mat.node_tree.links
bsdf = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
if bsdf is None:
    bsdf = nodes.new("ShaderNodeBsdfPrincipled")
    out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output), None)
    if out is None:
        out = nodes.new("ShaderNodeOutputMaterial")
    links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    print("scatterlab: added a Principled BSDF to", mat.name, "and connected it to the output")
unit_scale = bpy.context.scene.unit_settings.scale_length or 1.0
bsdf.subsurface_method = "BURLEY"
if bsdf.inputs["Base Color"].is_linked:
    print("scatterlab: Base Color is driven by a texture; it stays (the albedo of this look is", BASE_COLOR[:3], ")")
else:
    bsdf.inputs["Base Color"].default_value = BASE_COLOR
bsdf.inputs["Subsurface Weight"].default_value = 1.0
bsdf.inputs["Subsurface Radius"].default_value = SUBSURFACE_RADIUS
bsdf.inputs["Subsurface Scale"].default_value = SUBSURFACE_SCALE_M / unit_scale
bsdf.inputs["IOR"].default_value = IOR
print("scatterlab: set", mat.name, "for a scene of", unit_scale, "m per unit")
