//! The sources the firmware is built from, carried inside the `codegen` binary and unpacked into a cache
//! directory on first use, so that an installed `codegen` runs a project from any directory: nothing is
//! looked up in the checkout the binary was built in.
//!
//! `codegen/build.rs` embeds the runtime crate, the cell applications, codegen's own crate, the workspace's `Cargo.lock`, `rust-toolchain.toml`,
//! `.cargo/config.toml`, a workspace manifest holding those three alone, and the RP2040 harness. They
//! are unpacked into `CACHE/firmware-VERSION-DIGEST/`, where `DIGEST` is the first 16 hex digits of the
//! SHA-256 of every embedded path and its bytes: a binary with other sources unpacks beside, never over,
//! another's. `CACHE` is `$SCT_CODEGEN_CACHE`, else `$XDG_CACHE_HOME/sct-codegen`, else
//! `$HOME/.cache/sct-codegen`. Cargo builds in `$CARGO_TARGET_DIR`, else `CACHE/target`, shared by
//! every version, so the firmware's dependencies compile once. A directory is unpacked whole under a
//! temporary name and renamed into place, so a process never sees half of one.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

use sha2::{Digest, Sha256};

use super::lock::FileLock;

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/embedded_sources.rs"));
}

/// The harness's directory, relative to the sources' root.
pub const HARNESS_DIR: &str = "harness/rp2040";

/// The sources could not be unpacked or completed.
#[derive(Debug, thiserror::Error)]
pub enum SourcesError {
    /// No cache directory can be named.
    #[error("no cache directory for the firmware sources: set SCT_CODEGEN_CACHE (or HOME)")]
    NoCache,
    /// A file operation failed.
    #[error("{what} {}: {source}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// `npm ci` could not install the harness's packages.
    #[error("installing the RP2040 harness's packages (npm ci in {}) failed: {detail}", dir.display())]
    Npm {
        /// The harness's directory.
        dir: PathBuf,
        /// Why: npm's stderr or the error starting it.
        detail: String,
    },
}

/// The cache directory: `$SCT_CODEGEN_CACHE`, else `$XDG_CACHE_HOME/sct-codegen`, else
/// `$HOME/.cache/sct-codegen` (see the module documentation).
pub fn cache_dir() -> Result<PathBuf, SourcesError> {
    cache_dir_in(&|name| std::env::var_os(name))
}

/// [`cache_dir`] with the environment read through `env`.
fn cache_dir_in(env: &dyn Fn(&str) -> Option<OsString>) -> Result<PathBuf, SourcesError> {
    let var = |name| env(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    var("SCT_CODEGEN_CACHE")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("sct-codegen")))
        .or_else(|| var("HOME").map(|d| d.join(".cache/sct-codegen")))
        .ok_or(SourcesError::NoCache)
}

/// Where cargo builds the firmware: `$CARGO_TARGET_DIR`, else `CACHE/target`.
pub fn target_dir() -> Result<PathBuf, SourcesError> {
    match std::env::var_os("CARGO_TARGET_DIR").filter(|v| !v.is_empty()) {
        Some(dir) => Ok(PathBuf::from(dir)),
        None => Ok(cache_dir()?.join("target")),
    }
}

/// First 16 hex digits of the SHA-256 of every embedded file's path and bytes, in path order.
pub fn digest() -> &'static str {
    static DIGEST: OnceLock<String> = OnceLock::new();
    DIGEST.get_or_init(|| {
        let mut hash = Sha256::new();
        for (path, bytes) in embedded::FILES {
            hash.update((path.len() as u64).to_le_bytes());
            hash.update(path.as_bytes());
            hash.update((bytes.len() as u64).to_le_bytes());
            hash.update(bytes);
        }
        hash.finalize().iter().take(8).map(|b| format!("{b:02x}")).collect()
    })
}

/// The bytes of the carried file `rel` (a path relative to the sources' root), if this binary carries it.
pub fn carried(rel: &str) -> Option<&'static [u8]> {
    embedded::FILES.iter().find(|(p, _)| *p == rel).map(|(_, bytes)| *bytes)
}

/// The root of the unpacked sources (a workspace of `firmware`, `apps/cell` and `codegen`), unpacked now if this
/// binary's sources are not in the cache yet.
pub fn unpacked() -> Result<PathBuf, SourcesError> {
    unpack_into(&cache_dir()?)
}

