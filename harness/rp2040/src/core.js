// Corrections to rp2040js's Cortex-M0+ core, where it departs from the architecture in a way the firmware
// can see. Each one is found by a firmware that ran differently here than the architecture says it must,
// and is pinned by `test/core.test.js` on the emulated core itself.
//
// Exception entry. The architecture branches to the vector with its Thumb bit cleared (ARMv6-M
// `ExceptionTaken`: `BranchTo(tmp AND 0xFFFFFFFE)`). rp2040js 1.4.1 loads the vector into PC as it is,
// bit 0 set, and the handler's straight-line code and branches keep it. Most instructions never see it —
// it masks PC where it fetches and where it takes a literal — but `ADD Rd, PC` and `MOV Rd, PC` read PC
// plus 4 *with* the bit: one too many. That is the first half of the case-table idiom LLVM emits for a
// dense `match` on Thumb-1 (`add r0, pc; ldrb r0, [r0, #4]; lsls r0, #1; add pc, r0`), so a handler built
// with `opt-level = 3` read the next entry of its table: the Pico's edge interrupt pushed the event of the
// next input pin, and the closed loop saw hundreds of violations no silicon would have.
//
// A peripheral interrupt pended by software. On the architecture the NVIC's pending state is a latch:
// a write to NVIC_ISPR sets it, taking the exception clears it, and the peripheral's line sets it again
// for as long as the line is asserted (ARMv6-M B3.4: an interrupt whose signal is still high when its
// handler returns is pending again). rp2040js 1.4.1 keeps one bit per peripheral interrupt that mirrors
// the line and clears it only when the peripheral drops the line, so an ISPR write to a peripheral whose
// line is already low pends it for good: the handler runs, returns and runs again, and thread mode never
// gets past its next instruction. RTIC's `rtic::pend` of a bound interrupt is such a write; the Pico's USB
// link build makes it when bytes wait in its serial class's buffer, and the emulated firmware stopped
// answering (the realtime closed loops' "no STATUS answer") where silicon would have gone on.

/** Interrupts 0..25 are the RP2040's peripherals' (RP2040 datasheet, 2.3.2); above are software's. */
const PERIPHERAL_IRQS = 26;

/** Makes `mcu`'s core enter exception handlers at the vector's address with the Thumb bit cleared, and
 * clear a peripheral interrupt's pending state as it takes the exception unless the line is still up. */
export function correctCore(mcu) {
  const { core } = mcu;
  /** The peripherals' interrupt lines, as they last set them. */
  let lines = 0;
  const setInterrupt = core.setInterrupt.bind(core);
  core.setInterrupt = (irq, value) => {
    lines = value ? lines | (1 << irq) : lines & ~(1 << irq);
    setInterrupt(irq, value);
  };
  const enter = core.exceptionEntry.bind(core);
  core.exceptionEntry = (exceptionNumber) => {
    enter(exceptionNumber);
    core.PC = core.PC & ~1;
    const irq = exceptionNumber - 16;
    if (irq >= 0 && irq < PERIPHERAL_IRQS && !(lines & (1 << irq))) core.pendingInterrupts &= ~(1 << irq);
  };
}
