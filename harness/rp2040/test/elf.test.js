// The ELF reader and the image check: a mislinked image is refused, a malformed file is an error.

import assert from 'node:assert/strict';
import test from 'node:test';

import { ElfError, parseElf } from '../src/elf.js';
import { checkImage, ImageError, loadImage, VECTOR_TABLE } from '../src/image.js';
import { RP2040 } from 'rp2040js';

import { makeElf } from './elf-builder.mjs';

/** A vector table: initial stack pointer, reset vector. */
function vectors(sp, reset) {
  const b = Buffer.alloc(8);
  b.writeUInt32LE(sp, 0);
  b.writeUInt32LE(reset, 4);
  return b;
}

test('reads segments and symbols', () => {
  const elf = parseElf(makeElf([[0x10000100, 0x10000100, vectors(0x20040000, 0x100001c1)]], [['SCT_STATUS', 0x2000003c, 1]]));
  assert.equal(elf.segments.length, 1);
  assert.equal(elf.segments[0].vaddr, 0x10000100);
  assert.deepEqual([...elf.segments[0].data.subarray(0, 4)], [0x00, 0x00, 0x04, 0x20]);
  assert.deepEqual(elf.symbols.find((s) => s.name === 'SCT_STATUS'), { name: 'SCT_STATUS', value: 0x2000003c, size: 0, type: 1 });
});

test('a malformed file is an error naming it, not a crash', () => {
  const good = makeElf([[0x10000100, 0x10000100, vectors(0x20040000, 0x100001c1)]]);
  assert.throws(() => parseElf(Buffer.from('hello'), 'x.elf'), (e) => e instanceof ElfError && e.message.startsWith('x.elf:'));
  assert.throws(() => parseElf(good.subarray(0, 100), 't'), ElfError);
  const thumb64 = Buffer.from(good);
  thumb64[4] = 2;
  assert.throws(() => parseElf(thumb64), /not a 32-bit ELF/);
  const wild = Buffer.from(good);
  wild.writeUInt32LE(0xfffffff0, 52 + 4); // segment offset beyond the file
  assert.throws(() => parseElf(wild), /outside the file/);
});

test('an image linked for the RP2040 is taken and started at its vector table', () => {
  const elf = parseElf(makeElf([
    [0x10000000, 0x10000000, Buffer.alloc(256, 0xaa)],
    [0x10000100, 0x10000100, vectors(0x20040000, 0x100001c1)],
    [0x20000000, 0x10000200, Buffer.from([1, 2, 3, 4])],
    [0x20000004, 0x20000004, Buffer.alloc(0), 64],
  ]));
  checkImage(elf);
  const mcu = new RP2040();
  loadImage(mcu, elf);
  assert.equal(mcu.core.VTOR, VECTOR_TABLE);
  assert.equal(mcu.core.SP, 0x20040000);
  assert.equal(mcu.core.PC, 0x100001c0);
  assert.equal(mcu.flash[0], 0xaa);
});

test('an image linked for another chip is refused', () => {
  // As the Pico build was once linked, with the lm3s6965's memory.x: vector table at 0, in the ROM.
  const lm3s = parseElf(makeElf([[0, 0, vectors(0x20010000, 0xc1)]]));
  assert.throws(() => checkImage(lm3s, 'cell-pico'), (e) => e instanceof ImageError && /cell-pico is not linked for the RP2040: segment at 0x00000000/.test(e.message));
  const dataInRam = parseElf(makeElf([[0x10000100, 0x10000100, vectors(0x20040000, 0x100001c1)], [0x20000000, 0x20000000, Buffer.from([1])]]));
  assert.throws(() => checkImage(dataInRam), /loaded at 0x20000000 .* lies outside flash/);
  const noVectors = parseElf(makeElf([[0x10000000, 0x10000000, Buffer.alloc(16)]]));
  assert.throws(() => checkImage(noVectors), /no vector table at 0x10000100/);
  const badStack = parseElf(makeElf([[0x10000100, 0x10000100, vectors(0x20050000, 0x100001c1)]]));
  assert.throws(() => checkImage(badStack), /stack pointer 0x20050000 is not in SRAM/);
});
