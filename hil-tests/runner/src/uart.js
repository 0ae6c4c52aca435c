//! A PL011 UART model that replaces rp2040js's UART0 (whose defects 1 and 2 are listed in
//! shared/reference/firmware-toolchain.md): UARTDMACR is a real register (reads 0 until written, so
//! embassy's buffered interrupt handler no longer thinks RX DMA is on), the TX interrupt fires once when
//! the TX FIFO drains to its trigger level, and the wire is timed: each character takes
//! (1 start + data + parity + stop) bit periods at the baud the divisors give, BUSY is set while the
//! TX FIFO or the shift register holds data, RX characters arrive one character time apart, and the
//! receive-timeout interrupt fires after 32 idle bit periods, as on the chip.

import { BasePeripheral } from 'rp2040js';

const UARTDR = 0x00;
const UARTRSR = 0x04;
const UARTFR = 0x18;
const UARTIBRD = 0x24;
const UARTFBRD = 0x28;
const UARTLCR_H = 0x2c;
const UARTCR = 0x30;
const UARTIFLS = 0x34;
const UARTIMSC = 0x38;
const UARTRIS = 0x3c;
const UARTMIS = 0x40;
const UARTICR = 0x44;
const UARTDMACR = 0x48;
const PERIPH_ID = [0x11, 0x10, 0x34, 0x00, 0x0d, 0xf0, 0x05, 0xb1];

const FR_TXFE = 1 << 7;
const FR_RXFF = 1 << 6;
const FR_TXFF = 1 << 5;
const FR_RXFE = 1 << 4;
const FR_BUSY = 1 << 3;

const INT_OE = 1 << 10;
const INT_RT = 1 << 6;
const INT_TX = 1 << 5;
const INT_RX = 1 << 4;

const CR_UARTEN = 1 << 0;
const CR_TXE = 1 << 8;
const CR_RXE = 1 << 9;
const LCR_FEN = 1 << 4;

const FIFO_DEPTH = 32;
/** IFLS trigger levels in FIFO entries for selector values 0..4 (1/8, 1/4, 1/2, 3/4, 7/8 of 32). */
const LEVELS = [4, 8, 16, 24, 28];

export class PacedUart extends BasePeripheral {
  /**
   * @param rp2040 the emulated chip
   * @param name peripheral name for log messages
   * @param irq interrupt number (UART0_IRQ = 20)
   */
  constructor(rp2040, name, irq) {
    super(rp2040, name);
    this.irq = irq;
    this.clock = rp2040.clock;
    this.txFifo = [];
    this.rxFifo = [];
    /** Character being shifted out, or null when the transmitter is idle. */
    this.shifting = null;
    this.cr = CR_RXE | CR_TXE;
    this.lcrH = 0;
    this.ifls = 0b010010;
    this.imsc = 0;
    this.ris = 0;
    this.dmacr = 0;
    this.ibrd = 0;
    this.fbrd = 0;
    /** Called as a character starts on the TX pin; what it returns is handed to onTxChar. */
    this.onTxStart = null;
    /** Called with (byte, startNanos, endNanos, tag) when a character has fully left the TX pin. */
    this.onTxChar = null;
    /** Called when the transmitter goes idle (FIFO and shift register empty). */
    this.onTxIdle = null;
    /** Called with the baud rate whenever the divisors change. */
    this.onBaudRateChange = null;
    this.txAlarm = this.clock.createAlarm(() => this.txCharDone());
    this.rtAlarm = this.clock.createAlarm(() => this.receiveTimeout());
    this.stats = { txChars: 0, rxChars: 0, overruns: 0 };
  }

  get enabled() {
    return (this.cr & CR_UARTEN) !== 0;
  }

  get baudRate() {
    const divider = this.ibrd + this.fbrd / 64;
    return divider ? this.rp2040.clkPeri / (16 * divider) : 0;
  }

  /** Bits per character on the wire: start + data + optional parity + 1 or 2 stop bits. */
  get bitsPerChar() {
    const data = 5 + ((this.lcrH >>> 5) & 3);
    const parity = this.lcrH & (1 << 1) ? 1 : 0;
    const stop = this.lcrH & (1 << 3) ? 2 : 1;
    return 1 + data + parity + stop;
  }

  get bitNanos() {
    const baud = this.baudRate;
    return baud ? 1e9 / baud : 0;
  }

  get charNanos() {
    return this.bitsPerChar * this.bitNanos;
  }

  get fifoDepth() {
    return this.lcrH & LCR_FEN ? FIFO_DEPTH : 1;
  }

  get txLevel() {
    return LEVELS[Math.min(this.ifls & 7, 4)];
  }

  get rxLevel() {
    return LEVELS[Math.min((this.ifls >>> 3) & 7, 4)];
  }

  clkPeriChanged() {
    if (this.baudRate) this.onBaudRateChange?.(this.baudRate);
  }

