// The RP2040's edge interrupts as the corrected emulator (`src/gpio.js`) gives them, seen through the
// registers the firmware reads (RP2040 datasheet, IO_BANK0: INTR, PROC0_INTE, PROC0_INTS): an edge
// latches in INTR when a pin's level changes, and only then, whether or not its interrupt is enabled; it
// stays latched until a 1 is written to its bit; PROC0_INTS is INTR & PROC0_INTE, and IO_IRQ_BANK0 is
// pending while any of it is set. The pads come out of reset with their input enabled, and the levels
// pins have from power-on are no edges.

import assert from 'node:assert/strict';
import test from 'node:test';

import { RP2040 } from 'rp2040js';

import { correctGpio, EDGE_HIGH, EDGE_LOW, PAD_RESET, powerOn } from '../src/gpio.js';

const IO_BANK0 = 0x40014000;
const INTR0 = IO_BANK0 + 0x0f0;
const PROC0_INTE0 = IO_BANK0 + 0x100;
const PROC0_INTS0 = IO_BANK0 + 0x120;
/** IO_IRQ_BANK0's number in the NVIC. */
const IO_IRQ_BANK0 = 13;
/** The input-enable bit of a pad register. */
const PAD_IE = 0x40;
const PADS_BANK0 = 0x4001c000;
const PIN = 2;
const pad = (pin) => PADS_BANK0 + 4 + 4 * pin;

/** The edge latches of `PIN` in INTR, as the firmware reads them. */
const edges = (mcu) => (mcu.readUint32(INTR0) >>> (4 * PIN)) & (EDGE_LOW | EDGE_HIGH);

/** Writes 1s to `PIN`'s edge latches, as the firmware clears them. */
const clear = (mcu) => mcu.writeUint32(INTR0, (EDGE_LOW | EDGE_HIGH) << (4 * PIN));

/** Whether IO_IRQ_BANK0 is pending in the NVIC. */
const pending = (mcu) => !!(mcu.core.pendingInterrupts & (1 << IO_IRQ_BANK0));

function corrected() {
  const mcu = new RP2040();
  correctGpio(mcu);
  return mcu;
}

test('an edge latches when the level changes, and only then', () => {
  const mcu = corrected();
  const gpio = mcu.gpio[PIN];
  gpio.setInputValue(false);
  assert.equal(edges(mcu), 0, 'low, set low: no edge');
  gpio.setInputValue(true);
  assert.equal(edges(mcu), EDGE_HIGH);
  clear(mcu);
  gpio.setInputValue(true);
  assert.equal(edges(mcu), 0, 'high, set high: no edge');
  gpio.setInputValue(false);
  assert.equal(edges(mcu), EDGE_LOW);
  gpio.setInputValue(true);
  assert.equal(edges(mcu), EDGE_LOW | EDGE_HIGH, 'both latched until cleared');
});

test('an edge latches whether or not its interrupt is enabled, and interrupts once it is', () => {
  const mcu = corrected();
  const gpio = mcu.gpio[PIN];
  gpio.setInputValue(false);
  gpio.setInputValue(true);
  assert.equal(mcu.readUint32(PROC0_INTE0), 0, 'no interrupt enabled');
  assert.equal(edges(mcu), EDGE_HIGH, 'the rise latched all the same');
  assert.equal(mcu.readUint32(PROC0_INTS0), 0);
  assert.equal(pending(mcu), false);
  mcu.writeUint32(PROC0_INTE0, EDGE_HIGH << (4 * PIN));
  assert.equal(mcu.readUint32(PROC0_INTS0), EDGE_HIGH << (4 * PIN), 'the edge latched before is taken now');
  assert.equal(pending(mcu), true);
  clear(mcu);
  assert.equal(mcu.readUint32(PROC0_INTS0), 0);
  assert.equal(pending(mcu), false);
});

test("INTR's edge bits are cleared by writing 1s to them, each alone; its level bits are not latches", () => {
  const mcu = corrected();
  const gpio = mcu.gpio[PIN];
  gpio.setInputValue(true);
  gpio.setInputValue(false);
  assert.equal(edges(mcu), EDGE_LOW | EDGE_HIGH);
  mcu.writeUint32(INTR0, 0);
  assert.equal(edges(mcu), EDGE_LOW | EDGE_HIGH, 'a 0 written clears nothing');
  mcu.writeUint32(INTR0, EDGE_LOW << (4 * PIN));
  assert.equal(edges(mcu), EDGE_HIGH, 'a 1 written to EDGE_LOW clears it alone');
  mcu.writeUint32(INTR0, EDGE_LOW << (4 * (PIN + 1)));
  assert.equal(edges(mcu), EDGE_HIGH, "another pin's bit written clears nothing here");
  mcu.writeUint32(INTR0, EDGE_HIGH << (4 * PIN));
  assert.equal(edges(mcu), 0);
  const LEVEL_LOW = 1 << 0;
  mcu.writeUint32(INTR0, LEVEL_LOW << (4 * PIN));
  assert.equal((mcu.readUint32(INTR0) >>> (4 * PIN)) & LEVEL_LOW, LEVEL_LOW, 'LEVEL_LOW follows the pin, low');
});

