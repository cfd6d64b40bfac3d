//! Which diffusion profiles to merge so a project fits HDRP's list
//! (`scatterlab budget`): a partition of the profiles into at most N
//! groups, each drawn with one merged profile, that least changes what the
//! materials draw.
//!
//! What a material loses when its profile p is drawn as q
//! ([`member_cost`]), each term a fraction where 1 is "as bad as drawing
//! no scattering at all":
//! - shape: the largest channel's shape error of r·R(r) (energy-normalised,
//!   `model::fit::shape_error`, the measure `convert` and the fits report).
//!   HDRP keeps the albedo in the material, so only d changes, and a
//!   Burley shape depends on d alone; the error of q against p is
//!   g(ln(d_q/d_p)), tabulated once ([`ShapeTable`]);
//! - colour: the CIE 1976 ΔE*ab of the transmission tint (HDRP multiplies
//!   transmitted light by it) over 100;
//! - modes: 1 for each of the texturing and transmission modes that
//!   changes (a different way of drawing, not a nearby one).
//!
//! A group's cost is the sum of its members' costs weighted by how many
//! materials use each (a profile no material uses weighs 0.01: it still
//! takes a slot if kept). The merged profile of a group ([`merged_of`])
//! takes per channel the d that minimises Σ w·g² (Brent's method on
//! ln d), the weighted mean tint, the modes of the heaviest weight, and the
//! heaviest member's other fields. The partition ([`plan`]) is searched
//! exactly up to [`EXACT_UP_TO`] profiles and otherwise by agglomerative
//! merging (the cheapest pair each step) followed by single moves while
//! any lowers the total ([`plan_greedy`]); `tests/budget.rs` checks the
//! greedy search against an exhaustive one on 6-profile cases.

use crate::model::burley::Burley;
use crate::model::fit::shape_error;
use crate::model::quad::minimize_scalar;
use crate::model::{ModelError, Rgb};
use crate::settings::profile::{BurleyShape, BurleySpec};
use crate::settings::{Preset, ProfileSpec};
use std::collections::HashMap;

/// Profiles up to which [`plan`] searches every partition (Bell(9) =
/// 21 147 of them).
pub const EXACT_UP_TO: usize = 9;

/// The weight of a profile no material uses.
pub const UNUSED_WEIGHT: f64 = 0.01;

/// One profile to budget: its look and how many materials use it.
#[derive(Debug, Clone)]
pub struct Candidate {
    pub name: String,
    pub preset: Preset,
    pub materials: usize,
}

impl Candidate {
    fn weight(&self) -> f64 {
        if self.materials == 0 {
            UNUSED_WEIGHT
        } else {
            self.materials as f64
        }
    }
}

/// g(x): the shape error of a Burley profile of d·eˣ against one of d,
/// tabulated on x ∈ [−16, 16] (Burley's distances span ln(10⁷) = 16.1).
pub struct ShapeTable {
    step: f64,
    values: Vec<f64>,
}

const TABLE_X: f64 = 16.0;
const TABLE_STEP: f64 = 0.025;

impl ShapeTable {
    pub fn new() -> Result<Self, ModelError> {
        let n = (2.0 * TABLE_X / TABLE_STEP).round() as usize + 1;
        let mut values = Vec::with_capacity(n);
        for i in 0..n {
            let x = -TABLE_X + i as f64 * TABLE_STEP;
            // Both distances inside Burley's range, centred on √(0.1) mm.
            let d = 0.1f64.sqrt() * (-x / 2.0).exp();
            let target = Burley::from_scattering_distance([0.5; 3], [d; 3])?;
            let model = Burley::from_scattering_distance([0.5; 3], [d * x.exp(); 3])?;
            values.push(shape_error(&target, &model)[0]);
        }
        Ok(Self {
            step: TABLE_STEP,
            values,
        })
    }

