#!/usr/bin/env bash
# The README's test command: set up a fresh machine, then run every test of the workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/thumb-targets.sh path
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -- -D warnings
# The API docs of the host crates (codegen, the firmware runtime with its host-side `build` feature, the
# end-to-end support library), broken intra-doc links and every other rustdoc warning denied. (The cell
# applications are Cortex-M binaries, linted below for each board.)
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace --exclude cell
cargo test --workspace
bash scripts/reference/differential.sh
# The firmware for every target and board (lints included).
cargo clippy -p cell --features qemu --target thumbv7m-none-eabi --release --bins -- -D warnings
cargo clippy -p cell --features pico --target thumbv6m-none-eabi --release --bins -- -D warnings
cargo clippy -p cell --features nucleo --target thumbv7em-none-eabihf --release --bins -- -D warnings
cargo clippy -p cell --features nrf52840 --target thumbv7em-none-eabihf --release --bins -- -D warnings
cargo qemu-build
cargo pico-build
# Measurements, checked against .ci/expected/ (the scripts' own tests first): the runtime's cost under QEMU
# and on the emulated RP2040 (with the Pico build's footprint), the footprint from the symbol table in both
# symbol manglings rustc uses. (The Pico closed loop and the RP2040 harness's own tests run in
# `cargo test`: tests/pico.rs.)
python3 -m unittest discover -s scripts/measure
python3 scripts/measure/cost.py
python3 scripts/measure/pico_cost.py
python3 scripts/measure/footprint.py
# The cell deployed reduced, on both cores (tables, code, instructions per event).
python3 scripts/measure/layouts.py --layouts ranked --supervisors reduced --pico-events 20000 \
  --expected .ci/expected/cell-reduced.txt
# The station's state feedback against its event-based tables on the Cortex-M3 (flash, RAM, instructions).
python3 scripts/measure/state.py
python3 scripts/measure/footprint.py --target-dir target/v0-mangling \
  --cargo-config 'target.thumbv7m-none-eabi.rustflags=["-Csymbol-mangling-version=v0"]' | tail -n 20
# A machine without the thumb targets builds and runs the firmware (from rust-src).
bash scripts/from-source-check.sh
