//! The station's parsers of untrusted input as properties: the configuration and regimen
//! TOML over arbitrary and mutated text, and `telerehab recover` over truncated and corrupted
//! recordings. None panics; a refusal names the problem (a bad value names its field and the
//! allowed range, a bad exercise its position); what is accepted reads back the same. The
//! same entry points run under cargo-fuzz: `fuzz/README.md`.

use proptest::prelude::*;
use record::recover::recover;
use regimen::Regimen;
use session::config::StationConfig;
use std::io::Cursor;
use std::path::Path;

/// A TOML float, as the user would type it (TOML spells NaN and the infinities `nan`, `inf`).
fn toml_float(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{v:?}")
    }
}

/// A value outside `[lo, hi]` (or the open end `(lo, …` when `open_lo`).
fn outside(lo: f64, hi: f64, open_lo: bool) -> impl Strategy<Value = f64> {
    let below = if open_lo {
        lo
    } else {
        lo - 1e-3 * (1.0 + lo.abs())
    };
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        (-1e12f64..=below),
        ((hi + 1e-3 * (1.0 + hi.abs()))..1e12f64),
    ]
}

/// Numeric configuration fields: (TOML table, key, lower end, upper end, lower end open).
const CONFIG_FIELDS: &[(&str, &str, f64, f64, bool)] = &[
    ("session", "duration_s", 0.001, 4.0 * 3600.0, false),
    ("session", "loop_rate_hz", 100.0, 2000.0, false),
    ("haptic", "road_feel_nm_per_kn", 0.0, 2.0, false),
    ("haptic", "replug_grace_s", 0.0, 600.0, false),
    ("haptic.safety", "slew_nm_per_s", 0.0, 10_000.0, true),
    ("haptic.safety", "soft_start_s", 0.0, 60.0, true),
    ("haptic.safety", "fade_out_s", 0.0, 5.0, true),
    ("haptic.safety", "max_tick_gap_s", 0.0, 1.0, true),
    ("haptic.safety", "max_reading_age_s", 0.0, 1.0, true),
    ("haptic.centring", "k_nm_per_rad", 0.0, 200.0, false),
    ("haptic.centring", "b_nm_s_per_rad", 0.0, 10.0, false),
    ("wheel", "gain", 0.0, 1.0, true),
    ("wheel", "rated_torque_nm", 0.0, 40.0, true),
];

fn sample_regimens() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../regimens");
    let mut texts: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    texts.sort();
    assert!(texts.len() >= 3, "the sample regimens are missing");
    texts
}

