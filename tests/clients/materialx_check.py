"""Validates a scatterlab MaterialX export with the MaterialX library
(PyPI `materialx`, the Academy Software Foundation's reference
implementation) against its standard data libraries, which define
ND_open_pbr_surface_surfaceshader (libraries/bxdf/open_pbr_surface.mtlx),
then reads the subsurface back and converts it to Burley's d with
Christensen & Burley 2015 eq. 5 typed here: d = l / s(A),
s(A) = 1.85 - A + 7 |A - 0.8|^3, l = subsurface_radius (in the unit its
`unit` attribute names) x subsurface_radius_scale.

Usage: python materialx_check.py DOC.mtlx
Prints JSON {"d_mm": [...], "albedo": [...]}.
"""

import json
import sys

import MaterialX as mx

MM_PER_UNIT = {"millimeter": 1.0, "centimeter": 10.0, "meter": 1000.0}


def main():
    stdlib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), stdlib)
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, sys.argv[1])
    doc.importLibrary(stdlib)
    ok, message = doc.validate()
    if not ok:
        print("FAIL: MaterialX validation: " + message)
        sys.exit(1)
    materials = [n for n in doc.getNodes() if n.getType() == "material"]
    shaders = [n for n in doc.getNodes() if n.getCategory() == "open_pbr_surface"]
    if len(materials) != 1 or len(shaders) != 1:
        print("FAIL: %d materials, %d open_pbr_surface nodes" % (len(materials), len(shaders)))
        sys.exit(1)
    sh = shaders[0]
    if materials[0].getInput("surfaceshader").getNodeName() != sh.getName():
        print("FAIL: the material does not use the OpenPBR shader")
        sys.exit(1)
    if sh.getNodeDef() is None or sh.getNodeDef().getName() != "ND_open_pbr_surface_surfaceshader":
        print("FAIL: no standard nodedef for the shader")
        sys.exit(1)
    radius_in = sh.getInput("subsurface_radius")
    unit = radius_in.getUnit()
    if radius_in.getUnitType() != "distance" or unit not in MM_PER_UNIT:
        print("FAIL: subsurface_radius unit %r/%r" % (radius_in.getUnitType(), unit))
        sys.exit(1)
    radius_mm = radius_in.getValue() * MM_PER_UNIT[unit]
    scale = list(sh.getInput("subsurface_radius_scale").getValue().asTuple())
    albedo = list(sh.getInput("subsurface_color").getValue().asTuple())
    weight = sh.getInput("subsurface_weight").getValue()
    if weight != 1.0:
        print("FAIL: subsurface_weight %r" % weight)
        sys.exit(1)
    d = [radius_mm * scale[c] / (1.85 - a + 7 * abs(a - 0.8) ** 3) for c, a in enumerate(albedo)]
    print(json.dumps({"d_mm": d, "albedo": albedo}))


if __name__ == "__main__":
    main()
