//! The bus link's lock step and wire timing, against a scripted servo chain process that answers
//! every burst with a fixed status packet after a fixed return delay: the times are computed by hand
//! from the character time (10 bits at 1 Mbaud = 10 us).

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { RP2040 } from 'rp2040js';
import { BusLink } from '../src/bus.js';
import { PacedUart } from '../src/uart.js';

const PEER = `
  const rl = require('node:readline').createInterface({ input: process.stdin });
  rl.on('line', (l) => {
    const m = JSON.parse(l);
    const reply = m.tx === '02'
      ? { segments: [{ delay_ns: 100000, rx: 'a1' }, { delay_ns: 50000, rx: 'b2c3' }] }
      : { rx: 'a1b2c3', delay_ns: 250000 };
    if (m.tx !== undefined) process.stdout.write(JSON.stringify(reply) + '\\n');
  });`;

function rig() {
  const rp2040 = new RP2040();
  const clock = rp2040.clock;
  const uart = new PacedUart(rp2040, 'UART0', 20);
  // 1 Mbaud 8N1 with FIFOs, enabled.
  uart.writeUint32Atomic(0x24, 7, 0);
  uart.writeUint32Atomic(0x28, 52, 0);
  uart.writeUint32Atomic(0x2c, (3 << 5) | (1 << 4), 0);
  uart.writeUint32Atomic(0x30, (1 << 9) | (1 << 8) | 1, 0);
  const pin = { outputValue: true };
  const board = { rp2040: { clock, gpio: { 2: pin } }, uart, epoch: 0, hold: false };
  board.simNanos = (n = clock.nanos) => n;
  const received = [];
  const receive = uart.receiveChar.bind(uart);
  uart.receiveChar = (b) => {
    received.push([b, clock.nanos]);
    receive(b);
  };
  let replied;
  const reply = new Promise((r) => (replied = r));
  const bus = new BusLink([process.execPath, '-e', PEER], { onReply: () => replied() });
  bus.attach(board);
  return { clock, uart, pin, board, bus, received, reply };
}

test('a burst is sent when the line goes idle and time holds until the answer', async () => {
  const { clock, uart, pin, board, bus, received, reply } = rig();
  try {
    for (const b of [0xff, 0xff, 0xfd]) uart.writeUint32Atomic(0, b, 0);
    clock.tick(30_000); // three characters: the burst ends at 30 us
    assert.equal(board.hold, true, 'simulated time is held for the servo chain');
    assert.equal(bus.stats.txChars, 3);
    await reply;
    assert.equal(board.hold, false);
    pin.outputValue = false; // firmware turns the bus around to listen
    clock.tick(1_000_000);
    // 30 us + 250 us return delay, then one character time per byte.
    assert.deepEqual(received, [
      [0xa1, 290_000],
      [0xb2, 300_000],
      [0xc3, 310_000],
    ]);
  } finally {
    bus.close();
  }
});

test('chained replies keep their gaps', async () => {
  const { clock, uart, pin, bus, received, reply } = rig();
  try {
    uart.writeUint32Atomic(0, 0x02, 0);
    clock.tick(10_000); // burst ends at 10 us
    await reply;
    pin.outputValue = false;
    clock.tick(1_000_000);
    // 10 + 100 + 10 = 120 us; then 50 us gap after it: 120 + 50 + 10 = 180, 190.
    assert.deepEqual(received, [
      [0xa1, 120_000],
      [0xb2, 180_000],
      [0xc3, 190_000],
    ]);
  } finally {
    bus.close();
  }
});

test('a reply overlapping another one on the wire arrives corrupted, never all at once', async () => {
  const { clock, uart, pin, bus, received, reply } = rig();
  try {
    uart.writeUint32Atomic(0, 0x01, 0);
    clock.tick(10_000); // burst ends at 10 us; its reply is due at 270..290 us
    await reply;
    // A second answer whose bytes would land on top of the first one's.
    bus.pendingReply = { end: 10_000, boardEpoch: 0 };
    bus.reply(JSON.stringify({ rx: '0102', delay_ns: 255_000 }));
    pin.outputValue = false;
    clock.tick(1_000_000);
    const times = received.map(([, t]) => t);
    assert.deepEqual(times, [270_000, 280_000, 290_000, 300_000, 310_000], 'one character time apart');
    assert.ok(bus.stats.collisions > 0);
    assert.notDeepEqual(
      received.map(([b]) => b),
      [0xa1, 0xb2, 0xc3, 0x01, 0x02],
    );
  } finally {
    bus.close();
  }
});

test('characters sent while the direction pin is low never reach the bus', async () => {
  const { clock, uart, pin, bus } = rig();
  try {
    uart.writeUint32Atomic(0, 0x55, 0);
    clock.tick(5_000);
    pin.outputValue = false; // dropped mid-character, before BUSY cleared
    clock.tick(10_000);
    assert.equal(bus.stats.lostTx, 1);
    assert.equal(bus.stats.bursts, 0);
  } finally {
    bus.close();
  }
});

test('a reply arriving while the board still drives the bus is lost', async () => {
  const { clock, uart, received, bus, reply } = rig();
  try {
    uart.writeUint32Atomic(0, 0x01, 0);
    clock.tick(10_000);
    await reply;
    clock.tick(1_000_000); // direction pin left high: the buffer does not pass the reply
    assert.equal(received.length, 0);
    assert.equal(bus.stats.lostRx, 3);
  } finally {
    bus.close();
  }
});
