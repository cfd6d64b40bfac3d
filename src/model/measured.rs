//! Measured σ′s and σa (mm⁻¹) of Jensen et al. 2001 and Narasimhan et al.
//! 2006, from pbrt (`assets/data/measured_media_jensen2001_narasimhan2006.csv`).

use super::dipole::Medium;
use super::{ModelError, Rgb};

const TABLE: &str = include_str!("../../assets/data/measured_media_jensen2001_narasimhan2006.csv");

/// One measured material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub sigma_s_prime_per_mm: Rgb,
    pub sigma_a_per_mm: Rgb,
}

impl Material {
    pub fn medium(&self) -> Medium {
        Medium {
            sigma_a_per_mm: self.sigma_a_per_mm,
            sigma_s_prime_per_mm: self.sigma_s_prime_per_mm,
        }
    }
}

/// All materials in table order.
pub fn all() -> Vec<Material> {
    TABLE
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .filter_map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |i: usize| f.get(i).and_then(|s| s.trim().parse::<f64>().ok());
            Some(Material {
                name: f.first()?.trim().to_owned(),
                sigma_s_prime_per_mm: [num(1)?, num(2)?, num(3)?],
                sigma_a_per_mm: [num(4)?, num(5)?, num(6)?],
            })
        })
        .collect()
}

/// Normalises a name for lookup: case, spaces, '-', '_' and '&' are ignored.
fn key(name: &str) -> String {
    name.chars()
        .filter(|c| c.is_alphanumeric())
        .flat_map(char::to_lowercase)
        .collect()
}

/// Finds a material by name ("Skin1", "whole milk", "wholemilk" …).
pub fn find(name: &str) -> Result<Material, ModelError> {
    let k = key(name);
    all()
        .into_iter()
        .find(|m| key(&m.name) == k)
        .ok_or_else(|| {
            let names: Vec<String> = all().into_iter().map(|m| m.name).collect();
            ModelError::invalid(
                "measured",
                format!("unknown material `{name}`; known: {}", names.join(", ")),
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_parses_completely() {
        let rows = TABLE
            .lines()
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .count();
        assert_eq!(all().len(), rows);
        assert_eq!(rows, 47);
        let s = find("skin 1").unwrap();
        assert_eq!(s.sigma_a_per_mm, [0.032, 0.17, 0.48]);
        assert_eq!(s.sigma_s_prime_per_mm, [0.74, 0.88, 1.01]);
        assert!(find("Head & Shoulders Shampoo").is_ok());
        assert!(find("unobtainium")
            .unwrap_err()
            .to_string()
            .contains("Skin1"));
    }
}
