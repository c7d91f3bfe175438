// The harness proper: a Pico board under emulation, driven through its pins by a host that speaks the
// firmware link protocol (`protocol.js`; README of this directory). Host events become edges on the
// input pins (`pins.js`), output pin changes become commands back to the host, the control bytes are
// answered as the QEMU firmware answers them, and what only pins show is counted.
//
// Events reach the pins in the host's order: two edges the firmware reads at once (one sample, one pass
// of the edge handler) it takes in its own order — the pin table's — not in the order they came, so an
// event whose edge comes while an earlier one is still unread is *simultaneous*, and is made at once only
// if the firmware's order puts it after every unread one; else it waits until they have been read (edge
// interrupts: the handler cleared their latches; timer sampling: the next sample). With `together` the
// harness does not wait and the order is lost as on real pins (the report then shows what that does).
// An event also waits until its pin may change again (`pins.js`).
// Nor does an event reach the pins while a command pulse is being given: a device commanded by a pulse
// answers once it has the whole pulse, and the plant's answer must not let the firmware fire the same
// pulse again while it is still high (`overlap` lifts this; the events that waited are counted).
// Also counted: a pulse the firmware never sampled (missed), an edge arriving while the firmware is
// inside `decide` (inexact synchronisation), a command level too short for a real plant to see, and
// commands the firmware counts as fired that no output edge showed.
//
// Time is the board's emulated time; the host's bytes take effect at the emulated instant the harness
// reads them. For a given seed and the same bytes at the same instants, a run is the same.

import { Board, Cost, CYCLE_NS } from './board.js';
import { EDGE_HIGH, EDGE_LOW } from './gpio.js';
import { PinMap } from './pins.js';
import { EXIT, GO, HOLD, MAX_EVENT, READY, RESET, SAFE, STATUS, statusFrame } from './protocol.js';
import { BitSource } from './rosc.js';

const RUNNING = 1;
const SAFE_FLAG = 2;
/** Emulated time a STATUS or EXIT waits for unread edges at most (then it is answered anyway). */
const BARRIER_LIMIT_NS = 100_000_000;
/** Instructions per call of `step`, so the host's bytes are read often. */
const STEP_BUDGET = 20_000;

/**
 * `image`: the checked ELF with its addresses (`main.js`); `map`: the pin map JSON; `options`: `{ seed,
 * inputPulseNs, shortPulseNs, together, overlap }`; `send(bytes)`: to the host; `log(bytes)`: RTT bytes, or null;
 * `trace(line)`: one line per host byte, edge, output change and byte sent, with the emulated time in
 * ns, or null.
 */
export class Harness {
  constructor(image, map, options, send, log, trace = null) {
    this.image = image;
    this.pins = new PinMap(map, options.inputPulseNs);
    this.shortPulseNs = options.shortPulseNs;
    this.together = Boolean(options.together);
    this.overlap = Boolean(options.overlap);
    this.bits = new BitSource(options.seed);
    this.trace = trace;
    this.sent = false;
    this.send = (bytes) => {
      trace?.(`${this.now()} send ${Buffer.from(bytes).toString('hex')}`);
      this.sent = true;
      send(bytes);
    };
    this.log = log;
    this.inbox = [];
    this.stats = {
      target: 'rp2040',
      seed: Number(options.seed),
      sampling: this.pins.sampling,
      sample_period_us: this.pins.samplePeriodNs / 1000,
      input_pulse_us: options.inputPulseNs / 1000,
      short_pulse_us: options.shortPulseNs / 1000,
      order: this.together ? 'together' : 'apart',
      inputs_during_pulses: this.overlap,
      boots: 0,
      emulated_ms: 0,
      cycles: 0,
      rosc_bits: 0,
      edges: 0,
      deferred: 0,
      after_pulse: 0,
      longest_wait_us: 0,
      longest_queue: 0,
      simultaneous: 0,
      kept_in_order: 0,
      missed: 0,
      during_decide: 0,
      unmapped: 0,
      impossible: 0,
      commands_seen: 0,
      short_pulses: 0,
      hidden_commands: 0,
      host_unknown: 0,
      forced_answers: 0,
      emulator_warnings: [],
    };
    this.totalCost = null;
    this.exitStatus = null;
    this.elapsedNs = 0;
    this.held = null;
    this.boot();
  }

