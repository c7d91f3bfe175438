// The ROM stand-in. rp2040js ships no bootrom (its ROM reads as zeros), and Raspberry Pi's bootrom image is
// not ours to ship. The firmware needs only what rp2040-hal's `rom_data` asks of the ROM: the lookup
// routine at the halfword 0x18, the function table at the halfword 0x14 (the data table at 0x16 is given,
// empty), and four routines from it — `MS` memset, `S4` memset4, `MC` memcpy, `C4` memcpy44 — which the
// HAL's `__aeabi_memclr*`/`__aeabi_memcpy*` call during RTIC's init and at run time. They are plain
// Thumb-1 byte loops written for this file (assembled with llvm-mc; the source is beside each
// halfword), so the core executes them and their cycles count like any other code. Any other code
// asked of the table (flash programming, popcount, floating point, …) looks up as 0, and calling it
// jumps to 0, where `UDF` stops the run with a message (see `ROM_TRAP`).

/** Where the routines lie in ROM. */
const CODE = 0x100;
/** Where the function table lies. */
const FUNC_TABLE = 0x80;
/** Where the (empty) data table lies. */
const DATA_TABLE = 0xa0;
/** The `UDF` immediate at address 0: a call through a code the table does not have. */
export const ROM_TRAP = 0xfe;

// lookup(table: *const u16 r0, code: u32 r1) -> r0: the pointer paired with `code` in `table`, or 0.
// Table entries are (code, pointer) halfword pairs, ended by a zero code.
const LOOKUP = [
  0x8802, // 00 loop:  ldrh r2, [r0]
  0x428a, // 02        cmp  r2, r1
  0xd003, // 04        beq  found
  0x2a00, // 06        cmp  r2, #0
  0xd003, // 08        beq  none
  0x3004, // 0a        adds r0, #4
  0xe7f8, // 0c        b    loop
  0x8840, // 0e found: ldrh r0, [r0, #2]
  0x4770, // 10        bx   lr
  0x2000, // 12 none:  movs r0, #0
  0x4770, // 14        bx   lr
];
// memset(ptr r0, c r1, n r2) -> ptr: stores the byte c at ptr[n-1] down to ptr[0].
const MEMSET = [
  0x3a01, // 00 loop: subs r2, #1
  0xd301, // 02       blo  done
  0x5481, // 04       strb r1, [r0, r2]
  0xe7fb, // 06       b    loop
  0x4770, // 08 done: bx   lr
];
// memcpy(dest r0, src r1, n r2) -> dest: copies src[n-1] down to src[0] (regions do not overlap).
const MEMCPY = [
  0x3a01, // 00 loop: subs r2, #1
  0xd302, // 02       blo  done
  0x5c8b, // 04       ldrb r3, [r1, r2]
  0x5483, // 06       strb r3, [r0, r2]
  0xe7fa, // 08       b    loop
  0x4770, // 0a done: bx   lr
];

/** The two-letter codes the ROM answers, as the HAL passes them (little-endian halfword of the letters). */
export const ROM_CODES = ['MS', 'S4', 'MC', 'C4'];

const code = (letters) => letters.charCodeAt(0) | (letters.charCodeAt(1) << 8);

/** Writes the stand-in into `mcu.bootrom` (which must read as zeros before). */
export function installRom(mcu) {
  const rom = new DataView(mcu.bootrom.buffer);
  const halfwords = (at, words) => words.forEach((w, i) => rom.setUint16(at + 2 * i, w, true));
  const lookup = CODE;
  const memset = lookup + 2 * LOOKUP.length;
  const memcpy = memset + 2 * MEMSET.length;
  halfwords(0, [0xde00 | ROM_TRAP]); // udf: a call through a null pointer stops here
  halfwords(lookup, LOOKUP);
  halfwords(memset, MEMSET);
  halfwords(memcpy, MEMCPY);
  // Thumb bit set on every code pointer.
  const routines = { MS: memset, S4: memset, MC: memcpy, C4: memcpy };
  const table = ROM_CODES.flatMap((c) => [code(c), routines[c] | 1]);
  halfwords(FUNC_TABLE, [...table, 0, 0]);
  halfwords(DATA_TABLE, [0, 0]);
  halfwords(0x14, [FUNC_TABLE, DATA_TABLE, lookup | 1]);
}
