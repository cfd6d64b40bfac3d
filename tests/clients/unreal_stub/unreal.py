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


class EditorUtilityLibrary:
    @staticmethod
    def get_selected_assets():
        return []


class _AssetTools:
    def create_asset(self, asset_name, package_path, asset_class, factory):
        if asset_class is not SubsurfaceProfile:
            raise TypeError("unexpected asset class")
        asset = SubsurfaceProfile(package_path + "/" + asset_name)
        CREATED.append(asset)
        return asset


class AssetToolsHelpers:
    @staticmethod
    def get_asset_tools():
        return _AssetTools()


class EditorAssetLibrary:
    saved = []

    @staticmethod
    def save_loaded_asset(asset):
        EditorAssetLibrary.saved.append(asset)
        return True