  /**
   * A fresh board (power-on, or RESET): pins at rest, nothing scheduled. Reset while the host holds
   * the board, it stays off until GO — as the QEMU firmware, reset on hold, decides nothing until GO —
   * and READY goes out at once; otherwise it starts now and READY follows when its loop runs.
   */
  boot() {
    if (this.board) this.retire();
    this.pins.rest();
    this.timeline = [];
    this.unread = [];
    this.sampled = false;
    this.queue = [];
    this.outputs = new Map();
    this.pulsing = new Set();
    this.barrier = null;
    this.running = false;
    this.safeAnnounced = false;
    this.off = this.held !== null;
    this.readySent = this.off;
    this.stats.boots++;
    this.seenThisBoot = 0;
    this.board = new Board(this.image, this.pins, this.bits, {
      output: (pin, level) => this.onOutput(pin, level),
      sample: () => this.onSample(),
      ack: () => this.board.stop(),
    });
    if (this.off) this.send(Uint8Array.of(READY));
  }

  /** Folds the current board's figures into the run's before it goes. Commands the firmware counts
   * as fired but its pins never showed (no edge: merged into a pulse, or no output) are hidden. */
  retire() {
    const b = this.board;
    this.drainLog();
    b.settleCosts();
    this.stats.hidden_commands += this.hidden(b);
    this.elapsedNs += b.nanos;
    this.stats.cycles += b.mcu.core.cycles;
    for (const w of b.warnings) if (this.stats.emulator_warnings.length < 20) this.stats.emulator_warnings.push(w);
    this.totalCost ??= { apply: new Cost(), decision: new Cost(), idle: new Cost(), redecided: new Cost() };
    for (const [k, c] of Object.entries(b.costs)) this.totalCost[k].merge(c);
  }

  /** Emulated nanoseconds since the run began. */
  now() {
    return this.elapsedNs + (this.board ? this.board.nanos : 0);
  }

  /** Bytes from the host, handled in order by `step`. */
  receive(bytes) {
    for (const b of bytes) this.inbox.push(b);
  }

  /** Whether bytes went to the host since the last call (so the caller flushes them soon). */
  takeSent() {
    const sent = this.sent;
    this.sent = false;
    return sent;
  }

  /** Whether the run is over (EXIT answered); `exitStatus` is then the firmware's status. */
  get finished() {
    return this.exitStatus !== null;
  }

  /** Runs the board a little: the host's bytes, then emulated time up to the next thing to do. */
  step() {
    this.handleInbox();
    if (this.finished || this.off) return;
    const b = this.board;
    this.pump();
    const head = this.queue[0];
    const waitsForPin =
      this.running &&
      head !== undefined &&
      (this.together || this.inOrder(head.event)) &&
      (this.pulsing.size === 0 || this.overlap);
    const ready = waitsForPin ? this.pins.readyAt(head.event) : Infinity;
    const next = Math.min(this.timeline.length > 0 ? this.timeline[0].at : Infinity, ready);
    b.run(next, STEP_BUDGET);
    while (this.timeline.length > 0 && this.timeline[0].at <= b.nanos) this.applyEdge(this.timeline.shift());
    this.pump();
    if (b.sleeping) this.watchFirmware();
    this.drainLog();
  }

  handleInbox() {
    let i = 0;
    while (i < this.inbox.length && this.barrier === null && !this.finished) {
      const byte = this.inbox[i++];
      this.trace?.(`${this.now()} host ${byte.toString(16).padStart(2, '0')}`);
      if (byte <= MAX_EVENT) {
        if (this.held) this.held.push(byte);
        else this.inject(byte);
        continue;
      }
      switch (byte) {
        case HOLD:
          this.held ??= [];
          break;
        case GO:
          this.off = false;
          for (const e of this.held ?? []) this.inject(e);
          this.held = null;
          break;
        case RESET:
          this.boot();
          break;
        case STATUS:
        case EXIT:
          this.barrier = { kind: byte, since: this.board.nanos };
          if (this.off) this.answer(this.board.status());
          break;
        default:
          this.stats.host_unknown++;
      }
    }
    this.inbox.splice(0, i);
  }

