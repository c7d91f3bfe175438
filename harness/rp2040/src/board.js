// One emulated Pico: an rp2040js RP2040 with the firmware image loaded, the ROM stand-in and the seeded
// ring oscillator in place, and the hooks the harness watches it through — output pin levels, reads of
// the input register (the firmware's samples), writes that drive an output already at that level, the
// `SCT_STATUS` block the firmware publishes, its RTT log, and the cycles spent in the runtime's entry
// points. `run` executes it in emulated time: one instruction at a time, and straight to the next timer
// alarm while the core sleeps in `wfi`.

import { GPIOPinState, RP2040 } from 'rp2040js';

import { correctCore } from './core.js';
import { correctGpio, powerOn } from './gpio.js';
import { loadImage } from './image.js';
import { installRom, ROM_TRAP } from './rom.js';
import { installRosc } from './rosc.js';

/** Nanoseconds per core cycle: the Pico's 125 MHz system clock, as the firmware configures it. */
export const CYCLE_NS = 8;
/** Offsets in the SIO block. */
const GPIO_IN = 0x004;
/** IO_BANK0 base and its raw interrupt (edge latch) registers. */
const IO_BANK0 = 0x40014000;
const INTR0 = 0x0f0;
const INTR3 = 0x0fc;

/** A fault of the emulated firmware (it broke, or ran into something the emulator does not have). */
export class BoardFault extends Error {}

/** Running statistics of one measured entry point: calls, cycles and instructions, sum and worst. */
export class Cost {
  constructor() {
    this.calls = 0;
    this.cycles = 0;
    this.maxCycles = 0;
    this.instructions = 0;
    this.maxInstructions = 0;
  }

  add(cycles, instructions) {
    this.calls++;
    this.cycles += cycles;
    this.instructions += instructions;
    this.maxCycles = Math.max(this.maxCycles, cycles);
    this.maxInstructions = Math.max(this.maxInstructions, instructions);
  }

  /** Adds the calls of `other`. */
  merge(other) {
    this.calls += other.calls;
    this.cycles += other.cycles;
    this.instructions += other.instructions;
    this.maxCycles = Math.max(this.maxCycles, other.maxCycles);
    this.maxInstructions = Math.max(this.maxInstructions, other.maxInstructions);
  }

  toJSON() {
    const avg = (x) => (this.calls === 0 ? 0 : Math.round((10 * x) / this.calls) / 10);
    return {
      calls: this.calls,
      avg_cycles: avg(this.cycles),
      max_cycles: this.maxCycles,
      avg_instructions: avg(this.instructions),
      max_instructions: this.maxInstructions,
    };
  }
}

/**
 * The emulated board. `image`: `{ elf, status, probes: { apply, decide }, rtt }` (addresses found by
 * the harness); `bits`: the ROSC's bit source; `events`: callbacks `{ output(pin, level), sample(), ack() }` (ack: the
 * firmware cleared edge latches).
 */
export class Board {
  constructor(image, pins, bits, events) {
    this.image = image;
    this.events = events;
    const mcu = new RP2040();
    this.mcu = mcu;
    this.warnings = [];
    mcu.logger = {
      debug() {},
      info() {},
      warn: (component, message) => this.warnings.push(`${component}: ${message}`),
      error: (component, message) => {
        throw new BoardFault(`emulator: ${component}: ${message}`);
      },
    };
    correctCore(mcu);
    correctGpio(mcu);
    installRom(mcu);
    installRosc(mcu, bits);
    loadImage(mcu, image.elf);
    mcu.onBreak = (code) => {
      const pc = (mcu.core.PC - mcu.core.breakRewind) >>> 0;
      const why = pc === 0 && code === ROM_TRAP ? 'called a ROM routine the stand-in does not have' : `hit BKPT/UDF #${code}`;
      throw new BoardFault(`firmware ${why} at 0x${pc.toString(16)} (a panic or a fault: see the RTT log)`);
    };
    powerOn(mcu, pins.restLevels());
    for (const pin of pins.outputPins.keys()) {
      let last = false;
      mcu.gpio[pin].addListener((state) => {
        const level = state === GPIOPinState.High;
        if (level !== last) {
          last = level;
          events.output(pin, level);
        }
      });
    }
    // Interrupt acknowledgements: a write to IO_BANK0's INTR registers clears edge latches.
    const io = mcu.peripherals[(IO_BANK0 >>> 14) << 2];
    const ioWrite = io.writeUint32.bind(io);
    io.writeUint32 = (offset, value) => {
      ioWrite(offset, value);
      if (offset >= INTR0 && offset <= INTR3) events.ack();
    };
    const { sio } = mcu;
    const read = sio.readUint32.bind(sio);
    sio.readUint32 = (offset) => {
      if (offset === GPIO_IN) events.sample();
      return read(offset);
    };
    // Decisions are told apart after the fact: the firmware publishes its counters once per loop turn,
    // after the turn's one `decide`, so the next entry (or `settleCosts`) sees whether it fired a command,
    // was dropped by the guard, or found nothing to do.
    this.costs = { apply: new Cost(), decision: new Cost(), idle: new Cost(), redecided: new Cost() };
    this.measuring = null;
    this.pendingDecide = null;
    this.stopping = false;
  }

