// Builds small ELF files for the tests (not a test itself).

/** A minimal 32-bit ARM executable: one loadable segment per `[vaddr, paddr, bytes, memSize]`, and a
 * symbol table of `[name, value, type]`. */
export function makeElf(segments, symbols = []) {
  const strtab = Buffer.concat([Buffer.from([0]), ...symbols.map(([n]) => Buffer.from(`${n}\0`))]);
  const shstr = Buffer.from('\0.symtab\0.strtab\0');
  const phoff = 52;
  let data = phoff + 32 * segments.length;
  const placed = segments.map(([, , bytes]) => {
    const at = data;
    data += bytes.length;
    return at;
  });
  const symoff = data;
  const symtab = Buffer.alloc(16 * (symbols.length + 1));
  let nameAt = 1;
  symbols.forEach(([name, value, type], i) => {
    symtab.writeUInt32LE(nameAt, 16 * (i + 1));
    symtab.writeUInt32LE(value, 16 * (i + 1) + 4);
    symtab[16 * (i + 1) + 12] = type;
    nameAt += name.length + 1;
  });
  const stroff = symoff + symtab.length;
  const shstroff = stroff + strtab.length;
  const shoff = shstroff + shstr.length;
  const out = Buffer.alloc(shoff + 40 * 4);
  out.writeUInt32BE(0x7f454c46, 0);
  out[4] = 1;
  out[5] = 1;
  out[6] = 1;
  out.writeUInt16LE(2, 16);
  out.writeUInt16LE(40, 18);
  out.writeUInt32LE(1, 20);
  out.writeUInt32LE(phoff, 28);
  out.writeUInt32LE(shoff, 32);
  out.writeUInt16LE(52, 40);
  out.writeUInt16LE(32, 42);
  out.writeUInt16LE(segments.length, 44);
  out.writeUInt16LE(40, 46);
  out.writeUInt16LE(4, 48);
  out.writeUInt16LE(3, 50);
  segments.forEach(([vaddr, paddr, bytes, memSize], i) => {
    const at = phoff + 32 * i;
    out.writeUInt32LE(1, at);
    out.writeUInt32LE(placed[i], at + 4);
    out.writeUInt32LE(vaddr, at + 8);
    out.writeUInt32LE(paddr, at + 12);
    out.writeUInt32LE(bytes.length, at + 16);
    out.writeUInt32LE(memSize ?? bytes.length, at + 20);
    Buffer.from(bytes).copy(out, placed[i]);
  });
  symtab.copy(out, symoff);
  strtab.copy(out, stroff);
  shstr.copy(out, shstroff);
  const section = (i, name, type, offset, size, link, entsize) => {
    const at = shoff + 40 * i;
    out.writeUInt32LE(name, at);
    out.writeUInt32LE(type, at + 4);
    out.writeUInt32LE(offset, at + 16);
    out.writeUInt32LE(size, at + 20);
    out.writeUInt32LE(link, at + 24);
    out.writeUInt32LE(entsize, at + 36);
  };
  section(1, 1, 2, symoff, symtab.length, 2, 16);
  section(2, 9, 3, stroff, strtab.length, 0, 0);
  section(3, 0, 3, shstroff, shstr.length, 0, 0);
  return out;
}