    /// g(x), linear between the table's points, held at its ends.
    pub fn at(&self, x: f64) -> f64 {
        let t = ((x + TABLE_X) / self.step).clamp(0.0, (self.values.len() - 1) as f64);
        let i = (t.floor() as usize).min(self.values.len() - 2);
        let f = t - i as f64;
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }
}

/// A profile's scattering distance d per channel (mm).
fn distance(p: &Preset) -> Result<Rgb, ModelError> {
    Ok(crate::export::burley_of(&p.profile)?
        .0
        .scattering_distance_mm())
}

/// CIE 1976 L*a*b* (D65) of a linear sRGB colour: the IEC 61966-2-1
/// matrix to XYZ, then CIE 15:2004 eqs. 8.1–8.3.
pub fn lab(c: Rgb) -> [f64; 3] {
    let m = [
        [0.412_456_4, 0.357_576_1, 0.180_437_5],
        [0.212_672_9, 0.715_152_2, 0.072_175_0],
        [0.019_333_9, 0.119_192_0, 0.950_304_1],
    ];
    let xyz: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| m[i][j] * c[j]).sum());
    let white = [0.950_47, 1.0, 1.088_83];
    let f = |t: f64| {
        const D: f64 = 6.0 / 29.0;
        if t > D * D * D {
            t.cbrt()
        } else {
            t / (3.0 * D * D) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (
        f(xyz[0] / white[0]),
        f(xyz[1] / white[1]),
        f(xyz[2] / white[2]),
    );
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// ΔE*ab (CIE 1976) of two linear sRGB colours.
pub fn delta_e(a: Rgb, b: Rgb) -> f64 {
    let (x, y) = (lab(a), lab(b));
    ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt()
}

/// What one material loses when its profile is drawn as another.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemberCost {
    /// The largest channel's shape error of r·R(r).
    pub shape: f64,
    /// ΔE*ab of the transmission tint.
    pub tint_delta_e: f64,
    /// How many of the texturing and transmission modes change.
    pub modes_changed: u32,
}

impl MemberCost {
    /// The cost: shape + ΔE/100 + modes changed.
    pub fn total(&self) -> f64 {
        self.shape + self.tint_delta_e / 100.0 + self.modes_changed as f64
    }
}

/// What drawing `member` as `merged` costs a material.
pub fn member_cost(
    table: &ShapeTable,
    member: &Preset,
    merged: &Preset,
) -> Result<MemberCost, ModelError> {
    let (dm, dq) = (distance(member)?, distance(merged)?);
    let shape = (0..3)
        .map(|c| table.at((dq[c] / dm[c]).ln()))
        .fold(0.0, f64::max);
    let (a, b) = (&member.rendering, &merged.rendering);
    Ok(MemberCost {
        shape,
        tint_delta_e: delta_e(a.transmission_tint, b.transmission_tint),
        modes_changed: (a.texturing != b.texturing) as u32
            + (a.transmission != b.transmission) as u32,
    })
}

/// The one profile that draws a group: per channel the d minimising
/// Σ w·g(ln d/d_p)², the weighted mean tint, the modes with the most
/// weight, the heaviest member's other fields. `members` is not empty.
pub fn merged_of(table: &ShapeTable, members: &[&Candidate]) -> Result<Preset, ModelError> {
    let heaviest = members
        .iter()
        .copied()
        .max_by(|a, b| a.weight().total_cmp(&b.weight()))
        .ok_or_else(|| ModelError::Invalid {
            field: "budget".into(),
            reason: "a group with no profile".into(),
        })?;
    if members.len() == 1 {
        return Ok(heaviest.preset.clone());
    }
    let ds: Vec<(f64, Rgb)> = members
        .iter()
        .map(|m| Ok((m.weight(), distance(&m.preset)?)))
        .collect::<Result<_, ModelError>>()?;
    let d: Rgb = std::array::from_fn(|c| {
        let logs: Vec<(f64, f64)> = ds.iter().map(|(w, d)| (*w, d[c].ln())).collect();
        let lo = logs.iter().map(|l| l.1).fold(f64::INFINITY, f64::min);
        let hi = logs.iter().map(|l| l.1).fold(f64::NEG_INFINITY, f64::max);
        if hi - lo < 1e-12 {
            return lo.exp();
        }
        let obj = |x: f64| {
            logs.iter()
                .map(|(w, l)| w * table.at(x - l).powi(2))
                .sum::<f64>()
        };
        minimize_scalar(obj, lo, hi, 1e-9).0.exp()
    });
    let total: f64 = members.iter().map(|m| m.weight()).sum();
    let tint: Rgb = std::array::from_fn(|c| {
        members
            .iter()
            .map(|m| m.weight() * m.preset.rendering.transmission_tint[c])
            .sum::<f64>()
            / total
    });
    let vote = |f: &dyn Fn(&Candidate) -> u8| {
        let mut best = (0u8, f64::NEG_INFINITY);
        for v in members.iter().map(|m| f(m)) {
            let w: f64 = members
                .iter()
                .filter(|m| f(m) == v)
                .map(|m| m.weight())
                .sum();
            if w > best.1 {
                best = (v, w);
            }
        }
        best.0
    };
    let mut p = heaviest.preset.clone();
    let texturing = vote(&|m| m.preset.rendering.texturing as u8);
    let transmission = vote(&|m| m.preset.rendering.transmission as u8);
    if let Some(m) = members
        .iter()
        .find(|m| m.preset.rendering.texturing as u8 == texturing)
    {
        p.rendering.texturing = m.preset.rendering.texturing;
    }
    if let Some(m) = members
        .iter()
        .find(|m| m.preset.rendering.transmission as u8 == transmission)
    {
        p.rendering.transmission = m.preset.rendering.transmission;
    }
    p.rendering.transmission_tint = tint;
    let albedo = crate::export::burley_of(&heaviest.preset.profile)?
        .0
        .albedo();
    p.profile = ProfileSpec::Burley(BurleySpec {
        albedo,
        shape: BurleyShape::ScatteringDistance {
            mm: d,
            multiplier: 1.0,
        },
    });
    p.name = format!(
        "Merged {}",
        members
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            .join(" + ")
    );
    p.description = "A merge of HDRP diffusion profiles, written by scatterlab budget.".into();
    p.validate()?;
    Ok(p)
}

/// Group costs, memoised by member set (a bit per candidate).
pub struct Costs<'a> {
    table: ShapeTable,
    candidates: &'a [Candidate],
    memo: HashMap<u64, f64>,
}