  /** Files the last measured `decide` under what it did, from the counters published since. */
  settleCosts() {
    const d = this.pendingDecide;
    if (d === null) return;
    this.pendingDecide = null;
    const [, commands, , , redecisions] = this.status().counters;
    const cost = commands !== d.commands ? this.costs.decision : redecisions !== d.redecisions ? this.costs.redecided : this.costs.idle;
    cost.add(d.cycles, d.instructions);
  }

  /** Emulated nanoseconds since this board was created. */
  get nanos() {
    return this.mcu.clock.nanosCounter;
  }

  /** Whether the core sleeps in `wfi`. */
  get sleeping() {
    return this.mcu.core.waiting;
  }

  /** Whether the core is inside the runtime's `decide`. */
  get deciding() {
    return this.measuring !== null && this.measuring.decide;
  }

  /** Ends the current `run` once the core is back in thread mode (the interrupt handler that read the
   * inputs has finished): the harness has something to do. */
  stop() {
    this.stopping = true;
  }

  /** Drives input `pin` to `level`. */
  setInput(pin, level) {
    this.mcu.gpio[pin].setInputValue(level);
  }

  /** The edge latch bits (IO_BANK0 INTR: 4 edge-high, 8… see `pins`) still set on `pin`. */
  latched(pin) {
    return this.mcu.gpio[pin].irqStatus;
  }

  /** `{ counters: [6 × u32], flags }` from the firmware's `SCT_STATUS` block. */
  status() {
    const view = this.mcu.sramView;
    const at = this.image.status - 0x20000000;
    const counters = [];
    for (let i = 0; i < 6; i++) counters.push(view.getUint32(at + 4 * i, true));
    return { counters, flags: view.getUint32(at + 24, true) };
  }

  /** Moves the bytes the firmware wrote to its RTT up-channel 0 (defmt frames) out; returns them. */
  drainRtt() {
    const at = this.image.rtt;
    if (at === undefined) return new Uint8Array(0);
    const view = this.mcu.sramView;
    const ram = (a) => a - 0x20000000;
    const up = ram(at) + 24; // after the 16-byte id and the two buffer counts
    const buffer = view.getUint32(up + 4, true);
    const size = view.getUint32(up + 8, true);
    const write = view.getUint32(up + 12, true);
    const readAt = view.getUint32(up + 16, true);
    if (size === 0 || write >= size || readAt >= size || write === readAt) return new Uint8Array(0);
    const start = ram(buffer);
    const bytes =
      write > readAt
        ? this.mcu.sram.slice(start + readAt, start + write)
        : Buffer.concat([this.mcu.sram.slice(start + readAt, start + size), this.mcu.sram.slice(start, start + write)]);
    view.setUint32(up + 16, write, true);
    return bytes;
  }

  /**
   * Runs until emulated time reaches `until` (ns on this board's clock), the core falls asleep
   * (`'sleep'`, so the caller can look at the firmware's state), `stop` was called and the core is
   * in thread mode (`'stop'`), or
   * `budget` instructions have run.
   */
  run(until, budget) {
    const { core, clock } = this.mcu;
    const regs = core.registers;
    const { apply, decide } = this.image.probes;
    for (let n = 0; n < budget; n++) {
      const now = clock.nanosCounter;
      if (now >= until) return 'deadline';
      if (core.waiting) {
        const alarm = clock.nextAlarm ? clock.nextAlarm.nanos - now : Infinity;
        const step = Math.min(alarm, until - now);
        if (step === Infinity) throw new BoardFault('the core sleeps with no timer armed: nothing can wake it');
        clock.tick(step);
        continue;
      }
      const pc = regs[15];
      const m = this.measuring;
      if (m === null && (pc === apply || pc === decide) && core.IPSR === 0) {
        if (pc === decide) this.settleCosts();
        const [, commands, , , redecisions] = pc === decide ? this.status().counters : [];
        this.measuring = {
          decide: pc === decide,
          commands,
          redecisions,
          back: regs[14] & ~1,
          sp: regs[13],
          cycles: 0,
          instructions: 0,
        };
      }
      const thread = core.IPSR === 0;
      const before = core.cycles;
      core.executeInstruction();
      const cycles = core.cycles - before;
      clock.tick(cycles * CYCLE_NS);
      const cur = this.measuring;
      if (cur !== null && thread && core.IPSR === 0) {
        cur.cycles += cycles;
        cur.instructions++;
        if (regs[15] === cur.back && regs[13] === cur.sp) {
          if (cur.decide) this.pendingDecide = cur;
          else this.costs.apply.add(cur.cycles, cur.instructions);
          this.measuring = null;
        }
      }
      if (core.waiting) return 'sleep';
      if (this.stopping && core.IPSR === 0) {
        this.stopping = false;
        return 'stop';
      }
    }
    return 'budget';
  }
}
