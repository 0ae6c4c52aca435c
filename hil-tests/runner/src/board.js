//! One emulated Drosophibot II controller: an rp2040js chip with the firmware's flash image, the
//! stand-in boot ROM, the paced UART0 and the fixed USB OUT path, run on simulated time.
//!
//! The five emulator defects of shared/reference/firmware-toolchain.md are fixed here at run time:
//! 1 and 2 by replacing UART0 with PacedUart (uart.js), 3 and 4 by CdcHost (cdc.js), and 5 (SEV does
//! nothing, so embassy's thread-mode executor sleeps in WFE until the next interrupt) by turning the
//! core's "SEV" log call into what SEV does: setting the event register.
//!
//! A reset builds a new chip and keeps the flash contents, so the gait store survives like on a
//! board; simulated time keeps counting across resets.

import { RP2040 } from 'rp2040js';
import { installBootrom } from './bootrom.js';
import { CdcHost } from './cdc.js';
import { SpinSkipper, watchAccesses } from './spin.js';
import { PacedUart } from './uart.js';

const UART0_BASE = 0x40034;
const UART0_IRQ = 20;
const WATCHDOG_BASE = 0x40058;
const XIP_CTRL_BASE = 0x14000000;

/** XIP_CTRL registers of an idle XIP block: CTRL = EN|ERR_BADWRITE, STAT = FIFO_EMPTY|FLUSH_READY. */
function xipCtrlRead(offset) {
  switch (offset) {
    case 0x00:
      return 0x3;
    case 0x08:
      return 0x3;
    default:
      return 0; // counters, STREAM_ADDR, STREAM_CTR (no stream running), STREAM_FIFO
  }
}
const CYCLE_NANOS = 1e9 / 125e6;

export class Board {
  /**
   * @param flash the 16 MB flash image (Uint8Array), kept and shared across resets
   * @param hooks { onUsbData(bytes), onUsbConfigured(), onWarn(msg), onFlashWrite(kind, off, len) }
   * @param options { fastForward: skip busy-wait loops (spin.js; default true) }
   */
  constructor(flash, hooks, { fastForward = true } = {}) {
    this.flash = flash;
    this.hooks = hooks;
    this.fastForward = fastForward;
    /** Instructions the core has executed, over all resets. */
    this.instructions = 0;
    /** Busy-wait fast-forward totals over all resets (spin.js). */
    this.spinStats = { skips: 0, skippedTurns: 0, skippedNanos: 0 };
    this.epoch = 0;
    this.baseNanos = 0;
    this.build();
  }

