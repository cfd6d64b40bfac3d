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
    let d = [
        base,
        base * (0.3 + 0.6 * rng.next()),
        base * (0.1 + 0.5 * rng.next()),
    ];
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

/// Copies a folder, recursively.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// tests/clients/unity_budget_check.py on a folder: the materials' profile
/// references, the profiles' hashes and the lists, read by HDRP's rules in
/// Python (not by scatterlab's code).
fn hdrp_view(dir: &Path) -> serde_json::Value {
    let out = Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/clients/unity_budget_check.py"))
        .arg(dir)
        .output()
        .expect("python3");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn files_of(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.clone(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// The fixture project (tests/data/unity_budget: 24 profiles over 40
/// materials, a LayeredLit and a Shader Graph material among them, two
/// profiles used by none, written by its make_fixture.py with HDRP's
/// encodings) budgeted into 15 slots:
/// - the report states each merge's cost per profile and renders the
///   head old beside merged; budget.json has 15 profiles after;
/// - the list names 15 profiles, each an original or a merged one, and
///   each merged asset's `hash` is the one HDRP gives its GUID (checked in
///   Python by HDRP's MonoStringHash);
/// - the project is unchanged until `--apply`; then every material's
///   references (decoded in Python by HDRP's ConvertVector4ToGUID) name
///   a profile of the list with its hash, 15 profiles at most are in use,
///   and `backup/` holds each rewritten material as it was;
/// - a second run asks for --force, a second --apply refuses to overwrite
///   the backup.
#[test]
fn budget_fits_24_profiles_into_15_slots() {
    let project = tmp("budget_project");
    let _ = std::fs::remove_dir_all(&project);
    copy_dir(&data("unity_budget/project"), &project);
    let before = files_of(&project);
    let out = tmp("budget_out");
    let _ = std::fs::remove_dir_all(&out);
    let (code, stdout, stderr) = cli(&[
        "budget",
        project.to_str().unwrap(),
        "--slots",
        "15",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    // Two profiles no material uses (Old_Skin_Test and Unused_Wax_Test in
    // make_fixture.py) are dropped before any merge (issue 52: they were
    // merged in, spending merges on nothing).
    assert!(
        stdout.contains(
            "24 profiles (2 used by no material: dropped), 22 used by 40 of 40 materials"
        ),
        "{stdout}"
    );
    assert_eq!(
        files_of(&project),
        before,
        "the project changed without --apply"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("budget.json")).unwrap()).unwrap();
    assert_eq!(report["profiles_before"], 24);
    assert_eq!(report["profiles_after"], 15);
    assert_eq!(
        report["dropped"],
        serde_json::json!(["Old_Skin_Test", "Unused_Wax_Test"])
    );
    for m in report["merges"].as_array().unwrap() {
        for mem in m["members"].as_array().unwrap() {
            assert_ne!(mem["materials"], 0, "an unused profile merged in: {mem}");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for m in report["merges"].as_array().unwrap() {
        for mem in m["members"].as_array().unwrap() {
            let shape = mem["shape_error"].as_f64().unwrap();
            assert!(shape.is_finite() && shape < 0.5, "{mem}");
            assert!(
                md.contains(&format!(
                    "| {} | {} | {shape:.4} |",
                    mem["name"].as_str().unwrap(),
                    mem["materials"]
                )),
                "{mem}"
            );
            let dl = mem["delta_l_mean"].as_f64().unwrap();
            assert!(dl.is_finite() && dl >= 0.0);
            for f in mem["pair"].as_array().unwrap() {
                assert!(out.join(f.as_str().unwrap()).is_file(), "{f}");
            }
        }
    }
    let view = hdrp_view(&out);
    let list = view["lists"]
        .as_object()
        .unwrap()
        .values()
        .next()
        .unwrap()
        .as_array()
        .unwrap()
        .clone();
    assert_eq!(list.len(), 15);
    let originals = hdrp_view(&project);
    let known: Vec<&str> = originals["profiles"]
        .as_object()
        .unwrap()
        .values()
        .chain(view["profiles"].as_object().unwrap().values())
        .map(|v| v[0].as_str().unwrap())
        .collect();
    for g in &list {
        assert!(known.contains(&g.as_str().unwrap()), "{g} is no profile");
    }
    for (p, v) in view["profiles"].as_object().unwrap() {
        assert_eq!(v[1], true, "{p}: its hash is not HDRP's for its GUID");
    }
    // Again without --force: refused, nothing lost.
    let (code, _, stderr) = cli(&[
        "budget",
        project.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-renders",
    ]);
    assert_ne!(code, 0);
    assert!(stderr.contains("--force"), "{stderr}");
    // --apply.
    let (code, stdout, stderr) = cli(&[
        "budget",
        project.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--force",
        "--no-renders",
        "--apply",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let after = hdrp_view(&project);
    let mut in_use = std::collections::BTreeSet::new();
    let mut changed = 0;
    for (mat, refs) in after["materials"].as_object().unwrap() {
        let old = &originals["materials"][mat];
        for r in refs.as_array().unwrap() {
            assert_eq!(r[2], true, "{mat}: hash float is not HDRP's for {}", r[1]);
            assert!(list.contains(&r[1]), "{mat}: {} is not in the list", r[1]);
            in_use.insert(r[1].as_str().unwrap().to_owned());
        }
        if refs != old {
            changed += 1;
            let backed = std::fs::read(out.join("backup").join(mat)).unwrap();
            let original = std::fs::read(data("unity_budget/project").join(mat)).unwrap();
            assert_eq!(backed, original, "{mat}: the backup is not the original");
        }
    }
    assert!(in_use.len() <= 15, "{in_use:?}");
    assert_eq!(after["materials"].as_object().unwrap().len(), 40);
    assert!(changed > 0);
    assert!(project.join("Assets/scatterlab_budget").is_dir());
    // A second --apply would overwrite the backup: refused.
    let (code, _, stderr) = cli(&[
        "budget",
        project.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--force",
        "--no-renders",
        "--apply",
    ]);
    assert_ne!(code, 0);
    assert!(stderr.contains("backup"), "{stderr}");
}
