#!/usr/bin/env node
//! The HIL emulator runner: runs the firmware ELF on an emulated RP2040 (board.js) and wires it up.
//!
//! Usage: node src/main.js --elf FIRMWARE_ELF [--flash-file F] [--usb-socket PATH]
//!          [--bus-cmd JSON_ARGV] [--defmt-print PATH] [--realtime X]
//!
//! - stdin/stdout: the control channel, one JSON object per line (protocol.js lists the commands and
//!   events). The Rust harness (hil-tests/src/emulator.rs) is the client.
//! - --usb-socket: a Unix socket the runner connects to; bytes from it are USB CDC-ACM OUT data (host
//!   to board), IN data is written back. The harness puts a pseudo-terminal behind it.
//! - --bus-cmd: argv (JSON array) of the virtual servo chain process on UART0 (bus.js).
//! - --flash-file: flash persistence; loaded at start (then the ELF is programmed over it, like
//!   flashing with a probe keeps the rest of the flash), written back after flash writes and at exit.
//! - defmt: the RTT up-buffer bytes go to `defmt-print -e ELF`, whose lines become `log` events.
//! - --realtime X: keep simulated time at most X times wall time (default: as fast as possible).
//! - --paced-by PID,...: simulated time passes only while every thread of those processes is
//!   blocked (the host waits), so a loaded machine's host does not fall behind the board (pace.js).

import { spawn } from 'node:child_process';
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { connect } from 'node:net';
import { createInterface } from 'node:readline';
import { parseArgs } from 'node:util';
import { Board } from './board.js';
import { BusLink } from './bus.js';
import { loadFlash, parseElf } from './elf.js';
import { HostPacer } from './pace.js';
import { Control } from './protocol.js';
import { RttReader } from './rtt.js';

const FLASH_SIZE = 2 * 1024 * 1024;
const SLICE_NANOS = 1_000_000;

const { values: opts } = parseArgs({
  options: {
    elf: { type: 'string' },
    'flash-file': { type: 'string' },
    'usb-socket': { type: 'string' },
    'bus-cmd': { type: 'string' },
    'defmt-print': { type: 'string', default: 'defmt-print' },
    realtime: { type: 'string' },
    'paced-by': { type: 'string' },
  },
});

const control = new Control(process.stdin, process.stdout);
// Each distinct warning once: rp2040js warns on every access to a peripheral it does not model
// (ROSC, VREG, some USB registers), which embassy-rp touches at boot and which do not matter here.
const warned = new Set();
const warn = (msg) => {
  if (warned.has(msg)) return;
  warned.add(msg);
  control.event('warn', { msg });
};

function fail(msg) {
  control.event('fatal', { msg });
  process.exit(2);
}

if (!opts.elf) fail('missing --elf FIRMWARE_ELF');
let elf;
try {
  elf = parseElf(readFileSync(opts.elf));
} catch (e) {
  fail(`cannot load firmware ELF ${opts.elf}: ${e.message}`);
}
const flash = new Uint8Array(FLASH_SIZE).fill(0xff);
if (opts['flash-file'] && existsSync(opts['flash-file'])) {
  const saved = readFileSync(opts['flash-file']);
  if (saved.length !== FLASH_SIZE) {
    fail(`flash file ${opts['flash-file']} has ${saved.length} bytes, expected ${FLASH_SIZE}`);
  }
  flash.set(saved);
}
try {
  loadFlash(elf, flash);
} catch (e) {
  fail(`${opts.elf}: ${e.message}`);
}

// Flash writes: counted, persisted, and the reset-during-write test point.
const flashStats = { erases: 0, programs: 0, programBytes: 0 };
// While `usb_trace` is on: USB OUT packets (simulated time handed to the chip, bytes) and when the
// host's bytes reached the runner.
let usbTrace = null;
let flashDirty = false;
let resetArm = null;
let resetRequest = null;
const hooks = {
  onUsbData: (data) => usbSocket?.write(data),
  onUsbConfigured: () => control.event('usb_configured', { sim_ns: board.simNanos() }),
  onUsbOut: (packet) =>
    usbTrace?.push({ sim_ns: board.simNanos(), data: Buffer.from(packet).toString('hex') }),
  onWarn: warn,
  onWatchdog(reason) {
    resetRequest = reason & 2 ? 'watchdog (forced)' : 'watchdog (timer expired)';
  },
  onFlashWrite(kind, offset, length) {
    flashDirty = true;
    if (kind === 'erase') flashStats.erases++;
    else {
      flashStats.programs++;
      flashStats.programBytes += length;
    }
    if (resetArm && kind === 'program' && --resetArm.remaining === 0) {
      resetRequest = `after flash program #${resetArm.nth} at offset 0x${offset.toString(16)}`;
      resetArm = null;
      board.halted = 'reset requested';
    }
  },
  // The armed program operation is cut short after `torn_bytes` bytes, as a power loss would.
  tornProgram(_offset, count) {
    if (resetArm && resetArm.remaining === 1 && resetArm.tornBytes !== undefined) {
      return Math.min(count, resetArm.tornBytes);
    }
    return undefined;
  },
};

