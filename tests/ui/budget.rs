//! `edit --budget DIR`: a budget report's merges as compare pairs.

use super::*;
use scatterlab::app::state::{CompareB, CompareMode};
use scatterlab::app::windows::budget::BudgetPairs;

/// A budget folder as `scatterlab budget` writes one: budget.json and the
/// pair presets it names.
pub(super) fn budget_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "scatterlab-ui-budget-{}-{name}",
        std::process::id()
    ));
    std::fs::create_dir_all(dir.join("pairs")).unwrap();
    let mut a = Preset::default_skin();
    a.name = "Skin_Villager_A".into();
    a.save(&dir.join("pairs/1_Skin_Villager_A.ron")).unwrap();
    let mut m = Preset::default_skin();
    m.name = "Merged Skin_Villager_A + Skin_Villager_B".into();
    m.save(&dir.join("pairs/1_merged.ron")).unwrap();
    let json = serde_json::json!({
        "dropped": ["Unused_Wax_Test"],
        "merges": [{
            "merged": {"name": m.name, "guid": "d7a40e0306ba8dd0684474b2cfad7bc3"},
            "members": [{
                "name": "Skin_Villager_A", "materials": 4, "shape_error": 0.0123,
                "tint_delta_e": 0.5, "delta_l_mean": 0.03,
                "pair": ["pairs/1_Skin_Villager_A.ron", "pairs/1_merged.ron"],
            }],
        }],
    });
    std::fs::write(dir.join("budget.json"), json.to_string()).unwrap();
    dir
}

/// The window lists the merge and its profile's figures, and the unused
/// profiles dropped before merging; Compare opens
/// the profile as A and its merge as B, side by side.
#[test]
fn budget_merges_open_as_compare_pairs() {
    let dir = budget_dir("pairs");
    let pairs = BudgetPairs::load(&dir).unwrap();
    let mut h = harness(false);
    h.state_mut().open_budget(pairs);
    h.run_steps(4);
    h.get_by_label_contains("Merged Skin_Villager_A + Skin_Villager_B");
    h.get_by_label("0.0123");
    // Issue 52: the profiles no material uses were dropped, and it says so.
    h.get_by_label("Dropped (no material uses them): Unused_Wax_Test");
    h.get_by_label("A | B").click();
    h.run_steps(4);
    let app = h.state();
    assert_eq!(app.doc.preset.name, "Skin_Villager_A");
    assert_eq!(app.ui_state.compare, CompareMode::SideBySide);
    assert_eq!(
        app.ui_state.compare_b,
        CompareB::Preset(dir.join("pairs/1_merged.ron"))
    );
}

/// A folder that is no budget report, or one whose pair is gone, is
/// refused with the file named.
#[test]
fn a_broken_budget_folder_is_refused_by_name() {
    let dir = budget_dir("broken");
    std::fs::remove_file(dir.join("pairs/1_merged.ron")).unwrap();
    let e = BudgetPairs::load(&dir).unwrap_err();
    assert!(e.contains("1_merged.ron") && e.contains("missing"), "{e}");
    let e = BudgetPairs::load(&std::env::temp_dir().join("no-such-budget")).unwrap_err();
    assert!(e.contains("budget.json"), "{e}");
}
