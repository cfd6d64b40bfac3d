//! The profile part of a look: which model and its parameters, in units.

use crate::model::burley::Burley;
/// How a mean free path becomes a shape; presets store it by name.
pub use crate::model::burley::ScalingFit;
use crate::model::dipole::{Dipole, Medium};
use crate::model::gaussian::{GaussianSum, DEON_SKIN};
use crate::model::jimenez::{Jimenez2012, DEFAULT_FALLOFF, DEFAULT_STRENGTH};
use crate::model::multipole::{Layer, LayeredMultipole, MultipoleSlab, DEFAULT_DIPOLES};
use crate::model::separable::ArtistTwoGaussian;
use crate::model::{measured, ModelError, RadialProfile, Rgb};
use serde::{Deserialize, Serialize};

/// Unity HDRP's default skin scattering distance (mm), as Golubev 2018 ships it in HDRP.
pub const UNITY_DEFAULT_SKIN_DISTANCE_MM: Rgb = [0.756_862_8, 0.321_568_64, 0.2];

/// A diffusion profile model with its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ProfileSpec {
    /// Burley normalized diffusion (Christensen & Burley 2015).
    Burley(BurleySpec),
    /// A sum of 2D Gaussians (d'Eon 2007).
    Gaussians(GaussiansSpec),
    /// Jimenez 2012 separable SSS (strength/falloff).
    Jimenez2012(Jimenez2012Spec),
    /// Jimenez 2015 artist-friendly two-Gaussian model.
    Artist(ArtistSpec),
    /// Dipole (Donner & Jensen 2005 form) from optical properties.
    Dipole(DipoleSpec),
    /// Dipole of a measured material (Jensen 2001, Narasimhan 2006).
    Measured(MeasuredSpec),
    /// Multipole stack of slabs (Donner & Jensen 2005).
    Multipole(MultipoleSpec),
}

impl Default for ProfileSpec {
    fn default() -> Self {
        ProfileSpec::Burley(BurleySpec::default())
    }
}

/// How a Burley profile's shape is given. Unknown fields inside either
/// variant are errors, as everywhere in a preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum BurleyShape {
    /// Unity's parameter: d per channel (mm) times a multiplier.
    ScatteringDistance { mm: Rgb, multiplier: f64 },
    /// A (diffuse) mean free path (mm) through one of the published fits.
    MeanFreePath { mm: Rgb, fit: ScalingFit },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BurleySpec {
    /// Volume albedo A = total diffuse reflectance, linear RGB in [0, 1].
    pub albedo: Rgb,
    pub shape: BurleyShape,
}

impl Default for BurleySpec {
    fn default() -> Self {
        Self {
            albedo: [1.0; 3],
            shape: BurleyShape::ScatteringDistance {
                mm: UNITY_DEFAULT_SKIN_DISTANCE_MM,
                multiplier: 1.0,
            },
        }
    }
}

/// The scattering distance's multiplier (Unity's).
pub const MULTIPLIER_RANGE: (f64, f64) = (1e-6, 1e6);

impl BurleySpec {
    pub fn build(&self) -> Result<Burley, ModelError> {
        let (lo, hi) = crate::model::burley::ALBEDO_RANGE;
        crate::model::check_rgb("albedo", self.albedo, lo, hi, "")?;
        match &self.shape {
            BurleyShape::ScatteringDistance { mm, multiplier } => {
                let (lo, hi) = MULTIPLIER_RANGE;
                crate::model::check_range("shape.multiplier", *multiplier, lo, hi, "")?;
                let d = crate::model::rgb_map(|c| mm[c] * multiplier);
                Burley::from_scattering_distance(self.albedo, d).map_err(|e| prefix("shape.", e))
            }
            BurleyShape::MeanFreePath { mm, fit } => {
                Burley::from_mean_free_path(self.albedo, *mm, *fit)
            }
        }
    }
}

