"""A stand-in for Unreal Editor's `unreal` Python module that accepts exactly
the documented editor properties of `unreal.SubsurfaceProfileStruct` and
rejects any other name, so a script that runs here uses only real names.

Property names: the UE 5.1-5.7 Python API page of SubsurfaceProfileStruct
(dev.epicgames.com/documentation/en-us/unreal-engine/python-api/class/
SubsurfaceProfileStruct); UE 5.0's page lacks enable_mean_free_path
(set SCATTERLAB_UNREAL_STUB_VERSION=5.0 to get that API). Clamps: the
UPROPERTY metadata in Engine/Classes/Engine/SubsurfaceProfile.h (UE 5.1.1,
lines 19-108); the editor clamps to them, so a value outside is an error
here.

Substrate (UE 5.7 Python API pages, dev.epicgames.com/documentation/en-us/
unreal-engine/python-api/class/<Name>?application_version=5.7):
MaterialExpressionSubstrateSlabBSDF's editor properties (sub_surface_type,
subsurface_profile, specular_profile, desc); MaterialSubSurfaceType's members
(MSS_NONE, MSS_WRAP, MSS_TWO_SIDED_WRAP, MSS_DIFFUSION, MSS_SIMPLE_VOLUME:
the C++ enum's MSS_DiffusionProfile is UMETA(Hidden) and not in Python);
MaterialInterface.subsurface_profile; MaterialProperty.MP_FRONT_MATERIAL;
MaterialEditingLibrary's create_material_expression, connect_material_
expressions, connect_material_property, delete_all_material_expressions and
recompile_material; EditorAssetLibrary's does_asset_exist, load_asset,
get_metadata_tag, set_metadata_tag. The Slab's input names are those of
UMaterialExpressionSubstrateSlabBSDF::GetInputName (MaterialExpression
Substrate.cpp, UE 5.8 source; the names connect_material_expressions
matches), and a name outside them fails to connect, as in the editor.
SCATTERLAB_UNREAL_STUB_SUBSTRATE=0 gives an engine without Substrate.
"""

import os

_VERSION = os.environ.get("SCATTERLAB_UNREAL_STUB_VERSION", "5.1")

_COLOR, _FLOAT, _BOOL = "LinearColor", "float", "bool"
# name: (type, min, max)
PROPERTIES = {
    "surface_albedo": (_COLOR, 0.01, 1.0),
    "mean_free_path_color": (_COLOR, 0.001, 1.0),
    "mean_free_path_distance": (_FLOAT, 0.1, 50.0),
    "world_unit_scale": (_FLOAT, 0.1, 50.0),
    "enable_burley": (_BOOL, None, None),
    "enable_mean_free_path": (_BOOL, None, None),
    "tint": (_COLOR, 0.0, 1.0),
    "scatter_radius": (_FLOAT, 0.1, 1000.0),
    "subsurface_color": (_COLOR, 0.0, 1.0),
    "falloff_color": (_COLOR, 0.0, 1.0),
    "boundary_color_bleed": (_COLOR, 0.0, 1.0),
    "extinction_scale": (_FLOAT, 0.01, 1.0),
    "normal_scale": (_FLOAT, 0.01, 1.0),
    "scattering_distribution": (_FLOAT, 0.01, 1.0),
    "ior": (_FLOAT, 1.0, 3.0),
    "roughness0": (_FLOAT, 0.5, 2.0),
    "roughness1": (_FLOAT, 0.5, 2.0),
    "lobe_mix": (_FLOAT, 0.1, 0.9),
    "transmission_tint_color": (_COLOR, 0.001, 1.0),
}
if _VERSION == "5.0":
    del PROPERTIES["enable_mean_free_path"]

CREATED = []


class LinearColor:
    def __init__(self, r=0.0, g=0.0, b=0.0, a=1.0):
        self.r, self.g, self.b, self.a = float(r), float(g), float(b), float(a)


class SubsurfaceProfileStruct:
    def __init__(self):
        self.values = {}

    def set_editor_property(self, name, value):
        if name not in PROPERTIES:
            raise Exception("SubsurfaceProfileStruct: Failed to find property '%s'" % name)
        kind, lo, hi = PROPERTIES[name]
        if kind == _BOOL:
            if not isinstance(value, bool):
                raise TypeError("%s takes a bool, got %r" % (name, value))
        elif kind == _FLOAT:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise TypeError("%s takes a float, got %r" % (name, value))
            if not lo <= value <= hi:
                raise ValueError("%s = %r is outside UE's clamp %r..%r" % (name, value, lo, hi))
        else:
            if not isinstance(value, LinearColor):
                raise TypeError("%s takes a LinearColor, got %r" % (name, value))
            for ch in (value.r, value.g, value.b):
                if not lo <= ch <= hi:
                    raise ValueError("%s channel %r is outside UE's clamp %r..%r" % (name, ch, lo, hi))
        self.values[name] = value

    def get_editor_property(self, name):
        return self.values[name]


class SubsurfaceProfile:
    def __init__(self, name="Selected"):
        self.name = name
        self.settings = None

    def set_editor_property(self, name, value):
        if name != "settings" or not isinstance(value, SubsurfaceProfileStruct):
            raise Exception("SubsurfaceProfile: Failed to find property '%s'" % name)
        self.settings = value


