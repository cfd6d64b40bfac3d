# Unreal SubsurfaceProfile for "Skin (default)": written by scatterlab 0.1.0 from "Skin (default)" (presets/skin_default.ron).
# Needs Unreal Engine 5.1 or later (checked against the 5.1 to 5.7 Python API).
# MeanFreePathDistance is in cm (UE keeps it at 0.1 cm or more, so shorter
# paths are folded into the colour as UE's own upgrade does); WorldUnitScale
# 0.1 keeps it physical. How close this is to the scatterlab look:
# - exact Burley parameters.
# Run in the editor's Python console with a SubsurfaceProfile selected in the
# Content Browser, or it creates /Game/SSS_Skin__default.
import unreal

settings = unreal.SubsurfaceProfileStruct()
try:
    settings.set_editor_property("enable_mean_free_path", True)
except Exception as error:
    raise RuntimeError(
        "This profile needs Unreal Engine 5.1 or later: this engine has no "
        "enable_mean_free_path and would read MeanFreePathColor/Distance as a "
        "diffuse mean free path, a different look."
    ) from error
settings.set_editor_property("enable_burley", True)
settings.set_editor_property("surface_albedo", unreal.LinearColor(0.91058, 0.338275, 0.2718, 1.0))
settings.set_editor_property("mean_free_path_color", unreal.LinearColor(0.43090552583341296, 0.4246193606137818, 0.31317084004512, 1.0))
settings.set_editor_property("mean_free_path_distance", 0.1)
settings.set_editor_property("world_unit_scale", 0.1)
settings.set_editor_property("transmission_tint_color", unreal.LinearColor(1, 1, 1, 1.0))
settings.set_editor_property("ior", 1.4)
settings.set_editor_property("roughness0", 0.75)
settings.set_editor_property("roughness1", 1.3)
settings.set_editor_property("lobe_mix", 0.85)

selected = [a for a in unreal.EditorUtilityLibrary.get_selected_assets()
            if isinstance(a, unreal.SubsurfaceProfile)]
if selected:
    profile = selected[0]
else:
    tools = unreal.AssetToolsHelpers.get_asset_tools()
    profile = tools.create_asset("SSS_Skin__default", "/Game", unreal.SubsurfaceProfile, None)
profile.set_editor_property("settings", settings)
unreal.EditorAssetLibrary.save_loaded_asset(profile)