/// `text` with a few bytes replaced, inserted or removed, read back as (lossy) UTF-8.
fn mutate(text: &[u8], edits: &[(prop::sample::Index, u8, u8)]) -> String {
    let mut b = text.to_vec();
    for (at, op, byte) in edits {
        if b.is_empty() {
            b.push(*byte);
            continue;
        }
        let i = at.index(b.len());
        match op % 3 {
            0 => b[i] = *byte,
            1 => b.insert(i, *byte),
            _ => {
                b.remove(i);
            }
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

fn edits() -> impl Strategy<Value = Vec<(prop::sample::Index, u8, u8)>> {
    proptest::collection::vec(
        (
            any::<prop::sample::Index>(),
            any::<u8>(),
            prop_oneof![
                any::<u8>(),
                prop::sample::select(b"=[]\"'.,{}#\n -+0123456789eE".to_vec())
            ],
        ),
        1..6,
    )
}

fn check_config(text: &str) -> Result<(), TestCaseError> {
    match StationConfig::from_toml(text, "station.toml") {
        Ok(cfg) => {
            let back = toml::to_string(&cfg).map_err(|e| TestCaseError::fail(e.to_string()))?;
            let again = StationConfig::from_toml(&back, "again.toml")
                .map_err(|e| TestCaseError::fail(format!("{e}\n{back}")))?;
            prop_assert_eq!(again, cfg);
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(
                msg.contains("station.toml") || msg.contains("config"),
                "{msg}"
            );
            prop_assert!(msg.len() > 20, "{msg}");
        }
    }
    Ok(())
}

fn check_regimen(text: &str) -> Result<(), TestCaseError> {
    match Regimen::from_toml(text, "regimen.toml") {
        Ok(r) => {
            prop_assert!(!r.exercises.is_empty());
            let back = toml::to_string(&r).map_err(|e| TestCaseError::fail(e.to_string()))?;
            let again = Regimen::from_toml(&back, "again.toml")
                .map_err(|e| TestCaseError::fail(format!("{e}\n{back}")))?;
            prop_assert_eq!(again, r);
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.starts_with("regimen regimen.toml"), "{msg}");
            prop_assert!(msg.len() > 25, "{msg}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn a_config_value_out_of_range_is_refused_naming_its_field_and_range(
        (field, v) in (0..CONFIG_FIELDS.len()).prop_flat_map(|i| {
            let (_, _, lo, hi, open_lo) = CONFIG_FIELDS[i];
            (Just(i), outside(lo, hi, open_lo))
        }),
    ) {
        let (table, key, ..) = CONFIG_FIELDS[field];
        let text = format!("[{table}]\n{key} = {}\n", toml_float(v));
        let msg = StationConfig::from_toml(&text, "station.toml")
            .err()
            .map(|e| e.to_string())
            .ok_or_else(|| TestCaseError::fail(format!("accepted: {text}")))?;
        prop_assert!(msg.contains(key), "{text}: {msg} does not name {key}");
        prop_assert!(msg.contains("allowed"), "{text}: {msg} gives no range");
    }

    #[test]
    fn config_text_mutated_or_arbitrary_never_panics(
        edits in edits(),
        arbitrary in "[ -~\n]{0,200}",
    ) {
        let valid = toml::to_string(&StationConfig::default()).unwrap();
        check_config(&mutate(valid.as_bytes(), &edits))?;
        check_config(&arbitrary)?;
    }

    #[test]
    fn regimen_text_mutated_or_arbitrary_never_panics(
        which in any::<prop::sample::Index>(),
        edits in edits(),
        arbitrary in "[ -~\n]{0,200}",
    ) {
        let samples = sample_regimens();
        check_regimen(&mutate(which.get(&samples).as_bytes(), &edits))?;
        check_regimen(&arbitrary)?;
    }

    #[test]
    fn a_bad_regimen_value_is_refused_naming_the_exercise_and_field(
        good_before in 0usize..4,
        (key, table, bad) in prop_oneof![
            outside(0.0, 200.0, false).prop_map(|v| ("k_nm_per_rad", "[exercise.haptic.model]", v)),
            outside(0.0, 10.0, false).prop_map(|v| ("b_nm_s_per_rad", "[exercise.haptic.model]", v)),
            outside(0.0, 20.0, false).prop_map(|v| ("ceiling_nm", "[exercise.haptic]", v)),
            outside(0.0, 1.0, false).prop_map(|v| ("gain", "[[exercise.haptic.effects]]\nkind = { constant = { level_nm = 0.1 } }", v)),
        ],
    ) {
        let mut text = String::new();
        for _ in 0..good_before {
            text.push_str("[[exercise]]\nkind = \"straight\"\n\n");
        }
        text.push_str(&format!("[[exercise]]\nkind = \"dial\"\n{table}\n{key} = {}\n", toml_float(bad)));
        let msg = Regimen::from_toml(&text, "regimen.toml")
            .err()
            .map(|e| e.to_string())
            .ok_or_else(|| TestCaseError::fail(format!("accepted: {text}")))?;
        prop_assert!(msg.contains(key), "{msg} does not name {key}");
        prop_assert!(
            msg.contains(&format!("exercise {}", good_before + 1)),
            "{msg} does not name exercise {}",
            good_before + 1
        );
    }
}

/// A small recording in several chunks: two schemas, three channels, metadata, `n` messages.
fn recording(n: u64) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    let mut w = mcap::WriteOptions::new()
        .chunk_size(Some(512))
        .compression(Some(mcap::Compression::Zstd))
        .create(&mut out)
        .unwrap();
    let s1 = w
        .add_schema("telerehab.Wheel", "jsonschema", b"{}")
        .unwrap();
    let s2 = w
        .add_schema("telerehab.Score", "jsonschema", b"{}")
        .unwrap();
    let meta = std::collections::BTreeMap::new();
    let chans = [
        w.add_channel(s1, "/wheel", "json", &meta).unwrap(),
        w.add_channel(s2, "/score", "json", &meta).unwrap(),
        w.add_channel(0, "/raw", "cbor", &meta).unwrap(),
    ];
    for i in 0..n {
        let channel_id = chans[(i % 3) as usize];
        let body = format!("{{\"tick\":{i},\"torque_nm\":{}}}", (i as f64 * 0.01).sin());
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id,
                sequence: i as u32,
                log_time: i * 1_000_000,
                publish_time: i * 1_000_000,
            },
            body.as_bytes(),
        )
        .unwrap();
    }
    w.write_metadata(&mcap::records::Metadata {
        name: "session".into(),
        metadata: [("seed".to_string(), "7".to_string())].into(),
    })
    .unwrap();
    w.finish().unwrap();
    drop(w);
    out.into_inner()
}

/// Recover `bytes`; when it succeeds, the output is a finished recording holding what the
/// recovery says it copied.
fn check_recover(bytes: &[u8]) -> Result<Option<u64>, TestCaseError> {
    match recover(bytes, Cursor::new(Vec::new())) {
        Ok((copied, out)) => {
            let out = out.into_inner();
            let summary = mcap::Summary::read(&out)
                .map_err(|e| TestCaseError::fail(format!("unreadable summary: {e}")))?
                .ok_or_else(|| TestCaseError::fail("no summary section"))?;
            prop_assert_eq!(summary.channels.len(), copied.channels);
            let mut n = 0u64;
            for m in mcap::MessageStream::new(&out)
                .map_err(|e| TestCaseError::fail(format!("recovered file unreadable: {e}")))?
            {
                m.map_err(|e| TestCaseError::fail(format!("recovered message unreadable: {e}")))?;
                n += 1;
            }
            prop_assert_eq!(n, copied.messages);
            Ok(Some(n))
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.len() > 10, "{msg}");
            Ok(None)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn recover_of_a_truncated_recording_keeps_what_was_complete(cut in any::<prop::sample::Index>()) {
        let full = recording(300);
        let at = cut.index(full.len() + 1);
        let n = check_recover(&full[..at])?;
        // The writer puts the magic and the header record first: anything past them is
        // recovered, never refused.
        let header_end = 8 + 9 + u64::from_le_bytes(full[9..17].try_into().unwrap()) as usize;
        if at >= header_end {
            prop_assert!(n.is_some(), "refused a recording cut at {at} of {}", full.len());
        }
        if at == full.len() {
            prop_assert_eq!(n, Some(300));
        }
    }

    #[test]
    fn recover_of_a_corrupted_recording_never_panics(
        cut in any::<prop::sample::Index>(),
        flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..16),
    ) {
        let mut bytes = recording(120);
        for (at, byte) in flips {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let at = cut.index(bytes.len() + 1);
        check_recover(&bytes[..at])?;
    }

    #[test]
    fn recover_of_arbitrary_bytes_never_panics(
        bytes in proptest::collection::vec(any::<u8>(), 0..600),
        magic in any::<bool>(),
    ) {
        let mut input = if magic { b"\x89MCAP0\r\n".to_vec() } else { Vec::new() };
        input.extend_from_slice(&bytes);
        check_recover(&input)?;
    }
}

#[test]
fn a_recording_cut_inside_its_header_is_refused_as_not_mcap() {
    let full = recording(3);
    for at in [0, 4, 8, 12] {
        let msg = recover(&full[..at], Cursor::new(Vec::new()))
            .err()
            .map(|e| e.to_string())
            .unwrap_or_else(|| panic!("recovered a file cut at {at}"));
        assert!(msg.starts_with("not an MCAP file"), "{msg}");
    }
}

/// Found by the `recover_mcap` fuzz target: a 9-byte header record whose profile string claims
/// 3.65 GB. The MCAP parser reserves the claimed length before it finds the record too short
/// (an out-of-memory abort under the fuzzer's 2 GB malloc limit); recover checks every length
/// inside a record against the record first and names the field.
#[test]
fn a_header_claiming_gigabytes_for_a_string_is_refused_before_parsing() {
    let input: [u8; 26] = [
        0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a, 0x01, 0x09, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0xab, 0x95, 0xd9, 0x72, 0x52, 0x00, 0x35, 0x52,
    ];
    let msg = recover(&input[..], Cursor::new(Vec::new()))
        .err()
        .map(|e| e.to_string())
        .expect("a header that cannot be read is refused");
    assert!(
        msg.starts_with("not an MCAP file") && msg.contains("profile claims 3650464512 bytes"),
        "{msg}"
    );
}

/// One MCAP record: opcode, little-endian u64 length, content.
fn record(opcode: u8, content: &[u8]) -> Vec<u8> {
    let mut r = vec![opcode];
    r.extend_from_slice(&(content.len() as u64).to_le_bytes());
    r.extend_from_slice(content);
    r
}

/// An MCAP string or byte field: little-endian u32 length, bytes.
fn prefixed(bytes: &[u8]) -> Vec<u8> {
    let mut f = (bytes.len() as u32).to_le_bytes().to_vec();
    f.extend_from_slice(bytes);
    f
}

#[test]
fn a_channel_whose_metadata_claims_more_than_its_record_ends_the_copy_there() {
    let mut input = b"\x89MCAP0\r\n".to_vec();
    input.extend(record(0x01, &[prefixed(b""), prefixed(b"test")].concat()));
    // A metadata entry whose key claims 4 GB inside a map of 8 bytes.
    let map = prefixed(&[0xff, 0xff, 0xff, 0xff, b'k', b'e', b'y', b'!']);
    let channel = [
        vec![1, 0, 0, 0],
        prefixed(b"/wheel"),
        prefixed(b"json"),
        map,
    ]
    .concat();
    input.extend(record(0x04, &channel));
    let (copied, _) = recover(&input[..], Cursor::new(Vec::new())).unwrap();
    assert_eq!(copied.channels, 0);
    let why = copied
        .stopped_at
        .expect("the copy stops at the damaged channel");
    assert!(
        why.contains("0x04") && why.contains("channel metadata claims 4294967295 bytes"),
        "{why}"
    );
}

#[test]
fn a_config_error_in_a_section_names_the_section_and_field() {
    let msg = StationConfig::from_toml("[haptic.safety]\nfade_out_s = -1.0\n", "station.toml")
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("haptic.safety") && msg.contains("fade_out_s") && msg.contains("allowed"),
        "{msg}"
    );
}
