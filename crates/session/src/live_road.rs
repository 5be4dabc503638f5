//! The road around the car for the therapist's live view: in every live summary of a road
//! exercise, the road centre's offset to the car's left at a few fixed distances ahead of (and
//! behind) the car along its heading, and the lane width. The console draws the lane from
//! them in a car-centred window of fixed scale; without them (an older station) it draws the
//! car's path alone.
//!
//! Budget: the lane width and [`AHEAD_M`]'s seven offsets, rounded to the centimetre, add at
//! most [`ROAD_BUDGET_BYTES`] to a summary's JSON (2.6 kB/s at 10 Hz; 172 bytes measured on
//! netlink's encoding by the test below, BENCHMARKS.md).

use exercises::Road;
use record::VehicleSample;

/// Distances ahead of the car along its heading (negative: behind) at which a summary gives
/// the road centre's offset, m: the console's window spans 20 m behind to 40 m ahead.
pub const AHEAD_M: [i32; 7] = [-20, -10, 0, 10, 20, 30, 40];

/// Most bytes the road adds to a live summary's JSON.
pub const ROAD_BUDGET_BYTES: usize = 256;

/// Centre-line samples are taken this far behind the car's place on the road, m …
const SEARCH_BEHIND_M: f64 = 40.0;
/// … to this far ahead of it, m …
const SEARCH_AHEAD_M: f64 = 60.0;
/// … this far apart, m (between two, the centre line is taken as straight: off by under
/// 5 mm on the library's tightest bends).
const SEARCH_STEP_M: f64 = 1.0;

/// The summary's name for the road centre's offset to the car's left at `ahead_m` ahead of
/// it, m: `road_left_m_-20`, …, `road_left_m_40`.
pub fn key(ahead_m: i32) -> String {
    format!("road_left_m_{ahead_m}")
}

/// The lane width (`lane_width_m`) and the road centre's offset to the car's left at each of
/// [`AHEAD_M`] (see [`key`]), m, rounded to the centimetre. An offset is left out where the
/// centre line does not cross that distance near the car (a bend turning away by more than a
/// right angle); none is ever infinite or NaN.
pub fn road_around(road: &dyn Road, car: &VehicleSample) -> Vec<(String, f64)> {
    let (sin, cos) = car.yaw_rad.sin_cos();
    // Centre-line samples in the car's frame: (distance along the road, ahead, left), m.
    let steps = ((SEARCH_BEHIND_M + SEARCH_AHEAD_M) / SEARCH_STEP_M) as usize;
    let samples: Vec<[f64; 3]> = (0..=steps)
        .map(|i| {
            let s = car.s_m - SEARCH_BEHIND_M + i as f64 * SEARCH_STEP_M;
            let ([x, y], _, _) = road.centre(s);
            let (dx, dy) = (x - car.x_m, y - car.y_m);
            [s, dx * cos + dy * sin, -dx * sin + dy * cos]
        })
        .collect();
    let mut named = vec![("lane_width_m".to_owned(), centimetres(road.lane_width_m()))];
    for ahead in AHEAD_M {
        let d = f64::from(ahead);
        let near_s = car.s_m + d;
        // Every crossing of "ahead = d", the one nearest the car's own place + d along the road.
        let crossing = samples
            .windows(2)
            .filter(|w| (w[0][1] - d) * (w[1][1] - d) <= 0.0 && w[0][1] != w[1][1])
            .map(|w| {
                let t = (d - w[0][1]) / (w[1][1] - w[0][1]);
                (
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][2] + t * (w[1][2] - w[0][2]),
                )
            })
            .min_by(|a, b| (a.0 - near_s).abs().total_cmp(&(b.0 - near_s).abs()));
        if let Some((_, left)) = crossing.filter(|c| c.1.is_finite()) {
            named.push((key(ahead), centimetres(left)));
        }
    }
    named
}