test('PROC0_INTS is INTR & PROC0_INTE, pin by pin', () => {
  const mcu = corrected();
  // Pin 2 rises and falls, pin 3 rises, pin 4 stays low; pin 2 has both edges enabled, pin 3 its falling
  // edge only, pin 4 its rising edge.
  mcu.gpio[2].setInputValue(true);
  mcu.gpio[2].setInputValue(false);
  mcu.gpio[3].setInputValue(true);
  mcu.writeUint32(INTR0, 0xcccccccc & ~(0xccc << 8)); // every other pin of the register cleared
  const inte = ((EDGE_LOW | EDGE_HIGH) << 8) | (EDGE_LOW << 12) | (EDGE_HIGH << 16);
  mcu.writeUint32(PROC0_INTE0, inte);
  const intr = mcu.readUint32(INTR0) & 0xcccccccc;
  assert.equal(intr, ((EDGE_LOW | EDGE_HIGH) << 8) | (EDGE_HIGH << 12));
  assert.equal(mcu.readUint32(PROC0_INTS0), intr & inte);
  assert.equal(mcu.readUint32(PROC0_INTS0), (EDGE_LOW | EDGE_HIGH) << 8);
  assert.equal(pending(mcu), true);
  mcu.writeUint32(INTR0, (EDGE_LOW | EDGE_HIGH) << 8);
  assert.equal(mcu.readUint32(PROC0_INTS0), 0, "pin 3's latched rise is not enabled");
  assert.equal(pending(mcu), false);
});

test('an enabled edge interrupt is raised by a change only', () => {
  const mcu = corrected();
  const gpio = mcu.gpio[PIN];
  gpio.irqEnableMask = EDGE_LOW;
  gpio.setInputValue(false);
  assert.equal(gpio.irqValue, false, 'a low pin set low raises no falling-edge interrupt');
  gpio.setInputValue(true);
  gpio.setInputValue(false);
  assert.equal(gpio.irqValue, true);
});

test('the pads come out of reset as on silicon, and a pad write on a still pin latches nothing', () => {
  const mcu = corrected();
  assert.equal(mcu.readUint32(pad(PIN)), PAD_RESET);
  mcu.gpio[PIN].setInputValue(false);
  mcu.writeUint32(pad(PIN), PAD_RESET & ~0x40); // input off …
  mcu.writeUint32(pad(PIN), PAD_RESET | 0x08); // … on again, pulled up as well
  assert.equal(edges(mcu), 0);
});

test("a pad's input enable gates the level the edges are latched from", () => {
  const mcu = corrected();
  mcu.gpio[PIN].setInputValue(true);
  clear(mcu);
  mcu.writeUint32(pad(PIN), PAD_RESET & ~PAD_IE);
  assert.equal(edges(mcu), EDGE_LOW, 'a high pin whose input is turned off falls');
  clear(mcu);
  mcu.writeUint32(pad(PIN), PAD_RESET);
  assert.equal(edges(mcu), EDGE_HIGH, 'and rises when it is turned on again');
});

test('the levels from power-on are no edges', () => {
  const mcu = corrected();
  powerOn(mcu, [
    [PIN, true],
    [PIN + 1, false],
  ]);
  assert.equal(mcu.readUint32(INTR0) & 0xcccccccc, 0);
  assert.equal(mcu.gpio[PIN].inputValue, true);
});

test('rp2040js alone latches a falling edge on a pin that never moved: the departure the correction is for', () => {
  // When this fails, rp2040js latches transitions as the silicon does: the correction can go.
  const mcu = new RP2040();
  mcu.writeUint32(pad(PIN), PAD_RESET);
  clear(mcu);
  mcu.gpio[PIN].setInputValue(false);
  assert.equal(edges(mcu), EDGE_LOW);
  assert.notEqual(new RP2040().gpio[PIN].padValue, PAD_RESET, 'and its pads start with their input off');
});
