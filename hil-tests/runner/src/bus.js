//! The half-duplex Dynamixel bus between the emulated UART0 and an external virtual servo chain
//! process, in lock step with simulated time.
//!
//! Wiring modelled: GPIO0 (UART0 TX) and GPIO1 (UART0 RX) go through a tri-state buffer whose
//! direction pin is GPIO2 (high = drive the bus). A character reaches the bus only if the direction
//! pin is high for its whole time on the wire (sampled when it starts and when its stop bit ends),
//! and a reply character reaches the RX pin only while the pin is low, so a firmware that drops the
//! direction pin before BUSY clears loses its last byte, as a real board would.
//!
//! Lock step: when the transmitter goes idle the runner sends the burst to the servo chain process
//! as one JSON line `{"tx":"<hex>","start_ns":..,"end_ns":..,"baud":..}` and stops simulated time
//! until the process answers with exactly one line, `{"segments":[{"delay_ns":..,"rx":"<hex>"},..]}`
//! (possibly no segments): each segment starts `delay_ns` after the end of the previous one (the
//! first after the end of the burst) and its characters arrive one character time apart, so chained
//! status packets of a Sync Read keep their gaps. `{"rx":"<hex>","delay_ns":..}` is short for one
//! segment. Lines `{"control":{..}}` from the runner (fault injection) are not answered. Simulated
//! time never runs ahead of the servo model, so timing does not depend on the host machine's speed.

import { spawn } from 'node:child_process';
import { createInterface } from 'node:readline';

const DIRECTION_PIN = 2;

export class BusLink {
  constructor(argv, { onWarn, onExit, onReply }) {
    this.onWarn = onWarn;
    this.onReply = onReply;
    this.proc = spawn(argv[0], argv.slice(1), { stdio: ['pipe', 'pipe', 'inherit'] });
    this.proc.on('exit', (code, signal) => onExit?.(code, signal));
    this.proc.on('error', (e) => onWarn?.(`servo chain process ${argv[0]} failed: ${e.message}`));
    this.pendingReply = null;
    createInterface({ input: this.proc.stdout }).on('line', (line) => this.reply(line));
    this.stats = { bursts: 0, txChars: 0, rxChars: 0, lostTx: 0, lostRx: 0, collisions: 0 };
    /** Every burst (start and end of its characters on the wire, ns of simulated time) while recording is on. */
    this.trace = null;
  }

  /** Attaches to a (new) chip: called at start and after every reset. */
  attach(board) {
    this.board = board;
    this.burst = [];
    this.burstStart = 0;
    this.rxQueue = [];
    const { uart } = board;
    const pin = () => board.rp2040.gpio[DIRECTION_PIN].outputValue;
    uart.onTxStart = () => pin();
    uart.onTxChar = (byte, start, end, pinAtStart) => {
      if (!(pin() && pinAtStart)) {
        this.stats.lostTx++;
        return;
      }
      if (this.burst.length === 0) this.burstStart = start;
      this.burst.push(byte);
      this.burstEnd = end;
    };
    uart.onTxIdle = () => this.flush();
    this.rxAlarm = board.rp2040.clock.createAlarm(() => this.rxChar());
  }

  /** True while simulated time must wait for the servo chain's answer. */
  get waiting() {
    return this.pendingReply !== null;
  }

  flush() {
    if (this.burst.length === 0) return;
    const tx = Buffer.from(this.burst);
    this.burst = [];
    this.stats.bursts++;
    this.stats.txChars += tx.length;
    const start = this.board.simNanos(this.burstStart);
    // Instruction byte of a Protocol 2.0 packet at the start of the burst (FF FF FD 00 id len len inst).
    const header = tx.length > 7 && tx[0] === 0xff && tx[1] === 0xff && tx[2] === 0xfd;
    const entry = {
      start_ns: start,
      end_ns: this.board.simNanos(this.burstEnd),
      len: tx.length,
      inst: header ? tx[7] : null,
      rx_end_ns: null,
    };
    this.trace?.push(entry);
    this.pendingReply = { end: this.burstEnd, boardEpoch: this.board.epoch, entry };
    this.board.hold = true;
    const msg = {
      tx: tx.toString('hex'),
      start_ns: start,
      end_ns: this.board.simNanos(this.burstEnd),
      baud: Math.round(this.board.uart.baudRate),
    };
    if (this.trace) entry.tx = msg.tx; // the bytes too, for tests that decode what went out
    this.proc.stdin.write(JSON.stringify(msg) + '\n');
  }

  reply(line) {
    let msg;
    try {
      msg = JSON.parse(line);
    } catch {
      this.onWarn?.(`servo chain process sent a line that is not JSON: ${line.slice(0, 80)}`);
      return;
    }
    const pending = this.pendingReply;
    this.pendingReply = null;
    this.board.hold = false;
    this.onReply?.();
    if (!pending || pending.boardEpoch !== this.board.epoch) return;
    const segments = msg.segments ?? [{ delay_ns: msg.delay_ns, rx: msg.rx }];
    const { uart, rp2040 } = this.board;
    const charNanos = uart.charNanos;
    // Each segment begins delay_ns after the previous one's last stop bit; one character per byte.
    let end = pending.end;
    for (const seg of segments) {
      const rx = Buffer.from(seg.rx ?? '', 'hex');
      const first = end + (seg.delay_ns ?? 0) + charNanos;
      for (let i = 0; i < rx.length; i++) this.queueRx(first + i * charNanos, rx[i], charNanos);
      end = first + (rx.length - 1) * charNanos;
    }
    // When the burst's answer ends on the wire: the bus is busy from the burst's start until then.
    if (pending.entry && segments.some((seg) => (seg.rx ?? '').length > 0)) {
      pending.entry.rx_end_ns = this.board.simNanos(end);
    }
    this.armRx(rp2040.clock.nanos);
  }

  /**
   * Queues a character that completes at `at`. A character that would overlap the one queued before
   * it means two drivers on the wire at once (e.g. a late reply running into the board's next
   * request's answer): both arrive corrupted and the later one waits its turn, so the collision
   * shows as a CRC error to the firmware instead of bytes teleporting into the FIFO.
   */
  queueRx(at, byte, charNanos) {
    const last = this.rxQueue[this.rxQueue.length - 1];
    if (last && at < last.at + charNanos) {
      this.stats.collisions++;
      last.byte ^= 0xff;
      this.rxQueue.push({ at: last.at + charNanos, byte: byte ^ 0xff });
      return;
    }
    this.rxQueue.push({ at, byte });
  }

  armRx(now) {
    if (this.rxQueue.length === 0) return;
    this.rxAlarm.schedule(Math.max(0, this.rxQueue[0].at - now));
  }

  rxChar() {
    this.rxAlarm.scheduled = false;
    const { rp2040, uart } = this.board;
    const { byte } = this.rxQueue.shift();
    if (rp2040.gpio[DIRECTION_PIN].outputValue) {
      this.stats.lostRx++;
    } else {
      this.stats.rxChars++;
      uart.receiveChar(byte);
    }
    this.armRx(rp2040.clock.nanos);
  }

  /** Sends a control message to the servo chain (e.g. inject a fault); it is not answered. */
  control(msg) {
    this.proc.stdin.write(JSON.stringify({ control: msg }) + '\n');
  }

  close() {
    this.proc.stdin.end();
    this.proc.kill();
  }
}
