#!/usr/bin/env bash
# Differential tests of `codegen synth` against libFAUDES and TCT (see differential.py); run by
# scripts/test.sh after `bash scripts/setup.sh` installed the reference tools into .venv.
set -euo pipefail
cd "$(dirname "$0")/../.."
target="${CARGO_TARGET_DIR:-target}"
cargo build --quiet -p codegen --bin codegen --example families
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# libFAUDES prints warnings about optional graphics modules on import; keep them out of the log.
.venv/bin/python scripts/reference/differential.py "$target/debug/codegen" "$target/debug/examples/families" "$work" \
  2> >(grep -v "wont do interactive graphics" >&2)