impl<'a> Costs<'a> {
    pub fn new(candidates: &'a [Candidate]) -> Result<Self, ModelError> {
        if candidates.len() > 64 {
            return Err(ModelError::Invalid {
                field: "budget".into(),
                reason: format!("{} profiles: the budget plans at most 64", candidates.len()),
            });
        }
        for c in candidates {
            distance(&c.preset)?;
        }
        Ok(Self {
            table: ShapeTable::new()?,
            candidates,
            memo: HashMap::new(),
        })
    }

    pub fn table(&self) -> &ShapeTable {
        &self.table
    }

    /// The merged profile of a group (its members' indices).
    pub fn merged(&self, group: &[usize]) -> Result<Preset, ModelError> {
        let members: Vec<&Candidate> = group.iter().map(|&i| &self.candidates[i]).collect();
        merged_of(&self.table, &members)
    }

    /// Σ weight × cost of a group's members against its merged profile.
    pub fn group(&mut self, group: &[usize]) -> f64 {
        let key = group.iter().fold(0u64, |k, &i| k | 1 << i);
        if let Some(v) = self.memo.get(&key) {
            return *v;
        }
        let v = self
            .merged(group)
            .and_then(|q| {
                group
                    .iter()
                    .map(|&i| {
                        let c = &self.candidates[i];
                        Ok(c.weight() * member_cost(&self.table, &c.preset, &q)?.total())
                    })
                    .sum::<Result<f64, ModelError>>()
            })
            .unwrap_or(f64::INFINITY);
        self.memo.insert(key, v);
        v
    }