class MaterialSubSurfaceType:
    MSS_NONE = "MSS_NONE"
    MSS_WRAP = "MSS_WRAP"
    MSS_TWO_SIDED_WRAP = "MSS_TWO_SIDED_WRAP"
    MSS_DIFFUSION = "MSS_DIFFUSION"
    MSS_SIMPLE_VOLUME = "MSS_SIMPLE_VOLUME"


class MaterialProperty:
    MP_FRONT_MATERIAL = "MP_FRONT_MATERIAL"
    MP_BASE_COLOR = "MP_BASE_COLOR"


class _Object:
    """An object with a fixed set of editor properties: name -> check."""

    EDITOR_PROPERTIES = {}

    def __init__(self):
        self.values = {}

    def set_editor_property(self, name, value):
        check = self.EDITOR_PROPERTIES.get(name)
        if check is None:
            raise Exception("%s: Failed to find property '%s'" % (type(self).__name__, name))
        if not check(value):
            raise TypeError("%s.%s cannot take %r" % (type(self).__name__, name, value))
        self.values[name] = value

    def get_editor_property(self, name):
        if name not in self.EDITOR_PROPERTIES:
            raise Exception("%s: Failed to find property '%s'" % (type(self).__name__, name))
        return self.values.get(name)


def _profile_or_none(v):
    return v is None or isinstance(v, SubsurfaceProfile)


class Material(_Object):
    EDITOR_PROPERTIES = {"subsurface_profile": _profile_or_none}

    def __init__(self, name):
        super().__init__()
        self.name = name
        self.expressions = []
        self.front_material = None
        self.compiled = False
        self.metadata = {}


class MaterialFactoryNew:
    pass


class MaterialExpression(_Object):
    INPUTS = ()


class MaterialExpressionSubstrateSlabBSDF(MaterialExpression):
    EDITOR_PROPERTIES = {
        "sub_surface_type": lambda v: v in vars(MaterialSubSurfaceType).values(),
        "subsurface_profile": _profile_or_none,
        "specular_profile": lambda v: True,
        "desc": lambda v: isinstance(v, str),
    }
    INPUTS = ("Diffuse Albedo", "F0", "F90", "Roughness", "Anisotropy", "Normal", "Tangent",
              "SSS MFP", "SSS MFP Scale", "SSS Phase Anisotropy", "Emissive Color",
              "Second Roughness", "Second Roughness Weight", "Fuzz Roughness", "Fuzz Amount",
              "Fuzz Color", "Glint Density", "Glint UVs")


class MaterialExpressionConstant3Vector(MaterialExpression):
    EDITOR_PROPERTIES = {"constant": lambda v: isinstance(v, LinearColor)}


class MaterialExpressionConstant(MaterialExpression):
    EDITOR_PROPERTIES = {"r": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)}


if os.environ.get("SCATTERLAB_UNREAL_STUB_SUBSTRATE", "1") == "0":
    del MaterialExpressionSubstrateSlabBSDF


class MaterialEditingLibrary:
    @staticmethod
    def create_material_expression(material, expression_class, node_pos_x=0, node_pos_y=0):
        if not isinstance(material, Material) or not issubclass(expression_class, MaterialExpression):
            raise TypeError("create_material_expression(material, expression_class, x, y)")
        node = expression_class()
        node.inputs = {}
        material.expressions.append(node)
        return node

    @staticmethod
    def connect_material_expressions(from_expression, from_output_name, to_expression, to_input_name):
        if to_input_name not in type(to_expression).INPUTS:
            return False
        to_expression.inputs[to_input_name] = (from_expression, from_output_name)
        return True

    @staticmethod
    def connect_material_property(from_expression, from_output_name, property_):
        if property_ != MaterialProperty.MP_FRONT_MATERIAL:
            return False
        owner = [m for m in CREATED if isinstance(m, Material) and from_expression in m.expressions]
        if len(owner) != 1:
            return False
        owner[0].front_material = from_expression
        return True

    @staticmethod
    def delete_all_material_expressions(material):
        material.expressions = []
        material.front_material = None

    @staticmethod
    def recompile_material(material):
        material.compiled = True


class EditorUtilityLibrary:
    @staticmethod
    def get_selected_assets():
        return []


class _AssetTools:
    def create_asset(self, asset_name, package_path, asset_class, factory):
        if asset_class is SubsurfaceProfile:
            asset = SubsurfaceProfile(package_path + "/" + asset_name)
        elif asset_class is Material and isinstance(factory, MaterialFactoryNew):
            asset = Material(package_path + "/" + asset_name)
        else:
            raise TypeError("unexpected asset class or factory")
        CREATED.append(asset)
        return asset


class AssetToolsHelpers:
    @staticmethod
    def get_asset_tools():
        return _AssetTools()


class EditorAssetLibrary:
    saved = []

    @staticmethod
    def does_asset_exist(path):
        return any(a.name == path for a in CREATED)

    @staticmethod
    def load_asset(path):
        return next(a for a in CREATED if a.name == path)

    @staticmethod
    def get_metadata_tag(obj, tag):
        return obj.metadata.get(tag)

    @staticmethod
    def set_metadata_tag(obj, tag, value):
        obj.metadata[tag] = value

    @staticmethod
    def save_loaded_asset(asset):
        EditorAssetLibrary.saved.append(asset)
        return True


def log_warning(message):
    WARNINGS.append(message)


WARNINGS = []
