//! The ground truth gathered on the GPU (`render --reference-gpu`:
//! shaders/ground_truth.wgsl, with the scene pass's own `shade` for the
//! light it evaluates afresh) held to the CPU ground truth, the reference
//! it must reproduce, and to the d → 0 limit (the `none` frame) on its
//! own. Runs on lavapipe in CI.
//!
//! One test, so that lavapipe compiles the gather's shader once: llvmpipe
//! compiles a compute shader at its first dispatch, and this one (the walk
//! with the scene pass inlined) took 148 s cold on this 2-core machine and
//! 0.3 s from Mesa's shader cache.
#![allow(clippy::unwrap_used)]

mod common;
use common::scan::{scan, scan_view};

use scatterlab::bench::{floor, metrics};
use scatterlab::model::burley::Burley;
use scatterlab::render::{GpuContext, Mesh, Method, ProfileInputs, RenderSettings, Renderer};
use scatterlab::settings::OrbitView;
use std::path::PathBuf;

/// The default head at 320×180, full mesh (the ground truth's own), no
/// SSS level of detail.
fn head_view(method: Method, yaw_deg: f32, light_azimuth_deg: f32) -> RenderSettings {
    RenderSettings {
        view: OrbitView {
            camera_yaw_rad: yaw_deg.to_radians(),
            light_azimuth_rad: light_azimuth_deg.to_radians(),
            light_elevation_rad: 25f32.to_radians(),
            ..Default::default()
        },
        width: 320,
        height: 180,
        method,
        lod: false,
        mesh_lod: false,
        deterministic: true,
        ..Default::default()
    }
}

fn on_gpu(inputs: &ProfileInputs) -> ProfileInputs {
    let mut i = inputs.clone();
    i.options.reference.gpu = true;
    i
}

/// Writes the GPU frame's scattered diffuse and |GPU − CPU| × 10 beside it
/// (Reinhard, for eyes) to target/test-output, for a failed comparison.
fn write_failure(name: &str, a: &[[f32; 4]], b: &[[f32; 4]], (w, h): (u32, u32)) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/test-output");
    std::fs::create_dir_all(&dir).unwrap();
    let tone = |v: f32| ((v / (1.0 + v)).clamp(0.0, 1.0) * 255.0) as u8;
    let mut img = image::RgbImage::new(2 * w, h);
    for (i, (p, q)) in a.iter().zip(b).enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        img.put_pixel(x, y, image::Rgb([tone(p[0]), tone(p[1]), tone(p[2])]));
        let d = |c: usize| tone(10.0 * (p[c] - q[c]).abs());
        img.put_pixel(w + x, y, image::Rgb([d(0), d(1), d(2)]));
    }
    let path = dir.join(format!("{name}-gpu-and-diff.png"));
    img.save(&path).unwrap();
    eprintln!("wrote {}", path.display());
}

/// Renders `s` with the CPU and the GPU gather and holds the GPU frame
/// within `bound` relative RMSE of the CPU's over the SSS pixels. The GPU
/// must have finished at least 3/4 of the points itself (lavapipe ends a
/// long walk early; those points are gathered on the CPU, so a comparison
/// with too few GPU points would prove little).
fn gpu_matches_cpu(r: &mut Renderer, inputs: &ProfileInputs, s: &RenderSettings, name: &str) {
    let (_, cpu, cpu_stats) = r.render_with_diffuse(inputs, s).unwrap();
    let (_, gpu, stats) = r.render_with_diffuse(&on_gpu(inputs), s).unwrap();
    assert_eq!(
        cpu_stats.reference_gpu_unfinished, None,
        "{name}: the CPU frame"
    );
    let mask = metrics::sss_mask(&cpu);
    let pixels = mask.iter().filter(|m| **m).count() as u64;
    let unfinished = stats.reference_gpu_unfinished.unwrap();
    let off = metrics::relative_rmse(&gpu, &cpu, &mask);
    eprintln!(
        "{name}: {pixels} SSS pixels, {unfinished} finished on the CPU, GPU from CPU {off:.5} \
         (CPU {:.0} ms, GPU {:.0} ms)",
        cpu_stats.reference_cpu_ms.unwrap_or(0.0),
        stats.reference_cpu_ms.unwrap_or(0.0)
    );
    assert!(pixels > 5000, "{name}: {pixels} SSS pixels");
    assert!(
        4 * unfinished <= pixels,
        "{name}: the GPU finished only {} of {pixels} points",
        pixels - unfinished
    );
    if off >= 0.002 {
        write_failure(name, &gpu, &cpu, (s.width, s.height));
    }
    assert!(off < 0.002, "{name}: GPU truth {off:.5} from the CPU truth");
}

/// Issue 38's bounds for the GPU path, on lavapipe:
/// - the GPU frame within 0.2 % relative RMSE of the CPU frame on the
///   default head (the view: camera yaw 20°, light azimuth 50°,
///   elevation 25°; and a back-lit one, light azimuth 160°, where the
///   light reaches the seen skin through the ear and from surface the
///   camera does not see) and on two views of the scan with its own maps;
/// - a profile that scatters nothing (d = 1 µm, `bench::floor`) gathered
///   on the GPU gives back the unscattered frame within 0.5 %.
///
/// Before the walk reported an end it did not reach, the default head's
/// GPU frame was 9.7 % from the CPU's: lavapipe stopped the walk at 65,535
/// loop iterations (the eyes, lips and ear, where triangles are small).
#[test]
fn gpu_truth_is_the_cpu_truth() {
    let ctx = GpuContext::new_headless().expect("a GPU adapter (lavapipe)");
    let mut r = Renderer::new(ctx, &Mesh::default_head().unwrap()).unwrap();
    let profile = Burley::from_scattering_distance([0.8; 3], [1.0, 0.5, 0.25]).unwrap();
    let inputs = ProfileInputs::new(&profile, 21, 17).unwrap();

    let zero = floor::d_to_zero_inputs(&inputs).unwrap();
    let (_, none, _) = r
        .render_with_diffuse(&zero, &head_view(Method::None, 20.0, 50.0))
        .unwrap();
    let (_, gpu, _) = r
        .render_with_diffuse(&on_gpu(&zero), &head_view(Method::Reference, 20.0, 50.0))
        .unwrap();
    let mask = metrics::sss_mask(&none);
    let off = metrics::relative_rmse(&gpu, &none, &mask);
    eprintln!("d → 0 on the GPU: {off:.5} from none");
    if off >= 0.005 {
        write_failure("head-d-to-zero", &gpu, &none, (320, 180));
    }
    assert!(off < 0.005, "d → 0 on the GPU: {off:.5} from none");

    for (yaw, light) in [(20.0, 50.0), (-30.0, 160.0)] {
        let s = head_view(Method::Reference, yaw, light);
        gpu_matches_cpu(
            &mut r,
            &inputs,
            &s,
            &format!("head yaw {yaw} light {light}"),
        );
    }

    let mesh = scan();
    let mut r = Renderer::new(GpuContext::new_headless().unwrap(), &mesh).unwrap();
    let skin = scatterlab::settings::Preset::default_skin()
        .build_profile()
        .unwrap();
    let look = ProfileInputs::new(skin.as_ref(), 21, 17).unwrap();
    for (name, yaw, light) in [("side", 70.0, (50.0, 25.0)), ("front", 25.0, (60.0, 20.0))] {
        gpu_matches_cpu(
            &mut r,
            &look,
            &scan_view(&mesh, yaw, light),
            &format!("scan {name}"),
        );
    }
}
