// The seeded ring-oscillator bit.

import assert from 'node:assert/strict';
import test from 'node:test';

import { RP2040 } from 'rp2040js';

import { BitSource, installRosc, ROSC_BASE } from '../src/rosc.js';

const bits = (source, n) => Array.from({ length: n }, () => source.bit()).join('');

test('a seed gives one stream of bits, another seed another; neither is constant', () => {
  const a = bits(new BitSource(1n), 256);
  assert.equal(a, bits(new BitSource(1n), 256));
  assert.notEqual(a, bits(new BitSource(2n), 256));
  const ones = [...a].filter((b) => b === '1').length;
  assert.ok(ones > 96 && ones < 160, `about half ones: ${ones}`);
  assert.notEqual(bits(new BitSource(0n), 64), '0'.repeat(64), 'seed 0 is not the stuck state');
});

test('the firmware reads RANDOMBIT from the seeded source, and the reads are counted', () => {
  const mcu = new RP2040();
  mcu.logger = { debug() {}, info() {}, warn: assert.fail, error: assert.fail };
  const source = new BitSource(7n);
  installRosc(mcu, source);
  const read = Array.from({ length: 64 }, () => mcu.readUint32(ROSC_BASE + 0x1c)).join('');
  assert.equal(read, bits(new BitSource(7n), 64));
  assert.equal(source.reads, 64);
  assert.equal(mcu.readUint32(ROSC_BASE + 0x18) >>> 31, 1, 'STATUS: stable');
});
