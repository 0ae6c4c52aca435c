//! The hardware page's pin table (`docs/hardware.md`, "Pin map") and the pins `rp.rs` opens are
//! the firmware's one pin map, `firmware::pins`: a page or an `rp.rs` that disagrees fails here.

use firmware::pins::{BUS_UART, PINS};

fn read(rel: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `(gpio, function, connects to)` of each row of the "## Pin map" section's table.
fn page_rows(page: &str) -> Vec<(u8, String, String)> {
    let section = page
        .split("\n## ")
        .find(|s| s.starts_with("Pin map"))
        .expect("docs/hardware.md has a \"## Pin map\" section");
    section
        .lines()
        // Rows, not the header: `| GPIO<n> |`.
        .filter(|l| {
            l.strip_prefix("| GPIO")
                .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
        })
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
            assert_eq!(
                cells.len(),
                4,
                "pin row `{l}`: GPIO, Pico pin, function, connects to"
            );
            let gpio = cells[0]
                .strip_prefix("GPIO")
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("pin row `{l}`: `{}` is not GPIO<n>", cells[0]));
            (gpio, cells[2].to_owned(), cells[3].to_owned())
        })
        .collect()
}

#[test]
fn the_hardware_page_lists_exactly_the_firmware_pins() {
    let rows = page_rows(&read("../docs/hardware.md"));
    let want: Vec<(u8, String, String)> = PINS
        .iter()
        .map(|p| (p.gpio, p.function.to_owned(), p.connects.to_owned()))
        .collect();
    assert_eq!(
        rows, want,
        "docs/hardware.md's pin table against firmware::pins"
    );
}

#[test]
fn rp_rs_opens_the_uart_and_pins_of_the_table() {
    let rp = read("src/rp.rs");
    assert!(
        rp.contains(&format!("p.UART{BUS_UART},")),
        "rp.rs opens UART{BUS_UART}"
    );
    for p in PINS {
        assert!(
            rp.contains(&format!("p.PIN_{},", p.gpio)),
            "rp.rs does not open PIN_{} ({})",
            p.gpio,
            p.function
        );
    }
}

#[test]
fn the_page_parser_reads_a_changed_row() {
    // The check can fail: a page that moved the direction pin reads differently.
    let page = "# Page\n\n## Pin map\n\n| GPIO | Pico pin | function | connects to |\n|---|---|---|---|\n\
                | GPIO3 | 5 | bus direction | x |\n";
    assert_eq!(
        page_rows(page),
        vec![(3, "bus direction".to_owned(), "x".to_owned())]
    );
}
