#!/usr/bin/env node
//! Replays a recorded run (main.js with DBOT_HIL_RECORD_USB=FILE: the host's USB bytes and the
//! bus_control messages, each with its simulated time) on the firmware ELF and the servo chain
//! process, deterministically: inputs enter at the same simulated times in every replay, so two
//! replays must produce the same wire. With --compare it replays twice, busy-wait fast-forward off
//! and on (spin.js), and checks that the bus bursts (start, length, instruction, end of the answer),
//! the USB IN bytes and the defmt (RTT) bytes are identical; it prints instructions executed and
//! wall and CPU time for both. Chip resets, USB re-plugs and armed flash-write resets are not
//! recorded: runs that use them do not replay. A replay need not match the live run it was
//! recorded from in every nanosecond (there, input met the chip between run slices as wall time
//! allowed), but it is a faithful run of the firmware on those inputs, and it repeats exactly.
//!
//! Usage: node tools/replay.js --elf ELF --bus-cmd JSON_ARGV --record FILE [--until-ms N]
//!          [--compare] [--defmt-print PATH] [--trace-from-ms A [--trace-to-ms B]]
//! Without --compare it replays once (fast-forward on) and prints the log (with --defmt-print) and
//! the bus bursts between A and B ms of simulated time.

import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { parseArgs } from 'node:util';
import { Board } from '../src/board.js';
import { BusLink } from '../src/bus.js';
import { loadFlash, parseElf } from '../src/elf.js';
import { RttReader } from '../src/rtt.js';

const SLICE_NANOS = 1_000_000;

const { values: opts } = parseArgs({
  options: {
    elf: { type: 'string' },
    'bus-cmd': { type: 'string' },
    record: { type: 'string' },
    'until-ms': { type: 'string' },
    compare: { type: 'boolean', default: false },
    'defmt-print': { type: 'string' },
    'trace-from-ms': { type: 'string' },
    'trace-to-ms': { type: 'string' },
  },
});
if (!opts.elf || !opts['bus-cmd'] || !opts.record) {
  console.error('usage: node tools/replay.js --elf ELF --bus-cmd JSON_ARGV --record FILE [--compare]');
  process.exit(2);
}
const elf = parseElf(readFileSync(opts.elf));
const record = JSON.parse(readFileSync(opts.record, 'utf8'));
const last = record.length ? record[record.length - 1].sim_ns : 0;
const until = opts['until-ms'] ? Number(opts['until-ms']) * 1e6 : last + 1e9;

async function replay(fastForward) {
  const flash = new Uint8Array(2 * 1024 * 1024).fill(0xff);
  loadFlash(elf, flash);
  const usbIn = [];
  const board = new Board(flash, { onUsbData: (d) => usbIn.push(Buffer.from(d)) }, { fastForward });
  let wake = null;
  const bus = new BusLink(JSON.parse(opts['bus-cmd']), { onReply: () => wake?.() });
  bus.attach(board);
  bus.trace = [];
  const rtt = new RttReader(board.rp2040, elf.symbols.get('_SEGGER_RTT'));
  const logs = [];
  let next = 0;
  const wall0 = performance.now();
  const cpu0 = process.cpuUsage();
  while (board.simNanos() < until && board.halted === null) {
    // Inputs due by now enter between slices, as the runner's I/O does.
    while (next < record.length && record[next].sim_ns <= board.simNanos()) {
      const r = record[next++];
      if (r.hex !== undefined) board.usb.send(Buffer.from(r.hex, 'hex'));
      else bus.control(r.control);
    }
    if (board.hold) {
      await new Promise((resolve) => (wake = resolve));
      wake = null;
    } else board.runUntil(board.clock.nanos + SLICE_NANOS);
    const bytes = rtt.drain();
    if (bytes) logs.push(bytes);
  }
  const wall = performance.now() - wall0;
  const cpu = process.cpuUsage(cpu0);
  bus.close();
  return {
    trace: bus.trace,
    usbIn: Buffer.concat(usbIn),
    rtt: Buffer.concat(logs),
    simNanos: board.simNanos(),
    halted: board.halted,
    wall,
    cpuMs: (cpu.user + cpu.system) / 1e3,
    instructions: board.instructions,
    fastForward: board.fastForwardStats,
  };
}

function summary(name, r) {
  const sim = r.simNanos / 1e9;
  console.log(
    `${name}: ${sim.toFixed(3)} s simulated in ${(r.wall / 1e3).toFixed(2)} s wall ` +
      `(${(sim / (r.wall / 1e3)).toFixed(3)} x real time; ` +
      `runner CPU ${(r.cpuMs / 1e3).toFixed(2)} s = ` +
      `${(sim / (r.cpuMs / 1e3)).toFixed(3)} simulated s per CPU s), ${r.instructions} instructions ` +
      `(${(r.instructions / (r.simNanos / 1e6)).toFixed(0)} per simulated ms), ` +
      `${r.trace.length} bus bursts, ${r.usbIn.length} USB IN bytes, ${r.rtt.length} RTT bytes, ` +
      `skipped ${r.fastForward.skippedTurns} loop turns = ` +
      `${(r.fastForward.skippedNanos / 1e6).toFixed(1)} ms` +
      (r.halted ? `, halted: ${r.halted}` : ''),
  );
}

if (opts.compare) {
  const off = await replay(false);
  summary('fast-forward off', off);
  const on = await replay(true);
  summary('fast-forward on ', on);
  const diffs = [];
  if (JSON.stringify(off.trace) !== JSON.stringify(on.trace)) diffs.push('bus bursts');
  if (!off.usbIn.equals(on.usbIn)) diffs.push('USB IN bytes');
  if (!off.rtt.equals(on.rtt)) diffs.push('defmt (RTT) bytes');
  if (off.simNanos !== on.simNanos) diffs.push('end time');
  if (diffs.length) {
    console.log(`DIFFERENT: ${diffs.join(', ')}`);
    process.exit(1);
  }
  console.log('identical: bus bursts, USB IN bytes, defmt bytes, end time');
} else {
  const r = await replay(true);
  summary('replay', r);
  if (opts['trace-from-ms']) {
    // The board's bursts in a window: start, length, instruction, end of the servos' answer (ms).
    const from = Number(opts['trace-from-ms']) * 1e6;
    const to = opts['trace-to-ms'] ? Number(opts['trace-to-ms']) * 1e6 : Infinity;
    for (const b of r.trace.filter((b) => b.start_ns >= from && b.start_ns <= to)) {
      const inst = b.inst === null ? '-' : `0x${b.inst.toString(16)}`;
      const end = b.rx_end_ns === null ? 'no answer' : `answer ends ${(b.rx_end_ns / 1e6).toFixed(3)}`;
      console.log(`${(b.start_ns / 1e6).toFixed(3)} ms: ${b.len} bytes, instruction ${inst}, ${end}`);
    }
  }
  if (opts['defmt-print']) {
    const out = spawnSync(opts['defmt-print'], ['-e', opts.elf, 'stdin'], { input: r.rtt });
    process.stdout.write(out.stdout);
    process.stdout.write(out.stderr);
  }
}
