//! The budget's use case (`scatterlab budget PROJECT --slots 15 --out
//! DIR` is its shell, `cli/budget.rs`): which of a Unity
//! project's diffusion profiles to merge so that HDRP's list holds them
//! (15 slots), what each merge costs the materials that use it, and the
//! files to make it so. The search and its costs are
//! `export::unity_budget`; the project's encodings `export::unity_project`.
//! Nothing in the project changes without `--apply`, which first copies
//! every file it rewrites under `DIR/backup/`.

use super::budget::{
    member_cost, BudgetReport, Candidate, Costs, MemberCost, MergedProfile, ReportMember,
    ReportMerge,
};
use super::budget_pictures::{curves_chart, with_material_albedo, HeadRenderer};
use super::project::{self as project, MaterialUse};
use crate::export::Provenance;
use crate::settings::Preset;
use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a budget is asked for (the command line's flags).
#[derive(Debug, Clone)]
pub struct BudgetOptions {
    /// The Unity project (its folder, or its Assets folder).
    pub project: PathBuf,
    /// How many profiles the list may hold (HDRP: 15, its 16 slots less
    /// the neutral profile).
    pub slots: usize,
    /// Where the merged profiles, the Diffusion Profile List, the remap
    /// table and the report are written.
    pub out: PathBuf,
    /// Also change the project: copy the merged profiles and the list into
    /// Assets/scatterlab_budget/ and point each remapped material at its new
    /// profile, after copying every file it rewrites to DIR/backup/.
    pub apply: bool,
    /// Replace an earlier report in DIR.
    pub force: bool,
    /// Leave out the head renders (old beside new, with ΔL*), which take a
    /// few seconds a profile on a CPU renderer.
    pub no_renders: bool,
    /// Side of each head render, in pixels.
    pub render_size: u32,
}

/// FNV-1a, 64 bits, from `seed`.
fn fnv(seed: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(seed, |h, b| {
        (h ^ *b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A new asset's GUID from `key`: 32 hex digits whose four floats are all
/// finite (a NaN pattern would not survive a material's text).
fn new_guid(key: &str) -> String {
    for salt in 0u32.. {
        let k = format!("scatterlab budget {key} {salt}");
        let a = fnv(0xcbf2_9ce4_8422_2325, k.as_bytes());
        let b = fnv(0x8422_2325_cbf2_9ce4, k.as_bytes());
        let g = format!("{a:016x}{b:016x}");
        if project::guid_to_vector4(&g).is_some_and(|v| v.iter().all(|x| x.is_finite())) {
            return g;
        }
    }
    unreachable!("some salt gives finite floats")
}

/// A file name from a look's name.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let s = s.trim_matches('_');
    let s = if s.len() > 80 { &s[..80] } else { s };
    if s.is_empty() {
        "profile".into()
    } else {
        s.to_owned()
    }
}

pub(super) fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    if let Some(d) = path.parent() {
        std::fs::create_dir_all(d).with_context(|| format!("{}: cannot create", d.display()))?;
    }
    crate::fsutil::write_atomic(path, bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// One profile of a merge, with what the merge costs it.
struct Member {
    index: usize,
    cost: MemberCost,
    delta_l: Option<(f32, f32)>,
    image: Option<String>,
    preset_file: String,
}

struct Merge {
    members: Vec<Member>,
    merged: Preset,
    guid: String,
    stem: String,
    curves: String,
}

impl BudgetOptions {
    /// Plans the merges, writes every file under `out` (and with `apply`
    /// changes the project); what to tell the user.
    pub fn run(&self) -> Result<String> {
        if self.slots == 0 {
            bail!("--slots 0: a list needs at least one profile");
        }
        let report_path = self.out.join("report.md");
        if report_path.exists() && !self.force {
            bail!(
                "{}: a budget report is there already; --force replaces it",
                report_path.display()
            );
        }
        let mut scan = project::scan(&self.project)?;
        if scan.profiles.is_empty() {
            bail!(
                "{}: no HDRP diffusion profile (a DiffusionProfileSettings .asset with a .meta) in the project",
                self.project.display()
            );
        }
        let dropped = drop_unused(&mut scan);
        let (users, candidates) = candidates(&scan);
        let mut costs = Costs::new(&candidates)?;
        let groups = crate::export::unity_budget::plan(&mut costs, self.slots);
        let total = costs.total(&groups);
        std::fs::create_dir_all(&self.out)
            .with_context(|| format!("{}: cannot create", self.out.display()))?;

        let (mut merges, list_guids) = merges(&scan, &candidates, &costs, &groups)?;
        let (list_name, list_guid) = self.write_assets(&merges, list_guids)?;
        let remapped = self.write_remap(&scan, &candidates, &users, &merges)?;
        // Pairs for the editor, curves and renders.
        self.pairs_and_pictures(&mut merges, &candidates)?;
        let summary = self.report(
            &scan,
            &candidates,
            &users,
            &groups,
            &merges,
            total,
            &dropped,
        )?;
        // As it happens: the project changed, then what the report says.
        let applied = match self.apply {
            true => format!(
                "{}\n",
                self.apply(&merges, &remapped, list_name, &list_guid)?
            ),
            false => String::new(),
        };
        Ok(format!("{applied}{summary}\n{}", report_path.display()))
    }

    /// The merged profiles as HDRP's assets with HDRP's hash, and the
    /// Diffusion Profile List naming `list_guids`; the list's name and GUID.
    fn write_assets(
        &self,
        merges: &[Merge],
        list_guids: Vec<String>,
    ) -> Result<(&'static str, String)> {
        let prov = Provenance::new(&Preset::default(), Some(&self.project));
        for m in merges {
            let text = crate::export::unity_asset(&m.merged, &prov, &m.stem)?;
            let text = with_hash(&text, project::hdrp_profile_hash(&m.guid));
            let asset = self.out.join("profiles").join(format!("{}.asset", m.stem));
            write(&asset, text.as_bytes())?;
            write(
                &asset.with_file_name(format!("{}.asset.meta", m.stem)),
                project::asset_meta(&m.guid).as_bytes(),
            )?;
        }
        let list_guid = new_guid(&list_guids.join(","));
        let list_name = "Diffusion Profile List (scatterlab budget)";
        write(
            &self.out.join(format!("{list_name}.asset")),
            project::profile_list_asset(list_name, &list_guids).as_bytes(),
        )?;
        write(
            &self.out.join(format!("{list_name}.asset.meta")),
            project::asset_meta(&list_guid).as_bytes(),
        )?;
        Ok((list_name, list_guid))
    }

    /// `remap.csv`: every material whose profile changes, from which to
    /// which; the uses repointed, with their new GUIDs.
    fn write_remap<'a>(
        &self,
        scan: &'a project::Project,
        candidates: &[Candidate],
        users: &[Vec<&MaterialUse>],
        merges: &[Merge],
    ) -> Result<Vec<(&'a MaterialUse, String)>> {
        let mut remap = String::from(
            "material,property,old_profile,old_guid,new_profile,new_guid,shape_error,tint_delta_e,modes_changed\n",
        );
        let mut remapped: Vec<(&MaterialUse, String)> = Vec::new();
        for m in merges {
            for mem in &m.members {
                for u in &users[mem.index] {
                    for r in scan
                        .uses
                        .iter()
                        .filter(|r| r.material == u.material && r.guid == u.guid)
                    {
                        remap.push_str(&format!(
                            "{},{},{},{},{},{},{:.4},{:.2},{}\n",
                            csv(&rel(&self.project, &r.material)),
                            r.asset_property,
                            csv(&candidates[mem.index].name),
                            r.guid,
                            csv(&m.stem),
                            m.guid,
                            mem.cost.shape,
                            mem.cost.tint_delta_e,
                            mem.cost.modes_changed
                        ));
                        remapped.push((r, m.guid.clone()));
                    }
                }
            }
        }
        write(&self.out.join("remap.csv"), remap.as_bytes())?;
        Ok(remapped)
    }

    /// Each merge's member and merged presets (for the editor's compare
    /// pairs), its curves, and with renders the head old beside new.
    fn pairs_and_pictures(&self, merges: &mut [Merge], candidates: &[Candidate]) -> Result<()> {
        for d in ["pairs", "images"] {
            std::fs::create_dir_all(self.out.join(d))
                .with_context(|| format!("{}: cannot create", self.out.join(d).display()))?;
        }
        let mut renderer = if self.no_renders {
            None
        } else {
            Some(HeadRenderer::new(self.render_size)?)
        };
        for (k, m) in merges.iter_mut().enumerate() {
            let n = k + 1;
            let merged_file = format!("pairs/{n}_merged.ron");
            with_material_albedo(&m.merged).save(&self.out.join(&merged_file))?;
            m.curves = format!("images/merge_{n}_curves.png");
            let members: Vec<(&str, &Preset)> = m
                .members
                .iter()
                .map(|mem| {
                    (
                        candidates[mem.index].name.as_str(),
                        &candidates[mem.index].preset,
                    )
                })
                .collect();
            curves_chart(&self.out.join(&m.curves), &members, &m.merged)?;
            for mem in m.members.iter_mut() {
                let c = &candidates[mem.index];
                mem.preset_file = format!("pairs/{n}_{}.ron", file_stem(&c.name));
                with_material_albedo(&c.preset).save(&self.out.join(&mem.preset_file))?;
                if let Some(r) = renderer.as_mut() {
                    let image = format!("images/merge_{n}_{}.png", file_stem(&c.name));
                    let (dl_mean, dl_max) =
                        r.side_by_side(&c.preset, &m.merged, &self.out.join(&image))?;
                    mem.delta_l = Some((dl_mean, dl_max));
                    mem.image = Some(image);
                }
            }
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn report(
        &self,
        scan: &project::Project,
        candidates: &[Candidate],
        users: &[Vec<&MaterialUse>],
        groups: &[Vec<usize>],
        merges: &[Merge],
        total: f64,
        dropped: &[String],
    ) -> Result<String> {
        let mut md = String::new();
        let unused = match dropped.len() {
            0 => String::new(),
            n => format!(" ({n} used by no material: dropped)"),
        };
        let summary = format!(
            "{} profiles{unused}, {} used by {} of {} materials; {} slots: {} profiles after {} merge{} (weighted cost {:.3})",
            scan.profiles.len() + dropped.len(),
            users.iter().filter(|u| !u.is_empty()).count(),
            users.iter().flatten().map(|u| &u.material).collect::<std::collections::BTreeSet<_>>().len(),
            scan.materials,
            self.slots,
            groups.len(),
            merges.len(),
            if merges.len() == 1 { "" } else { "s" },
            total
        );
        md.push_str(&format!(
            "# Diffusion profile budget: {}\n\n{summary}.\n\n",
            self.project.display()
        ));
        md.push_str("Each material's cost is the worst channel's shape error of r·R(r) (energy-normalised, the measure `scatterlab fit` and `convert` report: 1 is as far as drawing no scattering at all), plus the transmission tint's CIE 1976 ΔE*ab / 100, plus 1 for each of the texturing and transmission modes that changes; the merges minimise its sum over the materials.");
        md.push_str(if self.no_renders {
            " The heads were not rendered (`--no-renders`).\n\n"
        } else {
            " HDRP keeps the albedo in the material, so the heads are rendered with the default skin's albedo, old profile on the left, merged on the right, the difference's |ΔL*| (CIE lightness) on the far right.\n\n"
        });
        md += &self.left_out_md(scan);
        if !dropped.is_empty() {
            md.push_str("## Dropped: no material uses them

Left out of the list before any merge (they would take a slot, or pull a merge towards themselves, for nothing); their assets are left in the project:

");
            for name in dropped {
                md.push_str(&format!(
                    "- {name}
"
                ));
            }
            md.push('\n');
        }
        for (k, m) in merges.iter().enumerate() {
            md += &self.merge_md(k, m, candidates);
        }
        md.push_str("## Kept as they are\n\n");
        for g in groups.iter().filter(|g| g.len() == 1) {
            md.push_str(&format!(
                "- {} ({} materials)\n",
                candidates[g[0]].name, candidates[g[0]].materials
            ));
        }
        md.push_str("\n## Files\n\n- `profiles/`: the merged profiles, with `.meta` files.\n- `Diffusion Profile List (scatterlab budget).asset`: a volume profile whose Diffusion Profile List override names the profiles kept and merged. Add it to a Volume in the scene (HDRP 17), or copy its list into the HDRP Global Settings (HDRP 12–16).\n- `remap.csv`: each material whose profile changes, from which to which.\n- `pairs/`: each profile and its merge as presets, for the editor.\n\nNothing in the project was changed");
        md.push_str(if self.apply {
            " until `--apply`: the merged profiles and the list were copied into `Assets/scatterlab_budget/`, the remapped materials rewritten, and every rewritten file first copied to `backup/`.\n"
        } else {
            ": `--apply` copies the profiles and the list into `Assets/scatterlab_budget/` and points the materials at them, after copying each to `backup/`.\n"
        });
        write(&self.out.join("report.md"), md.as_bytes())?;
        let report = BudgetReport {
            project: self.project.clone(),
            slots: self.slots,
            profiles_before: scan.profiles.len() + dropped.len(),
            profiles_after: groups.len(),
            dropped: dropped.to_vec(),
            weighted_cost: total.is_finite().then_some(total),
            merges: merges
                .iter()
                .enumerate()
                .map(|(k, m)| ReportMerge {
                    merged: MergedProfile {
                        name: m.merged.name.clone(),
                        guid: m.guid.clone(),
                        asset: format!("profiles/{}.asset", m.stem),
                    },
                    members: m
                        .members
                        .iter()
                        .map(|mem| ReportMember {
                            name: candidates[mem.index].name.clone(),
                            guid: scan.profiles[mem.index].guid.clone(),
                            materials: candidates[mem.index].materials,
                            shape_error: mem.cost.shape,
                            tint_delta_e: mem.cost.tint_delta_e,
                            modes_changed: mem.cost.modes_changed,
                            delta_l_mean: mem.delta_l.map(|d| d.0),
                            delta_l_max: mem.delta_l.map(|d| d.1),
                            pair: [
                                mem.preset_file.clone(),
                                format!("pairs/{}_merged.ron", k + 1),
                            ],
                        })
                        .collect(),
                })
                .collect(),
        };
        write(&BudgetReport::path(&self.out), report.to_json().as_bytes())?;
        Ok(summary)
    }

    /// The material references that name no profile, and the files left
    /// out, as the report's Markdown.
    fn left_out_md(&self, scan: &project::Project) -> String {
        let mut md = String::new();
        if !scan.unresolved.is_empty() {
            md.push_str(&format!(
                "{} material references name no profile in the project (a deleted or package profile); they are left as they are:\n\n",
                scan.unresolved.len()
            ));
            for u in &scan.unresolved {
                md.push_str(&format!(
                    "- `{}` {} → {}\n",
                    rel(&self.project, &u.material),
                    u.asset_property,
                    u.guid
                ));
            }
            md.push('\n');
        }
        if !scan.skipped.is_empty() {
            md.push_str("Left out:\n\n");
            for (p, why) in &scan.skipped {
                md.push_str(&format!("- `{}`: {why}\n", rel(&self.project, p)));
            }
            md.push('\n');
        }
        md
    }

    /// Merge `k`'s section of the report: its members' costs, its
    /// curves and its heads.
    fn merge_md(&self, k: usize, m: &Merge, candidates: &[Candidate]) -> String {
        let mut md = String::new();
        md.push_str(&format!(
            "## Merge {}: {}\n\n`profiles/{}.asset` (GUID {}). Compare in the editor: `scatterlab edit --budget {}` ({} ← {}).\n\n| profile | materials | shape error | tint ΔE*ab | modes changed | head ΔL* mean / max |\n| --- | --- | --- | --- | --- | --- |\n",
            k + 1,
            m.merged.name,
            m.stem,
            m.guid,
            self.out.display(),
            format_args!("pairs/{}_merged.ron", k + 1),
            m.members.iter().map(|mem| mem.preset_file.as_str()).collect::<Vec<_>>().join(", ")
        ));
        for mem in &m.members {
            md.push_str(&format!(
                "| {} | {} | {:.4} | {:.2} | {} | {} |\n",
                candidates[mem.index].name,
                candidates[mem.index].materials,
                mem.cost.shape,
                mem.cost.tint_delta_e,
                mem.cost.modes_changed,
                mem.delta_l
                    .map(|(a, b)| format!("{a:.2} / {b:.2}"))
                    .unwrap_or_else(|| "not rendered".into())
            ));
        }
        md.push_str(&format!(
            "\n![r·R(r) of each profile and the merge]({})\n\n",
            m.curves
        ));
        for mem in &m.members {
            if let Some(img) = &mem.image {
                md.push_str(&format!(
                    "![{}: old, merged, |ΔL*|]({img})\n",
                    candidates[mem.index].name
                ));
            }
        }
        md.push('\n');
        md
    }

    /// Copies the merged profiles and the list into the project and points
    /// the materials at them, every rewritten file backed up first.
    fn apply(
        &self,
        merges: &[Merge],
        remapped: &[(&MaterialUse, String)],
        list_name: &str,
        list_guid: &str,
    ) -> Result<String> {
        let assets = if self.project.join("Assets").is_dir() {
            self.project.join("Assets")
        } else {
            self.project.clone()
        };
        let target = assets.join("scatterlab_budget");
        let backup = self.out.join("backup");
        if backup.exists()
            && std::fs::read_dir(&backup)
                .map(|mut d| d.next().is_some())
                .unwrap_or(false)
        {
            bail!(
                "{}: holds an earlier backup; move it away before --apply, so that no backup is lost",
                backup.display()
            );
        }
        // Every material's new text first, so that a failure writes nothing.
        let mut texts: BTreeMap<PathBuf, String> = BTreeMap::new();
        for (u, guid) in remapped {
            let text = match texts.get(&u.material) {
                Some(t) => t.clone(),
                None => std::fs::read_to_string(&u.material)
                    .with_context(|| format!("{}: cannot read", u.material.display()))?,
            };
            let new = project::repoint_material(&text, &u.asset_property, &u.hash_property, guid)
                .map_err(|e| {
                anyhow::anyhow!("{}: {}: {e}", u.material.display(), u.asset_property)
            })?;
            texts.insert(u.material.clone(), new);
        }
        for path in texts.keys() {
            let to = backup.join(path.strip_prefix(&self.project).unwrap_or(path));
            if let Some(d) = to.parent() {
                std::fs::create_dir_all(d)?;
            }
            std::fs::copy(path, &to).with_context(|| {
                format!("{}: cannot back up to {}", path.display(), to.display())
            })?;
        }
        for m in merges {
            for ext in ["asset", "asset.meta"] {
                let from = self.out.join("profiles").join(format!("{}.{ext}", m.stem));
                let to = target.join(format!("{}.{ext}", m.stem));
                if to.exists() {
                    let old = std::fs::read(&to)?;
                    let b = backup.join(to.strip_prefix(&self.project).unwrap_or(&to));
                    write(&b, &old)?;
                }
                write(&to, &std::fs::read(&from)?)?;
            }
        }
        for ext in ["asset", "asset.meta"] {
            let to = target.join(format!("{list_name}.{ext}"));
            if to.exists() {
                let b = backup.join(to.strip_prefix(&self.project).unwrap_or(&to));
                write(&b, &std::fs::read(&to)?)?;
            }
            let from = self.out.join(format!("{list_name}.{ext}"));
            write(&to, &std::fs::read(&from)?)?;
        }
        let _ = list_guid;
        for (path, text) in &texts {
            write(path, text.as_bytes())?;
        }
        Ok(format!(
            "applied: {} materials repointed, {} profiles and the list in {} (backup in {})",
            texts.len(),
            merges.len(),
            target.display(),
            backup.display()
        ))
    }
}

/// Leaves out of the scan the profiles no material uses, when some are
/// used: dropping one frees a slot at no cost to any material, where a
/// merge would spend one and pull the merged profile. Their names (file
/// stems), in the project's order.
fn drop_unused(scan: &mut project::Project) -> Vec<String> {
    let used = |p: &project::ProjectProfile| scan.uses.iter().any(|u| u.guid == p.guid);
    if !scan.profiles.iter().any(used) {
        return Vec::new();
    }
    let (kept, dropped): (Vec<_>, Vec<_>) = std::mem::take(&mut scan.profiles)
        .into_iter()
        .partition(|p| scan.uses.iter().any(|u| u.guid == p.guid));
    scan.profiles = kept;
    dropped
        .iter()
        .map(|p| {
            p.path
                .file_stem()
                .map_or_else(|| p.guid.clone(), |s| s.to_string_lossy().into_owned())
        })
        .collect()
}

/// The materials that use each profile (a material once per profile),
/// and each profile as a merge candidate weighted by them.
fn candidates(scan: &project::Project) -> (Vec<Vec<&MaterialUse>>, Vec<Candidate>) {
    let mut users: Vec<Vec<&MaterialUse>> = vec![Vec::new(); scan.profiles.len()];
    for u in &scan.uses {
        if let Some(i) = scan.profiles.iter().position(|p| p.guid == u.guid) {
            if !users[i].iter().any(|v| v.material == u.material) {
                users[i].push(u);
            }
        }
    }
    let candidates: Vec<Candidate> = scan
        .profiles
        .iter()
        .zip(&users)
        .map(|(p, u)| Candidate {
            name: p
                .path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| p.guid.clone()),
            preset: p.look.preset.clone(),
            materials: u.len(),
        })
        .collect();
    (users, candidates)
}

/// A merge for each group of two or more profiles (a new profile with a
/// GUID from its members'), and the GUIDs the list holds.
fn merges(
    scan: &project::Project,
    candidates: &[Candidate],
    costs: &Costs,
    groups: &[Vec<usize>],
) -> Result<(Vec<Merge>, Vec<String>)> {
    let mut merges = Vec::new();
    let mut list_guids = Vec::new();
    for g in groups {
        if g.len() == 1 {
            list_guids.push(scan.profiles[g[0]].guid.clone());
            continue;
        }
        let merged = costs.merged(g)?;
        let key: Vec<&str> = g.iter().map(|&i| scan.profiles[i].guid.as_str()).collect();
        let guid = new_guid(&key.join(","));
        let stem = file_stem(&merged.name);
        let members = g
            .iter()
            .map(|&i| {
                Ok(Member {
                    index: i,
                    cost: member_cost(costs.table(), &candidates[i].preset, &merged)?,
                    delta_l: None,
                    image: None,
                    preset_file: String::new(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        list_guids.push(guid.clone());
        merges.push(Merge {
            members,
            merged,
            guid,
            stem,
            curves: String::new(),
        });
    }
    Ok((merges, list_guids))
}

/// `text` (a profile asset) with its `hash:` line set to `hash`.
fn with_hash(text: &str, hash: u32) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with("hash:") {
                format!("    hash: {hash}")
            } else {
                l.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

fn rel(root: &Path, p: &Path) -> String {
    p.strip_prefix(root).unwrap_or(p).display().to_string()
}

fn csv(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}