  updateInterrupt() {
    this.rp2040.setInterrupt(this.irq, (this.ris & this.imsc) !== 0);
  }

  get flags() {
    let fr = 0;
    if (this.txFifo.length === 0) fr |= FR_TXFE;
    if (this.txFifo.length >= this.fifoDepth) fr |= FR_TXFF;
    if (this.rxFifo.length === 0) fr |= FR_RXFE;
    if (this.rxFifo.length >= this.fifoDepth) fr |= FR_RXFF;
    if (this.txFifo.length > 0 || this.shifting !== null) fr |= FR_BUSY;
    return fr;
  }

  /** Moves the next character into the shift register if the transmitter may run. */
  startTx() {
    if (this.shifting !== null || this.txFifo.length === 0) return;
    if (!this.enabled || !(this.cr & CR_TXE) || !this.charNanos) return;
    const before = this.txFifo.length;
    const byte = this.txFifo.shift();
    this.shifting = { byte, start: this.clock.nanos, tag: this.onTxStart?.(byte) };
    // The TX interrupt is an edge: it is raised when the FIFO drains through the trigger level.
    if (before > this.txLevel && this.txFifo.length <= this.txLevel) {
      this.ris |= INT_TX;
      this.updateInterrupt();
    }
    this.txAlarm.schedule(this.charNanos);
  }

  txCharDone() {
    const { byte, start, tag } = this.shifting;
    this.shifting = null;
    this.stats.txChars++;
    this.onTxChar?.(byte, start, this.clock.nanos, tag);
    this.startTx();
    if (this.shifting === null && this.txFifo.length === 0) this.onTxIdle?.();
  }

  /** A character has arrived complete on the RX pin. */
  receiveChar(byte) {
    if (!this.enabled || !(this.cr & CR_RXE)) return;
    if (this.rxFifo.length >= this.fifoDepth) {
      this.stats.overruns++;
      this.ris |= INT_OE;
      this.updateInterrupt();
      return;
    }
    this.stats.rxChars++;
    this.rxFifo.push(byte);
    if (this.rxFifo.length >= this.rxLevel) this.ris |= INT_RX;
    // Receive timeout: 32 bit periods after the last character with data still in the FIFO.
    this.rtAlarm.schedule(32 * this.bitNanos);
    this.updateInterrupt();
  }

  receiveTimeout() {
    if (this.rxFifo.length > 0) {
      this.ris |= INT_RT;
      this.updateInterrupt();
    }
  }

  readUint32(offset) {
    switch (offset) {
      case UARTDR: {
        const value = this.rxFifo.length ? this.rxFifo.shift() : 0;
        if (this.rxFifo.length < this.rxLevel) this.ris &= ~INT_RX;
        if (this.rxFifo.length === 0) this.ris &= ~INT_RT;
        this.updateInterrupt();
        return value;
      }
      case UARTRSR:
        return 0;
      case UARTFR:
        return this.flags;
      case UARTIBRD:
        return this.ibrd;
      case UARTFBRD:
        return this.fbrd;
      case UARTLCR_H:
        return this.lcrH;
      case UARTCR:
        return this.cr;
      case UARTIFLS:
        return this.ifls;
      case UARTIMSC:
        return this.imsc;
      case UARTRIS:
        return this.ris;
      case UARTMIS:
        return this.ris & this.imsc;
      case UARTDMACR:
        return this.dmacr;
    }
    if (offset >= 0xfe0 && offset <= 0xffc) return PERIPH_ID[(offset - 0xfe0) >> 2];
    return super.readUint32(offset);
  }

  writeUint32(offset, value) {
    switch (offset) {
      case UARTDR:
        if (this.txFifo.length < this.fifoDepth) {
          this.txFifo.push(value & 0xff);
          // Writing past the trigger level clears the TX interrupt, as on the PL011.
          if (this.txFifo.length > this.txLevel) {
            this.ris &= ~INT_TX;
            this.updateInterrupt();
          }
        }
        this.startTx();
        break;
      case UARTRSR:
        break;
      case UARTIBRD:
        this.ibrd = value & 0xffff;
        break;
      case UARTFBRD:
        this.fbrd = value & 0x3f;
        break;
      case UARTLCR_H:
        // On the PL011 a write to LCR_H latches the divisors: report the baud rate here.
        this.lcrH = value & 0xff;
        if (this.baudRate) this.onBaudRateChange?.(this.baudRate);
        break;
      case UARTCR:
        this.cr = value & 0xffff;
        this.startTx();
        break;
      case UARTIFLS:
        this.ifls = value & 0x3f;
        break;
      case UARTIMSC:
        this.imsc = value & 0x7ff;
        this.updateInterrupt();
        break;
      case UARTICR:
        this.ris &= ~this.rawWriteValue;
        this.updateInterrupt();
        break;
      case UARTDMACR:
        this.dmacr = value & 0x7;
        break;
      default:
        super.writeUint32(offset, value);
    }
  }
}
