//! Argument types: comma-separated lists, `R,G,B` colours and `;`-separated
//! colour lists, and the flags that choose a profile model.

use crate::model::units::{
    BlenderSubsurface, UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE,
};
use crate::model::Rgb;
use crate::settings::profile::{
    ArtistSpec, BurleyShape, BurleySpec, DipoleSpec, GaussianTerm, GaussiansSpec, Jimenez2012Spec,
    MeasuredSpec, MultipoleSpec, ScalingFit,
};
use crate::settings::{Preset, ProfileSpec};
use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::PathBuf;

/// A comma-separated list of numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct NumberList(pub Vec<f64>);

/// One colour `R,G,B`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Color(pub Rgb);

/// Colours separated by `;`: `R,G,B;R,G,B`.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorList(pub Vec<Rgb>);

fn number(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| format!("`{}` is not a number", s.trim()))
}

pub fn parse_list(s: &str) -> Result<NumberList, String> {
    if s.trim().is_empty() {
        return Err("expected comma-separated numbers, got nothing".into());
    }
    s.split(',')
        .map(number)
        .collect::<Result<Vec<_>, _>>()
        .map(NumberList)
}

pub fn parse_color(s: &str) -> Result<Color, String> {
    let v = parse_list(s)?.0;
    match v.as_slice() {
        [r, g, b] => Ok(Color([*r, *g, *b])),
        _ => Err(format!(
            "expected a colour R,G,B (three numbers), got {} number(s) in `{s}`",
            v.len()
        )),
    }
}

pub fn parse_color_list(s: &str) -> Result<ColorList, String> {
    s.split(';')
        .map(|c| parse_color(c).map(|c| c.0))
        .collect::<Result<Vec<_>, _>>()
        .map(ColorList)
}

/// What `--model` names: one of the look's models (`ProfileSpec::models`,
/// by its `model_name`), or an engine's parameters converted to Burley.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelKind {
    Model(ProfileSpec),
    /// Unity HDRP diffusion profile parameters (converted to Burley).
    Unity,
    /// Unreal Engine 5 subsurface profile parameters (converted to Burley).
    Unreal,
    /// Blender Principled BSDF Christensen–Burley parameters (converted to Burley).
    Blender,
}

/// The engines whose parameters `--model` converts, by name.
const ENGINE_MODELS: [(&str, ModelKind); 3] = [
    ("unity", ModelKind::Unity),
    ("unreal", ModelKind::Unreal),
    ("blender", ModelKind::Blender),
];

/// `--model`'s values: every model's name (`jimenez` also names Jimenez
/// 2012), then the engines'.
pub fn model_parser() -> impl clap::builder::TypedValueParser<Value = ModelKind> {
    use clap::builder::PossibleValue;
    let models = ProfileSpec::models().map(|m| m.model_name());
    let values = models
        .into_iter()
        .map(|name| match name {
            "jimenez2012" => PossibleValue::new(name).alias("jimenez"),
            _ => PossibleValue::new(name),
        })
        .chain(
            ENGINE_MODELS
                .iter()
                .map(|(name, _)| PossibleValue::new(*name)),
        );
    clap::builder::TypedValueParser::map(clap::builder::PossibleValuesParser::new(values), |name| {
        let model = ProfileSpec::models().into_iter().find(|m| {
            m.model_name() == name || (name == "jimenez" && m.model_name() == "jimenez2012")
        });
        match model {
            Some(m) => ModelKind::Model(m),
            None => ENGINE_MODELS
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(ModelKind::Unity, |(_, kind)| kind.clone()),
        }
    })
}