  build() {
    // RP2040's default clock is a SimulationClock (the class itself is not exported).
    const rp2040 = new RP2040();
    const clock = rp2040.clock;
    rp2040.flash.set(this.flash);
    this.flash = rp2040.flash;
    const core = rp2040.core;
    const { onWarn } = this.hooks;
    rp2040.logger = {
      debug() {},
      // Defect 5: SEV is logged and otherwise ignored by the core; make it set the event register.
      info(_name, msg) {
        if (msg === 'SEV') core.eventRegistered = true;
      },
      warn: (name, msg) => {
        // An undefined instruction is where panic-probe ends up (`udf`) and where a wild jump lands:
        // rp2040js has no HardFault, so stop the core instead of executing garbage.
        if (msg.includes('is not implemented yet') && this.halted === null) {
          this.halted = msg;
        }
        onWarn?.(`${name}: ${msg}`);
      },
      error: (name, msg) => onWarn?.(`${name}: ${msg}`),
    };
    // Not in the reference's list: XIP_CTRL (0x1400_0000) is unmapped in rp2040js, so a read returns
    // 0xffffffff and embassy-rp's flash driver spins forever on `STREAM_CTR != 0` before every
    // erase/program. Answer its registers as an idle XIP block does (no streaming, cache flushed).
    const readUint32 = rp2040.readUint32.bind(rp2040);
    rp2040.readUint32 = (address) => {
      const a = address >>> 0;
      if (a >= XIP_CTRL_BASE && a < XIP_CTRL_BASE + 0x20) return xipCtrlRead(a - XIP_CTRL_BASE);
      return readUint32(address);
    };
    const writeUint32 = rp2040.writeUint32.bind(rp2040);
    rp2040.writeUint32 = (address, value) => {
      const a = address >>> 0;
      if (a >= XIP_CTRL_BASE && a < XIP_CTRL_BASE + 0x4000) return;
      writeUint32(address, value);
    };
    // Defects 1 and 2: a PL011 model with UARTDMACR, edge TX interrupt and wire timing.
    const uart = new PacedUart(rp2040, 'UART0', UART0_IRQ);
    rp2040.uart[0] = uart;
    rp2040.peripherals[UART0_BASE] = uart;
    installBootrom(rp2040, {
      warn: onWarn,
      onFlashWrite: (kind, offset, length) => this.hooks.onFlashWrite?.(kind, offset, length),
      tornProgram: (offset, count) => this.hooks.tornProgram?.(offset, count),
      onBreakpoint: (n, pc) => {
        this.halted = `breakpoint #${n} at 0x${(pc - 2).toString(16)} (panic or semihosting call)`;
      },
    });
    this.usb = new CdcHost(rp2040, {
      onData: (data) => this.hooks.onUsbData?.(data),
      onConfigured: () => this.hooks.onUsbConfigured?.(),
      onOut: (packet) => this.hooks.onUsbOut?.(packet),
    });
    // The watchdog resets the chip (rp2040js only logs it). Its scratch registers and the reset
    // reason survive a watchdog reset, as on the chip, so firmware can tell why it rebooted.
    const watchdog = rp2040.peripherals[WATCHDOG_BASE];
    if (this.watchdogCarry) {
      watchdog.scratchData.set(this.watchdogCarry.scratch);
      watchdog.reason = this.watchdogCarry.reason;
      this.watchdogCarry = null;
    }
    watchdog.onWatchdogTrigger = () => {
      this.watchdogCarry = { scratch: watchdog.scratchData.slice(), reason: watchdog.reason };
      this.hooks.onWatchdog?.(watchdog.reason);
      this.halted = 'reset requested';
    };
    // Boot like the ROM does: run boot2 from the start of flash; it sets up XIP and enters the
    // vector table at 0x10000100.
    core.SP = 0x20042000;
    core.LR = 0;
    core.PC = 0x10000000;
    this.rp2040 = rp2040;
    this.clock = clock;
    if (this.spin) this.addSpinStats();
    this.spin = this.fastForward ? new SpinSkipper(core, clock, watchAccesses(rp2040)) : null;
    this.uart = uart;
    this.halted = null;
    this.hold = false;
  }

  addSpinStats() {
    for (const k of Object.keys(this.spinStats)) this.spinStats[k] += this.spin.stats[k];
    this.spin.stats = { skips: 0, skippedTurns: 0, skippedNanos: 0 };
  }

  /** Busy-wait fast-forward totals: skips, skipped loop turns, skipped simulated nanoseconds. */
  get fastForwardStats() {
    if (this.spin) this.addSpinStats();
    return { ...this.spinStats };
  }

  /** Simulated nanoseconds since the first boot for a time of the current chip's clock. */
  simNanos(chipNanos = this.clock.nanos) {
    return this.baseNanos + chipNanos;
  }

  /**
   * Resets the chip: a new RP2040 with the same flash contents; simulated time goes on. After a
   * watchdog trigger the watchdog's scratch and reason registers are carried over; any other reset
   * (the reset command: the RUN pin or power) clears them.
   */
  reset({ watchdog = false } = {}) {
    if (!watchdog) this.watchdogCarry = null;
    this.baseNanos += this.clock.nanos;
    this.epoch++;
    this.build();
  }

  /**
   * Runs until the chip clock reaches `target` (chip nanoseconds), something sets `hold` (the bus
   * waiting for the servo chain), or the core halts. Sleeping (WFI/WFE) skips straight to the next
   * alarm, one alarm at a time, so a hold set by an alarm stops time right there. Busy-wait loops
   * are fast-forwarded the same way, by whole loop turns (spin.js).
   */
  runUntil(target) {
    const { rp2040, clock, spin } = this;
    const core = rp2040.core;
    // Host I/O and commands ran since the last call: a loop seen before proves nothing now.
    spin?.invalidate();
    let instructions = 0;
    while (clock.nanos < target && this.halted === null && !this.hold) {
      if (core.waiting) {
        const next = clock.nextAlarm ? clock.nextAlarm.nanos : target;
        clock.tick(Math.max(0, Math.min(next, target) - clock.nanos));
      } else {
        if (spin !== null) spin.step(target);
        const cycles = core.executeInstruction();
        clock.tick(cycles * CYCLE_NANOS);
        instructions++;
      }
    }
    this.instructions += instructions;
  }
}
