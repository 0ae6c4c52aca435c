//! Prints the flash and static RAM use of a firmware ELF and fails when it is over budget.
//! Usage: `cargo run -p hil-tests --bin firmware-size -- target/thumbv6m-none-eabi/release/firmware`

fn main() -> anyhow::Result<()> {
    let path = std::env::args_os()
        .nth(1)
        .ok_or_else(|| anyhow::anyhow!("usage: firmware-size <firmware ELF>"))?;
    hil_tests::image::report(std::path::Path::new(&path))?;
    Ok(())
}