/// Unpacks the sources into `cache` unless they are there already; returns their root.
fn unpack_into(cache: &Path) -> Result<PathBuf, SourcesError> {
    let name = format!("firmware-{}-{}", env!("CARGO_PKG_VERSION"), digest());
    let root = cache.join(&name);
    if root.is_dir() {
        return Ok(root);
    }
    let io = |what, path: &Path| {
        let path = path.to_path_buf();
        move |source| SourcesError::Io { what, path, source }
    };
    // A staging directory per call: two threads of one process unpacking at once (two tests of one
    // binary) would otherwise write into, remove and rename one directory, and leave half of it in place.
    static STAGED: AtomicU32 = AtomicU32::new(0);
    let n = STAGED.fetch_add(1, Ordering::Relaxed);
    let staging = cache.join(format!(".{name}.{}.{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&staging);
    for (rel, bytes) in embedded::FILES {
        let path = staging.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(io("creating", parent))?;
        }
        std::fs::write(&path, bytes).map_err(io("writing", &path))?;
    }
    if let Err(source) = std::fs::rename(&staging, &root) {
        let _ = std::fs::remove_dir_all(&staging);
        // Another process unpacked the same sources first: theirs are as good as ours.
        if !root.is_dir() {
            return Err(SourcesError::Io { what: "renaming into place", path: root, source });
        }
    }
    Ok(root)
}

/// Makes cargo see the sources at `root` as newer than anything built in `target_dir` from other sources.
/// The target directory is shared by every version's sources, and cargo names a path package's
/// artifacts by its path relative to the workspace, so two versions share artifact names; cargo then
/// judges freshness by modification times alone, and sources unpacked *before* another version was
/// built would pass as built (an old application linked with a newer runtime). When the last build in
/// `target_dir` was from other sources (a stamp file names them), every file under `root` gets the
/// current time. Call it holding the build lock.
pub fn make_current(root: &Path, target_dir: &Path) -> Result<(), SourcesError> {
    let stamp = target_dir.join("codegen-last-sources");
    let name = root.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    if std::fs::read_to_string(&stamp).is_ok_and(|last| last == name) {
        return Ok(());
    }
    let now = std::time::SystemTime::now();
    let mut dirs = vec![root.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|source| SourcesError::Io {
            what: "listing",
            path: dir.clone(),
            source,
        })?;
        for entry in entries.flatten() {
            let path = entry.path();
            match entry.file_type() {
                // A harness's installed packages are not the firmware's sources.
                Ok(t) if t.is_dir() && entry.file_name() != "node_modules" => dirs.push(path),
                Ok(t) if t.is_file() => std::fs::File::options()
                    .write(true)
                    .open(&path)
                    .and_then(|f| f.set_modified(now))
                    .map_err(|source| SourcesError::Io { what: "touching", path, source })?,
                _ => {}
            }
        }
    }
    std::fs::write(&stamp, name).map_err(|source| SourcesError::Io { what: "writing", path: stamp, source })
}