// DBOT_HIL_FAST_FORWARD=0 turns the busy-wait fast-forward off (spin.js), to compare.
const board = new Board(flash.subarray(0), hooks, {
  fastForward: process.env.DBOT_HIL_FAST_FORWARD !== '0',
});
function saveFlash() {
  if (opts['flash-file']) writeFileSync(opts['flash-file'], board.flash.subarray(0, FLASH_SIZE));
  flashDirty = false;
}

// defmt: RTT bytes to defmt-print, its lines to `log` events.
const rttAddress = elf.symbols.get('_SEGGER_RTT');
let defmt = null;
if (rttAddress === undefined) warn('the ELF has no _SEGGER_RTT symbol: no defmt logs');
else {
  defmt = spawn(opts['defmt-print'], ['-e', opts.elf, 'stdin'], { stdio: ['pipe', 'pipe', 'pipe'] });
  defmt.on('error', (e) => {
    warn(`cannot run ${opts['defmt-print']} (install it with scripts/setup.d/30-hil.sh): ${e.message}`);
    defmt = null;
  });
  const onLine = (line) => control.event('log', { sim_ns: board.simNanos(), line });
  createInterface({ input: defmt.stdout }).on('line', onLine);
  createInterface({ input: defmt.stderr }).on('line', onLine);
}
let rtt = rttAddress === undefined ? null : new RttReader(board.rp2040, rttAddress);

// DBOT_HIL_RECORD_USB=FILE: the host's bytes and the bus_control messages with their simulated
// times, written at exit, to replay a run deterministically (tools/replay.js).
const usbRecord = process.env.DBOT_HIL_RECORD_USB ? [] : null;
let usbSocket = null;
if (opts['usb-socket']) {
  usbSocket = connect(opts['usb-socket']);
  usbSocket.on('data', (data) => {
    // With `usb_trace` on, when the host's bytes reached the runner (before the chip takes them).
    usbTrace?.push({ sim_ns: board.simNanos(), host_bytes: data.length });
    usbRecord?.push({ sim_ns: board.simNanos(), hex: data.toString('hex') });
    board.usb.send(data);
  });
  usbSocket.on('error', (e) => warn(`USB socket ${opts['usb-socket']}: ${e.message}`));
}

let wake = null;
const wakeUp = () => {
  const w = wake;
  wake = null;
  w?.();
};
let bus = null;
if (opts['bus-cmd']) {
  let argv;
  try {
    argv = JSON.parse(opts['bus-cmd']);
  } catch (e) {
    fail(`--bus-cmd must be a JSON array of strings: ${e.message}`);
  }
  bus = new BusLink(argv, {
    onWarn: warn,
    onExit: (code, signal) => {
      if (!quitting) control.event('fatal', { msg: `servo chain process exited (${code ?? signal})` });
    },
    onReply: wakeUp,
  });
  bus.attach(board);
}

function resetBoard(reason) {
  board.reset({ watchdog: reason.startsWith('watchdog') });
  rtt = rttAddress === undefined ? null : new RttReader(board.rp2040, rttAddress);
  bus?.attach(board);
  halted = null;
  control.event('reset', { sim_ns: board.simNanos(), reason });
}

