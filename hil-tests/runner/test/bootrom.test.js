//! The stand-in boot ROM: the lookup table finds the flash functions by their two-letter codes (RP2040
//! datasheet 2.8.3), and the flash follows NOR rules: erase sets whole 4 KB sectors to 0xFF, program
//! can only clear bits (0xF0 then 0x0F gives 0x00).

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { RP2040 } from 'rp2040js';
import { installBootrom } from '../src/bootrom.js';

function rom() {
  const rp2040 = new RP2040();
  rp2040.logger = { warn() {}, error() {}, info() {}, debug() {} };
  const writes = [];
  installBootrom(rp2040, { onFlashWrite: (...w) => writes.push(w) });
  const r = rp2040.core.registers;
  const view = new DataView(rp2040.bootrom.buffer);
  /** Calls a ROM function the way embassy-rp does: look it up, then run its stub. */
  const call = (name, ...args) => {
    r[0] = view.getUint16(0x14, true);
    r[1] = name.charCodeAt(0) | (name.charCodeAt(1) << 8);
    const lookup = view.getUint16(0x18, true);
    rp2040.onBreak(view.getUint16(lookup & ~1, true) & 0xff);
    const fn = r[0];
    assert.equal(fn & 1, 1, `${name}: a Thumb function pointer`);
    const insn = view.getUint16(fn & ~1, true);
    assert.equal(insn >> 8, 0xbe, `${name}: stub starts with bkpt`);
    args.forEach((a, i) => (r[i] = a));
    rp2040.onBreak(insn & 0xff);
  };
  return { rp2040, call, writes };
}

test('ROM header and lookup table', () => {
  const { rp2040 } = rom();
  const bytes = new Uint8Array(rp2040.bootrom.buffer);
  assert.deepEqual([...bytes.subarray(0x10, 0x13)], [0x4d, 0x75, 0x01]); // 'M' 'u' 1
});

test('erase sets one 4 KB sector to 0xFF and takes 45 ms of simulated time', () => {
  const { rp2040, call } = rom();
  rp2040.flash.fill(0x00, 0, 0x3000);
  const t0 = rp2040.clock.nanos;
  call('RE', 0x1000, 4096, 1 << 31, 0);
  assert.equal(rp2040.clock.nanos - t0, 45e6);
  assert.ok(rp2040.flash.subarray(0x1000, 0x2000).every((b) => b === 0xff));
  assert.equal(rp2040.flash[0x0fff], 0x00, 'sector below untouched');
  assert.equal(rp2040.flash[0x2000], 0x00, 'sector above untouched');
});

test('program only clears bits', () => {
  const { rp2040, call, writes } = rom();
  rp2040.sram.fill(0xf0, 0, 256);
  rp2040.sram.fill(0x0f, 256, 512);
  call('RP', 0x4000, 0x20000000, 256);
  assert.equal(rp2040.flash[0x4000], 0xf0);
  call('RP', 0x4000, 0x20000100, 256);
  assert.ok(rp2040.flash.subarray(0x4000, 0x4100).every((b) => b === 0x00));
  assert.equal(rp2040.flash[0x4100], 0xff, 'past the programmed range');
  assert.deepEqual(writes, [
    ['program', 0x4000, 256],
    ['program', 0x4000, 256],
  ]);
});

test('memcpy44 copies words between RAM areas', () => {
  const { rp2040, call } = rom();
  rp2040.sram.set([1, 2, 3, 4, 5, 6, 7, 8], 0);
  call('C4', 0x20000100, 0x20000000, 8);
  assert.deepEqual([...rp2040.sram.subarray(0x100, 0x108)], [1, 2, 3, 4, 5, 6, 7, 8]);
});
