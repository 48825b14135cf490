//! The project ships its own documentation (issue 9, item 7): no file of the project may send a
//! reader into the workplace's `shared` folder beside the checkout, by a relative path or an
//! absolute one (issue 45), which users of the project do not have. The model lives in
//! `docs/model.md`, the layout in `docs/architecture.md`.

use std::path::{Path, PathBuf};

/// Every file of the project below `dir`, skipping build output, the Python venv and git.
fn project_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            if !matches!(name.as_str(), "target" | ".venv" | ".git" | "out") {
                project_files(&path, out);
            }
        } else {
            out.push(path);
        }
    }
}

#[test]
fn no_file_points_outside_the_project() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    project_files(root, &mut files);
    assert!(files.len() > 50, "found only {} files", files.len());
    // Built so that this file does not match itself.
    for needle in [
        format!("../{}/", "shared"),
        format!("/{}/{}", "work", "shared"),
    ] {
        let offenders: Vec<String> = files
            .iter()
            .filter(|p| {
                std::fs::read(p)
                    .map(|bytes| String::from_utf8_lossy(&bytes).contains(&needle))
                    .unwrap_or(false)
            })
            .map(|p| p.strip_prefix(root).unwrap().display().to_string())
            .collect();
        assert!(
            offenders.is_empty(),
            "these files point to {needle}, which users do not have: {offenders:?}"
        );
    }
}

#[test]
fn the_model_is_documented_in_the_project() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = std::fs::read_to_string(root.join("docs/model.md")).unwrap();
    // The sections the code and the other docs cite as "model.md §N".
    for n in 1..=9 {
        assert!(
            model.contains(&format!("\n## {n}. ")),
            "docs/model.md has no section {n}"
        );
    }
    for eq in ["eq. 3", "eq. 4", "eq. 5", "eq. 6", "eq. 10", "eq. 11"] {
        assert!(model.contains(eq), "docs/model.md does not state {eq}");
    }
}
