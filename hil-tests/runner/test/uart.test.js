//! Wire timing of the PacedUart model against the PL011 rules and hand-computed character times,
//! driven through its registers the way embassy-rp drives them (no firmware involved).

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { RP2040 } from 'rp2040js';
import { PacedUart } from '../src/uart.js';

const DR = 0x00;
const FR = 0x18;
const IBRD = 0x24;
const FBRD = 0x28;
const LCR_H = 0x2c;
const CR = 0x30;
const IFLS = 0x34;
const IMSC = 0x38;
const RIS = 0x3c;
const DMACR = 0x48;
const BUSY = 1 << 3;
const TXIS = 1 << 5;
const RTIS = 1 << 6;

function chip() {
  const clock = new RP2040().clock; // a SimulationClock
  const irqs = [];
  const rp2040 = {
    clock,
    clkPeri: 125e6,
    setInterrupt: (irq, level) => irqs.push(level),
    logger: { warn() {}, error() {}, info() {}, debug() {} },
  };
  const uart = new PacedUart(rp2040, 'UART0', 20);
  return { clock, uart, irqs };
}

/** embassy-rp's setup for 8N1 with FIFOs: divisors for `baud` at clk_peri = 125 MHz. */
function setup(uart, baud) {
  const div = 125e6 / (16 * baud);
  uart.writeUint32Atomic(IBRD, Math.floor(div), 0);
  uart.writeUint32Atomic(FBRD, Math.round((div % 1) * 64), 0);
  uart.writeUint32Atomic(LCR_H, (0b11 << 5) | (1 << 4), 0);
  uart.writeUint32Atomic(IFLS, 0b100 << 3, 0);
  uart.writeUint32Atomic(CR, (1 << 9) | (1 << 8) | 1, 0);
}

test('UARTDMACR reads 0 until written (defect 1)', () => {
  const { uart } = chip();
  assert.equal(uart.readUint32(DMACR), 0);
});

test('a character takes 10 bit periods at 1 Mbaud 8N1 and BUSY covers it', () => {
  const { clock, uart } = chip();
  setup(uart, 1_000_000);
  const times = [];
  uart.onTxChar = (byte, start, end) => times.push([byte, start, end]);
  for (const b of [1, 2, 3]) uart.writeUint32Atomic(DR, b, 0);
  assert.ok(uart.readUint32(FR) & BUSY, 'BUSY right after the write');
  clock.tick(29_990);
  assert.equal(times.length, 2);
  assert.ok(uart.readUint32(FR) & BUSY, 'BUSY while the third character is on the wire');
  clock.tick(20);
  assert.deepEqual(times, [
    [1, 0, 10_000],
    [2, 10_000, 20_000],
    [3, 20_000, 30_000],
  ]);
  assert.equal(uart.readUint32(FR) & BUSY, 0, 'BUSY clears after the last stop bit');
});

test('4 Mbaud: 2.5 us per character', () => {
  const { clock, uart } = chip();
  setup(uart, 4_000_000);
  const ends = [];
  uart.onTxChar = (_b, _s, end) => ends.push(end);
  uart.writeUint32Atomic(DR, 0x55, 0);
  uart.writeUint32Atomic(DR, 0xaa, 0);
  clock.tick(10_000);
  assert.deepEqual(ends, [2_500, 5_000]);
});

test('TX interrupt fires once as the FIFO drains through 1/8 (defect 2)', () => {
  const { clock, uart } = chip();
  setup(uart, 1_000_000);
  uart.writeUint32Atomic(IMSC, TXIS, 0);
  for (let i = 0; i < 10; i++) uart.writeUint32Atomic(DR, i, 0);
  // 1 character in the shift register, 9 in the FIFO: the level is above 4, no interrupt.
  assert.equal(uart.readUint32(RIS) & TXIS, 0);
  clock.tick(10_000 * 4 + 1); // five characters have started: 5 left in the FIFO
  assert.equal(uart.readUint32(RIS) & TXIS, 0);
  clock.tick(10_000); // the sixth starts: 4 left, the trigger level
  assert.ok(uart.readUint32(RIS) & TXIS);
  uart.writeUint32Atomic(0x44, TXIS, 0); // ICR
  clock.tick(100_000);
  assert.equal(uart.readUint32(RIS) & TXIS, 0, 'not raised again while draining to empty');
});

test('receive timeout after 32 idle bit periods', () => {
  const { clock, uart } = chip();
  setup(uart, 1_000_000);
  uart.writeUint32Atomic(IMSC, RTIS, 0);
  uart.receiveChar(0x42);
  clock.tick(31_900);
  assert.equal(uart.readUint32(RIS) & RTIS, 0);
  clock.tick(200);
  assert.ok(uart.readUint32(RIS) & RTIS);
  assert.equal(uart.readUint32(DR), 0x42);
  assert.equal(uart.readUint32(RIS) & RTIS, 0, 'cleared once the FIFO is empty');
});
