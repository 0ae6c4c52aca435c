//! Fast-forward of busy-wait loops, like QEMU's idle detection but exact: when the core goes round a
//! short loop and one whole turn leaves it exactly where it started (same registers and flags, no
//! memory written, nothing read that can change on its own, no alarm due), every further turn would
//! do the same until the next alarm of the simulation clock fires (a UART character leaving the
//! shift register, a timer match, a USB packet): only an alarm or an interrupt can change what the
//! loop reads. So simulated time jumps ahead by a whole number of turns, stopping one turn short of
//! that alarm, and execution goes on instruction by instruction from there: the alarm fires in the
//! same instruction, at the same simulated nanosecond, with the core in the same state as without
//! the jump. The firmware's timing is unchanged; only the host's work for the skipped turns is saved.
//!
//! Typical loops: embassy-rp's `blocking_flush` waiting on the TX ring buffer (RAM, emptied by the
//! UART interrupt) and the firmware's BUSY spin on UARTFR before it releases the direction pin.
//!
//! What "can change on its own" means here: a read of anything but flash, boot ROM, SRAM and the
//! UART0 model's registers other than UARTDR counts as volatile (the TIMER counts microseconds,
//! SysTick counts down, SIO and the USB DPRAM are touched by others, reading UARTDR pops the RX FIFO),
//! and a turn with a volatile read is never skipped. RAM and UART0 change only through writes
//! (counted) or alarms (checked).

/** Longest backward branch considered a loop (bytes): spin loops are a handful of instructions. */
const MAX_LOOP_BYTES = 32;

const SRAM_START = 0x20000000;
const SRAM_END = 0x20042000;
const FLASH_END = 0x14000000; // boot ROM at 0, flash (and its XIP aliases) from 0x1000_0000
const UART0_START = 0x40034000;

/** Memory-access bookkeeping the board's bus wrappers keep for the detector. */
export class AccessCounters {
  constructor() {
    /** Writes to anything, boot ROM calls (they write flash and RAM) and exception entries. */
    this.writes = 0;
    /** Reads of a location that may change without a write or an alarm. */
    this.volatileReads = 0;
  }

  /** Counts a 32-bit read (8- and 16-bit reads outside RAM and flash end up here too). */
  read(address) {
    if (address < FLASH_END) return;
    if (address >= SRAM_START && address < SRAM_END) return;
    // UART0's registers change only through writes and alarms, except UARTDR (offset 0), whose read
    // pops the RX FIFO: a turn that reads it changes the UART even when it reads the same byte.
    if (address > UART0_START && address < UART0_START + 0x1000) return;
    this.volatileReads++;
  }
}

/**
 * Wraps the chip's bus functions (after the board's own wrappers and the boot ROM are installed) to
 * count writes and volatile reads. 8- and 16-bit reads outside flash and RAM go through readUint32;
 * a boot ROM call (flash erase/program, memcpy) changes memory behind the core's back and counts as a
 * write, and so does an exception entry (it pushes the registers).
 */
export function watchAccesses(rp2040) {
  const access = new AccessCounters();
  const readUint32 = rp2040.readUint32.bind(rp2040);
  rp2040.readUint32 = (address) => {
    access.read(address >>> 0);
    return readUint32(address);
  };
  for (const name of ['writeUint32', 'writeUint16', 'writeUint8']) {
    const write = rp2040[name].bind(rp2040);
    rp2040[name] = (address, value) => {
      access.writes++;
      write(address, value);
    };
  }
  const onBreak = rp2040.onBreak;
  rp2040.onBreak = (n) => {
    access.writes++;
    onBreak(n);
  };
  return access;
}

export class SpinSkipper {
  /**
   * @param core the rp2040js core
   * @param clock its simulation clock
   * @param access the AccessCounters the memory wrappers update
   */
  constructor(core, clock, access) {
    this.core = core;
    this.clock = clock;
    this.access = access;
    this.lastPc = 0;
    this.head = -1;
    this.regs = new Uint32Array(16);
    this.flags = 0;
    this.since = 0;
    this.alarmAt = 0;
    this.writes = 0;
    this.volatileReads = 0;
    this.stats = { skips: 0, skippedTurns: 0, skippedNanos: 0 };
  }

  /** Forgets the loop being watched: things outside the core (host I/O, commands) may have run. */
  invalidate() {
    this.head = -1;
  }

  /** Packs the state outside the general registers that a loop turn could change. */
  coreFlags() {
    const c = this.core;
    return (
      (c.N ? 1 : 0) |
      (c.Z ? 2 : 0) |
      (c.C ? 4 : 0) |
      (c.V ? 8 : 0) |
      (c.PM ? 16 : 0) |
      (c.SPSEL << 5) |
      (c.currentMode << 6) |
      (c.IPSR << 8)
    );
  }

  /**
   * Called before each instruction. Returns after possibly advancing the clock by whole loop turns,
   * never to or past `limit` (the end of the current run slice) or the next alarm.
   */
  step(limit) {
    const core = this.core;
    const pc = core.registers[15];
    const last = this.lastPc;
    this.lastPc = pc;
    if (pc >= last || last - pc > MAX_LOOP_BYTES) return;
    // A short backward branch has just been taken: `pc` is a loop head.
    const clock = this.clock;
    const now = clock.nanos;
    const access = this.access;
    if (
      pc === this.head &&
      now < this.alarmAt &&
      access.writes === this.writes &&
      access.volatileReads === this.volatileReads &&
      this.flags === this.coreFlags() &&
      sameRegisters(core.registers, this.regs)
    ) {
      // One whole turn changed nothing: a fixed point until the next alarm.
      const turn = now - this.since;
      const until = Math.min(this.alarmAt, limit);
      const turns = Math.floor((until - now) / turn) - 1;
      if (turn > 0 && turns > 0) {
        const skipped = turns * turn;
        clock.tick(skipped); // no alarm fires: now + skipped < alarmAt
        this.stats.skips++;
        this.stats.skippedTurns += turns;
        this.stats.skippedNanos += skipped;
      }
      this.since = clock.nanos;
      return;
    }
    this.head = pc;
    this.since = now;
    this.alarmAt = clock.nextAlarm ? clock.nextAlarm.nanos : Infinity;
    this.writes = access.writes;
    this.volatileReads = access.volatileReads;
    this.flags = this.coreFlags();
    this.regs.set(core.registers);
  }
}

/** r0..r14 equal (r15 is the loop head, equal by construction). */
function sameRegisters(a, b) {
  for (let i = 0; i < 15; i++) if (a[i] !== b[i]) return false;
  return true;
}
