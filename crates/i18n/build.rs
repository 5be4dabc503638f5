//! Rebuild when a catalogue file is added or removed: the embedding derive sees the files
//! present at compile time, and cargo alone would not notice a new one (the station's
//! `locales/` and the console's `console/`).

fn main() {
    println!("cargo:rerun-if-changed=locales");
    println!("cargo:rerun-if-changed=console");
}
