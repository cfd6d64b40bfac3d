// Reads a .gltf with the real readers and prints one JSON line:
// - Khronos' glTF validator (npm gltf-validator, pinned in package.json):
//   its report's counts and every message;
// - Babylon.js's glTF loader (@babylonjs/loaders) under NullEngine, twice:
//   as PBRMaterial (the loader's default) and as OpenPBRMaterial
//   (`useOpenPBR`), with the subsurface fields each material gets from
//   the file's first material.
//
// Usage: node gltf_check.mjs FILE.gltf
// Installed by tools/node-env.sh. Babylon reads the document through a
// "data:" string (a file path needs XMLHttpRequest, which node has not).

import { readFileSync } from "node:fs";
import { basename } from "node:path";
import validator from "gltf-validator";
import { NullEngine } from "@babylonjs/core/Engines/nullEngine.js";
import { Scene } from "@babylonjs/core/scene.js";
import { LoadAssetContainerAsync } from "@babylonjs/core/Loading/sceneLoader.js";
import "@babylonjs/loaders/glTF/index.js";

const file = process.argv[2];
const text = readFileSync(file, "utf8");
const doc = JSON.parse(text);
const materialName = doc.materials[0].name;

const report = await validator.validateBytes(new TextEncoder().encode(text), {
    uri: basename(file),
    format: "gltf",
    writeTimestamp: false,
    externalResourceFunction: async (uri) => {
        throw new Error("the export has no external resources, yet it names " + uri);
    },
});

const color = (c) => (c ? [c.r, c.g, c.b] : null);

async function babylon(useOpenPBR) {
    const engine = new NullEngine();
    const scene = new Scene(engine);
    // Babylon logs each extension it loads; keep stdout for the JSON line.
    const log = console.log;
    console.log = () => {};
    let container;
    try {
        container = await LoadAssetContainerAsync("data:" + text, scene, {
            pluginExtension: ".gltf",
            pluginOptions: { gltf: { useOpenPBR } },
        });
    } finally {
        console.log = log;
    }
    const m = container.materials.find((x) => x.name === materialName);
    let out;
    if (useOpenPBR) {
        out = {
            className: m.getClassName(),
            subsurfaceWeight: m.subsurfaceWeight,
            subsurfaceRadius: m.subsurfaceRadius,
            subsurfaceRadiusScale: color(m.subsurfaceRadiusScale),
            subsurfaceColor: color(m.subsurfaceColor),
        };
    } else {
        const ss = m.subSurface;
        out = {
            className: m.getClassName(),
            isTranslucencyEnabled: ss.isTranslucencyEnabled,
            translucencyIntensity: ss.translucencyIntensity,
            tintColor: color(ss.tintColor),
            diffusionDistance: color(ss.diffusionDistance),
            maximumThickness: ss.maximumThickness,
            volumeIndexOfRefraction: ss.volumeIndexOfRefraction,
            isScatteringEnabled: ss.isScatteringEnabled,
            albedo: color(m.albedoColor),
        };
    }
    engine.dispose();
    return out;
}

const pbr = await babylon(false);
const openpbr = await babylon(true);
console.log(
    JSON.stringify({
        validator: {
            version: report.validatorVersion,
            numErrors: report.issues.numErrors,
            numWarnings: report.issues.numWarnings,
            numInfos: report.issues.numInfos,
            messages: report.issues.messages,
        },
        babylon: { pbr, openpbr },
    }),
);
