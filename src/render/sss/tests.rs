use super::*;

/// Each method once, and each one's id is the name clap gives its
/// variant (`--method`), which is what reports and the bench's CSV carry.
#[test]
fn method_ids_are_clap_names() {
    let ids: Vec<&str> = Method::all().iter().map(|m| m.id()).collect();
    for &m in Method::all() {
        let name = clap::ValueEnum::to_possible_value(&m).map(|v| v.get_name().to_owned());
        assert_eq!(name.as_deref(), Some(m.id()));
    }
    let mut unique = ids.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), ids.len(), "{ids:?}");
}

/// The roles the renderer, the editor and the bench look up are each
/// held by exactly one method; exactly one is lit in the scene pass (its
/// tables are the scene's bindings); every method but the ground truth
/// has at least one bench configuration, each with a distinct variant and
/// count.
#[test]
fn each_role_is_held_by_one_method() {
    let count =
        |p: &dyn Fn(&MethodInfo) -> bool| Method::all().iter().filter(|m| p(m.sss())).count();
    assert_eq!(count(&|m| m.ground_truth), 1);
    assert_eq!(count(&|m| m.baseline), 1);
    assert_eq!(count(&|m| m.compare_partner), 1);
    assert_eq!(count(&|m| m.scene.is_some()), 1);
    assert!(Method::ground_truth().sss().ground_truth);
    assert!(Method::baseline().sss().baseline);
    assert!(Method::compare_partner().sss().compare_partner);
    assert_eq!(Method::ground_truth().preview(), Method::default());
    for &m in Method::all() {
        let knobs = (m.sss().bench)();
        assert!(!knobs.is_empty(), "{} has no bench configuration", m.id());
        let mut keys: Vec<_> = knobs.iter().map(|k| (k.variant, k.count)).collect();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), knobs.len(), "{}: {knobs:?}", m.id());
        // A fixed quality has no count; a sampled or tapped one has one.
        let fixed = m.sss().quality == Quality::Fixed;
        assert!(knobs.iter().all(|k| (k.count == 0) == fixed), "{}", m.id());
    }
}

/// The options' defaults are what the command line gives without its
/// flags (the editor uses the defaults, `render` the flags).
#[test]
fn method_options_default_to_the_flags_defaults() {
    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        options: MethodOptions,
    }
    let parsed = <Cli as clap::Parser>::try_parse_from(["x"]).unwrap();
    assert_eq!(parsed.options, MethodOptions::default());
}
