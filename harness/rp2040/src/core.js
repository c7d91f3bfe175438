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

/** Makes `mcu`'s core enter exception handlers at the vector's address with the Thumb bit cleared. */
export function correctCore(mcu) {
  const { core } = mcu;
  const enter = core.exceptionEntry.bind(core);
  core.exceptionEntry = (exceptionNumber) => {
    enter(exceptionNumber);
    core.PC = core.PC & ~1;
  };
}
