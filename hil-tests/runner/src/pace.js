//! Host pacing: simulated time passes only while the host waits, as on the in-process virtual robot.
//!
//! Free-running, the emulator races its host's wall clock: a host descheduled by a loaded machine
//! for half a second misses 100 bus cycles of a board that runs at 0.2 x real time, and a rule
//! counted in board cycles (the setpoint timeout of streaming) trips although the host did nothing
//! slower than its own code. With `--paced-by PID,...` the runner runs its next slice of simulated
//! time only when no thread of those processes is runnable (state R in /proc/PID/task/TID/stat):
//! the host (pytest, blocked reading the port or sleeping in `Board.wait`) and the pty bridge (the
//! `hil-emulator` process, which carries the host's bytes to the runner). A host that is computing,
//! or waiting for a CPU, stops the board's clock; it goes on once the host blocks again.
//!
//! What remains of the wall clock: the kernel hands bytes written to a pty to its reader from a
//! worker thread, so between the writer blocking and the reader waking the runner may run a slice
//! or two (1 ms of simulated time each) without those bytes: microseconds to milliseconds of board
//! time, never the tens of cycles of a descheduled host.
//!
//! A watched thread that never blocks (a spinning helper thread) would stop the board for good: after
//! STUCK_MS of wall time in one stretch the runner says so once (a `warn` event) and runs on.

import { readFileSync, readdirSync } from 'node:fs';

/** Wall time a watched process may stay runnable before the runner runs on regardless, ms. */
const STUCK_MS = 5000;

/** State letter of a /proc stat line (`pid (comm) S ...`; comm may contain spaces and parens). */
export function taskState(stat) {
  const close = stat.lastIndexOf(')');
  return close < 0 ? '?' : stat.charAt(close + 2);
}

export class HostPacer {
  /**
   * @param pids processes whose threads must all be blocked for simulated time to pass
   * @param onWarn called once with a message when a process stays runnable past STUCK_MS
   * @param proc the proc file system's root (tests give a fake one)
   */
  constructor(pids, { onWarn, proc = '/proc' } = {}) {
    this.pids = pids;
    this.onWarn = onWarn;
    this.proc = proc;
    this.busySince = null;
    this.warned = false;
    this.stats = { checks: 0, held: 0 };
  }

  /** The first runnable thread of a watched process, as `pid/tid`, or null when all are blocked. */
  runnable() {
    for (const pid of this.pids) {
      let tids;
      try {
        tids = readdirSync(`${this.proc}/${pid}/task`);
      } catch {
        continue; // gone: it waits for nothing any more
      }
      for (const tid of tids) {
        let stat;
        try {
          stat = readFileSync(`${this.proc}/${pid}/task/${tid}/stat`, 'latin1');
        } catch {
          continue; // the thread ended between the listing and the read
        }
        if (taskState(stat) === 'R') return `${pid}/${tid}`;
      }
    }
    return null;
  }

  /** True when the next slice may run: every watched thread blocked (or stuck past STUCK_MS). */
  mayRun(wallMs) {
    this.stats.checks++;
    const busy = this.runnable();
    if (busy === null) {
      this.busySince = null;
      return true;
    }
    this.busySince ??= wallMs;
    if (wallMs - this.busySince > STUCK_MS) {
      if (!this.warned) {
        this.warned = true;
        this.onWarn?.(
          `host pacing: thread ${busy} has been runnable for ${STUCK_MS} ms without blocking; ` +
            'simulated time runs on beside it (the board no longer waits for the host)',
        );
      }
      return true;
    }
    this.stats.held++;
    return false;
  }
}