  /** Queues uncontrollable event `event` for its edge (`pump`). */
  inject(event) {
    this.queue.push({ event, since: this.board.nanos, waited: false, reordered: false, deferred: false, afterPulse: false });
    this.stats.longest_queue = Math.max(this.stats.longest_queue, this.queue.length);
  }

  /**
   * Makes the edges of the queued events that may go now, in order: once the firmware's loop runs (an
   * edge before its pins are set up would be lost to the boot, not to the run), once the edge before
   * has been read (unless `together`), once the event's pin may change again.
   */
  pump() {
    const b = this.board;
    while (this.queue.length > 0 && this.running) {
      const head = this.queue[0];
      this.refreshUnread();
      if (this.unread.length > 0 && !head.waited) {
        head.waited = true;
        this.stats.simultaneous++;
      }
      if (this.unread.length > 0 && !this.together && !this.inOrder(head.event)) {
        if (!head.reordered) this.stats.kept_in_order++;
        head.reordered = true;
        return;
      }
      if (this.pulsing.size > 0 && !this.overlap) {
        if (!head.afterPulse) this.stats.after_pulse++;
        head.afterPulse = true;
        return;
      }
      if (this.pins.readyAt(head.event) > b.nanos) {
        if (!head.deferred) this.stats.deferred++;
        head.deferred = true;
        return;
      }
      this.queue.shift();
      this.stats.longest_wait_us = Math.max(this.stats.longest_wait_us, Math.round((b.nanos - head.since) / 1000));
      const { edges, problem } = this.pins.edgesFor(head.event, b.nanos);
      if (problem) {
        this.stats[problem]++;
        continue;
      }
      const [edge, ...later] = edges;
      for (const e of later) this.schedule(e);
      this.applyEdge(edge);
    }
  }

  /** Whether the firmware, reading `event`'s edge with the unread ones, takes it after all of them. */
  inOrder(event) {
    const order = this.pins.orderOf(event);
    return this.unread.every((u) => u.order < order);
  }

  /** Drops the edges the firmware has read from `unread` (edge interrupts: their latch is clear; timer
   * sampling: `onSample`), once the handler that read them has finished — the next edge must not land
   * in the middle of a read. */
  refreshUnread() {
    if (this.board.mcu.core.IPSR !== 0) return;
    if (this.sampled) {
      this.sampled = false;
      this.unread = [];
    }
    if (this.pins.sampling === 'interrupt' && this.unread.length > 0) {
      this.unread = this.unread.filter((u) => this.board.latched(u.pin) & u.bit);
    }
  }

  schedule(entry) {
    let i = this.timeline.length;
    while (i > 0 && this.timeline[i - 1].at > entry.at) i--;
    this.timeline.splice(i, 0, entry);
  }

  applyEdge({ pin, level, event }) {
    const b = this.board;
    if (event !== undefined) {
      this.stats.edges++;
      const bit = level ? EDGE_HIGH : EDGE_LOW;
      if (this.pins.sampling === 'interrupt' && b.latched(pin) & bit) this.stats.missed++; // latch still full
      if (b.deciding) this.stats.during_decide++;
      this.unread.push({ pin, bit, order: this.pins.orderOf(event) });
    } else if (this.pins.sampling === 'timer') {
      // A pulse's return: the firmware saw the pulse only if it sampled while it lasted.
      const open = this.sampled ? undefined : this.unread.find((u) => u.pin === pin);
      if (open) {
        this.stats.missed++;
        this.unread = this.unread.filter((u) => u !== open);
      }
    }
    this.trace?.(`${this.now()} in ${pin} ${level ? 1 : 0}`);
    b.setInput(pin, level);
  }

