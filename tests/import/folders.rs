//! `convert --from` and `import` over a folder laid out as a Unity project
//! (`tests/data/unity_project/`, its README lists what is there): it
//! recurses into subfolders, converts every profile of every version,
//! writes a look that a profile list names once, and skips what is not a
//! profile with a count; a broken profile in the folder still fails,
//! naming the file and the field.

use super::*;

fn project() -> PathBuf {
    data("unity_project")
}

#[test]
fn convert_from_a_unity_project_recurses_and_skips_what_is_not_a_profile() {
    let out = tmp("project_out");
    let _ = std::fs::remove_dir_all(&out);
    let (code, stdout, stderr) = cli(&[
        "convert",
        "--from",
        project().to_str().unwrap(),
        "--to",
        "unity",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let files = v["files"].as_array().unwrap();
    let name = |f: &serde_json::Value| {
        Path::new(f["file"].as_str().unwrap())
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned()
    };
    let looks = |n: &str| {
        files
            .iter()
            .find(|f| name(f) == n)
            .unwrap_or_else(|| panic!("{n} not converted: {stdout}"))["looks"]
            .as_array()
            .unwrap()
            .len()
    };
    // Every version: m_Version 0 (15 profiles in one asset), 1 and 2, in
    // three levels of subfolders.
    assert_eq!(looks("Default Diffusion Profile Settings.asset"), 15);
    assert_eq!(looks("Skin Diffusion Profile.asset"), 1);
    assert_eq!(looks("SkinDiffusionProfile.asset"), 1);
    assert_eq!(looks("FoliageDiffusionProfile.asset"), 1);
    assert_eq!(looks("ScleraDiffusionProfile 25mm.asset"), 1);
    // The volume profile names two of them: written once, from their own
    // files.
    let list = files
        .iter()
        .find(|f| name(f) == "SkinVolumeProfile.asset")
        .unwrap();
    assert_eq!(list["looks"].as_array().unwrap().len(), 0, "{stdout}");
    assert_eq!(list["looks_read_from_other_files"], 2, "{stdout}");
    assert_eq!(v["converted_files"], 6, "{stdout}");
    assert_eq!(v["failed_files"], 0, "{stdout}");
    // Skipped, with why: the README, Unity's version file, binary
    // lighting data, a pipeline asset with no profile. Never read: the
    // hidden folder's broken asset, the .meta and .mat files.
    let mut skipped: Vec<(String, String)> = v["skipped"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (name(s), s["why"].as_str().unwrap().to_owned()))
        .collect();
    skipped.sort();
    let names: Vec<&str> = skipped.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "HDRenderPipelineAsset.asset",
            "LightingData.asset",
            "ProjectVersion.txt",
            "README.txt"
        ],
        "{stdout}"
    );
    assert!(skipped[0].1.contains("no diffusion profile"), "{skipped:?}");
    assert!(skipped[1].1.contains("not text"), "{skipped:?}");
    assert!(
        skipped[3].1.contains("not a file scatterlab imports"),
        "{skipped:?}"
    );
    assert!(!stdout.contains(".history"), "{stdout}");
    // 19 looks written, and they import back as the looks they came from.
    let written: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert_eq!(written.len(), 19, "{written:?}");
    let back = &import(&out.join("ScleraDiffusionProfile 25mm.asset"))[0].preset;
    let from = &import(&project().join("Assets/Characters/Hero/ScleraDiffusionProfile 25mm.asset"))
        [0]
    .preset;
    same_shape(&burley_of(from), &burley_of(back), 1e-3);
    // Without --json: a summary line with the counts.
    let (code, stdout, _) = cli(&[
        "convert",
        "--from",
        project().to_str().unwrap(),
        "--to",
        "materialx",
        "--out",
        tmp("project_mtlx").to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(code, 0, "{stdout}");
    assert!(
        stdout
            .lines()
            .last()
            .unwrap()
            .starts_with("6 file(s) converted, 0 failed, 4 skipped (not engine profiles: "),
        "{stdout}"
    );
}

/// A broken profile among the project's files still fails the run, naming
/// the file and the field, while the others convert; a README named on
/// its own is refused, not skipped.
#[test]
fn a_broken_profile_in_a_folder_still_fails() {
    let dir = tmp("project_broken");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("Assets/Skin")).unwrap();
    let good = project().join("Assets/Characters/Hero/SkinDiffusionProfile.asset");
    std::fs::copy(&good, dir.join("Assets/Skin/Good.asset")).unwrap();
    let text = std::fs::read_to_string(&good)
        .unwrap()
        .replace("m_Version: 2", "m_Version: 7");
    assert!(text.contains("m_Version: 7"));
    std::fs::write(dir.join("Assets/Skin/Broken.asset"), text).unwrap();
    std::fs::write(dir.join("Assets/README.txt"), "notes\n").unwrap();
    let out = tmp("project_broken_out");
    let (code, stdout, stderr) = cli(&[
        "convert",
        "--from",
        dir.to_str().unwrap(),
        "--to",
        "unity",
        "--out",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert_ne!(code, 0, "{stdout}");
    let failed = stdout.lines().find(|l| l.contains("FAILED")).unwrap();
    assert!(
        failed.contains("Broken.asset") && failed.contains("m_Version") && failed.contains('7'),
        "{stdout}"
    );
    assert!(stdout.contains("Good.asset"), "{stdout}");
    assert!(
        stdout.contains("1 file(s) converted, 1 failed, 1 skipped"),
        "{stdout}"
    );
    assert!(
        stderr.contains("1 of 2 file(s) could not be converted"),
        "{stderr}"
    );
    // A folder with nothing but non-profiles: an error that says so.
    let (code, _, stderr) = cli(&[
        "convert",
        "--from",
        project().join("ProjectSettings").to_str().unwrap(),
        "--to",
        "unity",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(
        stderr.contains("no engine profile found; 0 file(s) converted, 0 failed, 1 skipped")
            && stderr.contains("ProjectVersion.txt"),
        "{stderr}"
    );
    let (code, stdout, _) = cli(&[
        "convert",
        "--from",
        dir.join("Assets/README.txt").to_str().unwrap(),
        "--to",
        "unity",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(
        stdout.contains("README.txt: FAILED: not a file scatterlab imports"),
        "{stdout}"
    );
}

/// `import DIR` reads a folder as `convert --from` does: 19 looks from the
/// project's six profile files, each written as a preset into `--out`, the
/// same four files skipped; again without --force it replaces nothing.
#[test]
fn import_reads_a_unity_project_folder() {
    let out = tmp("project_presets");
    let _ = std::fs::remove_dir_all(&out);
    let (code, stdout, stderr) = cli(&[
        "import",
        project().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let looks = v["looks"].as_array().unwrap();
    assert_eq!(looks.len(), 19, "{stdout}");
    assert_eq!(v["skipped"].as_array().unwrap().len(), 4, "{stdout}");
    assert!(v["failed"].as_array().unwrap().is_empty(), "{stdout}");
    let presets: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert_eq!(presets.len(), 19, "{presets:?}");
    // Each written preset loads as the look the JSON holds.
    for l in looks {
        let path = PathBuf::from(l["written"].as_str().unwrap());
        let p = Preset::load(&path).unwrap();
        assert_eq!(p.name, l["name"].as_str().unwrap(), "{}", path.display());
    }
    let (code, _, stderr) = cli(&[
        "import",
        project().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(stderr.contains("exists; pass --force"), "{stderr}");
}