/// Flags that choose and parameterise a profile. Without `--model` or
/// `--preset` the embedded default skin preset is used.
#[derive(Debug, Clone, Default, Args)]
pub struct ModelArgs {
    /// Profile model.
    #[arg(long, value_parser = model_parser())]
    pub model: Option<ModelKind>,
    /// Read the profile from a preset file (RON).
    #[arg(long, value_name = "FILE.ron", conflicts_with = "model")]
    pub preset: Option<PathBuf>,
    /// Burley volume albedo A, linear RGB in [0, 1].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub albedo: Option<Color>,
    /// Burley scattering distance d = 1/s per channel (mm).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub distance: Option<Color>,
    /// Burley (diffuse) mean free path per channel (mm), used with --fit.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B", conflicts_with = "distance")]
    pub mean_free_path: Option<Color>,
    /// Which Christensen-Burley s(A) fit turns --mean-free-path into a shape.
    #[arg(long, value_enum, requires = "mean_free_path")]
    pub fit: Option<ScalingFit>,
    /// Gaussian variances (mm²).
    #[arg(long, value_parser = parse_list, value_name = "V1,V2,…", requires = "weights", allow_hyphen_values = true)]
    pub variances: Option<NumberList>,
    /// Gaussian RGB weights, one colour per variance.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color_list, value_name = "R,G,B;R,G,B;…", requires = "variances")]
    pub weights: Option<ColorList>,
    /// Dipole absorption coefficient σa (1/mm).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub sigma_a: Option<Color>,
    /// Dipole reduced scattering coefficient σ′s (1/mm).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub sigma_s_prime: Option<Color>,
    /// Relative index of refraction η (default 1.3).
    #[arg(long, allow_hyphen_values = true)]
    pub eta: Option<f64>,
    /// A measured material (Jensen 2001, Narasimhan 2006), e.g. Skin1, Marble.
    #[arg(long, value_name = "NAME", conflicts_with_all = ["sigma_a", "sigma_s_prime"])]
    pub measured: Option<String>,
    /// Multipole layer stack (RON: layers, eta_above, eta_below, dipoles).
    #[arg(long, value_name = "FILE.ron")]
    pub layers: Option<PathBuf>,
    /// Multipole: mirrored dipole pairs per slab.
    #[arg(long)]
    pub dipoles: Option<u32>,
    /// Jimenez 2012 strength per channel in [0, 1].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub strength: Option<Color>,
    /// Jimenez 2012 falloff per channel in [0, 1].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub falloff: Option<Color>,
    /// Artist model σ′n per channel (relative to --scale).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub sigma_near: Option<Color>,
    /// Artist model σ′f per channel (relative to --scale).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub sigma_far: Option<Color>,
    /// Artist model near weight w in [0, 1].
    #[arg(long, allow_hyphen_values = true)]
    pub weight: Option<f64>,
    /// Artist model scale s (mm).
    #[arg(long, allow_hyphen_values = true)]
    pub scale: Option<f64>,
    /// Artist model: a Jimenez 2015 Table 2 kernel (single-layer, multi-layer, production).
    #[arg(long, value_name = "NAME")]
    pub artist_preset: Option<String>,
    /// Unity: Scattering Color (LDR, linear RGB).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub scattering_color: Option<Color>,
    /// Unity: scattering distance multiplier (mm at world scale 1).
    #[arg(long, allow_hyphen_values = true)]
    pub multiplier: Option<f64>,
    /// Unreal: Mean Free Path Color.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub mfp_color: Option<Color>,
    /// Unreal: Mean Free Path Distance (cm).
    #[arg(long, allow_hyphen_values = true)]
    pub mfp_distance_cm: Option<f64>,
    /// Unreal: World Unit Scale (default 0.1, physical).
    #[arg(long, allow_hyphen_values = true)]
    pub world_unit_scale: Option<f64>,
    /// Blender: Subsurface Radius.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub subsurface_radius: Option<Color>,
    /// Blender: Subsurface Scale (scene units).
    #[arg(long, allow_hyphen_values = true)]
    pub subsurface_scale: Option<f64>,
    /// Blender: metres per scene unit (default 1).
    #[arg(long = "blender-metres-per-unit", allow_hyphen_values = true)]
    pub blender_metres_per_unit: Option<f64>,
}