/// The unpacked RP2040 harness's entry point (`harness/rp2040/src/main.js`), its Node packages installed
/// (`npm ci`, from npm's cache when it has them) the first time.
pub fn harness_script() -> Result<PathBuf, SourcesError> {
    let dir = unpacked()?.join(HARNESS_DIR);
    let io = |what, path: &Path| {
        let path = path.to_path_buf();
        move |source| SourcesError::Io { what, path, source }
    };
    let stamp = dir.join("node_modules/.installed-lock");
    let lock_path = dir.join(".npm-ci.lock");
    let _lock = FileLock::exclusive(&lock_path).map_err(io("locking", &lock_path))?;
    if !stamp.is_file() {
        let npm = |detail: String| SourcesError::Npm { dir: dir.clone(), detail };
        let out = Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund", "--prefer-offline", "--loglevel=error"])
            .current_dir(&dir)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| npm(format!("cannot start npm: {e} (install Node.js and npm)")))?;
        if !out.status.success() {
            return Err(npm(String::from_utf8_lossy(&out.stderr).into_owned()));
        }
        std::fs::copy(dir.join("package-lock.json"), &stamp).map_err(io("writing", &stamp))?;
    }
    Ok(dir.join("src/main.js"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Switching the target directory to other sources makes every one of their files newer than the
    /// switch; building from the same sources again touches nothing.
    #[test]
    fn other_sources_are_made_newer_than_the_last_build_and_the_same_are_left_alone() {
        let base = std::env::temp_dir().join(format!("sct-make-current-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        let (a, b, target) = (base.join("firmware-a"), base.join("firmware-b"), base.join("target"));
        for dir in [a.join("src"), b.join("src"), target.clone()] {
            std::fs::create_dir_all(dir).unwrap();
        }
        let old = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000);
        for root in [&a, &b] {
            let file = root.join("src/lib.rs");
            std::fs::write(&file, "").unwrap();
            std::fs::File::options().write(true).open(&file).unwrap().set_modified(old).unwrap();
        }
        let mtime = |root: &Path| std::fs::metadata(root.join("src/lib.rs")).unwrap().modified().unwrap();
        make_current(&a, &target).unwrap();
        assert!(mtime(&a) > old && mtime(&b) == old);
        let touched = mtime(&a);
        make_current(&a, &target).unwrap();
        assert_eq!(mtime(&a), touched, "the same sources again: nothing touched");
        make_current(&b, &target).unwrap();
        assert!(mtime(&b) > old);
        std::fs::remove_dir_all(&base).unwrap();
    }

    /// The files the firmware build, a project's build script and the harness need are carried, and
    /// nothing of the end-to-end tests.
    #[test]
    fn the_firmware_build_travels_and_the_tests_do_not() {
        let paths: Vec<&str> = embedded::FILES.iter().map(|(p, _)| *p).collect();
        for needed in [
            "Cargo.toml",
            "Cargo.lock",
            "rust-toolchain.toml",
            ".cargo/config.toml",
            "firmware/Cargo.toml",
            "firmware/src/lib.rs",
            "apps/cell/Cargo.toml",
            "apps/cell/build.rs",
            "apps/cell/boards/lm3s6965/memory.x",
            "apps/cell/boards/pico/memory.x",
            "apps/cell/src/bin/cell_qemu/main.rs",
            "codegen/Cargo.toml",
            "codegen/build.rs",
            "codegen/src/project/build_script.rs",
            "harness/rp2040/package-lock.json",
            "harness/rp2040/src/main.js",
        ] {
            assert!(paths.contains(&needed), "{needed} is not embedded");
        }
        assert!(
            paths.iter().all(|p| !p.starts_with("codegen/tests/") && !p.starts_with("tests/")),
            "{paths:?}"
        );
        let mut sorted = paths.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), paths.len(), "each file once");
    }

    /// The workspace manifest that travels holds the runtime, the applications and codegen alone, with the
    /// checkout's release profile.
    #[test]
    fn the_embedded_workspace_is_the_firmware_alone() {
        let (_, bytes) = embedded::FILES.iter().find(|(p, _)| *p == "Cargo.toml").unwrap();
        let manifest: toml::Table = std::str::from_utf8(bytes).unwrap().parse().unwrap();
        let members: Vec<&str> =
            manifest["workspace"]["members"].as_array().unwrap().iter().filter_map(|m| m.as_str()).collect();
        assert_eq!(members, ["firmware", "apps/cell", "codegen"]);
        assert_eq!(manifest["profile"]["release"]["opt-level"].as_str(), Some("s"));
        assert_eq!(manifest["profile"]["release"]["lto"].as_bool(), Some(true));
    }

    /// The cache is `SCT_CODEGEN_CACHE`, else under `XDG_CACHE_HOME`, else under `HOME`; empty values
    /// count as unset.
    #[test]
    fn the_cache_directory_follows_the_environment_in_order() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| vars.iter().find(|(n, _)| *n == name).map(|(_, v)| OsString::from(v))
        };
        const ALL: &[(&str, &str)] = &[("SCT_CODEGEN_CACHE", "/c"), ("XDG_CACHE_HOME", "/x"), ("HOME", "/h")];
        assert_eq!(cache_dir_in(&env(ALL)).unwrap(), PathBuf::from("/c"));
        assert_eq!(cache_dir_in(&env(&ALL[1..])).unwrap(), PathBuf::from("/x/sct-codegen"));
        assert_eq!(
            cache_dir_in(&env(&[("XDG_CACHE_HOME", ""), ("HOME", "/h")])).unwrap(),
            PathBuf::from("/h/.cache/sct-codegen")
        );
        assert!(matches!(cache_dir_in(&env(&[])), Err(SourcesError::NoCache)));
    }

    /// Unpacking writes every file as embedded, under the digest's name, and only once.
    #[test]
    fn unpacks_every_file_once_under_its_digest() {
        let cache = std::env::temp_dir().join(format!("codegen-sources-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&cache);
        let root = unpack_into(&cache).unwrap();
        assert!(root.ends_with(format!("firmware-{}-{}", env!("CARGO_PKG_VERSION"), digest())));
        for (rel, bytes) in embedded::FILES {
            assert_eq!(std::fs::read(root.join(rel)).unwrap(), *bytes, "{rel}");
        }
        std::fs::write(root.join("Cargo.lock"), "changed by cargo").unwrap();
        assert_eq!(unpack_into(&cache).unwrap(), root);
        assert_eq!(std::fs::read_to_string(root.join("Cargo.lock")).unwrap(), "changed by cargo");
        let left: Vec<_> = std::fs::read_dir(&cache).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 1, "no staging directory left behind: {left:?}");
        std::fs::remove_dir_all(cache).unwrap();
    }

    /// Threads that unpack at once into an empty cache all get the whole sources, in one directory.
    #[test]
    fn threads_unpacking_at_once_each_get_the_whole_sources() {
        let cache = std::env::temp_dir().join(format!("codegen-sources-race-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&cache);
        let roots: Vec<PathBuf> = std::thread::scope(|s| {
            let all: Vec<_> = (0..4).map(|_| s.spawn(|| unpack_into(&cache).unwrap())).collect();
            all.into_iter().map(|t| t.join().unwrap()).collect()
        });
        assert!(roots.iter().all(|r| *r == roots[0]), "{roots:?}");
        for (rel, bytes) in embedded::FILES {
            assert_eq!(std::fs::read(roots[0].join(rel)).ok().as_deref(), Some(*bytes), "{rel}");
        }
        let left: Vec<_> = std::fs::read_dir(&cache).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 1, "no staging directory left behind: {left:?}");
        std::fs::remove_dir_all(cache).unwrap();
    }
}
