// The corrections to rp2040js's core (`src/core.js`), executed by the emulated core: an interrupt handler
// that reads PC with `ADD Rd, PC` sees its own address plus 4, as on silicon.

import assert from 'node:assert/strict';
import test from 'node:test';

import { RP2040 } from 'rp2040js';

import { correctCore } from '../src/core.js';

const RAM = 0x20000000;
const HANDLER = RAM + 0x200;
const IRQ = 5;

/** r0 after the first instruction of an IRQ handler that is `add r0, pc`, entered from thread mode. */
function pcSeenByHandler(corrected) {
  const mcu = new RP2040();
  if (corrected) correctCore(mcu);
  const { core } = mcu;
  core.VTOR = RAM;
  mcu.writeUint32(RAM + 4 * (16 + IRQ), HANDLER | 1); // a Thumb vector, as every linker writes it
  mcu.writeUint16(HANDLER, 0x4478); // add r0, pc
  mcu.writeUint16(RAM + 0x300, 0xbf00); // nop: where thread mode was
  core.SP = RAM + 0x1000;
  core.PC = RAM + 0x300;
  core.registers[0] = 0;
  core.exceptionEntry(16 + IRQ);
  core.executeInstruction();
  return core.registers[0] >>> 0;
}

test('an interrupt handler reads PC as its address plus 4', () => {
  assert.equal(pcSeenByHandler(true), HANDLER + 4);
});

test('rp2040js alone reads one more: the departure the correction is for', () => {
  // When this fails, rp2040js enters handlers as the architecture says: the correction can go.
  assert.equal(pcSeenByHandler(false), HANDLER + 5);
});

/**
 * Whether peripheral interrupt IRQ is still pending after its handler was entered, when software pended
 * it (an NVIC_ISPR write) and the peripheral's line is `line` (asserted or not).
 */
function pendingAfterEntry(corrected, line) {
  const mcu = new RP2040();
  if (corrected) correctCore(mcu);
  const { core } = mcu;
  core.VTOR = RAM;
  mcu.writeUint32(RAM + 4 * (16 + IRQ), HANDLER | 1);
  core.SP = RAM + 0x1000;
  core.PC = RAM + 0x300;
  mcu.setInterrupt(IRQ, line);
  core.enabledInterrupts |= 1 << IRQ;
  mcu.writeUint32(0xe000e200, 1 << IRQ); // NVIC_ISPR: pend it, as `rtic::pend` does
  assert.ok(core.pendingInterrupts & (1 << IRQ), 'the write pends it');
  core.exceptionEntry(16 + IRQ);
  return Boolean(core.pendingInterrupts & (1 << IRQ));
}

test('a peripheral interrupt pended by software is taken once when its line is low', () => {
  assert.equal(pendingAfterEntry(true, false), false);
});

test('a peripheral interrupt whose line is still up stays pending as its handler is entered', () => {
  assert.equal(pendingAfterEntry(true, true), true);
});

test('rp2040js alone keeps the software pend for good: the departure the correction is for', () => {
  // When this fails, rp2040js clears a taken interrupt's pending state as the architecture does.
  assert.equal(pendingAfterEntry(false, false), true);
});
