//! The release firmware image boots, logs over defmt (decoded by defmt-print from the RTT buffer),
//! opens the bus UART at the configured rate and enumerates as a USB CDC-ACM device whose pty
//! carries bytes to the firmware's read loop, and enumerates again after a cable re-plug. Runs on the emulator, or on a real board with DBOT_HIL_PORT.

use anyhow::{Context, Result};
use hil_tests::{Options, Target};
use std::io::Write;
use std::time::{Duration, Instant};

/// The gait store's (offset, size) as memory.x declares it: the independent source the firmware's
/// boot log must agree with.
fn gait_store_from_memory_x() -> Result<(u32, u32)> {
    let text = std::fs::read_to_string(hil_tests::paths::repo_root().join("memory.x"))?;
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("GAITS"))
        .context("memory.x has no GAITS region")?;
    let origin = line.split("ORIGIN =").nth(1).context("GAITS ORIGIN")?;
    let origin = origin
        .split(',')
        .next()
        .unwrap()
        .trim()
        .trim_start_matches("0x");
    let origin = u32::from_str_radix(origin, 16)?;
    let length = line
        .split("LENGTH =")
        .nth(1)
        .context("GAITS LENGTH")?
        .trim();
    let kib: u32 = length.trim_end_matches('K').parse()?;
    Ok((origin - 0x1000_0000, kib * 1024))
}

#[test]
fn firmware_boots_and_its_defmt_logs_are_decoded() -> Result<()> {
    let wall = Instant::now();
    let Some(board) = Target::start("firmware_boots", Options::default())? else {
        return Ok(());
    };
    let (offset, size) = gait_store_from_memory_x()?;
    let banner = board.wait_for_log("drosophibot firmware", Duration::from_secs(2))?;
    assert!(
        banner.contains(&format!("firmware {}", env!("CARGO_PKG_VERSION"))),
        "banner names the workspace version: {banner}"
    );
    assert!(
        banner.contains(&format!("gait store {offset:#x}+{size:#x}")),
        "banner's gait store agrees with memory.x ({offset:#x}+{size:#x}): {banner}"
    );
    board.wait_for_log("bus UART up at 1000000 baud", Duration::from_secs(2))?;
    if let Some(emu) = board.emulator() {
        // The UART model derives the rate from the divisors the firmware programmed (IBRD/FBRD at
        // clk_peri = 125 MHz): 125e6 / (16 * (7 + 52/64)) = 1_000_000 exactly.
        let stats = emu.stats()?;
        assert_eq!(stats["uart"]["baud"], 1_000_000, "{stats}");
        let sim = emu.sim_time()?;
        println!(
            "boot test: {:.3} s simulated in {:.3} s wall",
            sim.as_secs_f64(),
            wall.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

#[test]
fn usb_cdc_enumerates_and_the_pty_carries_bytes_to_the_firmware() -> Result<()> {
    let Some(board) = Target::start("usb_cdc_enumerates", Options::default())? else {
        return Ok(());
    };
    board.wait_for_log("host connected", Duration::from_secs(2))?;
    let mut port = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(board.port())
        .with_context(|| format!("open {}", board.port().display()))?;
    // 1000 bytes = 15 full 64-byte packets and one of 40: exercises the re-armed OUT endpoint.
    let sent: Vec<u8> = (0..1000u32).map(|i| (i * 7) as u8).collect();
    port.write_all(&sent)?;
    port.flush()?;
    let Some(emu) = board.emulator() else {
        hil_tests::target::skip(
            "usb_cdc byte count",
            "a real board cannot be unplugged from software; the byte count is checked on the emulator",
        )?;
        return Ok(());
    };
    // The runner hands a packet over only into an OUT buffer the firmware has armed, so all bytes
    // arriving means the firmware's read loop took a packet and re-armed the endpoint each time:
    // ceil(1000 / 64) = 16 packets of at most the 64-byte max packet size it declared.
    let started = Instant::now();
    loop {
        let stats = emu.stats()?;
        if stats["usb"]["out"].as_u64() == Some(sent.len() as u64) {
            assert_eq!(stats["usb"]["out_packets"], 16, "{stats}");
            break;
        }
        anyhow::ensure!(
            started.elapsed() < Duration::from_secs(30),
            "the board took {} of {} bytes",
            stats["usb"]["out"],
            sent.len()
        );
        emu.run_for(Duration::from_millis(5))?;
    }
    assert_eq!(emu.usb_pending()?, 0);
    emu.usb_replug()?;
    // After the bus reset the host enumerates again and the link comes back.
    emu.wait_event_n("usb_configured", 2, Duration::from_secs(30))?;
    Ok(())
}

#[test]
fn emulator_models_pass_their_unit_tests() -> Result<()> {
    // The UART wire-timing model is checked against hand-computed PL011 timings by node:test.
    let runner = hil_tests::paths::runner_dir();
    let node_ok = std::process::Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !node_ok || !runner.join("node_modules/rp2040js").exists() {
        return hil_tests::target::skip(
            "emulator_models_pass_their_unit_tests",
            "node or hil-tests/runner/node_modules missing (run scripts/setup.d/30-hil.sh)",
        );
    }
    let out = std::process::Command::new("node")
        .args(["--test", "test/"])
        .current_dir(&runner)
        .output()?;
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}");
    anyhow::ensure!(out.status.success(), "node --test failed:\n{text}");
    Ok(())
}
