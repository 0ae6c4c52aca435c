//! A stand-in for the RP2040 boot ROM: the lookup tables at 0x14/0x16/0x18 and the flash and memory
//! helpers embassy-rp calls through them, each a two-instruction stub (`bkpt #n; bx lr`) whose work is
//! done here in JS. Flash follows NOR rules: erase sets 4 KB sectors to 0xff, program can only clear
//! bits (new = old & data), so a driver that forgets to erase shows it. The real ROM is not shipped
//! with rp2040js and is not needed for the rest of an embassy app.

const STUB_BASE = 0x200;
const FUNC_TABLE = 0x100;
const DATA_TABLE = 0x1c0;
export const SECTOR = 4096;

const code = (s) => s.charCodeAt(0) | (s.charCodeAt(1) << 8);

// How long the flash chip is busy, typical values of the W25Q16JV datasheet (estimates: the real
// part varies, up to 400 ms per sector erase and 3 ms per page program at worst). Simulated time
// advances by these while the ROM call runs, with interrupts masked as on the board.
const ERASE_NANOS_PER_SECTOR = 45e6;
const PROGRAM_NANOS_PER_PAGE = 0.7e6;

/**
 * Installs the stand-in ROM into `rp2040.bootrom` and hooks `onBreak`. `hooks.onFlashWrite(kind,
 * offset, length)` is told of every erase/program after it is applied; it may return 'reset' to
 * request a reset (the runner's reset-during-write test point).
 */
export function installBootrom(rp2040, hooks = {}) {
  const { core } = rp2040;
  const regs = core.registers;
  const flash = rp2040.flash;
  const u8 = (addr) => rp2040.readUint8(addr);
  const functions = [
    ['IF', () => {}], // connect_internal_flash
    ['EX', () => {}], // flash_exit_xip
    ['FC', () => {}], // flash_flush_cache
    ['CX', () => {}], // flash_enter_cmd_xip
    [
      'RE', // flash_range_erase(offset, count, block_size, block_cmd)
      () => {
        const offset = regs[0] >>> 0;
        const count = regs[1] >>> 0;
        const start = offset - (offset % SECTOR);
        const end = Math.min(flash.length, Math.ceil((offset + count) / SECTOR) * SECTOR);
        flash.fill(0xff, start, end);
        rp2040.clock.tick(((end - start) / SECTOR) * ERASE_NANOS_PER_SECTOR);
        hooks.onFlashWrite?.('erase', start, end - start);
      },
    ],
    [
      'RP', // flash_range_program(offset, data, count)
      () => {
        const offset = regs[0] >>> 0;
        const data = regs[1] >>> 0;
        const count = regs[2] >>> 0;
        const torn = hooks.tornProgram?.(offset, count);
        const n = torn === undefined ? count : torn;
        for (let i = 0; i < n && offset + i < flash.length; i++) flash[offset + i] &= u8(data + i);
        rp2040.clock.tick(Math.ceil(n / 256) * PROGRAM_NANOS_PER_PAGE);
        hooks.onFlashWrite?.('program', offset, n);
      },
    ],
    [
      'C4', // memcpy44(dest, src, n)
      () => copy(rp2040, regs[0] >>> 0, regs[1] >>> 0, regs[2] >>> 0),
    ],
    [
      'MC', // memcpy(dest, src, n)
      () => copy(rp2040, regs[0] >>> 0, regs[1] >>> 0, regs[2] >>> 0),
    ],
    [
      'S4', // memset4(ptr, c, n)
      () => fill(rp2040, regs[0] >>> 0, regs[1] & 0xff, regs[2] >>> 0),
    ],
    [
      'MS', // memset(ptr, c, n)
      () => fill(rp2040, regs[0] >>> 0, regs[1] & 0xff, regs[2] >>> 0),
    ],
  ];

  const rom = new Uint8Array(rp2040.bootrom.buffer);
  rom.fill(0);
  const view = new DataView(rp2040.bootrom.buffer);
  view.setUint32(0, 0x20042000, true);
  rom.set([0x4d, 0x75, 0x01, 0x03], 0x10); // 'M' 'u' 0x01, version 3 (RP2040 B2)
  view.setUint16(0x14, FUNC_TABLE, true);
  view.setUint16(0x16, DATA_TABLE, true);
  const stub = (n) => {
    const addr = STUB_BASE + 4 * n;
    view.setUint16(addr, 0xbe00 | n, true); // bkpt #n
    view.setUint16(addr + 2, 0x4770, true); // bx lr
    return addr | 1;
  };
  view.setUint16(0x18, stub(0), true); // rom_table_lookup
  functions.forEach(([name], i) => {
    view.setUint16(FUNC_TABLE + 4 * i, code(name), true);
    view.setUint16(FUNC_TABLE + 4 * i + 2, stub(i + 1), true);
  });

  const lookup = () => {
    let table = regs[0] >>> 0;
    const wanted = regs[1] & 0xffff;
    for (;;) {
      const c = view.getUint16(table, true);
      if (c === 0) break;
      if (c === wanted) {
        regs[0] = view.getUint16(table + 2, true);
        return;
      }
      table += 4;
    }
    const name = String.fromCharCode(wanted & 0xff, wanted >> 8);
    hooks.warn?.(`boot ROM function or data '${name}' is not provided by the emulator runner`);
    regs[0] = 0;
  };

  rp2040.onBreak = (n) => {
    if (n === 0) return lookup();
    const entry = functions[n - 1];
    if (!entry) {
      hooks.onBreakpoint?.(n, core.PC);
      return;
    }
    entry[1]();
  };
}

function copy(rp2040, dest, src, n) {
  for (let i = 0; i < n; i++) rp2040.writeUint8(dest + i, rp2040.readUint8(src + i));
}

function fill(rp2040, dest, value, n) {
  for (let i = 0; i < n; i++) rp2040.writeUint8(dest + i, value);
}