// Commands of the control channel.
const waiters = [];
let quitting = false;
let halted = null;
control.handlers = {
  time: () => ({ sim_ns: board.simNanos() }),
  wait_until: (cmd, reply) => {
    waiters.push({ sim_ns: cmd.sim_ns, reply });
    return undefined;
  },
  reset: () => {
    resetBoard('reset command');
    return {};
  },
  reset_on_flash_program: (cmd) => {
    resetArm = { nth: cmd.nth, remaining: cmd.nth, tornBytes: cmd.torn_bytes };
    return {};
  },
  usb_replug: () => {
    board.usb.replug();
    return {};
  },
  usb_pending: () => ({ bytes: board.usb.queued }),
  save_flash: () => {
    saveFlash();
    return {};
  },
  bus_trace: (cmd) => {
    if (!bus) throw new Error('no servo chain attached (--bus-cmd)');
    if (cmd.on) {
      bus.trace = [];
      return {};
    }
    const trace = bus.trace ?? [];
    bus.trace = null;
    return { bursts: trace };
  },
  // Until the next reset (a new chip gets the default, 10 us).
  usb_out_delay: (cmd) => {
    board.usb.outDelayNanos = cmd.ns;
    return {};
  },
  usb_trace: (cmd) => {
    const packets = usbTrace ?? [];
    usbTrace = cmd.on ? [] : null;
    return { packets };
  },
  bus_control: (cmd) => {
    if (!bus) throw new Error('no servo chain attached (--bus-cmd)');
    usbRecord?.push({ sim_ns: board.simNanos(), control: cmd.msg });
    bus.control(cmd.msg);
    return {};
  },
  stats: () => ({
    sim_ns: board.simNanos(),
    wall_ms: Math.round(performance.now() - wallStart),
    uart: { ...board.uart.stats, baud: Math.round(board.uart.baudRate) },
    usb: {
      out: board.usb.outBytes,
      out_packets: board.usb.outPackets,
      in: board.usb.inBytes,
      configured: board.usb.configured,
    },
    bus: bus?.stats ?? null,
    flash: flashStats,
    fast_forward: board.fastForwardStats,
    instructions: board.instructions,
    pacing: pacer?.stats ?? null,
    halted,
  }),
  quit: () => {
    quit();
    return {};
  },
};
control.onClose = () => quit();

function quit() {
  if (quitting) return;
  quitting = true;
  if (flashDirty) saveFlash();
  if (usbRecord) writeFileSync(process.env.DBOT_HIL_RECORD_USB, JSON.stringify(usbRecord));
  bus?.close();
  defmt?.stdin.end();
  usbSocket?.end();
  setTimeout(() => process.exit(0), 200).unref();
}

// The run loop: slices of simulated time, I/O in between.
const wallStart = performance.now();
const realtime = opts.realtime ? Number(opts.realtime) : null;
let pacer = null;
if (opts['paced-by']) {
  const pids = opts['paced-by'].split(',').map(Number);
  if (pids.some((p) => !Number.isInteger(p) || p <= 0)) {
    fail(`--paced-by must be process IDs separated by commas, got ${opts['paced-by']}`);
  }
  pacer = new HostPacer(pids, { onWarn: warn });
}
let lastFlashSave = 0;
control.event('ready', { rtt: rttAddress ?? null, flash_bytes: FLASH_SIZE });
while (!quitting) {
  if (resetRequest !== null) {
    const reason = resetRequest;
    resetRequest = null;
    resetBoard(reason);
  } else if (board.halted !== null && halted === null) {
    halted = board.halted;
    control.event('halted', { sim_ns: board.simNanos(), reason: halted });
  }
  if (board.hold || halted !== null) {
    // Waiting for the servo chain's answer (or halted): sleep until something happens.
    await new Promise((resolve) => {
      wake = resolve;
      setTimeout(resolve, board.hold ? 1000 : 20);
    });
    wake = null;
  } else if (pacer !== null && !pacer.mayRun(performance.now() - wallStart)) {
    // The host is computing (or waiting for a CPU): the board's clock waits for it.
    await new Promise((r) => setTimeout(r, 1));
    continue;
  } else {
    board.runUntil(board.clock.nanos + SLICE_NANOS);
  }
  const bytes = rtt?.drain();
  if (bytes && defmt) defmt.stdin.write(bytes);
  const now = board.simNanos();
  for (let i = waiters.length - 1; i >= 0; i--) {
    if (now >= waiters[i].sim_ns) waiters.splice(i, 1)[0].reply({ sim_ns: now });
  }
  const wall = performance.now() - wallStart;
  if (flashDirty && wall - lastFlashSave > 200) {
    saveFlash();
    lastFlashSave = wall;
  }
  if (realtime !== null && now / 1e6 > realtime * wall) {
    await new Promise((r) => setTimeout(r, Math.min(50, now / 1e6 / realtime - wall)));
  } else {
    await new Promise((r) => setImmediate(r));
  }
}
