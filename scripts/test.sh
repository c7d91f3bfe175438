#!/usr/bin/env bash
# The README's test command: set up a fresh machine, then run every test of the workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace
bash scripts/reference/differential.sh
# The firmware for both targets (lints included), then the cost binary under QEMU as a smoke test: it runs
# the runtime on the cell's tables and exits non-zero on an unexpected event; the footprint (which checks
# the QEMU image's memory layout) and the Pico's cost on the emulated RP2040 against its expected figures.
# (The Pico closed loop and the RP2040 harness's own tests run in `cargo test`: tests/pico.rs.)
cargo clippy -p firmware --features qemu --target thumbv7m-none-eabi --release --bins -- -D warnings
cargo clippy -p firmware --features pico --target thumbv6m-none-eabi --release --bins -- -D warnings
cargo qemu-build
cargo pico-build
cargo qemu-cost
bash scripts/footprint.sh
bash scripts/pico-cost.sh
