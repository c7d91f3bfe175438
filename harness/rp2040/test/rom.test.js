// The ROM stand-in, executed by the emulated core the way rp2040-hal calls it: the lookup routine
// through the halfword pointers at 0x14 and 0x18, then the routines it returns.

import assert from 'node:assert/strict';
import test from 'node:test';

import { RP2040 } from 'rp2040js';

import { installRom, ROM_CODES, ROM_TRAP } from '../src/rom.js';

const RAM = 0x20000000;
const code = (letters) => letters.charCodeAt(0) | (letters.charCodeAt(1) << 8);

/** Calls the Thumb routine at `address` with `args` in r0–r2 on `mcu`; returns r0 and the cycles. */
function call(mcu, address, args) {
  const { core } = mcu;
  mcu.writeUint16(RAM, 0xbe00); // bkpt: where the call returns
  core.SP = RAM + 0x1000;
  args.forEach((a, i) => (core.registers[i] = a));
  core.LR = RAM | 1;
  core.PC = address & ~1;
  let stopped = false;
  mcu.onBreak = () => (stopped = true);
  const before = core.cycles;
  for (let n = 0; n < 100_000 && !stopped; n++) core.executeInstruction();
  assert.ok(stopped, 'the routine returned');
  return { r0: core.registers[0] >>> 0, cycles: core.cycles - before };
}

function rom() {
  const mcu = new RP2040();
  installRom(mcu);
  const lookup = mcu.readUint16(0x18);
  const find = (c) => call(mcu, lookup, [mcu.readUint16(0x14), code(c)]).r0;
  return { mcu, lookup, find };
}

test('the lookup finds each routine the HAL asks for, Thumb bit set, and nothing else', () => {
  const { mcu, find } = rom();
  for (const c of ROM_CODES) {
    const at = find(c);
    assert.equal(at & 1, 1, `${c} is a Thumb address`);
    assert.ok(at > 0x20 && at < 0x4000, `${c} lies in the ROM`);
  }
  assert.equal(find('MS'), find('S4'));
  assert.equal(find('MC'), find('C4'));
  for (const c of ['P3', 'RE', 'UB', 'FS']) assert.equal(find(c), 0, `${c} is not there`);
  const dataTable = mcu.readUint16(0x16);
  assert.equal(call(mcu, mcu.readUint16(0x18), [dataTable, code('CR')]).r0, 0);
});

test('memset and memcpy do what they say and return their destination', () => {
  const { mcu, find } = rom();
  const dst = RAM + 0x100;
  const src = RAM + 0x200;
  for (let i = 0; i < 16; i++) mcu.sram[0x200 + i] = i + 1;
  mcu.sram.fill(0xee, 0x100, 0x120);
  assert.equal(call(mcu, find('MC'), [dst, src, 13]).r0, dst);
  assert.deepEqual([...mcu.sram.subarray(0x100, 0x10f)], [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 0xee, 0xee]);
  assert.equal(call(mcu, find('MS'), [dst + 2, 0x5a, 5]).r0, dst + 2);
  assert.deepEqual([...mcu.sram.subarray(0x100, 0x109)], [1, 2, 0x5a, 0x5a, 0x5a, 0x5a, 0x5a, 8, 9]);
  assert.equal(call(mcu, find('S4'), [dst, 0, 0]).r0, dst, 'zero bytes: nothing written');
  assert.equal(mcu.sram[0x100], 1);
  const { cycles } = call(mcu, find('MC'), [dst, src, 16]);
  assert.ok(cycles > 16 * 5, `a byte loop costs cycles like any code (${cycles})`);
});

test('a call through a code the ROM does not have stops at the trap', () => {
  const { mcu } = rom();
  let trapped;
  mcu.writeUint16(RAM, 0xbe00);
  mcu.core.PC = 0;
  mcu.onBreak = (c) => (trapped = c);
  mcu.core.executeInstruction();
  assert.equal(trapped, ROM_TRAP);
});
