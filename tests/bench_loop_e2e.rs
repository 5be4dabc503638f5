//! `telerehab bench loop` end to end: a short run with a hub prints the station's and the
//! reference loop's lateness distributions and their ratio (no timing is asserted: the
//! figures belong in BENCHMARKS.md, not in a test on a shared machine).

use telerehab_tests::run_ok;

#[test]
fn bench_loop_prints_the_station_and_reference_distributions_and_their_ratio() {
    let out = run_ok(&[
        "bench",
        "loop",
        "--seconds",
        "1",
        "--with-hub",
        "--no-cyclictest",
    ]);
    let out = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.contains("lateness (µs)") && out.contains("p99.9"),
        "{out}"
    );
    let row = |name: &str| -> Vec<f64> {
        let line = out
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no {name} row in {out}"));
        line[name.len()..]
            .split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    // ticks, p50, p99, p99.9, max (and the skipped deadlines).
    for name in ["station (haptic loop)", "reference (same CPU)"] {
        let v = row(name);
        assert!(v.len() >= 5 && v[0] >= 1000.0, "{name}: {v:?} in {out}");
        assert!(
            v[1] <= v[2] && v[2] <= v[3] && v[3] <= v[4],
            "{name}: {v:?}"
        );
    }
    assert_eq!(row("station / reference").len(), 4, "{out}");
    // The hub acknowledged what the station sent.
    assert!(out.contains("summaries sent"), "{out}");
}
