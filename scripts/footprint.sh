#!/usr/bin/env bash
# Footprint of the cell firmware (cell-qemu, release): flash and RAM from llvm-size, and the runtime's
# share from the symbol table — code of the runtime library (firmware::{runtime,choice,rng,table,
# event_set,input_queue}) and the emitted tables the runtime reads. The runtime's entry points are out of
# line (`#[inline(never)]`), so their code carries their own names; interface code (UART, link protocol,
# RTIC glue, logs) is counted apart.
#
#   bash scripts/footprint.sh            # the committed cell tables
#   SCT_TABLES=other.rs bash scripts/footprint.sh
set -euo pipefail
cd "$(dirname "$0")/.."

cargo qemu-build --quiet
target_dir="${CARGO_TARGET_DIR:-target}"
elf="$target_dir/thumbv7m-none-eabi/release/cell-qemu"
bin="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin"

"$bin/llvm-size" "$elf"
"$bin/llvm-nm" --print-size --size-sort --radix=d -C "$elf" | awk '
  function add(kind, size, name) { total[kind] += size; items[kind] = items[kind] sprintf("    %5d  %s\n", size, name) }
  NF >= 4 {
    size = $2 + 0; type = $3; name = $4
    for (i = 5; i <= NF; i++) name = name " " $i
    if (type ~ /[tT]/ && name ~ /^firmware::(runtime|choice|rng|table|event_set|input_queue)::/) add("code", size, name)
    else if (type ~ /[rR]/ && name ~ /::tables::(BLOCK|MASKS|DESCRIPTORS|HOLDERS|PLANT_EVENTS|CHOICE_SITES|SET)::/) add("tables", size, name)
    else if (type ~ /[rR]/ && name ~ /::tables::(EVENT_NAMES|AUTOMATON_NAMES)::/) add("names", size, name)
    else if (type ~ /[bBdD]/ && name ~ /local_resource_runtime/) add("runtime RAM", size, name)
    else if (type ~ /[bBdD]/ && name ~ /queue/) add("input buffer RAM", size, name)
  }
  END {
    split("code|tables|names|runtime RAM|input buffer RAM", order, "|")
    for (k = 1; k <= 5; k++) { kind = order[k]; printf "%s: %d bytes\n%s", kind, total[kind], items[kind] }
    printf "runtime code + tables: %d bytes\n", total["code"] + total["tables"]
  }'
