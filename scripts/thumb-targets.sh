#!/usr/bin/env bash
# The Cortex-M targets' standard libraries (`core`, `alloc`, `compiler_builtins`), wherever they come from.
#
#   bash scripts/thumb-targets.sh install          # into the toolchain: rustup, else built from rust-src
#   bash scripts/thumb-targets.sh sysroot DIR      # built from rust-src into the sysroot DIR (the CI proof)
#   bash scripts/thumb-targets.sh path             # which path the toolchain's targets took, one line each
#
# `install` is what scripts/setup.sh runs. A target whose libraries are already in the toolchain is left as
# it is (quiet). Otherwise `rustup target add` is tried (the stock path); where rustup cannot give the
# target — a channel manifest that marks `rust-std` for it unavailable — the libraries are built from the
# `rust-src` component with cargo's `-Zbuild-std` and placed where `rustup target add` would have put them,
# so every unchanged `cargo … --target thumbv…` command works. SCT_THUMB_FROM_SOURCE=1 skips rustup (to try
# the from-source path on a machine where rustup works).
#
# `sysroot DIR` builds the same libraries into DIR/lib/rustlib/<target>/lib without touching the toolchain:
# scripts/from-source-check.sh builds the firmware against it, so CI proves the from-source path even on a
# machine that has the targets from rustup.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=(thumbv7m-none-eabi thumbv6m-none-eabi thumbv7em-none-eabihf)
MARK=sct-built-from-rust-src   # left beside the libraries this script built, with the compiler's version

has_libs() { compgen -G "$1/libcore-*.rlib" >/dev/null; }

# Builds core, alloc and compiler_builtins for target $1 from rust-src and copies the rlibs into $2; $3 says
# why (kept in the marker file).
# Bitcode is embedded because the firmware's release profile uses LTO; compiler_builtins carries memcpy and
# friends (`mem`), as the distributed no_std targets do.
build_from_source() {
  local target=$1 dest=$2 why=$3
  local work="${CARGO_TARGET_DIR:-target}/sysroot-src"
  rustup component add rust-src >/dev/null 2>&1 || true
  if [[ ! -d "$(rustc --print sysroot)/lib/rustlib/src/rust/library/core" ]]; then
    echo "thumb-targets: the rust-src component is missing and rustup could not add it" >&2
    return 1
  fi
  mkdir -p "$work/src"
  # Its own workspace, so the repository's workspace and profiles stay out of it; the toolchain file at the
  # root still selects the same compiler.
  cat >"$work/Cargo.toml" <<'EOF'
[package]
name = "sct-sysroot"
version = "0.0.0"
edition = "2021"
publish = false

[lib]
path = "src/lib.rs"

[workspace]

[profile.release]
opt-level = 3
debug = false
EOF
  echo '#![no_std]' >"$work/src/lib.rs"
  echo "thumb-targets: building core, alloc and compiler_builtins for $target from rust-src ($(rustc -V))" >&2
  (
    cd "$work"
    RUSTC_BOOTSTRAP=1 CARGO_ENCODED_RUSTFLAGS=-Cembed-bitcode=yes CARGO_TARGET_DIR="$PWD/target" \
      cargo build --quiet --release --target "$target" \
      -Zbuild-std=core,alloc,compiler_builtins -Zbuild-std-features=compiler-builtins-mem
  )
  local deps="$work/target/$target/release/deps"
  mkdir -p "$dest"
  rm -f "$dest"/lib*.rlib
  local lib n=0
  for lib in "$deps"/lib*.rlib; do
    case "$(basename "$lib")" in libsct_sysroot-*) continue ;; esac
    cp "$lib" "$dest/"
    n=$((n + 1))
  done
  if ! has_libs "$dest" || ((n < 3)); then
    echo "thumb-targets: the build for $target left no core library in $deps" >&2
    return 1
  fi
  { rustc -vV; echo "why: $why"; } >"$dest/$MARK"
}

install() {
  local target libdir why
  for target in "${TARGETS[@]}"; do
    libdir="$(rustc --print target-libdir --target "$target")"
    has_libs "$libdir" && continue
    if [[ "${SCT_THUMB_FROM_SOURCE:-0}" != 1 ]] && rustup target add "$target" >/dev/null 2>&1 && has_libs "$libdir"; then
      echo "thumb-targets: $target installed by rustup" >&2
      continue
    fi
    why="rustup could not install it"
    [[ "${SCT_THUMB_FROM_SOURCE:-0}" == 1 ]] && why="SCT_THUMB_FROM_SOURCE=1"
    echo "thumb-targets: $target: $why; providing it from rust-src" >&2
    build_from_source "$target" "$libdir" "$why"
    # Objects built for this target against other libraries must not be linked with these.
    rm -rf "${CARGO_TARGET_DIR:-target}/$target"
  done
}

path() {
  local target libdir
  for target in "${TARGETS[@]}"; do
    libdir="$(rustc --print target-libdir --target "$target")"
    if ! has_libs "$libdir"; then
      echo "$target: missing (run bash scripts/setup.sh)"
    elif [[ -f "$libdir/$MARK" ]]; then
      echo "$target: built from rust-src by scripts/thumb-targets.sh ($(sed -n 's/^why: //p' "$libdir/$MARK"))"
    else
      echo "$target: installed by rustup"
    fi
  done
}

sysroot() {
  local dir=$1 target host
  host="$(rustc -vV | sed -n 's/^host: //p')"
  mkdir -p "$dir/lib/rustlib"
  # The host's tools (rust-lld, which links the thumb targets) are looked up in the sysroot too.
  ln -sfn "$(rustc --print sysroot)/lib/rustlib/$host" "$dir/lib/rustlib/$host"
  for target in "${TARGETS[@]}"; do
    if [[ -f "$dir/lib/rustlib/$target/lib/$MARK" ]] && grep -qF "$(rustc -V)" "$dir/lib/rustlib/$target/lib/$MARK"; then
      continue
    fi
    build_from_source "$target" "$dir/lib/rustlib/$target/lib" "a sysroot of its own, for the from-source check"
  done
}

case "${1:-}" in
  install) install ;;
  path) path ;;
  sysroot) [[ -n "${2:-}" ]] || { echo "usage: $0 sysroot DIR" >&2; exit 2; }; sysroot "$(realpath -m "$2")" ;;
  *) echo "usage: $0 install | path | sysroot DIR" >&2; exit 2 ;;
esac
