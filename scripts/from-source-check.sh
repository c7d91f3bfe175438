#!/usr/bin/env bash
# CI's proof that a machine without the thumb targets can build and run the firmware: the targets' libraries
# built from rust-src (scripts/thumb-targets.sh), the cell firmware built against them, run under QEMU and
# measured against the committed expectations.
#
# On a machine whose toolchain already got its thumb targets from rust-src, every firmware build of the run
# took that path, and this says so. On a machine that has them from rustup, the libraries are built into a
# sysroot of their own (target/from-source/sysroot; the toolchain is not touched) and the firmware is built
# with `--sysroot` pointing there, into target/from-source.
set -euo pipefail
cd "$(dirname "$0")/.."

paths="$(bash scripts/thumb-targets.sh path)"
echo "$paths"
if ! grep -q 'installed by rustup' <<<"$paths"; then
  echo "from-source: the toolchain's thumb targets are built from rust-src: this whole run took that path"
  exit 0
fi

dir="${CARGO_TARGET_DIR:-target}/from-source"
bash scripts/thumb-targets.sh sysroot "$dir/sysroot"
sysroot="$(realpath "$dir/sysroot")"
echo "from-source: building and running the cell firmware against $sysroot"
python3 scripts/measure/cost.py --target-dir "$dir" \
  --cargo-config "target.thumbv7m-none-eabi.rustflags=[\"--sysroot\",\"$sysroot\"]"
