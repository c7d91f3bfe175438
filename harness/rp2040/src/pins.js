// The board's pin map as the plant sees it: which edges to make on the input pins for an uncontrollable
// event, and which controllable event a change of an output pin shows. Pure logic over times in
// nanoseconds; `harness.js` applies it to the emulated pins.
//
// The map is the JSON `codegen` writes from the manifest's `[board]` section (README of this directory):
//   { "board": "pico", "sampling": "interrupt" | "timer", "sample_period_us": N | null,
//     "inputs":  [{ "event": id, "name": "s_c1", "pin": 2, "edge": "rising", "pull": "down" }, …],
//     "outputs": [{ "event": id, "name": "e1_lig", "pin": 16, "action": "set" | "clear" | "pulse",
//                   "pulse_ms": N | null }, …] }
//
// Inputs. A pin whose only input is one `rising` (or `falling`) event is a *pulse* pin, like a sensor
// that pulses when something passes: it rests low (high), and each event is a pulse of the configured
// width. Any other input pin is a *level* pin: its events move the level (`rising` to high, `falling` to
// low, `both` toggles) and it rests at its pull's level. A pin makes its next edge no earlier than one
// pulse width after its previous one (a real sensor cannot pulse faster either; in timer sampling a
// shorter level may fall between two samples): such an edge is *deferred*, and counted. An event mapped
// to several inputs drives the first. An event a level pin cannot show (it asks for the level the pin
// already has) is *impossible* and dropped, counted.
//
// Outputs. A rising edge of an output pin is its `set` or `pulse` event, a falling edge its `clear`
// event (a pulse's end is no event). A map where
// one edge of a pin could be two events, or a pulse's end could be a `clear`, is refused: the plant could
// not tell them apart.

/** A pin map the harness cannot drive. */
export class PinMapError extends Error {}

const US = 1_000;

/** The pin map, checked. */
export class PinMap {
  /**
   * `map`: the parsed JSON; `inputPulseNs`: width of an input pulse (and the least time between two
   * edges of one input pin).
   */
  constructor(map, inputPulseNs) {
    const fail = (what) => {
      throw new PinMapError(`pin map: ${what}`);
    };
    if (!map || typeof map !== 'object') fail('not a JSON object');
    const { sampling, inputs = [], outputs = [] } = map;
    if (sampling !== 'interrupt' && sampling !== 'timer') fail(`sampling '${sampling}' (interrupt or timer)`);
    const period = map.sample_period_us;
    if (sampling === 'timer' && !(Number.isInteger(period) && period > 0)) fail('timer sampling needs sample_period_us > 0');
    this.sampling = sampling;
    this.samplePeriodNs = sampling === 'timer' ? period * US : 0;
    this.inputPulseNs = inputPulseNs;
    const checkPin = (p) => {
      if (!Number.isInteger(p) || p < 0 || p > 29) fail(`pin ${p} is not a GPIO of the RP2040 (0–29)`);
      return p;
    };
    const checkEvent = (e) => {
      if (!Number.isInteger(e) || e < 0 || e > 0xef) fail(`event id ${e} out of range`);
      return e;
    };

    /** Per input pin: { pin, kind: 'pulse' | 'level', rest, level, freeAt }. */
    this.inputPins = new Map();
    /** Per event: { pin, edge, order }, the first input mapped to it. */
    this.inputOf = new Map();
    for (const [index, i] of inputs.entries()) {
      const pin = checkPin(i.pin);
      const event = checkEvent(i.event);
      if (!['rising', 'falling', 'both'].includes(i.edge)) fail(`input ${i.name}: edge '${i.edge}'`);
      if (!['floating', 'up', 'down'].includes(i.pull)) fail(`input ${i.name}: pull '${i.pull}'`);
      // The order the firmware takes edges read at once in: the table's with timer sampling
      // (`Board::changes`), pin by pin with edge interrupts (the handler scans the pins in ascending order).
      const order = sampling === 'timer' ? index : pin * inputs.length + index;
      if (!this.inputOf.has(event)) this.inputOf.set(event, { pin, edge: i.edge, name: i.name, order });
      const on = inputs.filter((j) => j.pin === pin);
      const kind = on.length === 1 && i.edge !== 'both' ? 'pulse' : 'level';
      const rest = kind === 'pulse' ? i.edge === 'falling' : i.pull === 'up';
      this.inputPins.set(pin, { pin, kind, rest, level: rest, freeAt: 0 });
    }

    /** Per output pin: { rise: event | undefined, fall: event | undefined, pulse: bool }. */
    this.outputPins = new Map();
    for (const o of outputs) {
      const pin = checkPin(o.pin);
      const event = checkEvent(o.event);
      if (this.inputPins.has(pin)) fail(`pin ${pin} is both an input and an output`);
      const p = this.outputPins.get(pin) ?? { pin, rise: undefined, fall: undefined, pulse: false, names: {} };
      const edge = { set: 'rise', pulse: 'rise', clear: 'fall' }[o.action];
      if (!edge) fail(`output ${o.name}: action '${o.action}'`);
      if (o.action === 'pulse' && !(Number.isInteger(o.pulse_ms) && o.pulse_ms > 0)) fail(`output ${o.name}: pulse_ms`);
      if (p[edge] !== undefined && p[edge] !== event) {
        fail(`pin ${pin}: a ${edge === 'rise' ? 'rising' : 'falling'} edge would be both ${p.names[edge]} and ${o.name}`);
      }
      p[edge] = event;
      p.names[edge] = o.name;
      p.pulse ||= o.action === 'pulse';
      if (p.pulse && p.fall !== undefined) fail(`pin ${pin}: the end of a pulse would look like ${p.names.fall}`);
      this.outputPins.set(pin, p);
    }
  }

