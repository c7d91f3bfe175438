// The harness on the real Pico image (`cargo pico-build`, or the image `tests/pico.rs` builds, which runs
// these tests with PICO_ELF and PICO_PINS set): boot, READY and STATUS, events through the pins in
// order, the same run for the same bytes at the same steps.

import assert from 'node:assert/strict';
import fs from 'node:fs';
import test from 'node:test';

import { Harness } from '../src/harness.js';
import { firmwareImage } from '../src/image.js';
import { defaultInputPulseNs } from '../src/pins.js';
import { EXIT, GO, HOLD, READY, RESET, STATUS } from '../src/protocol.js';

const { PICO_ELF, PICO_PINS } = process.env;
/** PADS_BANK0's base: a pin's pad register is at 4 + 4 × its number. */
const PADS_BANK0 = 0x4001c000;
/** The input-enable bit of a pad register. */
const PAD_IE = 0x40;
const skip = !(PICO_ELF && PICO_PINS) && 'needs PICO_ELF and PICO_PINS (cargo test -p end-to-end --test pico sets them)';

function image() {
  return firmwareImage(fs.readFileSync(PICO_ELF), PICO_ELF);
}

/**
 * Runs a harness through `script`: `[steps, bytes]` pairs — run that many steps, then hand the host's
 * bytes over — and then until EXIT is answered; `setUp` gets the board at power-on, before it runs.
 * Returns what it sent, its trace and its figures.
 */
function drive(script, options = {}, setUp = () => {}) {
  const map = JSON.parse(fs.readFileSync(PICO_PINS, 'utf8'));
  const sent = [];
  const trace = [];
  const rtt = [];
  const h = new Harness(
    image(),
    map,
    { seed: 5n, inputPulseNs: defaultInputPulseNs(map), shortPulseNs: 1_000_000, ...options },
    (bytes) => sent.push(...bytes),
    (bytes) => rtt.push(...bytes),
    (line) => trace.push(line),
  );
  setUp(h.board);
  for (const [steps, bytes] of [...script, [0, [HOLD, STATUS, EXIT]]]) {
    for (let i = 0; i < steps; i++) h.step();
    h.receive(bytes);
  }
  for (let i = 0; i < 100_000 && !h.finished; i++) h.step();
  assert.ok(h.finished, 'EXIT answered');
  return { sent, trace, rtt, report: h.report(), status: h.exitStatus, map };
}

const eventsOf = (map) => map.inputs.map((i) => i.event);
const byPin = (map, pin) => map.inputs.find((i) => i.pin === pin).event;

test('boots, says READY, resets on hold and answers STATUS with the published counters', { skip }, () => {
  const { sent, report, status, map, rtt } = drive([[50, [HOLD, STATUS, RESET]], [10, [GO]], [200, []]]);
  assert.ok(rtt.length > 0, 'the defmt frames the firmware wrote over RTT were drained');
  assert.equal(sent.indexOf(READY) >= 0, true);
  const ready = sent.filter((b) => b === READY).length;
  assert.equal(ready, 2, 'once at power-on, once for the RESET');
  const status1 = sent.indexOf(STATUS);
  assert.ok(status1 > 0 && sent.length >= status1 + 25);
  assert.equal(report.boots, 2);
  assert.equal(status, 0);
  assert.ok(report.rosc_bits >= 32, 'the firmware seeded its generator from the ring oscillator');
  assert.deepEqual(report.emulator_warnings, []);
  assert.equal(report.hidden_commands, 0);
  const commands = sent.filter((b) => map.outputs.some((o) => o.event === b));
  assert.ok(commands.length > 0, 'the firmware fired its first commands');
  assert.ok(report.cost.idle_decision.calls > 0 && report.cost.decision.calls > 0);
});

test('a RESET not on hold powers the board on and says READY once its loop runs', { skip }, () => {
  const { sent, report } = drive([[50, [RESET]], [200, []]]);
  assert.equal(sent.filter((b) => b === READY).length, 2);
  assert.equal(report.boots, 2);
});

test('events reach the firmware through the pins, in the order sent', { skip }, () => {
  const map = JSON.parse(fs.readFileSync(PICO_PINS, 'utf8'));
  const pins = map.inputs.map((i) => i.pin).sort((a, b) => a - b);
  const [low, high] = [byPin(map, pins[0]), byPin(map, pins[pins.length - 1])];
  // The higher pin's event first: the firmware, reading both at once, would take the lower first.
  const script = [[50, [HOLD, STATUS, RESET, GO]], [100, [high, low]], [300, []]];
  const apart = drive(script);
  const edges = (run) => run.trace.filter((l) => / in \d+ 1$/.test(l)).map((l) => l.split(' '));
  const [a, b] = edges(apart);
  assert.equal(Number(a[2]), pins[pins.length - 1], 'sent first, made first');
  assert.ok(Number(b[0]) > Number(a[0]), 'the second waited for the first to be read');
  assert.equal(apart.report.kept_in_order, 1);
  assert.equal(apart.report.simultaneous, 1);
  assert.ok(apart.report.cost.apply.calls >= 2);
  const together = drive(script, { together: true });
  const [c, d] = edges(together);
  assert.equal(c[0], d[0], 'together: both at once, and the firmware takes them in its own order');
  assert.equal(together.report.kept_in_order, 0);
  assert.equal(together.report.simultaneous, 1);
  assert.ok(eventsOf(map).includes(low));
});

test('the same bytes at the same steps give the same run, to the cycle', { skip }, () => {
  const map = JSON.parse(fs.readFileSync(PICO_PINS, 'utf8'));
  const events = eventsOf(map);
  const script = [[50, [HOLD, STATUS, RESET, GO]], ...events.map((e, i) => [40 + 7 * i, [e]]), [200, []]];
  const one = drive(script);
  const two = drive(script);
  assert.deepEqual(one.sent, two.sent);
  assert.deepEqual(one.trace, two.trace);
  assert.equal(one.report.cycles, two.report.cycles);
  assert.equal(one.report.emulated_ms, two.report.emulated_ms);
  assert.deepEqual(one.report.cost, two.report.cost);
});

test('an edge latched while the firmware sets its pins up is no event', { skip }, () => {
  // A pull moving a line nothing drives yet, or a contact bouncing at power-on: the input pin goes
  // through both edges just after the firmware turns its pad's input on, before its interrupts are on.
  const map = JSON.parse(fs.readFileSync(PICO_PINS, 'utf8'));
  const pin = map.inputs[0].pin;
  let glitched = false;
  const glitch = ({ mcu }) => {
    const pads = mcu.findPeripheral(PADS_BANK0);
    const write = pads.writeUint32.bind(pads);
    pads.writeUint32 = (offset, value) => {
      write(offset, value);
      if (offset !== 4 + 4 * pin || glitched || !(value & PAD_IE)) return;
      glitched = true;
      const gpio = mcu.gpio[pin];
      const rest = gpio.rawInputValue;
      gpio.setInputValue(!rest);
      gpio.setInputValue(rest);
    };
  };
  const { report } = drive([[300, []]], {}, glitch);
  assert.ok(glitched, "the firmware turned the pad's input on");
  assert.equal(report.edges, 0);
  assert.equal(report.cost.apply.calls, 0, 'the firmware took no event');
});
