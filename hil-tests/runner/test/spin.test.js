//! The busy-wait fast-forward (spin.js) on hand-assembled Thumb loops run by the board (board.js):
//! with it on, each program must leave its loop at the very same simulated nanosecond, with the same
//! registers, as with it off (instruction by instruction), and loops that wait on something only an
//! alarm can change must be skipped. Loops that read a free-running counter, pop the RX FIFO or
//! write memory must never be skipped. Independent truth for the UART case: three characters of
//! 10 bits at 1 Mbaud take 30 us on the wire.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Board } from '../src/board.js';

const BKPT_DONE = 0xbef0; // an unknown breakpoint number: the board halts on it
const FLAG = 0x20000100;
const UART0 = 0x40034000;
const TIMERAWL = 0x40054028;
const MS = 1_000_000;

/**
 * Runs `program` (16-bit Thumb instructions at the start of flash) in 1 ms slices, as the runner's
 * main loop does, until it halts on BKPT_DONE or 20 ms pass.
 */
function run(program, fastForward, setup = () => {}) {
  const flash = new Uint8Array(4096).fill(0xff);
  const view = new DataView(flash.buffer);
  program.forEach((insn, i) => view.setUint16(2 * i, insn, true));
  const board = new Board(flash, { onWarn() {} }, { fastForward });
  setup(board, board.rp2040.core.registers);
  for (let t = MS; board.halted === null && t <= 20 * MS; t += MS) board.runUntil(t);
  assert.match(board.halted ?? 'still running', /breakpoint #240/);
  return {
    nanos: board.clock.nanos,
    registers: [...board.rp2040.core.registers],
    instructions: board.instructions,
    skips: board.fastForwardStats.skips,
  };
}

/** Runs with and without fast-forward; the two runs must agree exactly. */
function both(program, setup) {
  const slow = run(program, false, setup);
  const fast = run(program, true, setup);
  assert.equal(fast.nanos, slow.nanos, 'leaves the loop at the same simulated nanosecond');
  assert.deepEqual(fast.registers, slow.registers);
  assert.equal(slow.skips, 0);
  return { slow, fast };
}

/** A flag in RAM that an alarm (standing in for an interrupt's effect) sets at `at` ns. */
function flagAt(at) {
  return (board, r) => {
    r[0] = FLAG;
    const set = () => board.rp2040.sramView.setUint32(FLAG - 0x20000000, 1, true);
    board.clock.createAlarm(set).schedule(at);
  };
}

/** UART0 at 1 Mbaud (125 MHz / (16 x (7 + 52/64))), 8N1, FIFOs on, enabled. */
function uartOn(board) {
  const u = board.uart;
  u.writeUint32(0x24, 7);
  u.writeUint32(0x28, 52);
  u.writeUint32(0x2c, (3 << 5) | (1 << 4));
  u.writeUint32(0x30, (1 << 9) | (1 << 8) | 1);
}

test('a loop polling a RAM flag is skipped up to the alarm that sets it, exit time unchanged', () => {
  const program = [
    0x6801, // 0: ldr r1, [r0]
    0x2900, // 2: cmp r1, #0
    0xd0fc, // 4: beq 0
    BKPT_DONE,
  ];
  const at = 3 * MS + 4; // not on a loop-turn boundary
  const { slow, fast } = both(program, flagAt(at));
  assert.ok(slow.nanos > at && slow.nanos < at + 100, `left at ${slow.nanos} ns`);
  assert.ok(fast.skips > 0, 'skipped');
  const counts = `${fast.instructions} vs ${slow.instructions}`;
  assert.ok(fast.instructions * 100 < slow.instructions, counts);
});

test('the BUSY spin after three UART characters ends 30 us later, skipped, exit unchanged', () => {
  const program = [
    0x6981, // 0: ldr r1, [r0, #0x18]   UARTFR
    0x0709, // 2: lsls r1, r1, #28      BUSY (bit 3) into N
    0xd4fc, // 4: bmi 0
    BKPT_DONE,
  ];
  const { slow, fast } = both(program, (board, r) => {
    uartOn(board);
    for (const b of [0x55, 0xaa, 0x55]) board.uart.writeUint32(0, b);
    r[0] = UART0;
  });
  assert.ok(slow.nanos >= 30_000 && slow.nanos < 30_100, `left at ${slow.nanos} ns`);
  assert.ok(fast.skips > 0, 'skipped');
});

test('a loop reading the free-running TIMER is never skipped', () => {
  const program = [
    0x6801, // 0: ldr r1, [r0]   TIMERAWL (microseconds)
    0x4291, // 2: cmp r1, r2
    0xd3fc, // 4: bcc 0
    BKPT_DONE,
  ];
  const { slow, fast } = both(program, (_board, r) => {
    r[0] = TIMERAWL;
    r[2] = 2000;
  });
  assert.ok(slow.nanos >= 2 * MS && slow.nanos < 2 * MS + 100, `left at ${slow.nanos} ns`);
  assert.equal(fast.skips, 0);
});

test('a loop draining the RX FIFO through UARTDR is never skipped (a read that pops)', () => {
  const program = [
    0x6981, // 0: ldr r1, [r0, #0x18]   UARTFR
    0x06c9, // 2: lsls r1, r1, #27      RXFE (bit 4) into N
    0xd401, // 4: bmi 10
    0x6801, // 6: ldr r1, [r0]          UARTDR: the same byte every turn
    0xe7fa, // 8: b 0
    BKPT_DONE,
  ];
  const { fast } = both(program, (board, r) => {
    uartOn(board);
    for (let i = 0; i < 8; i++) board.uart.receiveChar(0xff);
    r[0] = UART0;
  });
  assert.equal(fast.skips, 0);
});

test('a loop that writes memory is never skipped', () => {
  const program = [
    0x6023, // 0: str r3, [r4]
    0x6801, // 2: ldr r1, [r0]
    0x2900, // 4: cmp r1, #0
    0xd0fb, // 6: beq 0
    BKPT_DONE,
  ];
  const { fast } = both(program, (board, r) => {
    flagAt(MS + 4)(board, r);
    r[3] = 7;
    r[4] = 0x20000200;
  });
  assert.equal(fast.skips, 0);
});
