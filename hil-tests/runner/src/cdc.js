//! The USB host side of the CDC-ACM link, with the run-time fixes for rp2040js defects 3 and 4 (see
//! shared/reference/firmware-toolchain.md). rp2040js's USBCDC helper does the enumeration (set
//! address, read the configuration descriptor, set configuration, raise DTR/RTS); this module takes
//! over the bulk OUT data path:
//! - defect 3: the controller clears AVAILABLE in an OUT buffer's control word as soon as firmware
//!   arms it, so embassy-rp's read sees a "completed" transfer with stale data. Here an armed OUT
//!   buffer (endpoint >= 1) keeps AVAILABLE set until the host really sends a packet.
//! - defect 4: USBCDC answers every armed OUT buffer at once, with zero-length packets when it has
//!   nothing. Here a packet is sent only when the host has data, at most the armed length.

import { USBCDC } from 'rp2040js';

const AVAILABLE = 1 << 10;
const FULL = 1 << 15;
const LEN_MASK = 0x3ff;
const EP0_OUT_BUFFER_CONTROL = 0x84;
const EP15_OUT_BUFFER_CONTROL = 0xfc;
/** Host turnaround before an OUT packet lands, as rp2040js uses for reads. */
const OUT_DELAY_NANOS = 10_000;

export class CdcHost {
  /**
   * @param rp2040 the chip
   * @param onData called with a Uint8Array for every IN packet the device sends
   * @param onConfigured called when enumeration is done and DTR is raised
   * @param onOut called with every OUT packet (Uint8Array) as it is handed to the chip
   */
  constructor(rp2040, { onData, onConfigured, onOut }) {
    this.rp2040 = rp2040;
    this.usb = rp2040.usbCtrl;
    this.queue = [];
    this.queued = 0;
    this.armed = new Map();
    this.outBytes = 0;
    this.outPackets = 0;
    this.inBytes = 0;
    this.deliverAlarm = rp2040.clock.createAlarm(() => this.deliver());
    this.onData = onData;
    this.onConfigured = onConfigured;
    this.onOut = onOut;
    /** Host turnaround before an OUT packet lands; tests sweep it to reach every cycle phase. */
    this.outDelayNanos = OUT_DELAY_NANOS;
    this.enumerate();
    const original = this.usb.DPRAMUpdated.bind(this.usb);
    this.usb.DPRAMUpdated = (offset, value) => {
      if (offset > EP0_OUT_BUFFER_CONTROL && offset <= EP15_OUT_BUFFER_CONTROL && offset & 4) {
        const endpoint = (offset - 0x80) >> 3;
        if (value & AVAILABLE) {
          this.armed.set(endpoint, value & LEN_MASK);
          this.schedule();
        } else {
          this.armed.delete(endpoint);
        }
        return;
      }
      original(offset, value);
    };
  }

  /** (Re)starts enumeration through a fresh USBCDC helper: used at boot and to re-plug the cable. */
  enumerate() {
    const cdc = new USBCDC(this.usb);
    this.cdc = cdc;
    this.armed.clear();
    cdc.onDeviceConnected = () => this.onConfigured?.();
    cdc.onSerialData = (data) => {
      this.inBytes += data.length;
      this.onData?.(data);
    };
    // Bulk OUT is handled through the DPRAM hook above; USBCDC must not answer it (defect 4).
    this.usb.onEndpointRead = () => {};
  }

  /** Simulates unplugging and re-plugging the cable: a USB bus reset and a new enumeration. */
  replug() {
    this.queue = [];
    this.queued = 0;
    this.enumerate();
    this.usb.resetDevice();
  }

  get configured() {
    return this.cdc.initialized && this.cdc.outEndpoint > 0;
  }

  send(bytes) {
    if (bytes.length === 0) return;
    this.queue.push(Buffer.from(bytes));
    this.queued += bytes.length;
    this.schedule();
  }

  schedule() {
    if (this.queued > 0 && this.configured && this.armed.has(this.cdc.outEndpoint)) {
      if (!this.deliverAlarm.scheduled) this.deliverAlarm.schedule(this.outDelayNanos);
    }
  }

  deliver() {
    this.deliverAlarm.scheduled = false;
    const endpoint = this.cdc.outEndpoint;
    const max = this.armed.get(endpoint);
    if (max === undefined || this.queued === 0) return;
    const packet = Buffer.alloc(Math.min(max, this.queued));
    let filled = 0;
    while (filled < packet.length) {
      const head = this.queue[0];
      const n = Math.min(head.length, packet.length - filled);
      head.copy(packet, filled, 0, n);
      filled += n;
      if (n === head.length) this.queue.shift();
      else this.queue[0] = head.subarray(n);
    }
    this.queued -= packet.length;
    this.outBytes += packet.length;
    this.outPackets++;
    this.armed.delete(endpoint);
    const usb = this.usb;
    const view = this.rp2040.usbDPRAMView;
    const control = EP0_OUT_BUFFER_CONTROL + endpoint * 8;
    this.rp2040.usbDPRAM.set(packet, usb.getEndpointBufferOffset(endpoint, true));
    let word = view.getUint32(control, true);
    word = (word & ~(AVAILABLE | LEN_MASK)) | FULL | packet.length;
    view.setUint32(control, word, true);
    usb.indicateBufferReady(endpoint, true);
    this.onOut?.(packet);
  }
}
