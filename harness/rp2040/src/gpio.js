// Corrections to rp2040js's GPIO, where it departs from the silicon in a way the firmware can see. Like
// `core.js`, each one is pinned by a test on the emulated chip (`test/gpio.test.js`), which also checks
// that rp2040js still needs it.
//
// Edge latches. On silicon an input's EDGE_HIGH / EDGE_LOW bit in IO_BANK0's INTR latches a *transition*
// of the level the pad passes in (the pin's level while its input is enabled, else low), whether or not
// that interrupt is enabled; it stays until written with a 1, and PROC0_INTS is INTR & PROC0_INTE.
// rp2040js 1.4.1 has the write-1-to-clear and the INTS, but its `GPIOPin.setInputValue` sets EDGE_LOW
// (or EDGE_HIGH) on every call, whether the level changed or not, and its pads call it again whenever a
// write changes a pad's input enable. So the harness putting a pin at its resting level, and the
// firmware enabling the pad's input, each latched a falling edge on every input pin that rests low: a
// firmware that enables its falling-edge interrupts then took an event that no pin made. The correction
// remembers each pin's level and latches an edge only when it changes.
//
// Pads at reset. The datasheet's reset value of PADS_BANK0 GPIOn is 0x56 (input enabled, 4 mA, pull-down,
// Schmitt trigger; rp2040-pac's RESET_VALUE); rp2040js starts them at 0x36, input disabled, so that a pin
// resting high read low until the firmware turned its input on. The pads start at 0x56. (rp2040-hal turns
// an input pad off and on again while it sets the pin up: a pin resting high then latches both edges, on
// silicon as here.)
//
// Power-on. INTR resets to 0, and the firmware resets IO_BANK0 before it uses the pins: the levels the
// pins have from power-on are no edges ([`powerOn`]). An edge that does latch while the firmware sets its
// pins up (a line settling) is the firmware's to clear before it enables the interrupt, as on silicon.

/** IO_BANK0 INTR latch bits of one pin. */
export const EDGE_LOW = 1 << 2;
export const EDGE_HIGH = 1 << 3;
const EDGES = EDGE_LOW | EDGE_HIGH;

/** PADS_BANK0 GPIOn at reset (RP2040 datasheet, PADS_BANK0 registers). */
export const PAD_RESET = 0x56;

/** The level pin `pin` passes in: its input, as its pad lets it through. */
const levelIn = (pin) => pin.rawInputValue && pin.inputEnable;

/** Makes `mcu`'s bank-0 pins latch edges on a change of level only, their pads as at reset. */
export function correctGpio(mcu) {
  for (const pin of mcu.gpio) {
    pin.padValue = PAD_RESET;
    let level = levelIn(pin);
    const set = pin.setInputValue.bind(pin);
    pin.setInputValue = (value) => {
      const latched = pin.irqStatus & EDGES;
      set(value);
      const now = levelIn(pin);
      const changed = now !== level;
      level = now;
      if (changed) return;
      const irq = pin.irqValue;
      pin.irqStatus = (pin.irqStatus & ~EDGES) | latched;
      if (pin.irqValue !== irq) mcu.updateIOInterrupt();
    };
  }
}

/** Puts the pins of `levels` (`[pin, level]` pairs) at their level from power-on: no edge latched. */
export function powerOn(mcu, levels) {
  for (const [pin, level] of levels) {
    const gpio = mcu.gpio[pin];
    gpio.setInputValue(level);
    gpio.irqStatus &= ~EDGES;
  }
  mcu.updateIOInterrupt();
}