/// One Gaussian: variance (mm²) and RGB weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GaussianTerm {
    pub variance_mm2: f64,
    pub weights: Rgb,
}

impl Default for GaussianTerm {
    fn default() -> Self {
        Self {
            variance_mm2: 1.0,
            weights: [1.0; 3],
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GaussiansSpec {
    pub gaussians: Vec<GaussianTerm>,
    /// Light per channel that leaves where it entered (a Dirac part at
    /// r = 0), as a Godot kernel or a Jimenez 2012 look keeps it; 0 in
    /// files from before the field.
    pub dirac: Rgb,
}

impl Default for GaussiansSpec {
    fn default() -> Self {
        Self {
            gaussians: DEON_SKIN
                .iter()
                .map(|(v, w)| GaussianTerm {
                    variance_mm2: *v,
                    weights: *w,
                })
                .collect(),
            dirac: [0.0; 3],
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Jimenez2012Spec {
    pub strength: Rgb,
    pub falloff: Rgb,
}

impl Default for Jimenez2012Spec {
    fn default() -> Self {
        Self {
            strength: DEFAULT_STRENGTH,
            falloff: DEFAULT_FALLOFF,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ArtistSpec {
    /// σ′n per channel, relative to `scale_mm`.
    pub sigma_near: Rgb,
    /// σ′f per channel, relative to `scale_mm`.
    pub sigma_far: Rgb,
    /// Weight w of the near Gaussian.
    pub weight: f64,
    /// Global scale s (mm).
    pub scale_mm: f64,
}

impl Default for ArtistSpec {
    fn default() -> Self {
        // Jimenez 2015 Table 2, "production".
        Self {
            sigma_near: [0.22, 0.07, 0.07],
            sigma_far: [1.0, 0.3, 0.15],
            weight: 0.65,
            scale_mm: 9.9,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DipoleSpec {
    pub sigma_a_per_mm: Rgb,
    pub sigma_s_prime_per_mm: Rgb,
    /// Relative index of refraction η ∈ [1, 2].
    pub eta: f64,
}

impl Default for DipoleSpec {
    fn default() -> Self {
        // Jensen 2001 Skin1.
        Self {
            sigma_a_per_mm: [0.032, 0.17, 0.48],
            sigma_s_prime_per_mm: [0.74, 0.88, 1.01],
            eta: 1.3,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MeasuredSpec {
    pub name: String,
    pub eta: f64,
}

impl Default for MeasuredSpec {
    fn default() -> Self {
        Self {
            name: "Skin1".into(),
            eta: 1.3,
        }
    }
}

/// One slab of a multipole stack.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LayerSpec {
    pub sigma_a_per_mm: Rgb,
    pub sigma_s_prime_per_mm: Rgb,
    pub eta: f64,
    /// Thickness (mm); `None` makes a semi-infinite base (last layer only).
    pub thickness_mm: Option<f64>,
}

impl Default for LayerSpec {
    fn default() -> Self {
        Self {
            sigma_a_per_mm: [0.032, 0.17, 0.48],
            sigma_s_prime_per_mm: [0.74, 0.88, 1.01],
            eta: 1.4,
            thickness_mm: None,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultipoleSpec {
    /// Top to bottom.
    pub layers: Vec<LayerSpec>,
    /// Index of the medium light comes from (air = 1).
    pub eta_above: f64,
    /// Index of the medium under a finite last layer.
    pub eta_below: f64,
    /// Mirrored dipole pairs n per slab (2n + 1 dipoles).
    pub dipoles: u32,
}

impl Default for MultipoleSpec {
    fn default() -> Self {
        // Donner & Jensen 2006 fig. 4a (Mikkelsen 2009 Table 3).
        Self {
            layers: vec![
                LayerSpec {
                    sigma_a_per_mm: [0.005; 3],
                    sigma_s_prime_per_mm: [1.3; 3],
                    eta: 1.4,
                    thickness_mm: Some(6.0),
                },
                LayerSpec {
                    sigma_a_per_mm: [0.01; 3],
                    sigma_s_prime_per_mm: [1.0; 3],
                    eta: 1.4,
                    thickness_mm: None,
                },
            ],
            eta_above: 1.0,
            eta_below: 1.0,
            dipoles: DEFAULT_DIPOLES,
        }
    }
}

impl MultipoleSpec {
    pub fn layers(&self) -> Vec<Layer> {
        self.layers
            .iter()
            .map(|l| Layer {
                medium: Medium {
                    sigma_a_per_mm: l.sigma_a_per_mm,
                    sigma_s_prime_per_mm: l.sigma_s_prime_per_mm,
                },
                thickness_mm: l.thickness_mm,
                eta: l.eta,
            })
            .collect()
    }

    /// One finite slab or a semi-infinite layer uses the closed forms;
    /// stacks go through frequency space.
    pub fn build(&self) -> Result<Box<dyn RadialProfile>, ModelError> {
        let layers = self.layers();
        match layers.as_slice() {
            [only] if only.thickness_mm.is_some() => Ok(Box::new(MultipoleSlab::new(
                only,
                self.eta_above,
                self.eta_below,
                self.dipoles,
                "layers[0].",
            )?)),
            [only] => {
                crate::model::check_range("eta_above", self.eta_above, 1.0, 2.0, "")?;
                crate::model::check_range("layers[0].eta", only.eta, 1.0, 2.0, "")?;
                Ok(Box::new(
                    Dipole::with_relative_index(only.medium, only.eta / self.eta_above)
                        .map_err(|e| prefix("layers[0].", e))?,
                ))
            }
            _ => Ok(Box::new(LayeredMultipole::new(
                &layers,
                self.eta_above,
                self.eta_below,
                self.dipoles,
            )?)),
        }
    }
}

fn prefix(p: &str, e: ModelError) -> ModelError {
    match e {
        ModelError::OutOfRange {
            field,
            value,
            min,
            max,
            unit,
        } => ModelError::OutOfRange {
            field: format!("{p}{field}"),
            value,
            min,
            max,
            unit,
        },
        ModelError::NotFinite { field, value } => ModelError::NotFinite {
            field: format!("{p}{field}"),
            value,
        },
        ModelError::Invalid { field, reason } => ModelError::Invalid {
            field: format!("{p}{field}"),
            reason,
        },
    }
}

impl ProfileSpec {
    /// Every model with its defaults, in the editor's picker order
    /// (`models_lists_every_variant_once` checks the list against
    /// [`ProfileSpec::describe`]'s exhaustive match).
    pub fn models() -> [ProfileSpec; 7] {
        [
            ProfileSpec::Burley(Default::default()),
            ProfileSpec::Jimenez2012(Default::default()),
            ProfileSpec::Artist(Default::default()),
            ProfileSpec::Gaussians(Default::default()),
            ProfileSpec::Dipole(Default::default()),
            ProfileSpec::Measured(Default::default()),
            ProfileSpec::Multipole(Default::default()),
        ]
    }

    /// The model's name in the editor and a one-line description (one
    /// exhaustive match: a new model does not compile until it has them).
    pub fn describe(&self) -> (&'static str, &'static str) {
        match self {
            ProfileSpec::Burley(_) => (
                "Burley (normalized diffusion)",
                "Christensen & Burley 2015; Unity HDRP and Unreal's Burley profile.",
            ),
            ProfileSpec::Jimenez2012(_) => (
                "Jimenez 2012 (strength/falloff)",
                "The separable SSS demo's kernel; Unreal's separable profile.",
            ),
            ProfileSpec::Artist(_) => (
                "Artist two-Gaussian (Jimenez 2015)",
                "Near and far Gaussians, weight and global scale.",
            ),
            ProfileSpec::Gaussians(_) => (
                "Sum of Gaussians (d'Eon 2007)",
                "Weighted 2D Gaussians, one table row each.",
            ),
            ProfileSpec::Dipole(_) => (
                "Dipole (σa, σs', η)",
                "Jensen 2001 diffusion dipole from optical properties.",
            ),
            ProfileSpec::Measured(_) => (
                "Measured material",
                "Dipole of a material measured by Jensen 2001 or Narasimhan 2006.",
            ),
            ProfileSpec::Multipole(_) => (
                "Multipole layer stack",
                "Donner & Jensen 2005 slabs; stacks bake in the background.",
            ),
        }
    }

    /// Short model name used by the CLI and the UI.
    pub fn model_name(&self) -> &'static str {
        match self {
            ProfileSpec::Burley(_) => "burley",
            ProfileSpec::Gaussians(_) => "gaussians",
            ProfileSpec::Jimenez2012(_) => "jimenez2012",
            ProfileSpec::Artist(_) => "artist",
            ProfileSpec::Dipole(_) => "dipole",
            ProfileSpec::Measured(_) => "measured",
            ProfileSpec::Multipole(_) => "multipole",
        }
    }

    /// Builds the model; errors name the field under `profile.`.
    pub fn build(&self) -> Result<Box<dyn RadialProfile>, ModelError> {
        let built: Result<Box<dyn RadialProfile>, ModelError> = match self {
            ProfileSpec::Burley(b) => b.build().map(|m| Box::new(m) as _),
            ProfileSpec::Gaussians(g) => {
                let terms: Vec<(f64, Rgb)> = g
                    .gaussians
                    .iter()
                    .map(|t| (t.variance_mm2, t.weights))
                    .collect();
                GaussianSum::with_dirac(&terms, g.dirac).map(|m| Box::new(m) as _)
            }
            ProfileSpec::Jimenez2012(j) => {
                Jimenez2012::new(j.strength, j.falloff).map(|m| Box::new(m) as _)
            }
            ProfileSpec::Artist(a) => {
                ArtistTwoGaussian::new(a.sigma_near, a.sigma_far, a.weight, a.scale_mm)
                    .map(|m| Box::new(m) as _)
            }
            ProfileSpec::Dipole(d) => Dipole::new(
                Medium {
                    sigma_a_per_mm: d.sigma_a_per_mm,
                    sigma_s_prime_per_mm: d.sigma_s_prime_per_mm,
                },
                d.eta,
            )
            .map(|m| Box::new(m) as _),
            ProfileSpec::Measured(m) => measured::find(&m.name)
                .and_then(|mat| Dipole::measured(&mat, m.eta))
                .map(|m| Box::new(m) as _),
            ProfileSpec::Multipole(m) => m.build(),
        };
        built.map_err(|e| prefix("profile.", e))
    }
}

#[cfg(test)]
mod model_list_tests {
    use super::*;

    /// `models` holds each variant once (the index is an exhaustive match,
    /// so a new variant fails to compile here until it has one), and every
    /// model's defaults validate and have a distinct editor name.
    #[test]
    fn models_lists_every_variant_once() {
        fn index(s: &ProfileSpec) -> usize {
            match s {
                ProfileSpec::Burley(_) => 0,
                ProfileSpec::Gaussians(_) => 1,
                ProfileSpec::Jimenez2012(_) => 2,
                ProfileSpec::Artist(_) => 3,
                ProfileSpec::Dipole(_) => 4,
                ProfileSpec::Measured(_) => 5,
                ProfileSpec::Multipole(_) => 6,
            }
        }
        let mut seen = [0; 7];
        let mut names = std::collections::HashSet::new();
        for m in ProfileSpec::models() {
            seen[index(&m)] += 1;
            assert!(names.insert(m.describe().0));
            assert!(m.build().is_ok(), "{}", m.model_name());
        }
        assert_eq!(seen, [1; 7]);
    }
}
