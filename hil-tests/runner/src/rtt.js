//! Reads the defmt RTT up-buffer (channel 0) out of emulated RAM, as a debug probe would: the bytes
//! between the read and write offsets, then moves the read offset on so the firmware can reuse the
//! space. The control block sits at the `_SEGGER_RTT` symbol: "SEGGER RTT\0..." (16 bytes),
//! max up buffers, max down buffers, then up-buffer descriptors of 6 words
//! (name, buffer, size, write offset, read offset, flags).

const RAM_BASE = 0x20000000;

export class RttReader {
  constructor(rp2040, address) {
    this.rp2040 = rp2040;
    this.address = address;
  }

  /** True once the firmware has initialised the control block (its id string is in place). */
  get ready() {
    const o = this.address - RAM_BASE;
    const { sram } = this.rp2040;
    return sram[o] === 0x53 && sram[o + 1] === 0x45 && sram[o + 7] === 0x52; // "SE...R"
  }

  /** Returns the bytes written since the last call (possibly empty). */
  drain() {
    if (!this.ready) return null;
    const view = this.rp2040.sramView;
    const desc = this.address - RAM_BASE + 24;
    const buffer = view.getUint32(desc + 4, true);
    const size = view.getUint32(desc + 8, true);
    const write = view.getUint32(desc + 12, true);
    let read = view.getUint32(desc + 16, true);
    if (size === 0 || write === read || write >= size || read >= size) return null;
    const chunks = [];
    const base = buffer - RAM_BASE;
    if (write < read) {
      chunks.push(this.rp2040.sram.slice(base + read, base + size));
      read = 0;
    }
    chunks.push(this.rp2040.sram.slice(base + read, base + write));
    view.setUint32(desc + 16, write, true);
    return Buffer.concat(chunks.map((c) => Buffer.from(c)));
  }
}
