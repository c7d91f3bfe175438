// Puts a firmware image into an emulated RP2040 the way the Pico's boot would leave it: every loadable
// segment in the QSPI flash (XIP window) or in SRAM, refusing any byte elsewhere — rp2040js keeps its ROM
// as a writable array, so an image linked for another chip (vector table at 0) would otherwise run
// anyway and prove nothing — then the core started at the application's vector table, after the
// second-stage bootloader (which only sets up the flash interface, already usable in the emulator).

import { parseElf } from './elf.js';
import { findMethod } from './symbols.js';

/** The RP2040's XIP flash window as the Pico fills it (2 MiB), and its SRAM (264 KiB). */
export const FLASH = { start: 0x10000000, end: 0x10000000 + 2 * 1024 * 1024 };
export const SRAM = { start: 0x20000000, end: 0x20000000 + 264 * 1024 };
/** The application's vector table, after the 256-byte second-stage bootloader. */
export const VECTOR_TABLE = 0x10000100;

/** An image that does not fit the RP2040. */
export class ImageError extends Error {}

const hex = (n) => `0x${n.toString(16).padStart(8, '0')}`;
const inside = (range, at, size) => at >= range.start && at + size <= range.end;

/**
 * Checks `elf` (from `parseElf`) against the RP2040's memory: each segment's run-time range (`vaddr`,
 * `memSize`) in flash or SRAM, its load range (`paddr`, `fileSize`) in flash, the vector table at
 * `VECTOR_TABLE`, its stack pointer in SRAM and its reset vector in flash. Throws `ImageError` naming
 * the first thing out of place.
 */
export function checkImage(elf, file = 'image') {
  const fail = (what) => {
    throw new ImageError(`${file} is not linked for the RP2040: ${what}`);
  };
  for (const s of elf.segments) {
    if (s.memSize === 0 && s.fileSize === 0) continue;
    if (!inside(FLASH, s.vaddr, s.memSize) && !inside(SRAM, s.vaddr, s.memSize)) {
      fail(`segment at ${hex(s.vaddr)} (${s.memSize} bytes) lies outside flash and SRAM`);
    }
    if (s.fileSize > 0 && !inside(FLASH, s.paddr, s.fileSize)) {
      fail(`segment loaded at ${hex(s.paddr)} (${s.fileSize} bytes) lies outside flash`);
    }
  }
  const word = (address) => {
    for (const s of elf.segments) {
      if (address >= s.paddr && address + 4 <= s.paddr + s.fileSize) {
        const at = address - s.paddr;
        return (s.data[at] | (s.data[at + 1] << 8) | (s.data[at + 2] << 16) | (s.data[at + 3] << 24)) >>> 0;
      }
    }
    return fail(`no vector table at ${hex(address)}`);
  };
  const sp = word(VECTOR_TABLE);
  const reset = word(VECTOR_TABLE + 4);
  if (!(sp > SRAM.start && sp <= SRAM.end)) fail(`initial stack pointer ${hex(sp)} is not in SRAM`);
  if (!inside(FLASH, reset & ~1, 2)) fail(`reset vector ${hex(reset)} is not in flash`);
}

/** Loads the checked `elf` into `mcu` (flash, and SRAM as the boot copy would be irrelevant: the
 * firmware's start-up code copies `.data` itself) and points the core at the vector table. */
export function loadImage(mcu, elf) {
  for (const s of elf.segments) {
    if (s.fileSize > 0) mcu.flash.set(s.data, s.paddr - FLASH.start);
  }
  const { core } = mcu;
  core.VTOR = VECTOR_TABLE;
  core.SP = mcu.readUint32(VECTOR_TABLE);
  core.PC = mcu.readUint32(VECTOR_TABLE + 4) & ~1;
}

/**
 * The firmware image in `bytes` (the file `file`), checked (`checkImage`), with the addresses the harness
 * needs: `{ elf, status, rtt, probes: { apply, decide } }` — the `SCT_STATUS` block the firmware
 * publishes, its `_SEGGER_RTT` control block (if any), and the runtime's two entry points. Throws
 * (`ElfError`, `ImageError`, or an `Error` for a missing symbol) naming the file.
 */
export function firmwareImage(bytes, file) {
  const elf = parseElf(bytes, file);
  checkImage(elf, file);
  const symbol = (name) => elf.symbols.find((s) => s.name === name)?.value;
  const status = symbol('SCT_STATUS');
  if (status === undefined) throw new ImageError(`${file}: no SCT_STATUS symbol (is it the cell-pico firmware?)`);
  try {
    const probes = {
      apply: findMethod(elf.symbols, 'firmware::runtime::Runtime', 'apply'),
      decide: findMethod(elf.symbols, 'firmware::runtime::Runtime', 'decide'),
    };
    return { elf, status, rtt: symbol('_SEGGER_RTT'), probes };
  } catch (e) {
    throw new ImageError(`${file}: ${e.message}`);
  }
}
