#!/usr/bin/env node
// Command line of the harness: loads the Pico firmware image, listens on a Unix socket, and runs the
// board for the one host that connects (README of this directory).
//
//   node src/main.js --elf FILE --pins FILE.json --socket PATH [--seed N] [--input-pulse-us N]
//                    [--short-pulse-us N] [--together] [--overlap] [--rtt FILE] [--stats FILE] [--trace FILE]
//   node src/main.js --uart --elf FILE --socket PATH [--seed N] [--rtt FILE] [--stats FILE]
//   node src/main.js --usb --elf FILE --socket PATH [--seed N] [--rtt FILE] [--stats FILE]

import fs from 'node:fs';
import net from 'node:net';
import { parseArgs } from 'node:util';

import { Harness } from './harness.js';
import { firmwareImage } from './image.js';
import { defaultInputPulseNs, PinMap } from './pins.js';
import { BitSource } from './rosc.js';
import { UartHarness } from './uart.js';
import { UsbHarness } from './usb.js';

/** Wall time one burst of stepping may take before the host's bytes are read again. */
const SLICE_MS = 2;

const USAGE = `usage: main.js --elf FILE --pins FILE.json --socket PATH [--seed N] [--input-pulse-us N]
                [--short-pulse-us N] [--together] [--overlap] [--rtt FILE] [--stats FILE] [--trace FILE]
       main.js --uart --elf FILE --socket PATH [--seed N] [--rtt FILE] [--stats FILE]
       main.js --usb --elf FILE --socket PATH [--seed N] [--rtt FILE] [--stats FILE]`;

function fail(message, code = 2) {
  process.stderr.write(`rp2040 harness: ${message}\n`);
  process.exit(code);
}

function options() {
  let values;
  try {
    ({ values } = parseArgs({
      options: {
        elf: { type: 'string' },
        pins: { type: 'string' },
        socket: { type: 'string' },
        seed: { type: 'string', default: '1' },
        'input-pulse-us': { type: 'string' },
        'short-pulse-us': { type: 'string', default: '1000' },
        rtt: { type: 'string' },
        stats: { type: 'string' },
        trace: { type: 'string' },
        together: { type: 'boolean', default: false },
        overlap: { type: 'boolean', default: false },
        uart: { type: 'boolean', default: false },
        usb: { type: 'boolean', default: false },
      },
      strict: true,
    }));
  } catch (e) {
    fail(`${e.message}\n${USAGE}`);
  }
  if (values.uart && values.usb) fail(`--uart and --usb: one link at a time\n${USAGE}`);
  for (const required of values.uart || values.usb ? ['elf', 'socket'] : ['elf', 'pins', 'socket']) if (!values[required]) fail(`--${required} is required\n${USAGE}`);
  const number = (name) => {
    const v = values[name];
    if (v === undefined) return undefined;
    if (!/^\d+$/.test(v)) fail(`--${name} ${v}: not a non-negative integer`);
    return Number(v);
  };
  if (!/^\d+$/.test(values.seed)) fail(`--seed ${values.seed}: not a non-negative integer`);
  return {
    ...values,
    seed: BigInt(values.seed),
    inputPulseUs: number('input-pulse-us'),
    shortPulseUs: number('short-pulse-us'),
  };
}

function main() {
  const opts = options();
  let img;
  try {
    img = firmwareImage(fs.readFileSync(opts.elf), opts.elf);
  } catch (e) {
    fail(e.message);
  }
  if (opts.uart) {
    serveLink(opts, img, UartHarness, 'UART0');
    return;
  }
  if (opts.usb) {
    serveLink(opts, img, UsbHarness, 'USB (CDC-ACM)');
    return;
  }
  let map;
  try {
    map = JSON.parse(fs.readFileSync(opts.pins, 'utf8'));
  } catch (e) {
    fail(`${opts.pins}: ${e.message}`);
  }
  const inputPulseNs = opts.inputPulseUs !== undefined ? opts.inputPulseUs * 1000 : defaultInputPulseNs(map);
  try {
    new PinMap(map, inputPulseNs); // refused before anyone connects
  } catch (e) {
    fail(`${opts.pins}: ${e.message}`);
  }
  const log = opts.rtt ? fs.openSync(opts.rtt, 'w') : null;
  try {
    fs.rmSync(opts.socket, { force: true });
  } catch (e) {
    fail(`${opts.socket}: ${e.message}`);
  }
  const server = net.createServer({ allowHalfOpen: false });
  server.maxConnections = 1;
  server.on('error', (e) => fail(`${opts.socket}: ${e.message}`));
  server.on('connection', (socket) => {
    server.close();
    let harness;
    try {
      const trace = opts.trace ? fs.openSync(opts.trace, 'w') : null;
      harness = new Harness(
        img,
        map,
        { seed: opts.seed, inputPulseNs, shortPulseNs: opts.shortPulseUs * 1000, together: opts.together, overlap: opts.overlap },
        (bytes) => socket.write(bytes),
        log === null ? null : (bytes) => fs.writeSync(log, bytes),
        trace === null ? null : (line) => fs.writeSync(trace, `${line}\n`),
      );
    } catch (e) {
      fail(e.message);
    }
    process.stderr.write(
      `rp2040 harness: ${opts.elf} on an emulated RP2040 (rp2040js); ROSC random bit from a seeded xorshift32, seed ${opts.seed}; ` +
        `${harness.pins.sampling} sampling, input pulses ${inputPulseNs / 1000} µs, command levels shorter than ${opts.shortPulseUs} µs counted as short pulses\n`,
    );
    let ended = false;
    const end = (code) => {
      if (ended) return;
      ended = true;
      const report = harness.report();
      if (opts.stats) fs.writeFileSync(opts.stats, `${JSON.stringify(report, null, 2)}\n`);
      process.stderr.write(`rp2040 harness: ${summary(report)}\n`);
      socket.end(() => process.exit(code));
      setTimeout(() => process.exit(code), 1000).unref();
    };
    socket.on('close', () => end(harness.exitStatus ?? 0));
    socket.on('error', () => end(harness.exitStatus ?? 0));
    // The board runs as fast as the emulator goes; the host's bytes are read between slices, and a
    // slice ends early when bytes went out, so the host hears of a command at once.
    const run = () => {
      if (ended) return;
      try {
        const until = Date.now() + SLICE_MS;
        do harness.step();
        while (Date.now() < until && !harness.finished && !harness.takeSent());
      } catch (e) {
        process.stderr.write(`rp2040 harness: ${e.message}\n`);
        end(3);
        return;
      }
      if (harness.finished) end(harness.exitStatus);
      else setImmediate(run);
    };
    socket.on('data', (bytes) => harness.receive(bytes));
    setImmediate(run);
  });
  server.listen(opts.socket);
}

