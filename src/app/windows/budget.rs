//! The merges of a `scatterlab budget` report as compare pairs (`edit
//! --budget DIR`): a window lists each merge's profiles with what the
//! merge costs them, and Compare opens the profile as A beside its merge
//! as B.

use super::{Action, Menu, Window, WindowView};
use crate::export::unity_budget::{BudgetReport, ReportMember, ReportMerge};
use std::path::{Path, PathBuf};

/// A budget report's merges, read from its `budget.json`, and the folder
/// its pairs are named in.
#[derive(Debug, Clone, PartialEq)]
pub struct BudgetPairs {
    pub dir: PathBuf,
    pub report: BudgetReport,
}

impl BudgetPairs {
    /// Reads `DIR/budget.json` ([`BudgetReport::read`]): an error names
    /// the file and the field or the missing pair.
    pub fn load(dir: &Path) -> Result<Self, String> {
        Ok(Self {
            dir: dir.to_owned(),
            report: BudgetReport::read(dir)?,
        })
    }
}

/// `edit --budget DIR`: the report's merges, and whether their window is
/// open.
#[derive(Default)]
pub struct BudgetWindow {
    pairs: Option<BudgetPairs>,
    open: bool,
}

impl BudgetWindow {
    /// Opens `pairs` in the window; the line for the status bar.
    pub fn load(&mut self, pairs: BudgetPairs) -> String {
        let said = format!(
            "Budget {}: {} merges; 'A | B' opens a profile beside its merge",
            pairs.dir.display(),
            pairs.report.merges.len()
        );
        self.pairs = Some(pairs);
        self.open = true;
        said
    }
}

/// One merge's profiles with what the merge costs each; the one whose
/// "A | B" was clicked.
fn merge_ui(ui: &mut egui::Ui, i: usize, m: &ReportMerge) -> Option<ReportMember> {
    let mut chosen = None;
    ui.strong(format!("{}. {}", i + 1, m.merged.name));
    egui::Grid::new(("budget", i)).striped(true).show(ui, |ui| {
        ui.label("profile");
        ui.label("mat.").on_hover_text("materials that use the profile");
        ui.label("shape").on_hover_text("shape error: the worst channel's relative L2 error of r·R(r), energy-normalised; 1 = no scattering at all");
        ui.label("tint ΔE").on_hover_text("CIE 1976 ΔE*ab of the transmission tint");
        ui.label("ΔL*").on_hover_text("mean CIE lightness difference on the rendered head, old against merged (— where not rendered)");
        ui.label("");
        ui.end_row();
        for mem in &m.members {
            ui.label(&mem.name);
            ui.label(mem.materials.to_string());
            ui.label(format!("{:.4}", mem.shape_error));
            ui.label(format!("{:.2}", mem.tint_delta_e));
            ui.label(mem.delta_l_mean.map_or("—".into(), |d| format!("{d:.2}")));
            if ui
                .button("A | B")
                .on_hover_text(format!("Compare: A {}, B the merge, side by side", mem.name))
                .clicked()
            {
                chosen = Some(mem.clone());
            }
            ui.end_row();
        }
    });
    ui.add_space(6.0);
    chosen
}

impl Window for BudgetWindow {
    fn title(&self) -> &'static str {
        "Budget merges"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::FilePresets)
    }
    fn menu_tooltip(&self) -> &'static str {
        "The merges of the budget report opened with --budget: compare each profile with its merge"
    }
    /// Listed only with a report opened (`edit --budget DIR`).
    fn in_menu(&self) -> bool {
        self.pairs.is_some()
    }
    fn is_open(&self) -> bool {
        self.open && self.pairs.is_some()
    }
    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let Some(pairs) = self.pairs.as_ref().filter(|_| self.open) else {
            return Vec::new();
        };
        let mut chosen = None;
        // Over the Profile panel: a pair chosen here shows in the viewport,
        // which it covered at 1280×720 when it opened inside it.
        let (pos, width) = view.over_profile_panel(460.0, 4.0);
        egui::Window::new(self.title())
            .open(&mut self.open)
            .default_width(width)
            .default_pos(pos)
            .show(ctx, |ui| {
                ui.label(pairs.dir.display().to_string());
                if !pairs.report.dropped.is_empty() {
                    ui.label(format!(
                        "Dropped (no material uses them): {}",
                        pairs.report.dropped.join(", ")
                    ))
                    .on_hover_text("Left out of the list before any merge: they took a slot for nothing. Their assets stay in the project.");
                }
                egui::ScrollArea::vertical()
                    .max_height(420.0)
                    .show(ui, |ui| {
                        for (i, m) in pairs.report.merges.iter().enumerate() {
                            chosen = merge_ui(ui, i, m).or(chosen.take());
                        }
                    });
            });
        chosen
            .map(|m| Action::ComparePair(m.pair.map(|p| pairs.dir.join(p))))
            .into_iter()
            .collect()
    }
}
