//! `telerehab`: the patient station and the therapist hub.

fn main() -> anyhow::Result<()> {
    station::cli::main()
}
