//! Why `texture-space` loses to `burley` on the head scan (issue 53, item
//! 1; docs/accuracy.md, "Why `texture-space` loses to `burley` on the
//! scan"): each suspect turned off or changed in turn on the bench's
//! scenes, the ground truth rendered again for each, and where
//! `texture-space`'s error exceeds `burley`'s.
//!
//! `cargo bench --bench texture_space_on_the_scan [-- WIDTH [SCENE,...]]`
//! (default 320 wide, 16:9; `scan_front`). Prints the share of `none`'s
//! error each configuration removes, and writes
//! `target/texture_space_on_the_scan/<scene>_excess.png` (red: texture-space
//! worse than burley; green: better; blue added where it is too bright).

use scatterlab::bench::metrics::{relative_rmse, sss_mask};
use scatterlab::bench::scenes::{scenes, Config};
use scatterlab::bench::{measure, renderer_for, Prepared};
use scatterlab::render::{Method, RenderSettings, TexturingMode};
use scatterlab::settings::Preset;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let width: u32 = args.first().map_or(Ok(320), |w| w.parse())?;
    let size = (width, width * 9 / 16);
    let wanted = args.get(1).cloned().unwrap_or_else(|| "scan_front".into());
    let out =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/texture_space_on_the_scan");
    std::fs::create_dir_all(&out)?;
    let prepared = Prepared::new(&Preset::default_skin())?;
    let all = scenes(size);
    for id in wanted.split(',') {
        let scene = all
            .iter()
            .find(|s| s.id == id)
            .ok_or_else(|| anyhow::anyhow!("no bench scene {id}"))?;
        let mut r = renderer_for(scene.stage)?;
        let cases = [
            ("as shipped", TexturingMode::PreAndPostScatter, 1.0f32),
            ("normal map off", TexturingMode::PreAndPostScatter, 0.0),
            ("post-scatter only", TexturingMode::PostScatter, 1.0),
        ];
        for (case, texturing, detail) in cases {
            let s = |m| RenderSettings {
                method: m,
                texturing,
                detail_normal_strength: detail * scene.settings.detail_normal_strength,
                ..scene.settings.clone()
            };
            let truth = measure(
                &mut r,
                &prepared.inputs(Config::reference())?,
                &s(Method::Reference),
                1,
            )?;
            let mask = sss_mask(&truth.diffuse);
            let none = measure(
                &mut r,
                &prepared.inputs(Config::none())?,
                &s(Method::None),
                1,
            )?;
            let e0 = relative_rmse(&none.diffuse, &truth.diffuse, &mask);
            let share =
                |d: &[[f32; 4]]| 100.0 * (1.0 - relative_rmse(d, &truth.diffuse, &mask) / e0);
            let burley_config =
                Config::of(Method::Burley, "improved", 21).expect("burley improved 21");
            let b = measure(
                &mut r,
                &prepared.inputs(burley_config)?,
                &s(Method::Burley),
                1,
            )?;
            let mut line = format!(
                "{id} {case}: none {e0:.4} | burley {:.0} %",
                share(&b.diffuse)
            );
            let ts_config =
                Config::of(Method::TextureSpace, "atlas1024", 21).expect("texture-space atlas1024");
            for (atlas, near) in [
                (1024u32, 1.0f32),
                (2048, 1.0),
                (1024, 0.0),
                (2048, 0.0),
                (1024, 3.0),
            ] {
                let mut inputs = prepared.inputs(ts_config)?;
                inputs.methods.texture_space.atlas_size = atlas;
                inputs.methods.texture_space.near_field_mm = near;
                inputs.options.texture_space.atlas_size = atlas;
                inputs.options.texture_space.near_field_mm = near;
                let t = measure(&mut r, &inputs, &s(Method::TextureSpace), 1)?;
                line += &format!(
                    " | texture-space {atlas}/{near} mm {:.0} %",
                    share(&t.diffuse)
                );
                if (atlas, near, case) == (1024, 1.0, "as shipped") {
                    excess(
                        &out,
                        id,
                        size,
                        &mask,
                        &truth.diffuse,
                        &t.diffuse,
                        &b.diffuse,
                    )?;
                }
            }
            println!("{line}");
        }
    }
    Ok(())
}

/// The map of where `texture-space`'s relative error (luminance) exceeds
/// `burley`'s, and the share of the gap in summed squared error held by
/// the pixels whose excess is over 4 %.
fn excess(
    out: &std::path::Path,
    id: &str,
    (w, h): (u32, u32),
    mask: &[bool],
    truth: &[[f32; 4]],
    ts: &[[f32; 4]],
    burley: &[[f32; 4]],
) -> anyhow::Result<()> {
    let lum = |p: [f32; 4]| f64::from(p[0] + p[1] + p[2]);
    let mut img = image::RgbImage::new(w, h);
    let (mut gap, mut gap_lines, mut lines, mut n) = (0.0f64, 0.0f64, 0usize, 0usize);
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let t = lum(truth[i]).max(1e-3);
        let et = (lum(ts[i]) - t) / t;
        let eb = (lum(burley[i]) - t) / t;
        let more = et.abs() - eb.abs();
        let v = (more.abs() * 2000.0).min(255.0) as u8;
        let (x, y) = (i as u32 % w, i as u32 / w);
        img.put_pixel(
            x,
            y,
            if more > 0.0 {
                image::Rgb([v, 0, if et > 0.0 { 128 } else { 0 }])
            } else {
                image::Rgb([0, v, 0])
            },
        );
        let d = et * et - eb * eb;
        gap += d;
        n += 1;
        if more > 0.04 {
            gap_lines += d;
            lines += 1;
        }
    }
    let path = out.join(format!("{id}_excess.png"));
    img.save(&path)?;
    println!(
        "{id}: the {lines} of {n} skin pixels where texture-space's error exceeds burley's by over 4 % hold {:.0} % of the gap in summed squared error ({})",
        100.0 * gap_lines / gap,
        path.display()
    );
    Ok(())
}
