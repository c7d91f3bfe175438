// The pin map: edges for events, commands from output changes, what the harness refuses.

import assert from 'node:assert/strict';
import test from 'node:test';

import { defaultInputPulseNs, PinMap, PinMapError } from '../src/pins.js';
import { statusFrame, STATUS } from '../src/protocol.js';

const US = 1000;
const map = (over = {}) => ({
  board: 't',
  sampling: 'interrupt',
  sample_period_us: null,
  inputs: [
    { event: 2, name: 'part', pin: 5, edge: 'rising', pull: 'down' },
    { event: 3, name: 'door_open', pin: 7, edge: 'rising', pull: 'up' },
    { event: 4, name: 'door_shut', pin: 7, edge: 'falling', pull: 'up' },
    { event: 5, name: 'ok', pin: 3, edge: 'rising', pull: 'down' },
  ],
  outputs: [
    { event: 0, name: 'on', pin: 16, action: 'set', pulse_ms: null },
    { event: 1, name: 'off', pin: 16, action: 'clear', pulse_ms: null },
    { event: 6, name: 'go', pin: 17, action: 'pulse', pulse_ms: 20 },
  ],
  ...over,
});

test('a pulse pin pulses for each event and waits a pulse width before the next', () => {
  const pins = new PinMap(map(), 100 * US);
  assert.deepEqual(pins.restLevels(), [[5, false], [7, true], [3, false]]);
  const first = pins.edgesFor(2, 1000);
  assert.deepEqual(first.edges, [
    { at: 1000, pin: 5, level: true, event: 2 },
    { at: 101_000, pin: 5, level: false, event: undefined },
  ]);
  assert.equal(pins.readyAt(2), 201_000, 'low for a pulse width too');
  assert.equal(pins.edgesFor(2, 150_000).deferred, true);
  pins.rest();
  assert.equal(pins.readyAt(2), 0);
});

test('a level pin moves with its events and cannot show an event it is already at', () => {
  const pins = new PinMap(map(), 100 * US);
  assert.deepEqual(pins.edgesFor(4, 0).edges, [{ at: 0, pin: 7, level: false, event: 4 }]);
  assert.equal(pins.edgesFor(4, 500_000).problem, 'impossible');
  assert.deepEqual(pins.edgesFor(3, 500_000).edges, [{ at: 500_000, pin: 7, level: true, event: 3 }]);
  assert.equal(pins.edgesFor(9, 0).problem, 'unmapped');
});

test('output edges are commands; a pulse end is none', () => {
  const pins = new PinMap(map(), 100 * US);
  assert.equal(pins.commandFor(16, true), 0);
  assert.equal(pins.commandFor(16, false), 1);
  assert.equal(pins.commandFor(17, true), 6);
  assert.equal(pins.commandFor(17, false), undefined);
  assert.equal(pins.commandFor(20, true), undefined);
});

test('edges read at once come in the firmware order: pins ascending with interrupts, the table with sampling', () => {
  const irq = new PinMap(map(), 100 * US);
  assert.ok(irq.orderOf(5) < irq.orderOf(2) && irq.orderOf(2) < irq.orderOf(3));
  const timer = new PinMap(map({ sampling: 'timer', sample_period_us: 1000 }), 1500 * US);
  assert.ok(timer.orderOf(2) < timer.orderOf(3) && timer.orderOf(3) < timer.orderOf(5));
  assert.equal(defaultInputPulseNs(map()), 100 * US);
  assert.equal(defaultInputPulseNs(map({ sampling: 'timer', sample_period_us: 500 })), 1500 * US, 'the tick is 1 ms');
  assert.equal(defaultInputPulseNs(map({ sampling: 'timer', sample_period_us: 4000 })), 6000 * US);
});

test('a map the plant could not read is refused', () => {
  const refused = (over, pattern) => assert.throws(() => new PinMap(map(over), 100 * US), (e) => e instanceof PinMapError && pattern.test(e.message));
  const outputs = map().outputs;
  refused({ outputs: [...outputs, { event: 7, name: 'also_on', pin: 16, action: 'set', pulse_ms: null }] }, /rising edge would be both on and also_on/);
  refused({ outputs: [...outputs, { event: 8, name: 'stop', pin: 17, action: 'clear', pulse_ms: null }] }, /end of a pulse would look like stop/);
  refused({ sampling: 'timer' }, /sample_period_us/);
  refused({ sampling: 'polling' }, /sampling 'polling'/);
  refused({ outputs: [{ event: 0, name: 'on', pin: 5, action: 'set', pulse_ms: null }] }, /pin 5 is both an input and an output/);
  refused({ inputs: [{ event: 2, name: 'x', pin: 30, edge: 'rising', pull: 'down' }] }, /pin 30 is not a GPIO/);
  refused({ outputs: [{ event: 6, name: 'go', pin: 17, action: 'pulse', pulse_ms: null }] }, /go: pulse_ms/);
});

test('the STATUS answer is the six counters little-endian after its byte', () => {
  const frame = statusFrame([1, 2, 3, 0x01020304, 0, 0xffffffff]);
  assert.equal(frame.length, 25);
  assert.equal(frame[0], STATUS);
  assert.deepEqual([...frame.subarray(13, 17)], [4, 3, 2, 1]);
  assert.deepEqual([...frame.subarray(21, 25)], [255, 255, 255, 255]);
});