/** Listens on `opts.socket` and wires the one host that connects to the link build `img` through
 * `Link` (`UartHarness`: UART0; `UsbHarness`: the USB port), until the host hangs up (status 0) or the
 * firmware faults (3). */
function serveLink(opts, img, Link, what) {
  const log = opts.rtt ? fs.openSync(opts.rtt, 'w') : null;
  fs.rmSync(opts.socket, { force: true });
  const server = net.createServer({ allowHalfOpen: false });
  server.maxConnections = 1;
  server.on('error', (e) => fail(`${opts.socket}: ${e.message}`));
  server.on('connection', (socket) => {
    server.close();
    let harness;
    try {
      const bits = new BitSource(opts.seed);
      harness = new Link(img, bits, (bytes) => socket.write(bytes), log === null ? null : (bytes) => fs.writeSync(log, bytes));
    } catch (e) {
      fail(e.message);
    }
    process.stderr.write(`rp2040 harness: ${opts.elf} on an emulated RP2040 (rp2040js), ${what} to the host; seed ${opts.seed}\n`);
    let ended = false;
    const end = (code) => {
      if (ended) return;
      ended = true;
      const report = harness.report();
      if (opts.stats) fs.writeFileSync(opts.stats, `${JSON.stringify(report, null, 2)}\n`);
      const c = report.cost;
      process.stderr.write(
        `rp2040 harness: ${report.emulated_ms} ms emulated, ${report.bytes_in} bytes in, ${report.bytes_out} bytes out; ` +
          `apply ${c.apply.avg_cycles}/${c.apply.max_cycles} cycles, decision ${c.decision.avg_cycles}/${c.decision.max_cycles} cycles (avg/max)\n`,
      );
      socket.end(() => process.exit(code));
      setTimeout(() => process.exit(code), 1000).unref();
    };
    socket.on('close', () => end(0));
    socket.on('error', () => end(0));
    // As in pin mode, but a core asleep with nothing to feed it waits for the host's next bytes.
    let waiting = false;
    const run = () => {
      waiting = false;
      if (ended) return;
      try {
        const until = Date.now() + SLICE_MS;
        do harness.step();
        while (Date.now() < until && !harness.idle && !harness.takeSent());
      } catch (e) {
        process.stderr.write(`rp2040 harness: ${e.message}\n`);
        end(3);
        return;
      }
      if (harness.idle) waiting = true;
      else setImmediate(run);
    };
    socket.on('data', (bytes) => {
      harness.receive(bytes);
      if (waiting) {
        waiting = false;
        setImmediate(run);
      }
    });
    setImmediate(run);
  });
  server.listen(opts.socket);
}

function summary(r) {
  const c = r.cost;
  return (
    `${r.emulated_ms} ms emulated, ${r.boots} boots, ${r.edges} input edges (${r.simultaneous} simultaneous, ${r.missed} missed, ` +
    `${r.deferred} deferred, ${r.during_decide} during a decision), ${r.commands_seen} commands seen (${r.short_pulses} short pulses, ` +
    `${r.hidden_commands} fired but not shown); apply ${c.apply.avg_cycles}/${c.apply.max_cycles} cycles, ` +
    `decision ${c.decision.avg_cycles}/${c.decision.max_cycles} cycles (avg/max)`
  );
}

main();
