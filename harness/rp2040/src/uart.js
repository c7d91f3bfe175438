// The harness's `--uart` mode: the Pico's link build (`cargo pico-link-build`, `cell-pico-link`) on the
// emulated RP2040, its UART0 wired to the host's connection byte for byte — no pins, no protocol spoken
// on the firmware's behalf: the firmware itself answers RESET, STATUS, SYNC and STEP, as under QEMU. The
// host's bytes enter UART0's receive FIFO (32 bytes) only while it has room, as a line with hardware flow
// control would deliver them; the bytes the firmware writes to UART0 go to the host at once.
//
// Time is the board's emulated time, advanced only while the core runs: a core asleep in `wfi` with no
// timer armed waits for the host's next byte (its receive interrupt wakes it).

import { Board } from './board.js';

/** Instructions per call of `step`, so the host's bytes are read often. */
export const STEP_BUDGET = 20_000;
/** Depth of the RP2040 UART's receive FIFO. */
const RX_FIFO = 32;

/** No pins: the link build takes none but UART0's. */
const NO_PINS = { restLevels: () => [], outputPins: new Map() };

/**
 * `image`: the checked ELF with its addresses (`image.js`); `bits`: the ROSC's bit source;
 * `send(bytes)`: to the host; `log(bytes)`: RTT bytes, or null.
 */
export class UartHarness {
  constructor(image, bits, send, log) {
    this.bits = bits;
    this.log = log;
    this.sent = false;
    this.inbox = [];
    this.received = 0;
    this.transmitted = 0;
    this.board = new Board(image, NO_PINS, bits, { output() {}, sample() {}, ack() {} });
    this.uart = this.board.mcu.uart[0];
    this.uart.onByte = (byte) => {
      this.transmitted++;
      this.sent = true;
      send(Uint8Array.of(byte));
    };
  }

  /** Bytes from the host, fed to UART0 by `step` as its FIFO has room. */
  receive(bytes) {
    for (const b of bytes) this.inbox.push(b);
  }

  /** Whether the firmware wrote bytes since the last call (the host should hear of them at once). */
  takeSent() {
    const s = this.sent;
    this.sent = false;
    return s;
  }

  /** A board never ends a run by itself: the host hangs up. */
  get finished() {
    return false;
  }

  /** Feeds what the receive FIFO takes, then runs the core until it sleeps or its budget is spent. */
  step() {
    let fed = 0;
    while (fed < this.inbox.length && this.uart.rxFIFO.itemCount < RX_FIFO) this.uart.feedByte(this.inbox[fed++]);
    if (fed > 0) this.inbox.splice(0, fed);
    this.received += fed;
    if (!this.board.sleeping) this.board.run(Infinity, STEP_BUDGET);
    this.drainLog();
  }

  /** Passes the firmware's RTT bytes to the log, if there is one. */
  drainLog() {
    if (this.log) {
      const bytes = this.board.drainRtt();
      if (bytes.length > 0) this.log(bytes);
    }
  }

  /** Whether the core sleeps with nothing left to feed it: the harness may wait for the host. */
  get idle() {
    return this.board.sleeping && this.inbox.length === 0;
  }

  /** The run's figures (JSON): bytes each way, emulated time, the cost of the runtime's entry points. */
  report() {
    const b = this.board;
    b.settleCosts();
    const c = b.costs;
    return JSON.parse(
      JSON.stringify({
        target: 'rp2040-uart',
        bytes_in: this.received,
        bytes_out: this.transmitted,
        emulated_ms: Math.round(b.nanos / 1e6),
        cycles: b.mcu.core.cycles,
        rosc_bits: this.bits.reads,
        cost: { apply: c.apply, decision: c.decision, idle_decision: c.idle, redecision: c.redecided },
      }),
    );
  }
}
