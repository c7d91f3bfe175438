//! Stack high-water mark by painting: fill the unused stack with a pattern at boot, later find the lowest
//! word the stack overwrote.
#![deny(clippy::undocumented_unsafe_blocks)]

const PAINT: u32 = 0xAAAA_5555;

extern "C" {
    static mut _stack_end: u32;
    static mut _stack_start: u32;
}

fn bounds() -> (*mut u32, *mut u32) {
    (core::ptr::addr_of_mut!(_stack_end), core::ptr::addr_of_mut!(_stack_start))
}

/// Paints the stack from its lowest address up to 256 bytes below the current frame.
#[inline(never)]
pub fn paint() {
    let here = 0u32;
    let limit = (core::ptr::addr_of!(here) as usize).saturating_sub(256);
    let (mut p, _) = bounds();
    while (p as usize) < limit {
        // SAFETY: `p` lies between the end of static RAM and 256 bytes below the live stack: memory no one
        // else uses yet.
        unsafe { p.write_volatile(PAINT) };
        p = p.wrapping_add(1);
    }
}

/// Bytes of stack ever used since [`paint`].
pub fn high_water() -> usize {
    let (mut p, top) = bounds();
    // SAFETY: reads of the stack region between its linker bounds, word aligned.
    while p < top && unsafe { p.read_volatile() } == PAINT {
        p = p.wrapping_add(1);
    }
    top as usize - p as usize
}
