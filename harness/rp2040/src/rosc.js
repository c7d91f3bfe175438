// The ring oscillator's random bit, which rp2040js does not model (its ROSC reads as 0xFFFFFFFF, so
// RANDOMBIT would always be 1). The harness puts this peripheral at the ROSC's address instead: RANDOMBIT
// answers from a seeded xorshift32, so a run is repeatable for a given seed; every other ROSC register
// reads as the reset value the firmware expects of a running oscillator (STATUS: stable and enabled) and
// ignores writes. Reads of RANDOMBIT are counted for the harness's report.

import { BasePeripheral } from 'rp2040js';

/** ROSC base address. */
export const ROSC_BASE = 0x40060000;
const CTRL = 0x00;
const STATUS = 0x18;
const RANDOMBIT = 0x1c;

/** A seeded xorshift32 stream of bits. */
export class BitSource {
  constructor(seed) {
    // xorshift32 has one fixed point, 0: fold the seed into a non-zero state.
    this.state = (Number(BigInt.asUintN(32, BigInt(seed))) ^ 0x9e3779b9) >>> 0 || 1;
    this.reads = 0;
  }

  /** The next bit. */
  bit() {
    let x = this.state;
    x ^= x << 13;
    x >>>= 0;
    x ^= x >>> 17;
    x ^= x << 5;
    this.state = x >>> 0;
    this.reads++;
    return this.state & 1;
  }
}

/** The ROSC, answering RANDOMBIT from `bits`. */
export class SeededRosc extends BasePeripheral {
  constructor(mcu, bits) {
    super(mcu, 'ROSC');
    this.bits = bits;
  }

  readUint32(offset) {
    switch (offset) {
      case RANDOMBIT:
        return this.bits.bit();
      case STATUS:
        return (1 << 31) | (1 << 12); // STABLE | ENABLED
      case CTRL:
        return 0xfab << 12; // ENABLE
      default:
        return 0;
    }
  }

  writeUint32() {}
}

/** Puts a ROSC answering from `bits` into `mcu`. */
export function installRosc(mcu, bits) {
  mcu.peripherals[(ROSC_BASE >>> 14) << 2] = new SeededRosc(mcu, bits);
}
