//! `scatterlab lut`: Penner's pre-integrated and penumbra tables.

use super::args::{parse_list, ModelArgs, NumberList};
use super::built;
use crate::model::lut::{self, LutEncoding, LutLayout, ShadowLayout};
use crate::model::Rgb;
use anyhow::{bail, Context, Result};
use clap::{Subcommand, ValueEnum};
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, Subcommand)]
pub enum LutCommand {
    /// Penner's pre-integrated D(θ, curvature radius).
    Preintegrated {
        #[command(flatten)]
        model: ModelArgs,
        /// Angles between N and L (radians).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "T1,T2,…")]
        theta: Option<NumberList>,
        /// Curvature radii (mm).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "C1,C2,…")]
        curvature_radius: Option<NumberList>,
        /// Write the table as a PNG (θ or N·L across, curvature down).
        #[arg(long, value_name = "FILE.png")]
        out: Option<PathBuf>,
        /// PNG encoding: linear D or FaceWorks' delta from saturate(N·L).
        #[arg(long, value_enum, default_value = "linear")]
        encoding: EncodingArg,
        /// Baked table size when no --theta/--curvature-radius lists are given.
        #[arg(long, default_value_t = 256)]
        size: usize,
        #[arg(long)]
        json: bool,
    },
    /// Penner's shadow-penumbra table (linear PNG).
    Shadow {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        #[arg(long, default_value_t = 64)]
        size: usize,
    },
}

impl LutCommand {
    pub fn run(self) -> Result<()> {
        match self {
            LutCommand::Preintegrated {
                model,
                theta,
                curvature_radius,
                out,
                encoding,
                size,
                json,
            } => lut_preintegrated(&model, theta, curvature_radius, out, encoding, size, json),
            LutCommand::Shadow { model, out, size } => lut_shadow(&model, &out, size),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    Linear,
    FaceworksDelta,
}

#[allow(clippy::too_many_arguments)]
fn lut_preintegrated(
    model: &ModelArgs,
    theta: Option<NumberList>,
    radii: Option<NumberList>,
    out: Option<PathBuf>,
    encoding: EncodingArg,
    size: usize,
    as_json: bool,
) -> Result<()> {
    let (_, p) = built(model)?;
    let enc = match encoding {
        EncodingArg::Linear => LutEncoding::Linear,
        EncodingArg::FaceworksDelta => LutEncoding::FaceWorksDelta,
    };
    match (theta, radii) {
        (Some(t), Some(c)) => {
            for &th in &t.0 {
                for &cr in &c.0 {
                    lut::check_lut_inputs(th, cr)?;
                }
            }
            let d: Vec<Vec<Rgb>> =
                t.0.iter()
                    .map(|&th| {
                        c.0.iter()
                            .map(|&cr| lut::preintegrated_d(p.as_ref(), th, cr))
                            .collect()
                    })
                    .collect();
            if let Some(path) = &out {
                let (w, h) = (t.0.len(), c.0.len());
                let mut px = Vec::with_capacity(w * h * 3);
                for j in 0..h {
                    for (i, th) in t.0.iter().enumerate() {
                        px.extend(d[i][j].map(|v| {
                            (enc.encode(v, th.cos()).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                        }));
                    }
                }
                write_png(path, w, h, px)?;
            }
            if as_json {
                println!("{}", json!({ "D": d }));
            } else if out.is_none() {
                for (th, row) in t.0.iter().zip(&d) {
                    for (cr, v) in c.0.iter().zip(row) {
                        println!(
                            "theta {th:.6} rad, curvature radius {cr:.4} mm: D = {:.6} {:.6} {:.6}",
                            v[0], v[1], v[2]
                        );
                    }
                }
            }
            Ok(())
        }
        (None, None) => {
            let Some(path) = out else {
                bail!(
                    "give --theta and --curvature-radius lists, or --out FILE.png to bake a table"
                )
            };
            if as_json {
                bail!("--json needs --theta and --curvature-radius lists");
            }
            let layout = LutLayout {
                width: size,
                height: size,
                ..LutLayout::default()
            };
            let table = lut::Lut::bake(p.as_ref(), layout)?;
            write_png(&path, size, size, table.to_rgb8(enc))?;
            println!(
                "wrote {} ({size}×{size}, x: N·L −1→1, y: 1/c from 1/{} to 1/{} mm⁻¹, {:?}, linear 8-bit)",
                path.display(),
                layout.curvature_radius_max_mm,
                layout.curvature_radius_min_mm,
                enc
            );
            Ok(())
        }
        _ => bail!("--theta and --curvature-radius go together"),
    }
}

fn lut_shadow(model: &ModelArgs, out: &std::path::Path, size: usize) -> Result<()> {
    let (_, p) = built(model)?;
    let layout = ShadowLayout {
        width: size,
        height: size,
        ..ShadowLayout::default()
    };
    let t = lut::bake_shadow(p.as_ref(), layout)?;
    let px: Vec<u8> = t
        .iter()
        .flat_map(|v| v.map(|x| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
        .collect();
    write_png(out, size, size, px)?;
    println!(
        "wrote {} ({size}×{size}, x: unscattered shadow 0→1, y: 1/penumbra width from 1/{} to 1/{} mm⁻¹, linear 8-bit)",
        out.display(),
        layout.penumbra_max_mm,
        layout.penumbra_min_mm
    );
    Ok(())
}

fn write_png(path: &std::path::Path, w: usize, h: usize, rgb8: Vec<u8>) -> Result<()> {
    let img = image::RgbImage::from_raw(w as u32, h as u32, rgb8)
        .context("internal: image size mismatch")?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    crate::fsutil::write_atomic(path, &bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}
