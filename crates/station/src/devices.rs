//! `telerehab devices`: list what is connected.

/// Print the devices found.
pub fn run() -> anyhow::Result<()> {
    println!("device discovery is not in this build yet");
    Ok(())
}
