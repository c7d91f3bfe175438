//! The Pico's USB link build (RP2040, rp2040-hal): the supervisors of `cell-pico` driven by the virtual
//! plant over the Pico's own USB port — a CDC-ACM serial device (`usb-device` + `usbd-serial`), which
//! the host sees as `/dev/ttyACM0` — so `codegen plant --connect serial:/dev/ttyACM0` needs no adapter.
//! The byte protocol is the QEMU firmware's (`firmware::link`), the runtime and event loop the same as
//! the UART link build's (`cell_pico_link.rs`; what they share is `link_app.rs`).
//!
//! USB interrupt → device poll → received bytes through the HOLD/GO filter into the input buffer, as
//! much as it has room for: the rest stays in the USB stack, which refuses (NAKs) the host's next packets
//! until the loop has drained the buffer — flow control a UART lacks. The decision loop runs in `idle`
//! and writes its commands back over USB. It boots on hold and seeds its choices from the manifest, as
//! under QEMU; EXIT, which a board cannot obey, leaves it idle. It answers TABLES with the digest of the
//! Cortex-M0+'s tables (`tables::m0plus::DIGEST`). On the emulated RP2040: the harness's `--usb` mode
//! (rp2040js's USB controller and its CDC host).
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

mod link_app;
mod link_loop;

use core::sync::atomic::AtomicBool;

use firmware::event_loop::{Note, Port};
use rp2040_hal::usb::UsbBus;
use usb_device::device::UsbDevice;
use usb_device::prelude::{UsbDeviceState, UsbError};
use usbd_serial::SerialPort;

/// The USB device and its CDC-ACM serial class, which the interrupt and the decision loop share.
pub struct Usb {
    device: UsbDevice<'static, UsbBus>,
    serial: SerialPort<'static, UsbBus>,
}

impl Usb {
    /// Services the bus (enumeration, transfers done); true when the serial class may have data.
    fn poll(&mut self) -> bool {
        self.device.poll(&mut [&mut self.serial])
    }

    /// Writes `byte`, servicing the bus until the serial class's buffer takes it; dropped while no host
    /// has configured the device (a READY at boot, before enumeration: the host's RESET asks again).
    fn send(&mut self, byte: u8) {
        while self.device.state() == UsbDeviceState::Configured {
            match self.serial.write(&[byte]) {
                Ok(_) => return,
                Err(UsbError::WouldBlock) => {
                    self.poll();
                }
                Err(_) => return,
            }
        }
    }
}

/// Set when the interrupt left bytes in the USB stack for want of room in the input buffer: the loop
/// raises the interrupt again once it has drained the buffer.
static STARVED: AtomicBool = AtomicBool::new(false);

/// Turns the USB controller's buffer-status interrupt on or off. Off while the input buffer is full:
/// a received packet the interrupt cannot take stays in the endpoint with its status bit set, and that
/// bit holds the interrupt line up, so the interrupt would run again the moment it returned and the
/// decision loop, which drains the buffer, would never run. Setup and bus-reset interrupts stay on.
fn buffer_interrupt(on: bool) {
    // SAFETY: INTE is written only here — by the interrupt (the highest priority that touches it) and
    // by the loop inside a critical section — and its other bits, which rp2040-hal set at `enable`,
    // are kept by the read-modify-write.
    let regs = unsafe { &*rp2040_hal::pac::USBCTRL_REGS::ptr() };
    regs.inte().modify(|_, w| w.buff_status().bit(on));
}

/// The USB serial port, behind the RTIC lock `L` the loop shares with the interrupt, as the event
/// loop's port: each byte sent holds the lock while it is written.
struct UsbPort<'a, L>(&'a mut L);

impl<L: rtic::Mutex<T = Usb>> Port for UsbPort<'_, L> {
    fn send(&mut self, byte: u8) {
        self.0.lock(|usb| usb.send(byte));
    }

    fn note(&mut self, note: Note) {
        link_loop::log_note(note);
    }
}

/// USB's identity: pid.codes' shared VID/PID for CDC-ACM test devices (`16c0:27dd`).
const VID_PID: (u16, u16) = (0x16c0, 0x27dd);

