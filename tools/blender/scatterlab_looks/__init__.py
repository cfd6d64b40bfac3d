"""scatterlab looks: the active material's Principled BSDF subsurface
written as a scatterlab look (.ron), and a scatterlab look applied to it.

Cycles' Christensen-Burley subsurface (intern/cycles/kernel/svm/closure.h,
closure/bssrdf.h `bssrdf_setup_radius`, Blender 4.x and 5.0) is Burley's
normalised diffusion with d = Subsurface Radius x Subsurface Scale / (4 pi)
in scene units and Base Color as the albedo, so:

    d_mm = Radius x Scale x unit_scale x 1000 / (4 pi),

with the scene's Unit Scale (metres per Blender unit). A look is written
with its albedo and d in millimetres (scatterlab's Burley parameters) and
read back the same way, in a scene of any unit scale. Looks of other
models (Gaussians, dipoles, ...) have no exact Cycles form: export them
from scatterlab as Blender (`scatterlab export --format blender`) to get
the Burley fit with its error.

File > Export > scatterlab look (.ron) and File > Import > scatterlab look
(.ron) act on the active object's active material. Blender 4.2 or later
(extensions); checked with bpy 4.5 and 5.0 (tests/clients/blender_addon.py).
"""

import math
import re

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

FOUR_PI = 4.0 * math.pi

# scatterlab's Burley d range (mm): model/burley.rs DISTANCE_RANGE_MM.
D_MIN_MM, D_MAX_MM = 1e-4, 1e3


class LookError(Exception):
    """A material or a look file that cannot be converted, in one line."""


def principled(mat):
    if mat is None:
        raise LookError("the active object has no material")
    tree = getattr(mat, "node_tree", None)
    if tree is None:
        raise LookError(f"material {mat.name!r} has no nodes")
    for node in tree.nodes:
        if node.type == "BSDF_PRINCIPLED":
            return node
    raise LookError(f"material {mat.name!r} has no Principled BSDF")


def unit_scale(scene):
    return scene.unit_settings.scale_length or 1.0


def look_from_material(mat, scene):
    """(name, albedo, d_mm, ior) of the material's subsurface."""
    bsdf = principled(mat)
    for socket in ("Base Color", "Subsurface Radius", "Subsurface Scale"):
        if bsdf.inputs[socket].is_linked:
            raise LookError(f"{socket} is driven by a texture or node: a look holds one value")
    albedo = [float(v) for v in bsdf.inputs["Base Color"].default_value[:3]]
    radius = [float(v) for v in bsdf.inputs["Subsurface Radius"].default_value[:3]]
    scale = float(bsdf.inputs["Subsurface Scale"].default_value)
    ior = float(bsdf.inputs["IOR"].default_value)
    metres = unit_scale(scene)
    d_mm = [r * scale * metres * 1000.0 / FOUR_PI for r in radius]
    for c, d in enumerate(d_mm):
        if not (D_MIN_MM <= d <= D_MAX_MM):
            raise LookError(
                f"Subsurface Radius x Scale gives d = {d:g} mm in {'RGB'[c]}, outside {D_MIN_MM}-{D_MAX_MM} mm"
            )
    albedo = [min(max(a, 0.0), 1.0) for a in albedo]
    return mat.name, albedo, d_mm, min(max(ior, 1.0), 2.0)


def ron_text(name, albedo, d_mm, ior, source):
    def triple(v):
        return "(" + ", ".join(repr(float(x)) for x in v) + ")"

    safe = name.replace("\\", "\\\\").replace('"', '\\"')
    return (
        "// scatterlab look written by the scatterlab Blender add-on.\n"
        "// Burley: albedo = Base Color, d = Radius x Scale x unit scale / (4 pi), in mm.\n"
        "(\n"
        "    format_version: 2,\n"
        f'    name: "{safe}",\n'
        '    description: "A Blender material\'s Principled BSDF subsurface (Christensen-Burley in Cycles).",\n'
        f'    source: "{source}",\n'
        "    profile: Burley((\n"
        f"        albedo: {triple(albedo)},\n"
        f"        shape: ScatteringDistance(mm: {triple(d_mm)}, multiplier: 1.0),\n"
        "    )),\n"
        "    rendering: (\n"
        f"        ior: {float(ior)!r},\n"
        "    ),\n"
        ")\n"
    )


NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
TRIPLE = rf"\(\s*({NUMBER})\s*,\s*({NUMBER})\s*,\s*({NUMBER})\s*,?\s*\)"


# Christensen & Burley 2015's s(A) fits, as scatterlab names them
# (model/burley.rs ScalingFit): d = mfp / s(A).
FITS = {
    "Perpendicular": lambda a: 1.85 - a + 7.0 * abs(a - 0.8) ** 3,
    "DiffuseSurface": lambda a: 1.9 - a + 3.5 * (a - 0.8) ** 2,
    "DiffuseMeanFreePath": lambda a: 3.5 + 100.0 * (a - 0.33) ** 4,
}