impl ModelArgs {
    /// Names of the flags given on the command line.
    fn given(&self) -> Vec<&'static str> {
        let flags: [(&str, bool); 18] = [
            ("--albedo", self.albedo.is_some()),
            ("--distance", self.distance.is_some()),
            ("--mean-free-path", self.mean_free_path.is_some()),
            ("--fit", self.fit.is_some()),
            ("--variances", self.variances.is_some()),
            ("--weights", self.weights.is_some()),
            ("--sigma-a", self.sigma_a.is_some()),
            ("--sigma-s-prime", self.sigma_s_prime.is_some()),
            ("--eta", self.eta.is_some()),
            ("--measured", self.measured.is_some()),
            ("--layers", self.layers.is_some()),
            ("--dipoles", self.dipoles.is_some()),
            ("--strength", self.strength.is_some()),
            ("--falloff", self.falloff.is_some()),
            ("--sigma-near", self.sigma_near.is_some()),
            ("--sigma-far", self.sigma_far.is_some()),
            ("--weight", self.weight.is_some()),
            ("--scale", self.scale.is_some()),
        ];
        let engine: [(&str, bool); 9] = [
            ("--artist-preset", self.artist_preset.is_some()),
            ("--scattering-color", self.scattering_color.is_some()),
            ("--multiplier", self.multiplier.is_some()),
            ("--mfp-color", self.mfp_color.is_some()),
            ("--mfp-distance-cm", self.mfp_distance_cm.is_some()),
            ("--world-unit-scale", self.world_unit_scale.is_some()),
            ("--subsurface-radius", self.subsurface_radius.is_some()),
            ("--subsurface-scale", self.subsurface_scale.is_some()),
            (
                "--blender-metres-per-unit",
                self.blender_metres_per_unit.is_some(),
            ),
        ];
        flags
            .iter()
            .chain(&engine)
            .filter(|f| f.1)
            .map(|f| f.0)
            .collect()
    }

    /// Rejects flags that the chosen model does not read.
    fn only(&self, model: &str, allowed: &[&str]) -> Result<()> {
        if let Some(extra) = self.given().into_iter().find(|f| !allowed.contains(f)) {
            bail!("{extra} does not apply to {model}");
        }
        Ok(())
    }

    /// The profile these flags describe, validated.
    pub fn spec(&self) -> Result<ProfileSpec> {
        let spec = match (&self.model, &self.preset) {
            (_, Some(path)) => {
                self.only("--preset", &[])?;
                Preset::load(path)?.profile
            }
            (None, None) => {
                self.only("the default preset (give --model)", &[])?;
                Preset::default_skin().profile
            }
            (Some(ModelKind::Model(model)), _) => self.model(model)?,
            (Some(ModelKind::Unity), _) => self.unity()?,
            (Some(ModelKind::Unreal), _) => self.unreal()?,
            (Some(ModelKind::Blender), _) => self.blender()?,
        };
        spec.build()?;
        Ok(spec)
    }

    /// The look's `model` from the flags that describe it.
    fn model(&self, model: &ProfileSpec) -> Result<ProfileSpec> {
        Ok(match model {
            ProfileSpec::Burley(_) => self.burley()?,
            ProfileSpec::Gaussians(_) => self.gaussians()?,
            ProfileSpec::Dipole(_) => self.dipole()?,
            ProfileSpec::Measured(_) if self.measured.is_none() => {
                bail!("--model measured needs --measured NAME (a Jensen 2001 or Narasimhan 2006 table, e.g. Skin1)")
            }
            ProfileSpec::Measured(_) => self.dipole()?,
            ProfileSpec::Multipole(_) => self.multipole()?,
            ProfileSpec::Jimenez2012(_) => {
                self.only("--model jimenez2012", &["--strength", "--falloff"])?;
                let d = Jimenez2012Spec::default();
                ProfileSpec::Jimenez2012(Jimenez2012Spec {
                    strength: self.strength.map_or(d.strength, |c| c.0),
                    falloff: self.falloff.map_or(d.falloff, |c| c.0),
                })
            }
            ProfileSpec::Artist(_) => self.artist()?,
        })
    }

    fn burley(&self) -> Result<ProfileSpec> {
        self.only(
            "--model burley",
            &["--albedo", "--distance", "--mean-free-path", "--fit"],
        )?;
        let d = BurleySpec::default();
        let shape = match (self.distance, self.mean_free_path) {
            (Some(c), _) => BurleyShape::ScatteringDistance {
                mm: c.0,
                multiplier: 1.0,
            },
            (None, Some(m)) => BurleyShape::MeanFreePath {
                mm: m.0,
                fit: self.fit.unwrap_or(ScalingFit::DiffuseMeanFreePath),
            },
            (None, None) => d.shape,
        };
        Ok(ProfileSpec::Burley(BurleySpec {
            albedo: self.albedo.map_or(d.albedo, |c| c.0),
            shape,
        }))
    }

    fn gaussians(&self) -> Result<ProfileSpec> {
        self.only("--model gaussians", &["--variances", "--weights"])?;
        Ok(match (&self.variances, &self.weights) {
            (Some(v), Some(w)) => {
                if v.0.len() != w.0.len() {
                    bail!(
                        "--variances has {} value(s) but --weights has {} colour(s)",
                        v.0.len(),
                        w.0.len()
                    );
                }
                ProfileSpec::Gaussians(GaussiansSpec {
                    gaussians: v
                        .0
                        .iter()
                        .zip(&w.0)
                        .map(|(v, w)| GaussianTerm {
                            variance_mm2: *v,
                            weights: *w,
                        })
                        .collect(),
                    dirac: [0.0; 3],
                })
            }
            _ => ProfileSpec::Gaussians(GaussiansSpec::default()),
        })
    }

    fn dipole(&self) -> Result<ProfileSpec> {
        self.only(
            "--model dipole",
            &["--sigma-a", "--sigma-s-prime", "--eta", "--measured"],
        )?;
        let eta = self.eta.unwrap_or(1.3);
        if let Some(name) = &self.measured {
            return Ok(ProfileSpec::Measured(MeasuredSpec {
                name: name.clone(),
                eta,
            }));
        }
        let d = DipoleSpec::default();
        match (self.sigma_a, self.sigma_s_prime) {
            (Some(a), Some(s)) => Ok(ProfileSpec::Dipole(DipoleSpec {
                sigma_a_per_mm: a.0,
                sigma_s_prime_per_mm: s.0,
                eta,
            })),
            (None, None) => Ok(ProfileSpec::Dipole(DipoleSpec { eta, ..d })),
            _ => bail!(
                "--model dipole needs both --sigma-a and --sigma-s-prime (or --measured NAME)"
            ),
        }
    }

    fn multipole(&self) -> Result<ProfileSpec> {
        self.only("--model multipole", &["--layers", "--dipoles"])?;
        let mut spec = match &self.layers {
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .with_context(|| format!("{}: cannot read", path.display()))?;
                ron::Options::default()
                    .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
                    .from_str::<MultipoleSpec>(&text)
                    .with_context(|| format!("{}: not a valid layer stack", path.display()))?
            }
            None => MultipoleSpec::default(),
        };
        if let Some(n) = self.dipoles {
            spec.dipoles = n;
        }
        let p = ProfileSpec::Multipole(spec);
        if let Some(path) = &self.layers {
            p.build().with_context(|| path.display().to_string())?;
        }
        Ok(p)
    }

    fn unity(&self) -> Result<ProfileSpec> {
        self.only(
            "--model unity",
            &["--albedo", "--scattering-color", "--multiplier"],
        )?;
        let color = self
            .scattering_color
            .context("--model unity needs --scattering-color R,G,B")?;
        let u = UnityProfile {
            scattering_distance_color: color.0,
            scattering_distance_multiplier: self.multiplier.unwrap_or(1.0),
            world_scale_m_per_unit: 1.0,
        };
        Ok(burley_spec(
            &u.to_burley(self.albedo.map_or([1.0; 3], |c| c.0))?,
        ))
    }

    fn unreal(&self) -> Result<ProfileSpec> {
        self.only(
            "--model unreal",
            &[
                "--albedo",
                "--mfp-color",
                "--mfp-distance-cm",
                "--world-unit-scale",
            ],
        )?;
        let u = UnrealProfile {
            surface_albedo: self
                .albedo
                .context("--model unreal needs --albedo R,G,B (SurfaceAlbedo)")?
                .0,
            mean_free_path_color: self
                .mfp_color
                .context("--model unreal needs --mfp-color R,G,B")?
                .0,
            mean_free_path_distance_cm: self
                .mfp_distance_cm
                .context("--model unreal needs --mfp-distance-cm X")?,
            world_unit_scale: self
                .world_unit_scale
                .unwrap_or(UNREAL_DEFAULT_WORLD_UNIT_SCALE),
        };
        Ok(burley_spec(&u.to_burley()?))
    }

    fn blender(&self) -> Result<ProfileSpec> {
        self.only(
            "--model blender",
            &[
                "--albedo",
                "--subsurface-radius",
                "--subsurface-scale",
                "--blender-metres-per-unit",
            ],
        )?;
        let b = BlenderSubsurface {
            base_color: self
                .albedo
                .context("--model blender needs --albedo R,G,B (Base Color)")?
                .0,
            subsurface_radius: self
                .subsurface_radius
                .context("--model blender needs --subsurface-radius R,G,B")?
                .0,
            subsurface_scale: self
                .subsurface_scale
                .context("--model blender needs --subsurface-scale X")?,
            metres_per_unit: self.blender_metres_per_unit.unwrap_or(1.0),
        };
        Ok(burley_spec(&b.to_burley()?))
    }

    fn artist(&self) -> Result<ProfileSpec> {
        self.only(
            "--model artist",
            &[
                "--sigma-near",
                "--sigma-far",
                "--weight",
                "--scale",
                "--artist-preset",
            ],
        )?;
        let base = match &self.artist_preset {
            Some(name) => {
                let m = crate::model::separable::ArtistTwoGaussian::table2(name)?;
                ArtistSpec {
                    sigma_near: m.sigma_near(),
                    sigma_far: m.sigma_far(),
                    weight: m.weight(),
                    scale_mm: m.scale_mm(),
                }
            }
            None => ArtistSpec::default(),
        };
        Ok(ProfileSpec::Artist(ArtistSpec {
            sigma_near: self.sigma_near.map_or(base.sigma_near, |c| c.0),
            sigma_far: self.sigma_far.map_or(base.sigma_far, |c| c.0),
            weight: self.weight.unwrap_or(base.weight),
            scale_mm: self.scale.unwrap_or(base.scale_mm),
        }))
    }
}

/// A Burley spec holding a built profile's A and d.
fn burley_spec(b: &crate::model::burley::Burley) -> ProfileSpec {
    ProfileSpec::Burley(BurleySpec {
        albedo: b.albedo(),
        shape: BurleyShape::ScatteringDistance {
            mm: b.scattering_distance_mm(),
            multiplier: 1.0,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers_accept_and_reject() {
        assert_eq!(parse_list("1, 2.5,3e-2").unwrap().0, vec![1.0, 2.5, 0.03]);
        assert!(parse_list("1,,2").is_err());
        assert_eq!(parse_color("0.1,0.2,0.3").unwrap().0, [0.1, 0.2, 0.3]);
        assert!(parse_color("0.1,0.2")
            .unwrap_err()
            .contains("three numbers"));
        assert_eq!(parse_color_list("1,2,3;4,5,6").unwrap().0.len(), 2);
    }
}
