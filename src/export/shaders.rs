//! The separable kernel and the Burley sample pattern as shader arrays
//! (HLSL, GLSL, WGSL) and as JSON.

use super::Provenance;
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::separable::SeparableKernel;
use crate::model::ModelError;
use crate::settings::Preset;
use serde_json::json;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderLanguage {
    Hlsl,
    Glsl,
    Wgsl,
}

fn kernel_and_pattern(preset: &Preset) -> Result<(SeparableKernel, SamplePattern), ModelError> {
    let profile = preset.build_profile()?;
    let kernel = SeparableKernel::importance_sampled(profile.as_ref(), preset.rendering.taps)?;
    let pattern = SamplePattern::new(
        profile.as_ref(),
        preset.rendering.samples,
        AngleSequence::GoldenAngle,
    )?;
    Ok((kernel, pattern))
}

/// `kernel[N]`: (weight r, g, b, offset mm), centre tap first, weights
/// summing to 1 per channel (the Jimenez demo's layout); `burleySamples[M]`:
/// (radius mm, angle rad, 0, 0) and `burleyWeights[M]`: per-channel
/// weight R_c(r)/(N·pdf(r)), whose sum estimates the channel's total
/// reflectance (Golubev 2018).
pub fn kernel_source(
    preset: &Preset,
    lang: ShaderLanguage,
    prov: &Provenance,
) -> Result<String, ModelError> {
    let (kernel, pattern) = kernel_and_pattern(preset)?;
    let f = |v: f64| format!("{:.9}", v as f32);
    let v4 = |a: f64, b: f64, c: f64, d: f64| match lang {
        ShaderLanguage::Hlsl => format!("float4({}, {}, {}, {})", f(a), f(b), f(c), f(d)),
        ShaderLanguage::Glsl => format!("vec4({}, {}, {}, {})", f(a), f(b), f(c), f(d)),
        ShaderLanguage::Wgsl => format!("vec4<f32>({}, {}, {}, {})", f(a), f(b), f(c), f(d)),
    };
    let array = |name: &str, rows: Vec<String>| {
        let n = rows.len();
        let body = rows
            .iter()
            .map(|r| format!("    {r},"))
            .collect::<Vec<_>>()
            .join("\n");
        match lang {
            ShaderLanguage::Hlsl => format!("static const float4 {name}[{n}] = {{\n{body}\n}};\n"),
            ShaderLanguage::Glsl => format!(
                "const vec4 {name}[{n}] = vec4[{n}](\n{}\n);\n",
                body.trim_end_matches(',')
            ),
            ShaderLanguage::Wgsl => format!(
                "const {name}: array<vec4<f32>, {n}> = array<vec4<f32>, {n}>(\n{body}\n);\n"
            ),
        }
    };
    let taps: Vec<String> = kernel
        .taps
        .iter()
        .map(|t| v4(t.weight[0], t.weight[1], t.weight[2], t.offset_mm))
        .collect();
    let positions: Vec<String> = pattern
        .samples
        .iter()
        .map(|s| v4(s.radius_mm, s.angle_rad, 0.0, 0.0))
        .collect();
    let weights: Vec<String> = pattern
        .samples
        .iter()
        .map(|s| v4(s.weight[0], s.weight[1], s.weight[2], 0.0))
        .collect();
    let name = preset.name.replace(['\n', '\r'], " ");
    Ok(format!(
        "// SSS kernels for \"{name}\": {}.
// kernel: {} taps of the pre-integrated separable kernel (Jimenez 2015),
//   xyz = per-channel weight (sums to 1), w = offset in mm; centre tap first.
// burleySamples / burleyWeights: {} Burley disk samples (Golubev 2018,
//   golden-angle): x = radius in mm, y = angle in radians; weights are
//   R_c(r)/(N pdf(r)) per channel; their sum estimates the total reflectance.
{}
{}
{}",
        prov.line(),
        kernel.taps.len(),
        pattern.samples.len(),
        array("kernel", taps),
        array("burleySamples", positions),
        array("burleyWeights", weights),
    ))
}

/// The Burley sample pattern as JSON: radius (mm), angle (rad) and
/// per-channel weight of each sample.
pub fn samples_json(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (_, pattern) = kernel_and_pattern(preset)?;
    let samples: Vec<_> = pattern
        .samples
        .iter()
        .map(|s| json!({"radius_mm": s.radius_mm, "angle_rad": s.angle_rad, "weight": s.weight}))
        .collect();
    let channel = ["r", "g", "b"][pattern.sampled_channel];
    let doc = json!({
        "generator": prov.line(),
        "preset": preset.name,
        "angles": pattern.angles.id(),
        "sampled_channel": channel,
        "units": {"radius": "mm", "angle": "rad", "weight": "R_c(r)/(N pdf(r)) per channel; the sum over samples estimates the total reflectance"},
        "samples": samples,
    });
    Ok(serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n")
}

/// A shader-array target: the kernel and sample pattern in `lang`.
macro_rules! shader_target {
    ($id:literal, $name:literal, $ext:literal, $lang:expr) => {
        super::Target {
            id: $id,
            name: $name,
            description: "separable kernel and Burley sample pattern as arrays",
            extension: $ext,
            companion: None,
            slow: false,
            write: |preset, prov, out, _, _| {
                super::write(out, kernel_source(preset, $lang, prov)?.as_bytes())
            },
            notes: super::no_notes,
            fidelity: super::no_fidelity,
            params: None,
            reader: None,
        }
    };
}

pub(super) const HLSL: super::Target = shader_target!(
    "hlsl",
    "HLSL kernel and samples",
    "hlsl",
    ShaderLanguage::Hlsl
);
pub(super) const GLSL: super::Target = shader_target!(
    "glsl",
    "GLSL kernel and samples",
    "glsl",
    ShaderLanguage::Glsl
);
pub(super) const WGSL: super::Target = shader_target!(
    "wgsl",
    "WGSL kernel and samples",
    "wgsl",
    ShaderLanguage::Wgsl
);

/// The Burley sample pattern as JSON.
pub(super) const SAMPLES_JSON: super::Target = super::Target {
    id: "samples-json",
    name: "Burley samples (JSON)",
    description: "Burley sample pattern: radius (mm), angle, weights",
    extension: "json",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, _| super::write(out, samples_json(preset, prov)?.as_bytes()),
    notes: super::no_notes,
    fidelity: super::no_fidelity,
    params: None,
    reader: None,
};
