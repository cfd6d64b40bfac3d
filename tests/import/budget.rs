//! `scatterlab budget` (issue 40 item 3): the search for merges against
//! an exhaustive one, and the command on a project shaped like a real one.

use super::*;
use scatterlab::export::unity_budget::{plan, plan_greedy, Candidate, Costs};
use scatterlab::settings::rendering::TransmissionId;

/// A small xorshift generator: the cases are the same on every run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn candidate(rng: &mut Rng, i: usize) -> Candidate {
    // Skin-like to foliage-like: a base distance 0.2–8 mm, red widest.
    let base = 0.2 * 40f64.powf(rng.next());
    let d = [base, base * (0.3 + 0.6 * rng.next()), base * (0.1 + 0.5 * rng.next())];
    let mut p = Preset::default_skin();
    p.name = format!("P{i}");
    p.profile = ProfileSpec::Burley(BurleySpec {
        albedo: [0.8, 0.5, 0.4],
        shape: BurleyShape::ScatteringDistance {
            mm: d,
            multiplier: 1.0,
        },
    });
    p.rendering.transmission_tint = [1.0, 0.5 + 0.5 * rng.next(), 0.3 + 0.7 * rng.next()];
    if rng.next() < 0.2 {
        p.rendering.transmission = TransmissionId::ThickObject;
    }
    Candidate {
        name: p.name.clone(),
        preset: p,
        materials: (rng.next() * 6.0) as usize,
    }
}

/// Every partition of `n` items into at most `k` blocks, written here
/// (restricted growth strings), with the least total cost.
fn exhaustive(costs: &mut Costs, n: usize, k: usize) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut count = 0;
    let mut a = vec![0usize; n];
    loop {
        let blocks = a.iter().max().map_or(0, |m| m + 1);
        if blocks <= k {
            count += 1;
            let groups: Vec<Vec<usize>> = (0..blocks)
                .map(|b| (0..n).filter(|&i| a[i] == b).collect())
                .collect();
            best = best.min(costs.total(&groups));
        }
        // Next restricted growth string: a[i] ≤ 1 + max(a[..i]).
        let mut i = n - 1;
        loop {
            let prefix_max = a[..i].iter().copied().max().unwrap_or(0);
            if i > 0 && a[i] <= prefix_max {
                a[i] += 1;
                for x in a.iter_mut().skip(i + 1) {
                    *x = 0;
                }
                break;
            }
            if i == 0 {
                return (best, count);
            }
            i -= 1;
        }
    }
}

/// On 6-profile cases (24 of them, seeded: distances, tints, thick or
/// thin transmission and material counts drawn at random) into 2 to 5
/// slots, the greedy search (agglomerative merges, then single moves) that
/// budgets a large project finds a partition as cheap as the best of all
/// of them, enumerated here; and `plan` (exact up to 9 profiles) finds it
/// too. Bell(6) = 203 partitions in all, counted.
#[test]
fn the_merge_search_matches_an_exhaustive_one() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut worst_gap = 0.0f64;
    for case in 0..24 {
        let cands: Vec<Candidate> = (0..6).map(|i| candidate(&mut rng, i)).collect();
        let slots = 2 + case % 4;
        let mut costs = Costs::new(&cands).unwrap();
        let (optimum, _) = exhaustive(&mut costs, 6, slots);
        let greedy = plan_greedy(&mut costs, slots);
        assert!(greedy.len() <= slots);
        let g = costs.total(&greedy);
        let exact = plan(&mut costs, slots);
        assert!((costs.total(&exact) - optimum).abs() < 1e-9, "case {case}");
        worst_gap = worst_gap.max(g - optimum);
        assert!(
            g <= optimum + 1e-9,
            "case {case}, {slots} slots: greedy {g} against the optimum {optimum} ({greedy:?})"
        );
    }
    let cands: Vec<Candidate> = (0..6).map(|i| candidate(&mut rng, i)).collect();
    let mut costs = Costs::new(&cands).unwrap();
    assert_eq!(exhaustive(&mut costs, 6, 6).1, 203);
    eprintln!("greedy against exhaustive, worst gap {worst_gap:e}");
}