    /// The total of a partition.
    pub fn total(&mut self, groups: &[Vec<usize>]) -> f64 {
        groups.iter().map(|g| self.group(g)).sum()
    }
}

/// The best partition into at most `slots` groups: exact up to
/// [`EXACT_UP_TO`] candidates, [`plan_greedy`] beyond.
pub fn plan(costs: &mut Costs, slots: usize) -> Vec<Vec<usize>> {
    let n = costs.candidates.len();
    if n <= slots {
        return (0..n).map(|i| vec![i]).collect();
    }
    if n <= EXACT_UP_TO {
        plan_exact(costs, slots)
    } else {
        plan_greedy(costs, slots)
    }
}

/// Every partition into at most `slots` groups (restricted growth strings).
fn plan_exact(costs: &mut Costs, slots: usize) -> Vec<Vec<usize>> {
    let n = costs.candidates.len();
    let mut best = (f64::INFINITY, Vec::new());
    let mut a = vec![0usize; n];
    fn rec(
        i: usize,
        used: usize,
        a: &mut Vec<usize>,
        slots: usize,
        costs: &mut Costs,
        best: &mut (f64, Vec<Vec<usize>>),
    ) {
        let n = a.len();
        if i == n {
            let groups: Vec<Vec<usize>> = (0..used)
                .map(|g| (0..n).filter(|&k| a[k] == g).collect())
                .collect();
            let t = costs.total(&groups);
            if t < best.0 {
                *best = (t, groups);
            }
            return;
        }
        for g in 0..(used + 1).min(slots) {
            a[i] = g;
            rec(i + 1, used.max(g + 1), a, slots, costs, best);
        }
    }
    rec(0, 0, &mut a, slots, costs, &mut best);
    best.1
}

/// Agglomerative merging to `slots` groups, then single moves of one
/// profile to another group while one lowers the total.
pub fn plan_greedy(costs: &mut Costs, slots: usize) -> Vec<Vec<usize>> {
    let n = costs.candidates.len();
    let mut groups: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
    while groups.len() > slots.max(1) {
        let mut best = (f64::INFINITY, 0, 1);
        for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                let mut u = groups[i].clone();
                u.extend(&groups[j]);
                u.sort_unstable();
                let delta = costs.group(&u) - costs.group(&groups[i]) - costs.group(&groups[j]);
                if delta < best.0 {
                    best = (delta, i, j);
                }
            }
        }
        let (_, i, j) = best;
        let moved = groups.remove(j);
        groups[i].extend(moved);
        groups[i].sort_unstable();
    }
    // Single moves (to another group, or alone where a slot is free).
    loop {
        let current = costs.total(&groups);
        let mut best: Option<(f64, Vec<Vec<usize>>)> = None;
        for (gi, g) in groups.iter().enumerate() {
            for &p in g {
                let targets = groups.len() + usize::from(groups.len() < slots);
                for gj in 0..targets {
                    if gj == gi {
                        continue;
                    }
                    let mut next = groups.clone();
                    next[gi].retain(|&k| k != p);
                    if gj == groups.len() {
                        next.push(vec![p]);
                    } else {
                        next[gj].push(p);
                        next[gj].sort_unstable();
                    }
                    next.retain(|g| !g.is_empty());
                    let t = costs.total(&next);
                    if t < current - 1e-12 && best.as_ref().is_none_or(|b| t < b.0) {
                        best = Some((t, next));
                    }
                }
            }
        }
        match best {
            Some((_, next)) => groups = next,
            None => break,
        }
    }
    groups.sort();
    groups
}

/// `budget.json`: what `scatterlab budget` decided, in one serde type
/// that the command writes and the editor's Budget merges window reads
/// (`edit --budget DIR`). Every field has a default, so a report written
/// by an older version (or by hand) still loads; the pairs it names are
/// checked to exist.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct BudgetReport {
    pub project: std::path::PathBuf,
    pub slots: usize,
    pub profiles_before: usize,
    pub profiles_after: usize,
    /// The profiles no material used, left out of the list before any
    /// merge (their file stems).
    pub dropped: Vec<String>,
    /// None where the cost was not finite (JSON has no NaN: null).
    pub weighted_cost: Option<f64>,
    pub merges: Vec<ReportMerge>,
}

