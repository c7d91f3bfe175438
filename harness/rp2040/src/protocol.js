// The byte protocol of the firmware link (`firmware/src/link.rs`), as the harness speaks it on the host's
// behalf: one byte per event (0x00–0xEF), and control bytes from 0xF0.

/** Host → board: back to the initial state; answered by READY. */
export const RESET = 0xf0;
/** Host → board: counters request; board → host: the answer's first byte, then six u32 LE. */
export const STATUS = 0xf1;
/** Host → board: end the run. */
export const EXIT = 0xf2;
/** Board → host: ready for events (at boot and after each RESET). */
export const READY = 0xf3;
/** Board → host: the firmware is in the safe state. */
export const SAFE = 0xf4;
/** Host → board: hold the following events back … */
export const HOLD = 0xf5;
/** … until GO, then make them all at one instant. */
export const GO = 0xf6;
/** Highest event id. */
export const MAX_EVENT = 0xef;

/** The STATUS answer for six counters. */
export function statusFrame(counters) {
  const frame = Buffer.alloc(25);
  frame[0] = STATUS;
  counters.forEach((c, i) => frame.writeUInt32LE(c >>> 0, 1 + 4 * i));
  return frame;
}