  /** The firmware read the input register (timer sampling): every edge made so far has been read. */
  onSample() {
    if (this.pins.sampling === 'timer' && this.unread.length > 0) {
      this.sampled = true;
      this.board.stop();
    }
  }

  /**
   * An output pin changed: the command it shows goes to the host at once. A command level undone within
   * `shortPulseNs` counts as a short pulse: a plant whose inputs filter shorter levels would miss it.
   */
  onOutput(pin, level) {
    const now = this.board.nanos;
    this.trace?.(`${this.now()} out ${pin} ${level ? 1 : 0}`);
    const last = this.outputs.get(pin);
    if (last && now - last.at < this.shortPulseNs && this.pins.commandFor(pin, last.level) !== undefined) {
      this.stats.short_pulses++;
    }
    this.outputs.set(pin, { level, at: now });
    if (this.pins.outputPins.get(pin)?.pulse) {
      if (level) this.pulsing.add(pin);
      else if (this.pulsing.delete(pin) && this.queue.length > 0) this.board.stop();
    }
    const command = this.pins.commandFor(pin, level);
    if (command !== undefined) {
      this.stats.commands_seen++;
      this.seenThisBoot++;
      this.send(Uint8Array.of(command));
    }
  }

  /** The core sleeps: the firmware's loop is between turns. READY, SAFE and waiting answers. */
  watchFirmware() {
    const status = this.board.status();
    const { flags } = status;
    if (!this.running && flags & RUNNING) {
      this.running = true;
      if (!this.readySent) this.send(Uint8Array.of(READY));
      this.readySent = true;
      this.pump();
    }
    if (flags & SAFE_FLAG && !this.safeAnnounced) {
      this.safeAnnounced = true;
      this.send(Uint8Array.of(SAFE));
    }
    const w = this.barrier;
    if (w === null || !this.running) return;
    this.refreshUnread();
    const settled = this.timeline.length === 0 && this.queue.length === 0 && this.unread.length === 0;
    const late = this.timeline.length === 0 && this.queue.length === 0 && this.board.nanos - w.since > BARRIER_LIMIT_NS;
    if (!settled && !late) return;
    if (!settled) this.stats.forced_answers++;
    this.answer(status);
  }

  /** Commands fired on board `b` that no output edge showed. */
  hidden(b) {
    return Math.max(0, b.status().counters[1] - this.seenThisBoot);
  }

  /** Answers the waiting STATUS or EXIT with the firmware's published `status`. */
  answer(status) {
    const w = this.barrier;
    this.barrier = null;
    if (w.kind === STATUS) {
      this.send(statusFrame(status.counters));
    } else {
      this.retire();
      this.board = null;
      this.exitStatus = status.flags & SAFE_FLAG ? 1 : 0;
    }
  }

  drainLog() {
    if (this.log && this.board) {
      const bytes = this.board.drainRtt();
      if (bytes.length > 0) this.log(bytes);
    }
  }

  /** The run's figures (JSON): counts, emulated time, the cost of the runtime's entry points. */
  report() {
    const s = { ...this.stats };
    const live = this.board;
    const costs = { apply: new Cost(), decision: new Cost(), idle: new Cost(), redecided: new Cost() };
    let nanos = this.elapsedNs;
    let cycles = s.cycles;
    const runs = [this.totalCost];
    if (live) {
      live.settleCosts();
      s.hidden_commands += this.hidden(live);
      nanos += live.nanos;
      cycles += live.mcu.core.cycles;
      runs.push(live.costs);
    }
    for (const run of runs) if (run) for (const [k, c] of Object.entries(run)) costs[k].merge(c);
    s.emulated_ms = Math.round(nanos / 1e6);
    s.cycles = cycles;
    s.rosc_bits = this.bits.reads;
    s.cycle_ns = CYCLE_NS;
    s.cost = { apply: costs.apply, decision: costs.decision, idle_decision: costs.idle, redecision: costs.redecided };
    return JSON.parse(JSON.stringify(s));
  }
}
