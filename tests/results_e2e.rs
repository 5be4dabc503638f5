//! End-to-end: a prescribed dial-then-road session's per-exercise results travel from the
//! simulated station (its recording and its `Bye`) to the hub (`hub patient show --json`),
//! and `telerehab report` shows them as a table per exercise with how the session ended.

use telerehab_tests::clinic::{Hub, clinic, ok, pair, show_json};

#[test]
fn a_dial_then_road_sessions_per_exercise_results_reach_the_hub_and_the_report() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, code) = clinic(tmp.path());
    let hub = Hub::serve(&data, "127.0.0.1:0");
    let home = tmp.path().join("station");
    pair(&hub, &code, &home);
    let regimen = tmp.path().join("two.toml");
    std::fs::write(
        &regimen,
        "[[exercise]]\nkind = \"dial\"\nduration_s = 4.0\n\n\
         [[exercise]]\nkind = \"sine\"\nduration_s = 4.0\n",
    )
    .unwrap();
    let regimen = regimen.to_str().unwrap();
    let report = ok(
        &[
            "run",
            "--sim",
            "--headless",
            "--speed",
            "max",
            "--regimen",
            regimen,
        ],
        Some(&home),
    );
    assert!(report.contains("exercise 1"), "{report}");
    assert!(report.contains("exercise 2"), "{report}");

    // At the hub: both exercises, in course order, each with its own scores.
    let session = &show_json(&data)["sessions"][0];
    assert_eq!(session["session"]["end_reason"], "complete");
    let at_hub = session["exercises"].as_array().unwrap().clone();
    assert_eq!(at_hub.len(), 2, "{session}");
    assert_eq!(
        (&at_hub[0]["index"], &at_hub[1]["index"]),
        (&0.into(), &1.into())
    );
    assert!(at_hub[0]["kind"].as_str().unwrap().starts_with("dial"));
    assert_eq!(at_hub[1]["name"], "Sine road");
    assert!(
        at_hub[0]["scores"]["dial_mean_abs_error_deg"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(at_hub[0]["scores"].get("rms_lateral_m").is_none());
    assert!(at_hub[1]["scores"]["rms_lateral_m"].as_f64().unwrap() > 0.0);
    assert!(at_hub[1]["scores"].get("dial_rms_error_deg").is_none());
    for e in &at_hub {
        assert_eq!(e["prescribed_s"], 4.0);
        let active_s = e["active_s"].as_f64().unwrap();
        assert!((active_s - 4.0).abs() < 0.01, "{e}");
    }
    hub.stop();

    // The hub holds exactly what the station recorded.
    let recordings: Vec<_> = std::fs::read_dir(home.join("recordings"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "mcap"))
        .collect();
    assert_eq!(recordings.len(), 1);
    let rec = record::Recording::open(&recordings[0]).unwrap();
    let metrics = &rec.metrics.last().unwrap().data;
    assert_eq!(metrics.end_reason, "complete");
    let recorded = serde_json::to_value(&metrics.exercises).unwrap();
    assert_eq!(recorded, serde_json::Value::Array(at_hub));

    // The report: a column per exercise and how the session ended.
    let html = tmp.path().join("report.html");
    ok(
        &[
            "report",
            recordings[0].to_str().unwrap(),
            "--out",
            html.to_str().unwrap(),
        ],
        None,
    );
    let html = std::fs::read_to_string(&html).unwrap();
    assert!(html.contains("Ended: complete"), "{html}");
    assert!(html.contains("<h3>Each exercise</h3>"));
    assert!(html.contains("2. Sine road"));
    assert!(html.contains("Dial: average distance from the angle asked"));
}
