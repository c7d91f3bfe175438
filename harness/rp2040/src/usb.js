// The harness's `--usb` mode: the Pico's USB link build (`cargo pico-usb-build`, `cell-pico-usb`) on the
// emulated RP2040, its USB port enumerated by rp2040js's CDC-ACM host model (`USBCDC`) and its serial
// data wired to the host's connection byte for byte. As in `--uart` mode the firmware itself speaks the
// link protocol. The host's bytes go to the device as it arms its OUT endpoint (USB's own flow control:
// a device with no room arms nothing); what the device sends on its IN endpoint goes to the host at once.
//
// Time is the board's emulated time, advanced only while the core runs or an alarm of the emulated USB
// controller is due (a transfer's completion, the bus reset): a core asleep in `wfi` with neither waits
// for the host's next bytes.

import { USBCDC } from 'rp2040js';

import { STEP_BUDGET, UartHarness } from './uart.js';

/** Bytes rp2040js's CDC host queues for the device (its transmit FIFO). */
const CDC_FIFO = 512;

/**
 * The USB link build's board: `UartHarness`'s stepping, log and figures, the link carried by USB. Its
 * UART0 stays unwired (the firmware does not use it).
 */
export class UsbHarness extends UartHarness {
  constructor(image, bits, send, log) {
    super(image, bits, () => {}, log);
    this.connected = false;
    /** An OUT transfer the device armed while the host had nothing to send: `[endpoint, size]`. */
    this.pendingRead = null;
    const usb = this.board.mcu.usbCtrl;
    const cdc = new USBCDC(usb);
    this.cdc = cdc;
    cdc.onDeviceConnected = () => {
      this.connected = true;
    };
    cdc.onSerialData = (bytes) => {
      this.transmitted += bytes.length;
      this.sent = true;
      send(Uint8Array.from(bytes));
    };
    // rp2040js's CDC host answers an armed OUT endpoint at once, with nothing when it has nothing, and
    // forgets one armed before enumeration told it the endpoint's number: hold the transfer until the
    // host's next bytes instead, as a real host's NAK would.
    const read = usb.onEndpointRead;
    this.completeRead = read;
    usb.onEndpointRead = (endpoint, size) => {
      if (endpoint !== 0 && (cdc.outEndpoint < 0 || cdc.txFIFO.itemCount === 0)) this.pendingRead = [endpoint, size];
      else read(endpoint, size);
    };
  }

  /** Feeds what the CDC host's FIFO takes (once the device is configured), then runs the core until it
   * sleeps with no USB alarm due or its budget is spent. */
  step() {
    if (this.connected) {
      const fifo = this.cdc.txFIFO;
      let fed = 0;
      while (fed < this.inbox.length && fifo.itemCount < CDC_FIFO) this.cdc.sendSerialByte(this.inbox[fed++]);
      if (fed > 0) this.inbox.splice(0, fed);
      this.received += fed;
      if (fifo.itemCount > 0 && this.pendingRead !== null && this.pendingRead[0] === this.cdc.outEndpoint) {
        const [endpoint, size] = this.pendingRead;
        this.pendingRead = null;
        this.completeRead(endpoint, size);
      }
    }
    // Asleep, the core runs only to the USB controller's next alarm: it may sleep on after it.
    const clock = this.board.mcu.clock;
    if (!this.board.sleeping) this.board.run(Infinity, STEP_BUDGET);
    else if (this.alarmDue) this.board.run(clock.nextAlarm.nanos, STEP_BUDGET);
    this.drainLog();
  }

  /** Whether an alarm of the emulated chip is set (the USB controller's: a transfer done, a bus reset). */
  get alarmDue() {
    return Boolean(this.board.mcu.clock.nextAlarm);
  }

  /** Whether the core sleeps with nothing due and nothing to feed it: the harness may wait for the host. */
  get idle() {
    return this.board.sleeping && !this.alarmDue && (this.inbox.length === 0 || !this.connected);
  }

  /** The figures of `UartHarness`, named for USB. */
  report() {
    return { ...super.report(), target: 'rp2040-usb' };
  }
}