fn centimetres(m: f64) -> f64 {
    (m * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use exercises::ExerciseSpec;

    /// The library's sine road (2 m amplitude, 150 m wavelength) and its lane width.
    fn sine_road() -> Box<dyn Road + Send> {
        ExerciseSpec::from_name("sine-road")
            .unwrap()
            .build()
            .unwrap()
            .road
            .unwrap()
    }

    /// A car at distance `s_m` along `road`, `off_m` left of its centre, heading `turned_rad`
    /// away from the road's heading there.
    fn car_on(road: &dyn Road, s_m: f64, off_m: f64, turned_rad: f64) -> VehicleSample {
        let ([x, y], heading, _) = road.centre(s_m);
        VehicleSample {
            x_m: x - off_m * heading.sin(),
            y_m: y + off_m * heading.cos(),
            yaw_rad: heading + turned_rad,
            s_m,
            lateral_m: off_m,
            ..Default::default()
        }
    }

    #[test]
    fn each_offset_sent_is_a_point_of_the_roads_centre_line_at_its_distance_ahead() {
        let road = sine_road();
        for (s_m, off_m, turned_rad) in [(0.0, 0.0, 0.0), (37.5, 1.2, 0.2), (120.0, -2.5, -0.35)] {
            let car = car_on(road.as_ref(), s_m, off_m, turned_rad);
            let named = road_around(road.as_ref(), &car);
            assert_eq!(named[0], ("lane_width_m".to_owned(), road.lane_width_m()));
            assert_eq!(named.len(), 1 + AHEAD_M.len(), "{named:?}");
            let (sin, cos) = car.yaw_rad.sin_cos();
            for (ahead, (name, left)) in AHEAD_M.iter().zip(&named[1..]) {
                assert_eq!(*name, key(*ahead));
                assert!(left.is_finite(), "{name} = {left}");
                // The point `ahead` m ahead and `left` m left of the car is on the centre line.
                let d = f64::from(*ahead);
                let (x, y) = (
                    car.x_m + d * cos - left * sin,
                    car.y_m + d * sin + left * cos,
                );
                let p = road.project(x, y, s_m + d);
                assert!(p.lateral_m.abs() < 0.02, "{name} at s {s_m}: {p:?}");
            }
            // Right under the car, the centre is where the car's offset says (nearly: the
            // car's frame is turned from the road's).
            let under = named.iter().find(|(n, _)| *n == key(0)).unwrap().1;
            assert!(
                (under + off_m / turned_rad.cos()).abs() < 0.05,
                "{under} {off_m}"
            );
        }
    }

    #[test]
    fn a_car_turned_away_from_the_road_gets_no_offset_where_the_road_never_crosses() {
        let road = sine_road();
        // Across the road: ahead of the car along its heading, the road is never there.
        let car = car_on(road.as_ref(), 50.0, 0.0, std::f64::consts::FRAC_PI_2);
        let named = road_around(road.as_ref(), &car);
        assert!(named.iter().all(|(_, v)| v.is_finite()), "{named:?}");
        assert!(!named.iter().any(|(n, _)| *n == key(40)), "{named:?}");
    }

    #[test]
    fn the_road_adds_at_most_its_budget_to_a_summarys_bytes() {
        let road = sine_road();
        let car = car_on(road.as_ref(), 37.5, -1.234_567, 0.123);
        let mut summary = netlink::Summary::example("2026-11-27T08-51-25.154Z-s7-f7575b1c", 42);
        summary.extra.extend([
            ("torque_nm".to_owned(), 0.123_456_789),
            ("car_x_m".to_owned(), 123.456_789),
        ]);
        let without = netlink::encode_to_vec(&netlink::Frame::Summary(summary.clone()))
            .unwrap()
            .len();
        summary.extra.extend(road_around(road.as_ref(), &car));
        let with = netlink::encode_to_vec(&netlink::Frame::Summary(summary))
            .unwrap()
            .len();
        let added_bytes = with - without;
        println!("a summary frame: {without} bytes, {with} with the road ({added_bytes} added)");
        assert!(
            added_bytes <= ROAD_BUDGET_BYTES,
            "{added_bytes} bytes > {ROAD_BUDGET_BYTES}"
        );
        // Not an empty promise: the offsets are there.
        assert!(added_bytes > 100, "{added_bytes} bytes");
    }
    /// Keeps every live summary of a session.
    struct Summaries(Vec<crate::LiveSummary>);

    impl crate::SessionObserver for Summaries {
        fn on_summary(&mut self, s: &crate::LiveSummary) {
            self.0.push(s.clone());
        }
    }

    #[test]
    fn a_road_exercises_summaries_carry_its_road_and_a_dial_tasks_none() {
        use crate::{Controls, SessionOptions, course};
        let text = "[[exercise]]\nkind = \"dial\"\nduration_s = 2.0\n\n\
                    [[exercise]]\nkind = \"sine\"\nduration_s = 4.0\n";
        let mut config = crate::config::StationConfig::default();
        config.session.seed = 7;
        config.session.duration_s = 60.0;
        config.validate().unwrap();
        let opts = SessionOptions {
            regimen: Some(regimen::Regimen::from_toml(text, "test").unwrap()),
            ..SessionOptions::simulated(config)
        };
        let mut kept = Summaries(Vec::new());
        crate::run(&opts, &Controls::default(), &mut kept).unwrap();
        let roads = course::roads(&opts.config, opts.regimen.as_ref()).unwrap();
        let road = roads[1].as_ref().unwrap();
        let is_road = |n: &str| n.starts_with("road_left_m_") || n == "lane_width_m";
        let (mut on_road, mut at_dial) = (0, 0);
        for s in &kept.0 {
            let sent: Vec<(String, f64)> = s
                .extra
                .iter()
                .filter(|(n, _)| is_road(n))
                .map(|(n, v)| (n.clone(), *v))
                .collect();
            let Some(car) = &s.record.vehicle else {
                assert!(sent.is_empty(), "a dial summary with {sent:?}");
                at_dial += 1;
                continue;
            };
            on_road += 1;
            assert_eq!(s.record.score.exercise_index, 1);
            let mut want = road_around(road.as_ref(), car);
            want.sort_by(|a, b| a.0.cmp(&b.0));
            assert_eq!(sent, want, "at {} s", s.record.t_ns as f64 * 1e-9);
            assert_eq!(sent.len(), 1 + AHEAD_M.len());
            assert!(sent.iter().all(|(_, v)| v.is_finite()));
            // Under the car, the road's centre is the car's own lateral deviation away.
            let under = s.extra[&key(0)];
            assert!(
                (under + car.lateral_m).abs() < 0.3,
                "{under} {}",
                car.lateral_m
            );
            assert!(s.extra.len() <= netlink::frame::MAX_EXTRA_ENTRIES);
        }
        assert!(
            on_road >= 30 && at_dial >= 15,
            "{on_road} on the road, {at_dial} at the dial"
        );
    }
}
