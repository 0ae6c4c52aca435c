//! Host pacing (pace.js) against real processes: a child blocked in a read is waited for by no one
//! (the slice may run), a child spinning in a loop holds simulated time, and one that never blocks
//! is given up on after the stuck limit with one warning. Independent truth: the kernel's own
//! thread states in /proc (S while blocked in read, R while computing).

import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdirSync, mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';
import { HostPacer, taskState } from '../src/pace.js';

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

test('the state letter follows the last parenthesis of the command name', () => {
  assert.equal(taskState('123 (python3) S 1 2 3'), 'S');
  assert.equal(taskState('123 (a) b (c)) R 1 2 3'), 'R');
  assert.equal(taskState('garbage'), '?');
});

test('a blocked host lets time pass, a computing one holds it', async () => {
  // Blocked reading its stdin (a pipe nobody writes to).
  const blocked = spawn('cat', [], { stdio: 'pipe' });
  // Computing: a loop that never blocks.
  const busy = spawn('sh', ['-c', 'while :; do :; done'], { stdio: 'ignore' });
  try {
    // Started and blocked in its read (on a loaded machine that can take a moment).
    const idle = new HostPacer([blocked.pid]);
    for (let i = 0; i < 100 && idle.runnable() !== null; i++) await sleep(50);
    assert.equal(idle.runnable(), null);
    assert.equal(idle.mayRun(0), true);
    const held = new HostPacer([blocked.pid, busy.pid]);
    // A spinning process may be off the CPU for a moment but stays runnable (R) throughout.
    assert.match(held.runnable() ?? 'none', new RegExp(`^${busy.pid}/`));
    assert.equal(held.mayRun(0), false);
    assert.equal(held.stats.held, 1);
  } finally {
    blocked.kill();
    busy.kill();
  }
});

test('a process gone waits for nothing; one runnable past the stuck limit is warned about once', () => {
  // A fake /proc: pid 7 has one running thread, pid 8 does not exist.
  const proc = mkdtempSync(join(tmpdir(), 'pace-'));
  mkdirSync(join(proc, '7/task/7'), { recursive: true });
  writeFileSync(join(proc, '7/task/7/stat'), '7 (spinner) R 1 7 7');
  assert.equal(new HostPacer([8], { proc }).mayRun(0), true);
  const warnings = [];
  const pacer = new HostPacer([7], { proc, onWarn: (m) => warnings.push(m) });
  assert.equal(pacer.mayRun(0), false);
  assert.equal(pacer.mayRun(4999), false);
  assert.equal(pacer.mayRun(5001), true);
  assert.equal(pacer.mayRun(6000), true);
  assert.equal(warnings.length, 1);
  assert.match(warnings[0], /thread 7\/7 has been runnable for 5000 ms/);
  // Once it blocks, the clock starts over.
  writeFileSync(join(proc, '7/task/7/stat'), '7 (spinner) S 1 7 7');
  assert.equal(pacer.mayRun(7000), true);
  writeFileSync(join(proc, '7/task/7/stat'), '7 (spinner) R 1 7 7');
  assert.equal(pacer.mayRun(8000), false);
});