/// One merge: the new profile and the profiles it replaces.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ReportMerge {
    pub merged: MergedProfile,
    pub members: Vec<ReportMember>,
}

/// A merged profile: its name, GUID and asset (relative to the report).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct MergedProfile {
    pub name: String,
    pub guid: String,
    pub asset: String,
}

/// A profile of a merge and what the merge costs the materials using it.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ReportMember {
    pub name: String,
    pub guid: String,
    pub materials: usize,
    pub shape_error: f64,
    pub tint_delta_e: f64,
    pub modes_changed: u32,
    /// Mean and largest |ΔL*| on the rendered head, old against merged
    /// (none: not rendered).
    pub delta_l_mean: Option<f32>,
    pub delta_l_max: Option<f32>,
    /// The profile's preset and the merge's, relative to the report.
    pub pair: [String; 2],
}

impl BudgetReport {
    /// The report's file in `dir`.
    pub fn path(dir: &std::path::Path) -> std::path::PathBuf {
        dir.join("budget.json")
    }

    /// Reads `DIR/budget.json`; an error names the file and what is wrong
    /// (a field, or a pair preset that is missing).
    pub fn read(dir: &std::path::Path) -> Result<Self, String> {
        let file = Self::path(dir);
        let text = std::fs::read_to_string(&file).map_err(|e| {
            format!(
                "{}: {e} (is {} a `scatterlab budget` folder?)",
                file.display(),
                dir.display()
            )
        })?;
        let report: Self = serde_json::from_str(&text)
            .map_err(|e| format!("{}: malformed: {e}", file.display()))?;
        for (i, m) in report.merges.iter().enumerate() {
            for (j, mem) in m.members.iter().enumerate() {
                for p in &mem.pair {
                    if p.is_empty() {
                        return Err(format!(
                            "{}: merges[{i}].members[{j}].pair is missing",
                            file.display()
                        ));
                    }
                    if !dir.join(p).is_file() {
                        return Err(format!(
                            "{}: {} is missing",
                            file.display(),
                            dir.join(p).display()
                        ));
                    }
                }
            }
        }
        Ok(report)
    }

    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIE L*a*b* of linear sRGB white and red against published values
    /// (Lindbloom's calculator, D65: red is (53.24, 80.09, 67.20)).
    #[test]
    fn lab_matches_published_values() {
        let w = lab([1.0; 3]);
        assert!(
            (w[0] - 100.0).abs() < 0.01 && w[1].abs() < 0.01 && w[2].abs() < 0.01,
            "{w:?}"
        );
        let r = lab([1.0, 0.0, 0.0]);
        for (got, want) in r.iter().zip([53.24, 80.09, 67.20]) {
            assert!((got - want).abs() < 0.05, "{r:?}");
        }
    }

    /// The table is the shape error itself (at points between its nodes,
    /// within 1 %), 0 at x = 0 and growing either way.
    #[test]
    fn shape_table_is_the_shape_error() {
        let t = ShapeTable::new().unwrap();
        assert!(t.at(0.0) < 1e-9);
        for x in [-2.3456f64, -0.51, 0.0371, 0.7, 1.9] {
            let a = Burley::from_scattering_distance([0.5; 3], [1.3; 3]).unwrap();
            let b = Burley::from_scattering_distance([0.5; 3], [1.3 * x.exp(); 3]).unwrap();
            let direct = shape_error(&a, &b)[0];
            assert!(
                (t.at(x) - direct).abs() <= 0.01 * direct + 1e-4,
                "{x}: {} vs {direct}",
                t.at(x)
            );
        }
        assert!(t.at(0.5) < t.at(1.0) && t.at(-0.5) < t.at(-1.0));
    }
}
