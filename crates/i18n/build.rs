//! Rebuild when a catalogue file is added or removed: the embedding derive sees the files
//! present at compile time, and cargo alone would not notice a new one.

fn main() {
    println!("cargo:rerun-if-changed=locales");
}