def parse_look(text, path="look"):
    """(name, albedo, d_mm, ior) of a scatterlab Burley look (.ron)."""
    text = re.sub(r"//[^\n]*", "", text)
    m = re.search(r"\bprofile\s*:\s*(\w+)\s*\(", text)
    if m is None:
        raise LookError(f"{path}: no profile: not a scatterlab look")
    if m.group(1) != "Burley":
        raise LookError(
            f"{path}: a {m.group(1)} look has no exact Cycles form; export it from scatterlab as Blender to get its Burley fit"
        )
    a = re.search(rf"\balbedo\s*:\s*{TRIPLE}", text)
    if a is None:
        raise LookError(f"{path}: profile.albedo missing")
    albedo = [float(a.group(i)) for i in (1, 2, 3)]
    sd = re.search(rf"ScatteringDistance\s*\(\s*mm\s*:\s*{TRIPLE}\s*,\s*multiplier\s*:\s*({NUMBER})", text)
    mfp = re.search(rf"MeanFreePath\s*\(\s*mm\s*:\s*{TRIPLE}\s*,\s*fit\s*:\s*(\w+)", text)
    if sd is not None:
        k = float(sd.group(4))
        d_mm = [float(sd.group(i)) * k for i in (1, 2, 3)]
    elif mfp is not None:
        fit = FITS.get(mfp.group(4))
        if fit is None:
            raise LookError(f"{path}: profile.shape.fit {mfp.group(4)!r} is not a fit scatterlab writes")
        d_mm = [float(mfp.group(i)) / fit(albedo[i - 1]) for i in (1, 2, 3)]
    else:
        raise LookError(f"{path}: profile.shape is neither ScatteringDistance nor MeanFreePath")
    i = re.search(rf"\bior\s*:\s*({NUMBER})", text)
    ior = float(i.group(1)) if i else 1.4
    n = re.search(r'\bname\s*:\s*"((?:[^"\\]|\\.)*)"', text)
    name = n.group(1) if n else "scatterlab look"
    for c in range(3):
        if not (0.0 <= albedo[c] <= 1.0) or not math.isfinite(albedo[c]):
            raise LookError(f"{path}: profile.albedo {albedo[c]} is outside 0-1")
        if not (D_MIN_MM <= d_mm[c] <= D_MAX_MM):
            raise LookError(f"{path}: d = {d_mm[c]} mm is outside {D_MIN_MM}-{D_MAX_MM} mm")
    return name, albedo, d_mm, ior


def apply_look(mat, scene, albedo, d_mm, ior):
    """Sets the Principled BSDF so that Cycles scatters d_mm with albedo."""
    bsdf = principled(mat)
    metres = unit_scale(scene)
    largest = max(d_mm)
    bsdf.subsurface_method = "BURLEY"
    bsdf.inputs["Subsurface Weight"].default_value = 1.0
    bsdf.inputs["Subsurface Radius"].default_value = [d / largest for d in d_mm]
    # Radius x Scale = 4 pi d in scene units.
    bsdf.inputs["Subsurface Scale"].default_value = FOUR_PI * largest / 1000.0 / metres
    if not bsdf.inputs["Base Color"].is_linked:
        bsdf.inputs["Base Color"].default_value = (albedo[0], albedo[1], albedo[2], 1.0)
    bsdf.inputs["IOR"].default_value = ior


class SCATTERLAB_OT_export_look(bpy.types.Operator, ExportHelper):
    """Write the active material's Principled BSDF subsurface as a scatterlab look"""

    bl_idname = "scatterlab.export_look"
    bl_label = "Export scatterlab look"
    filename_ext = ".ron"
    filter_glob: StringProperty(default="*.ron", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.active_material is not None

    def execute(self, context):
        mat = context.object.active_material
        try:
            name, albedo, d_mm, ior = look_from_material(mat, context.scene)
        except LookError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        source = f"Blender {bpy.app.version_string}, material {mat.name}"
        text = ron_text(name, albedo, d_mm, ior, source.replace('"', "'"))
        with open(self.filepath, "w", encoding="utf-8") as f:
            f.write(text)
        bsdf = principled(mat)
        if bsdf.subsurface_method != "BURLEY":
            self.report(
                {"WARNING"},
                f"the material uses {bsdf.subsurface_method}, not Christensen-Burley: its radius was read as Burley's",
            )
        if bsdf.inputs["Subsurface Weight"].default_value < 1.0:
            self.report({"WARNING"}, "Subsurface Weight is under 1: the material mixes in plain diffuse")
        self.report({"INFO"}, f"wrote {self.filepath}: d = {', '.join(f'{d:.4g}' for d in d_mm)} mm")
        return {"FINISHED"}


class SCATTERLAB_OT_apply_look(bpy.types.Operator, ImportHelper):
    """Apply a scatterlab look to the active material's Principled BSDF"""

    bl_idname = "scatterlab.apply_look"
    bl_label = "Apply scatterlab look"
    filename_ext = ".ron"
    filter_glob: StringProperty(default="*.ron", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.active_material is not None

    def execute(self, context):
        try:
            with open(self.filepath, encoding="utf-8") as f:
                _, albedo, d_mm, ior = parse_look(f.read(), self.filepath)
            apply_look(context.object.active_material, context.scene, albedo, d_mm, ior)
        except (OSError, LookError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"applied {self.filepath}")
        return {"FINISHED"}


def menu_export(self, context):
    self.layout.operator(SCATTERLAB_OT_export_look.bl_idname, text="scatterlab look (.ron)")


def menu_import(self, context):
    self.layout.operator(SCATTERLAB_OT_apply_look.bl_idname, text="scatterlab look (.ron)")


CLASSES = (SCATTERLAB_OT_export_look, SCATTERLAB_OT_apply_look)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    bpy.types.TOPBAR_MT_file_export.append(menu_export)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