#[rtic::app(device = rp2040_hal::pac)]
mod app {
    use super::link_app::Rt;
    use super::link_loop::{self, halt};
    use super::{buffer_interrupt, tables, Usb, UsbPort, STARVED, VID_PID};
    use core::sync::atomic::Ordering;
    use firmware::input_queue::{InputConsumer, InputProducer, InputQueue};
    use firmware::link::READY;
    use rp2040_hal::pac::Interrupt;
    use rp2040_hal::usb::UsbBus;
    use usb_device::bus::UsbBusAllocator;
    use usb_device::prelude::{StringDescriptors, UsbDeviceBuilder, UsbVidPid};
    use usbd_serial::SerialPort;

    #[shared]
    struct Shared {
        usb: Usb,
    }

    #[local]
    struct Local {
        producer: InputProducer<'static>,
        consumer: InputConsumer<'static>,
        runtime: Rt,
    }

    #[init(local = [
        queue: InputQueue<{ tables::INPUT_SLOTS }> = InputQueue::new(),
        bus: Option<UsbBusAllocator<UsbBus>> = None,
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut pac = cx.device;
        let clocks = super::link_app::clocks(
            pac.XOSC,
            pac.CLOCKS,
            pac.PLL_SYS,
            pac.PLL_USB,
            &mut pac.RESETS,
            pac.WATCHDOG,
        );
        let bus: &'static UsbBusAllocator<UsbBus> = cx.local.bus.insert(UsbBusAllocator::new(UsbBus::new(
            pac.USBCTRL_REGS,
            pac.USBCTRL_DPRAM,
            clocks.usb_clock,
            true,
            &mut pac.RESETS,
        )));
        let serial = SerialPort::new(bus);
        let strings = StringDescriptors::default()
            .manufacturer("sct-codegen")
            .product(tables::NAME)
            .serial_number("link");
        // Control packets of 64 bytes, the most full speed allows: a configuration descriptor's first
        // 9 bytes in one packet (rp2040js's CDC host reads them so).
        let Ok(builder) = UsbDeviceBuilder::new(bus, UsbVidPid(VID_PID.0, VID_PID.1))
            .strings(&[strings])
            .and_then(|b| b.max_packet_size_0(64))
        else {
            halt("usb descriptors")
        };
        let device = builder.device_class(usbd_serial::USB_CLASS_CDC).build();
        let mut usb = Usb { device, serial };

        let (producer, consumer) = cx.local.queue.split();
        let runtime = super::link_app::runtime("USB");
        usb.send(READY);
        (Shared { usb }, Local { producer, consumer, runtime })
    }

    /// Services the bus and moves received bytes into the input buffer (HOLD and GO act here), as many
    /// as it has room for; what is left waits in the USB stack (STARVED, the buffer-status interrupt
    /// off) until the loop drained it.
    #[task(binds = USBCTRL_IRQ, shared = [usb], local = [producer])]
    fn usb(mut cx: usb::Context) {
        let q = cx.local.producer;
        cx.shared.usb.lock(|usb| {
            usb.poll();
            // `None`: nothing more (WouldBlock), or not configured.
            let full = link_loop::receive_all(q, || {
                let mut byte = [0u8];
                matches!(usb.serial.read(&mut byte), Ok(1)).then_some(byte[0])
            });
            if full {
                STARVED.store(true, Ordering::Relaxed);
                buffer_interrupt(false);
            }
        });
    }

    /// The decision loop; raises the interrupt again once it has drained what the interrupt left in
    /// the USB stack (STARVED); sleeps in `wfi` while there is nothing to do.
    #[idle(shared = [usb], local = [consumer, runtime])]
    fn idle(mut cx: idle::Context) -> ! {
        let (rx, rt) = (cx.local.consumer, cx.local.runtime);
        link_loop::serve(rt, rx, &mut UsbPort(&mut cx.shared.usb), tables::m0plus::DIGEST, |rx| {
            if rx.is_empty() && STARVED.load(Ordering::Relaxed) {
                STARVED.store(false, Ordering::Relaxed);
                cortex_m::interrupt::free(|_| buffer_interrupt(true));
                // Bytes left in the serial class's own buffer raise no interrupt of their own.
                rtic::pend(Interrupt::USBCTRL_IRQ);
            }
        })
    }
}
