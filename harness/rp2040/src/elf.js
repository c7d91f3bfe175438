// Reads what the harness needs from a 32-bit little-endian ARM ELF executable: the loadable segments
// (program headers) and the symbol table. Only the fields used here are decoded; anything malformed is
// an `ElfError` naming the file and what is wrong, never an out-of-bounds read.

/** A file that is not the ELF the harness can load. */
export class ElfError extends Error {}

const PT_LOAD = 1;
const SHT_SYMTAB = 2;
const EM_ARM = 40;

/**
 * Parses `bytes` (a Buffer or Uint8Array holding the whole file) as a 32-bit little-endian ARM executable.
 * Returns `{ entry, segments, symbols }`: each segment `{ vaddr, paddr, fileSize, memSize, data }` with
 * `data` the bytes from the file (`fileSize` of them), each symbol `{ name, value, size, type }`.
 */
export function parseElf(bytes, file = 'ELF') {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const fail = (what) => {
    throw new ElfError(`${file}: ${what}`);
  };
  const need = (offset, length, what) => {
    if (offset < 0 || length < 0 || offset + length > bytes.byteLength) {
      fail(`${what} lies outside the file (offset ${offset}, ${length} bytes, file ${bytes.byteLength} bytes)`);
    }
  };
  need(0, 52, 'the ELF header');
  if (view.getUint32(0, false) !== 0x7f454c46) fail('not an ELF file');
  if (bytes[4] !== 1) fail('not a 32-bit ELF file');
  if (bytes[5] !== 1) fail('not a little-endian ELF file');
  if (view.getUint16(18, true) !== EM_ARM) fail('not an ARM executable');
  const entry = view.getUint32(24, true);
  const phoff = view.getUint32(28, true);
  const shoff = view.getUint32(32, true);
  const phentsize = view.getUint16(42, true);
  const phnum = view.getUint16(44, true);
  const shentsize = view.getUint16(46, true);
  const shnum = view.getUint16(48, true);

  const segments = [];
  for (let i = 0; i < phnum; i++) {
    const at = phoff + i * phentsize;
    need(at, 32, `program header ${i}`);
    if (view.getUint32(at, true) !== PT_LOAD) continue;
    const offset = view.getUint32(at + 4, true);
    const fileSize = view.getUint32(at + 16, true);
    need(offset, fileSize, `segment ${i}`);
    segments.push({
      vaddr: view.getUint32(at + 8, true),
      paddr: view.getUint32(at + 12, true),
      fileSize,
      memSize: view.getUint32(at + 20, true),
      data: bytes.subarray(offset, offset + fileSize),
    });
  }

  const symbols = [];
  for (let i = 0; i < shnum; i++) {
    const at = shoff + i * shentsize;
    need(at, 40, `section header ${i}`);
    if (view.getUint32(at + 4, true) !== SHT_SYMTAB) continue;
    const offset = view.getUint32(at + 16, true);
    const size = view.getUint32(at + 20, true);
    const link = view.getUint32(at + 24, true);
    const entsize = view.getUint32(at + 36, true) || 16;
    need(offset, size, 'the symbol table');
    const strAt = shoff + link * shentsize;
    need(strAt, 40, 'the string table header');
    const strOffset = view.getUint32(strAt + 16, true);
    const strSize = view.getUint32(strAt + 20, true);
    need(strOffset, strSize, 'the string table');
    const name = (n) => {
      if (n >= strSize) fail(`symbol name offset ${n} beyond the string table`);
      let end = strOffset + n;
      while (end < strOffset + strSize && bytes[end] !== 0) end++;
      return Buffer.from(bytes.subarray(strOffset + n, end)).toString('utf8');
    };
    for (let s = offset; s + 16 <= offset + size; s += entsize) {
      symbols.push({
        name: name(view.getUint32(s, true)),
        value: view.getUint32(s + 4, true),
        size: view.getUint32(s + 8, true),
        type: bytes[s + 12] & 0xf,
      });
    }
  }
  return { entry, segments, symbols };
}
