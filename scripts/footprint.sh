#!/usr/bin/env bash
# Footprint of the cell firmware (cell-qemu, release): flash and RAM from llvm-size, and the runtime's
# share from the symbol table — code of the runtime library (firmware::{runtime,choice,rng,table,
# event_set,input_queue}) and the emitted tables the runtime reads. The runtime's entry points are out of
# line (`#[inline(never)]`), so their code carries their own names; interface code (UART, link protocol,
# RTIC glue, logs) is counted apart.
#
#   bash scripts/footprint.sh            # the committed cell tables
#   SCT_TABLES=other.rs bash scripts/footprint.sh
#   ELF=path bash scripts/footprint.sh  # another image (the memory check fails on one not linked for QEMU)
set -euo pipefail
cd "$(dirname "$0")/.."

cargo qemu-build --quiet
target_dir="${CARGO_TARGET_DIR:-target}"
export elf="${ELF:-$target_dir/thumbv7m-none-eabi/release/cell-qemu}"
bin="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin"

# The image must be linked for the lm3s6965evb: vector table at 0, every loaded byte in its 256 KiB of
# flash or 64 KiB of SRAM, initialised data loaded from flash, stack at the top of SRAM.
"$bin/llvm-readobj" --elf-output-style=GNU -l -s "$elf" | awk '
  function hex(s,   v, i) { v = 0; sub(/^0x/, "", s); for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789abcdef", tolower(substr(s, i, 1))) - 1; return v }
  $1 == "LOAD" {
    vma = hex($3); lma = hex($4); file = hex($5); mem = hex($6)
    in_flash = vma + mem <= 262144; in_ram = vma >= 536870912 && vma + mem <= 536936448
    if (!in_flash && !in_ram) bad = bad sprintf("segment at %s (%d bytes) is outside flash and RAM\n", $3, mem)
    if (file > 0 && lma + file > 262144) bad = bad sprintf("segment loaded at %s is outside flash\n", $4)
  }
  $NF == "__RESET_VECTOR" && hex($2) != 4 { bad = bad "vector table is not at 0\n" }
  $NF == "_stack_start" && hex($2) != 536936448 { bad = bad "stack top is not 0x20010000\n" }
  $NF == "__RESET_VECTOR" || $NF == "_stack_start" { seen++ }
  END {
    if (seen != 2) bad = bad "no __RESET_VECTOR or _stack_start symbol\n"
    if (bad != "") { printf "footprint: %s is not linked for the lm3s6965evb:\n%s", ENVIRON["elf"], bad > "/dev/stderr"; exit 1 }
  }'
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
