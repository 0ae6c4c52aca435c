//! The runner's control channel: JSON lines on stdin (commands) and stdout (replies and events).
//!
//! Command: `{"id": 7, "cmd": "time"}`; reply: `{"id": 7, "ok": true, ...}` or
//! `{"id": 7, "ok": false, "error": "..."}`. Events carry no id: `{"event": "log", "sim_ns": ..,
//! "line": ".."}`, `ready`, `usb_configured`, `reset`, `halted`, `warn`, `fatal`.
//!
//! Commands (see main.js for the fields): time, wait_until {sim_ns}, reset,
//! reset_on_flash_program {nth, torn_bytes?}, usb_replug, usb_pending, save_flash,
//! bus_trace {on}, usb_trace {on}, usb_out_delay {ns}, bus_control {msg}, stats, quit.

import { createInterface } from 'node:readline';

export class Control {
  constructor(input, output) {
    this.output = output;
    this.handlers = {};
    this.onClose = null;
    const lines = createInterface({ input });
    lines.on('line', (line) => this.dispatch(line));
    lines.on('close', () => this.onClose?.());
  }

  send(obj) {
    this.output.write(JSON.stringify(obj) + '\n');
  }

  event(name, fields = {}) {
    this.send({ event: name, ...fields });
  }

  dispatch(line) {
    if (line.trim() === '') return;
    let cmd;
    try {
      cmd = JSON.parse(line);
    } catch (e) {
      this.event('warn', { msg: `control line is not JSON (${e.message}): ${line.slice(0, 80)}` });
      return;
    }
    const reply = (fields) => this.send({ id: cmd.id, ok: true, ...fields });
    const handler = this.handlers[cmd.cmd];
    if (!handler) {
      this.send({ id: cmd.id, ok: false, error: `unknown command '${cmd.cmd}'` });
      return;
    }
    try {
      const result = handler(cmd, reply);
      if (result !== undefined) reply(result);
    } catch (e) {
      this.send({ id: cmd.id, ok: false, error: e.message });
    }
  }
}
