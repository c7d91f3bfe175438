//! UART0 of the lm3s6965 (an ARM PL011 at `0x4000_C000`): exactly what the link needs, and the two QEMU
//! traps around it (see the embedded notes): a receive loop bounded by the queue's room, with the receive
//! interrupt masked while the queue is full; and only the receive-timeout bit cleared, only when the FIFO
//! is empty (clearing RX in ICR while bytes remain stalls QEMU 7.2's receiver).
#![deny(clippy::undocumented_unsafe_blocks)]

use core::ptr;

const BASE: usize = 0x4000_C000;
const DR: usize = 0x000;
const FR: usize = 0x018;
const LCRH: usize = 0x02C;
const CTL: usize = 0x030;
const IMSC: usize = 0x038;
const ICR: usize = 0x044;

const FR_RXFE: u32 = 1 << 4;
const FR_TXFF: u32 = 1 << 5;
const LCRH_FEN: u32 = 1 << 4;
const LCRH_WLEN8: u32 = 0b11 << 5;
const CTL_ENABLE: u32 = 1 | (1 << 8) | (1 << 9);
/// Receive and receive-timeout interrupts.
const IM_RX: u32 = (1 << 4) | (1 << 6);
const IC_RT: u32 = 1 << 6;

fn read(offset: usize) -> u32 {
    // SAFETY: BASE + offset is a 32-bit register of UART0, mapped on every lm3s6965; reads have no side
    // effect beyond the PL011's own (popping DR), which the callers intend.
    unsafe { ptr::read_volatile((BASE + offset) as *const u32) }
}

fn write(offset: usize, value: u32) {
    // SAFETY: as in `read`; the values written are the PL011 settings documented above.
    unsafe { ptr::write_volatile((BASE + offset) as *mut u32, value) }
}

/// 8N1 with FIFOs, receiver and transmitter on, receive interrupts unmasked.
pub fn init() {
    write(LCRH, LCRH_FEN | LCRH_WLEN8);
    write(CTL, CTL_ENABLE);
    write(IMSC, IM_RX);
}

/// The next received byte, if the FIFO holds one; clears the receive timeout once the FIFO is empty.
pub fn try_read() -> Option<u8> {
    if read(FR) & FR_RXFE != 0 {
        write(ICR, IC_RT);
        return None;
    }
    Some(read(DR) as u8)
}

/// Stops receive interrupts (backpressure: the input queue is full; QEMU holds further bytes back).
pub fn mask_rx() {
    write(IMSC, 0);
}

/// Resumes receive interrupts (the loop drained the input queue).
pub fn unmask_rx() {
    write(IMSC, IM_RX);
}

/// Sends one byte, waiting while the transmit FIFO is full.
pub fn send(byte: u8) {
    while read(FR) & FR_TXFF != 0 {}
    write(DR, u32::from(byte));
}
