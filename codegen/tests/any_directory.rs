//! An installed `codegen` runs a user's project from the user's directory: the binary, copied out of
//! the build tree, runs `codegen run project.toml` under QEMU with the current directory a temporary
//! project holding only the user's files, and builds the firmware from the sources it carries, unpacked
//! into an empty cache (`SCT_CODEGEN_CACHE`). Cargo is the one on `PATH`, as for an installed binary.
//! Only the target directory is the checkout's, so the firmware's dependencies are not compiled again.

mod common;

use std::process::Command;

use common::{repo, Temp};

#[test]
fn an_installed_codegen_runs_a_project_outside_the_checkout() {
    let temp = Temp(std::env::temp_dir().join(format!("codegen-any-directory-{}", std::process::id())));
    let (bin, project, cache) = (temp.0.join("bin"), temp.0.join("project"), temp.0.join("cache"));
    for dir in [&bin, &project] {
        std::fs::create_dir_all(dir).unwrap();
    }
    let codegen = bin.join("codegen");
    std::fs::copy(env!("CARGO_BIN_EXE_codegen"), &codegen).unwrap();
    std::fs::copy(repo("examples/factory/factory.wmod"), project.join("factory.wmod")).unwrap();
    std::fs::copy(repo("examples/factory/factory.toml"), project.join("project.toml")).unwrap();

    let out = Command::new(&codegen)
        .args(["run", "project.toml", "--events", "300", "--json"])
        .current_dir(&project)
        .env_remove("CARGO")
        .env("SCT_CODEGEN_CACHE", &cache)
        .env("CARGO_TARGET_DIR", repo("target"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((json["name"].as_str(), json["violations"].as_u64()), (Some("factory"), Some(0)));
    assert!(json["events"].as_u64().unwrap() >= 300);

    // The firmware was built from the sources unpacked into the empty cache, and only those.
    let unpacked: Vec<String> = std::fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(unpacked.len(), 1, "{unpacked:?}");
    assert!(unpacked[0].starts_with(&format!("firmware-{}-", env!("CARGO_PKG_VERSION"))), "{unpacked:?}");
    assert!(cache.join(&unpacked[0]).join("apps/cell/src/bin/cell_qemu/main.rs").is_file());
    let listed: Vec<_> = std::fs::read_dir(&project).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(listed.len(), 2, "the project directory is left as it was: {listed:?}");
}

/// Outside the checkout, `run` without a project says that its default is a path of the checkout.
#[test]
fn run_without_a_project_outside_the_checkout_says_to_name_one() {
    let temp =
        Temp(std::env::temp_dir().join(format!("codegen-any-directory-{}-default", std::process::id())));
    std::fs::create_dir_all(&temp.0).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_codegen")).arg("run").current_dir(&temp.0).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("examples/cell/cell.toml is not here") && stderr.contains("codegen run PROJECT"),
        "{stderr}"
    );
}