  /** The level each input pin rests at, as [pin, level] pairs. */
  restLevels() {
    return [...this.inputPins.values()].map((p) => [p.pin, p.rest]);
  }

  /** Forgets every edge made: the pins rest again (after a reset of the board). */
  rest() {
    for (const p of this.inputPins.values()) {
      p.level = p.rest;
      p.freeAt = 0;
    }
  }

  /** Where `event` comes among edges the firmware reads at once (-1 for an unmapped event). */
  orderOf(event) {
    return this.inputOf.get(event)?.order ?? -1;
  }

  /** When the input pin of `event` may change next (0 for an unmapped event). */
  readyAt(event) {
    const input = this.inputOf.get(event);
    return input ? this.inputPins.get(input.pin).freeAt : 0;
  }

  /**
   * The edges that show uncontrollable event `event` at time `now`: `{ edges: [{ at, pin, level,
   * event }], deferred, problem }`. `event` is set on the edge that makes the event (not on a pulse's
   * return). `problem` is 'unmapped' (no input pin) or 'impossible' (a level pin already at the level)
   * with no edges.
   */
  edgesFor(event, now) {
    const input = this.inputOf.get(event);
    if (!input) return { edges: [], deferred: false, problem: 'unmapped' };
    const p = this.inputPins.get(input.pin);
    const at = Math.max(now, p.freeAt);
    const width = this.inputPulseNs;
    if (p.kind === 'pulse') {
      p.freeAt = at + 2 * width;
      return {
        edges: [
          { at, pin: p.pin, level: !p.rest, event },
          { at: at + width, pin: p.pin, level: p.rest, event: undefined },
        ],
        deferred: at > now,
        problem: undefined,
      };
    }
    const target = input.edge === 'both' ? !p.level : input.edge === 'rising';
    if (target === p.level) return { edges: [], deferred: false, problem: 'impossible' };
    p.level = target;
    p.freeAt = at + width;
    return { edges: [{ at, pin: p.pin, level: target, event }], deferred: at > now, problem: undefined };
  }

  /** The controllable event an output pin's new `level` shows, if any. */
  commandFor(pin, level) {
    const p = this.outputPins.get(pin);
    if (!p) return undefined;
    return level ? p.rise : p.fall;
  }

  /** Whether driving output `pin` high is a command (its rising edge is an event). */
  risesToCommand(pin) {
    return this.outputPins.get(pin)?.rise !== undefined;
  }
}

/** The default input pulse width: one and a half sampling periods in timer mode (a level that long is
 * sampled at least once, whatever the jitter of the sampling tick), 100 µs with edge interrupts (which
 * latch any edge). The firmware samples on a 1 ms tick, so never more often than every millisecond. */
export function defaultInputPulseNs(map) {
  return map.sampling === 'timer' ? 1.5 * Math.max(map.sample_period_us, 1000) * US : 100 * US;
}
