//! The patient's screen for a session: the static geometry of each exercise of the course,
//! the conversion of a tick's record into a [`render::Scene`], and which card shows when
//! ([`CourseView::screen_state`]): the exercise's card before it starts and between
//! exercises, the rest's countdown, the pause, and the question before ending early.
//!
//! Everything on it is in plain words for the patient, from the catalogue (`session.ftl`) in
//! the language in force: exercise names by what the patient does, never internal ids
//! (`triangle-road`), and no units a patient has no use for.

use i18n::tr;
use record::{ArmSetup, TickRecord, Watchdog};
use regimen::Regimen;
use render::{
    self, ArmInset, CarPose, Dial, Hud, LiveScore, Movement, NextCard, RoadPoint, Scene,
    ScreenState,
};
use session::config::StationConfig;
use session::{BreakKind, BreakNow};

#[cfg(test)]
mod session_tests;
#[cfg(test)]
mod shots;
#[cfg(test)]
mod sizes;

/// Centre-line sample spacing for the screen's road mesh, m.
const ROAD_SAMPLE_M: f64 = 2.0;

pub use session::words::{capitalised, patient_instruction, patient_name, plain_name};

/// What the screen needs of one exercise.
struct ExerciseView {
    /// The short name (`sine-road`).
    short: String,
    name: String,
    road: Option<render::Road>,
    /// The patient drives the speed with the pedals.
    pedals: bool,
}

/// The screen's view of a course: one entry per exercise, in course order.
pub struct CourseView {
    exercises: Vec<ExerciseView>,
    /// The therapist's message for the start card ([`Self::set_message`]).
    message: Option<String>,
    /// A prescribed course (each exercise once), not laps of one exercise.
    in_regimen: bool,
    duration_s: f64,
    /// The arm and wheel geometry the station was set up with (the lengths drawn until the
    /// session measures the patient's own).
    arm_geometry: gyro_imu::arm::ArmGeometry,
}

impl CourseView {
    /// The view of the course a session of `cfg` (and `regimen`) runs.
    pub fn new(cfg: &StationConfig, regimen: Option<&Regimen>) -> anyhow::Result<Self> {
        let entries = session::course::entries(cfg, regimen)?;
        let mut exercises = Vec::with_capacity(entries.len());
        let mut course_s = 0.0;
        for entry in entries {
            // Built as the session builds it: the road drawn is the road driven.
            let ex = entry.exercise.build()?;
            course_s += ex.planned_duration_s();
            let road = ex.road.as_ref().map(|r| {
                let n = (ex.length_m / ROAD_SAMPLE_M).ceil() as usize;
                let centre = (0..=n)
                    .map(|i| {
                        let ([x, y], _, _) = r.centre((i as f64 * ROAD_SAMPLE_M).min(ex.length_m));
                        RoadPoint {
                            x_m: x,
                            y_m: y,
                            lane_width_m: ex.lane_width_m,
                        }
                    })
                    .collect();
                render::Road {
                    centre,
                    barriers: Vec::new(),
                    cones: ex.cones.clone(),
                }
            });
            exercises.push(ExerciseView {
                short: ex.name.clone(),
                name: patient_name(&ex.name),
                road,
                pedals: entry.pedals,
            });
        }
        Ok(Self {
            in_regimen: regimen.is_some(),
            exercises,
            message: None,
            // The session ends when its exercises are done, or at its duration cap.
            duration_s: course_s.min(cfg.session.duration_s),
            arm_geometry: cfg.arm.geometry,
        })
    }

    /// Shows `message` (the therapist's, plain text) on the start card, before the first
    /// exercise starts.
    pub fn set_message(&mut self, message: Option<String>) {
        self.message = message;
    }

    /// The scene for the tick `rec`, the arm drawn with the lengths the station was set up
    /// with.
    pub fn scene(&self, rec: &TickRecord, screen: ScreenState) -> Scene {
        self.scene_with_arm(rec, screen, None)
    }

    /// The arm inset for the tick `rec`: while the arm is tracked, its pose with the segment
    /// lengths in use: `measured_m` (upper arm, elbow to grip, m) once the session has
    /// measured them, the configured ones before. `None` without arm sensing or tracking.
    pub fn arm_inset(&self, rec: &TickRecord, measured_m: Option<[f64; 2]>) -> Option<ArmInset> {
        let arm = rec.arm?;
        let unit =
            |v: [f64; 3]| ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - 1.0).abs() < 1e-3;
        let pose_ok = arm.setup == ArmSetup::Tracking
            && unit(arm.upper_axis)
            && unit(arm.fore_axis)
            && arm.grip_m.iter().all(|x| x.is_finite());
        let g = &self.arm_geometry;
        let [upper_arm_m, forearm_m] = measured_m.unwrap_or([g.upper_arm_m, g.forearm_m]);
        pose_ok.then_some(ArmInset {
            grip_m: arm.grip_m,
            upper_axis: arm.upper_axis,
            fore_axis: arm.fore_axis,
            upper_arm_m,
            forearm_m,
            rim_radius_m: g.grip_radius_m,
            wheel_tilt_rad: g.wheel_tilt_rad,
            measured: measured_m.is_some(),
        })
    }

    /// The scene for the tick `rec`, the arm drawn with the patient's own lengths
    /// `measured_m` (upper arm, elbow to grip, m) once the session has measured them.
    pub fn scene_with_arm(
        &self,
        rec: &TickRecord,
        screen: ScreenState,
        measured_m: Option<[f64; 2]>,
    ) -> Scene {
        let ex = &self.exercises[(rec.score.exercise_index as usize).min(self.exercises.len() - 1)];
        // Pauses do not count: the exercise clock stops with the car.
        let t_s = rec.score.active_s;
        let (road, car, dial, score, speed) = match (&ex.road, rec.vehicle) {
            (Some(road), Some(v)) => (
                road.clone(),
                CarPose {
                    x_m: v.x_m,
                    y_m: v.y_m,
                    yaw_rad: v.yaw_rad,
                    steer_rad: v.steer_rad,
                },
                None,
                LiveScore::Road {
                    rms_lateral_m: rec.score.rms_lateral_m,
                    in_lane_pct: rec.score.pct_in_lane,
                },
                v.ux_m_s,
            ),
            // The strength test: the side from where the patient is asked to aim, the push
            // from the spring's torque (recorded as the road feel).
            _ if ex.short == "strength" => {
                let side =
                    rec.wheel.target_rad.signum() as i8 * i8::from(rec.wheel.target_rad != 0.0);
                let push_nm = (-f64::from(side) * rec.wheel.road_feel_nm).max(0.0);
                (
                    render::Road::default(),
                    CarPose::default(),
                    None,
                    LiveScore::Strength {
                        side,
                        push_nm: if push_nm.is_finite() { push_nm } else { 0.0 },
                        ceiling_nm: rec.wheel.ceiling_nm,
                    },
                    0.0,
                )
            }
            _ => (
                render::Road::default(),
                CarPose::default(),
                Some(Dial {
                    desired_rad: rec.wheel.target_rad,
                    actual_rad: rec.wheel.angle_rad,
                }),
                LiveScore::Dial {
                    rms_error_deg: rec.score.dial_rms_error_deg,
                },
                0.0,
            ),
        };
        Scene {
            road,
            car,
            camera: render::CameraMode::Chase,
            dial,
            hud: Hud {
                exercise: ex.name.clone(),
                time_left_s: (self.duration_s - t_s).max(0.0),
                score,
                speed_m_s: speed,
                assist_level: rec.assist.assistance_level,
                devices: pedal_hint(ex.pedals, speed)
                    .into_iter()
                    .chain(device_lines(rec))
                    .collect(),
                notice: trunk_cue(rec),
            },
            screen,
            arm: self.arm_inset(rec, measured_m),
        }
    }
}

/// What the patient is to do with the pedals, while the car stands still in an exercise they
/// drive with them (at `speed_m_s`).
fn pedal_hint(pedals: bool, speed_m_s: f64) -> Option<String> {
    (pedals && speed_m_s < 0.5).then(|| tr!("hud-press-pedal"))
}

/// The gentle cue to sit up while the haptic thread shows it (`arm::trunk_cue`); the
/// id is `speech::SIT_UP`'s, written out so the screen does not depend on the speech module.
fn trunk_cue(rec: &TickRecord) -> Option<String> {
    rec.arm
        .is_some_and(|a| a.trunk_cue_shown)
        .then(|| tr!("hud-sit-up"))
}

/// The devices' lines of the HUD, in plain words.
fn device_lines(rec: &TickRecord) -> Vec<String> {
    let wheel = match rec.wheel.watchdog {
        Watchdog::SoftStart | Watchdog::Running => "hud-wheel-working",
        Watchdog::Paused => "hud-wheel-resting",
        Watchdog::Stopping | Watchdog::Stopped => "hud-wheel-stopping",
        Watchdog::FaultMissedDeadline | Watchdog::FaultStaleReading | Watchdog::Fault => {
            "hud-wheel-problem"
        }
    };
    let gentle = (!rec.wheel.motor_rating_known).then(|| tr!("hud-gentle-force"));
    let arm = rec.arm.map(|a| {
        tr!(match a.setup {
            ArmSetup::Tracking => "hud-arm-working",
            ArmSetup::HoldStill | ArmSetup::TurnWheel | ArmSetup::Solving => "hud-arm-setting-up",
            ArmSetup::Failed => "hud-arm-not-working",
            ArmSetup::SensorLost => "hud-arm-not-answering",
        })
    });
    std::iter::once(tr!(wheel))
        .chain(gentle)
        .chain(arm)
        .collect()
}

/// What the patient's window knows beyond the tick: the break in progress (from the haptic
/// thread) and whether it is asking the patient to confirm ending the session.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowState {
    /// The break in progress.
    pub brk: BreakNow,
    /// Esc was pressed once: the window asks before ending the session.
    pub confirming_end: bool,
    /// The cards' animation time, s.
    pub anim_s: f64,
}

/// The page a session that cannot start shows instead: the device check's lines (what is
/// missing, in plain words) and how to try again.
pub fn cannot_start_page(lines: &[render::StatusLine]) -> render::Welcome {
    let mut lines: Vec<render::StatusLine> = lines
        .iter()
        .filter(|l| l.ok == Some(false))
        .map(|l| render::StatusLine {
            ok: l.ok,
            // This page does not update: the patient starts again once it is done.
            text: l.text.replace(" This page updates by itself.", ""),
        })
        .collect();
    lines.push(render::StatusLine {
        ok: None,
        text: tr!("cannot-start-then"),
    });
    render::Welcome {
        title: tr!("cannot-start-title"),
        lines,
        ..render::Welcome::default()
    }
}

/// The question before ending a session early.
pub fn confirm_end_card() -> ScreenState {
    ScreenState::Instruction {
        title: tr!("end-confirm-title"),
        lines: vec![tr!("end-confirm-yes"), tr!("end-confirm-no")],
    }
}

impl CourseView {
    /// Which screen the patient's window shows for the tick `rec`: the question before
    /// ending early over anything else, then the arm set-up's instructions, the card of the
    /// first exercise before it starts, the rest or break between exercises with what comes
    /// next, the pause card, or the running exercise.
    pub fn screen_state(&self, rec: &TickRecord, w: &WindowState) -> ScreenState {
        let live = live_screen_state(rec);
        // The wheel's cards: the unplugged wheel, "End now?", the pause's choices.
        if let Some(card) =
            session::wheel_cards::card(&w.brk, w.confirming_end, live == ScreenState::Paused)
        {
            return card;
        }
        let index = (rec.score.exercise_index as usize).min(self.exercises.len() - 1);
        match live {
            ScreenState::Start => {
                let start = i18n::tr!("controls-start");
                let mut card = self.next_card(index, None, w, &start);
                if let ScreenState::Next(c) = &mut card {
                    c.message.clone_from(&self.message);
                }
                card
            }
            ScreenState::Paused if w.brk.kind == BreakKind::Ready => {
                // After a rest: the next exercise waits for the patient, or counts down.
                let (left, key) = if w.brk.left_s > 0.0 {
                    let seconds = w.brk.left_s.ceil() as u64;
                    (
                        Some(w.brk.left_s),
                        i18n::tr!("controls-ready-countdown", seconds = seconds),
                    )
                } else {
                    (None, i18n::tr!("controls-ready-press"))
                };
                let mut card = self.next_card(index, left, w, &key);
                if let ScreenState::Next(c) = &mut card {
                    c.heading = i18n::tr!("controls-ready-title");
                }
                card
            }
            ScreenState::Paused if w.brk.kind != BreakKind::None => {
                let go_on = i18n::tr!("controls-go-on-now");
                let mut card = self.next_card(index, Some(w.brk.left_s), w, &go_on);
                if let ScreenState::Next(c) = &mut card {
                    c.heading = tr!(match w.brk.kind {
                        BreakKind::Asked => "card-rest-then-back",
                        BreakKind::Prescribed => "card-rest-then-next",
                        _ => "card-next",
                    });
                }
                card
            }
            // The pause's choice page (`wheel_cards::card` answers it first).
            ScreenState::Paused => {
                ScreenState::Welcome(session::wheel_cards::paused_card(w.brk.pause_choice))
            }
            other => other,
        }
    }

    /// The card of exercise `index`, with a countdown and the key to go on (`key`, the
    /// catalogue's words).
    fn next_card(
        &self,
        index: usize,
        countdown_s: Option<f64>,
        w: &WindowState,
        key: &str,
    ) -> ScreenState {
        let ex = &self.exercises[index];
        let title = if self.in_regimen && self.exercises.len() > 1 {
            tr!(
                "card-exercise-of",
                number = index + 1,
                total = self.exercises.len(),
                name = ex.name.clone()
            )
        } else {
            ex.name.clone()
        };
        ScreenState::Next(NextCard {
            heading: tr!("card-get-ready"),
            title,
            what: if ex.pedals {
                format!(
                    "{} {}",
                    patient_instruction(&ex.short),
                    tr!("instruction-pedals")
                )
            } else {
                patient_instruction(&ex.short)
            },
            movement: Movement::of_exercise(&ex.short),
            countdown_s,
            // The key line names the wheel's button itself (the catalogue's words).
            keys: vec![key.to_owned()],
            anim_s: w.anim_s,
            message: None,
        })
    }
}

/// Which screen a live session shows for the tick `rec`: a set-up instruction from the arm
/// sensing, the start card (until the patient first presses Space), the pause card, or the
/// running exercise.
pub fn live_screen_state(rec: &TickRecord) -> ScreenState {
    let seconds = |s: f64| tr!("setup-seconds-left", seconds = s.ceil().max(0.0));
    match rec.arm.map(|a| (a.setup, a.setup_remaining_s)) {
        _ if rec.tick == 0 => ScreenState::Start,
        Some((ArmSetup::HoldStill, left)) => ScreenState::Instruction {
            title: tr!("setup-hold-still"),
            lines: vec![tr!("setup-hold-still-how"), seconds(left)],
        },
        Some((ArmSetup::TurnWheel, left)) => ScreenState::Instruction {
            title: tr!("setup-turn-slowly"),
            lines: vec![tr!("setup-turn-slowly-how"), seconds(left)],
        },
        Some((ArmSetup::Solving, _)) => ScreenState::Instruction {
            title: tr!("setup-thank-you"),
            lines: vec![tr!("setup-getting-ready")],
        },
        // Not started yet: the patient starts the exercise with Space.
        _ if rec.score.paused && rec.score.active_s == 0.0 => ScreenState::Start,
        _ if rec.score.paused => ScreenState::Paused,
        _ => ScreenState::Running,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The card's title for exercise `number` of `total` called `name_id`.
    fn of(number: usize, total: usize, name_id: &str) -> String {
        tr!(
            "card-exercise-of",
            number = number,
            total = total,
            name = tr!(name_id)
        )
    }

    fn view() -> CourseView {
        let text = "[[exercise]]\nkind = \"sine\"\nduration_s = 30.0\nrest_s = 20.0\n\n\
                    [[exercise]]\nkind = \"dial\"\nduration_s = 30.0\n";
        let r = Regimen::from_toml(text, "test").unwrap();
        CourseView::new(&StationConfig::default(), Some(&r)).unwrap()
    }

    /// A tick `tick` of exercise `index` with `active_s` of exercise time.
    fn tick(tick: u64, index: u32, active_s: f64, paused: bool) -> TickRecord {
        let mut rec = TickRecord {
            tick,
            ..TickRecord::default()
        };
        rec.score.exercise_index = index;
        rec.score.active_s = active_s;
        rec.score.paused = paused;
        rec
    }

    fn next_card(state: ScreenState) -> NextCard {
        match state {
            ScreenState::Next(card) => card,
            other => panic!("not the exercise's card: {other:?}"),
        }
    }

    #[test]
    fn a_pedal_exercise_says_the_feet_set_the_speed_and_asks_for_the_accelerator_at_rest() {
        let text = "[[exercise]]\nkind = \"sine\"\nduration_s = 30.0\npedals = true\n";
        let r = Regimen::from_toml(text, "test").unwrap();
        let v = CourseView::new(&StationConfig::default(), Some(&r)).unwrap();
        let card = next_card(v.screen_state(&tick(0, 0, 0.0, true), &WindowState::default()));
        assert!(
            card.what.contains(&tr!("instruction-pedals")),
            "{}",
            card.what
        );
        let mut rec = tick(10, 0, 0.01, false);
        rec.vehicle = Some(record::VehicleSample::default());
        let at_rest = v.scene(&rec, ScreenState::Running);
        assert_eq!(at_rest.hud.devices[0], tr!("hud-press-pedal"));
        rec.vehicle = Some(record::VehicleSample {
            ux_m_s: 8.0,
            ..Default::default()
        });
        let moving = v.scene(&rec, ScreenState::Running);
        let pedal = tr!("hud-press-pedal");
        assert!(!moving.hud.devices.contains(&pedal));
        // Automatic speed: no word about pedals.
        let auto = view().scene(&tick(10, 0, 0.01, false), ScreenState::Running);
        assert!(!auto.hud.devices.contains(&pedal));
        let card = next_card(view().screen_state(&tick(0, 0, 0.0, true), &WindowState::default()));
        assert!(
            !card.what.contains(&tr!("instruction-pedals")),
            "{}",
            card.what
        );
    }

    #[test]
    fn before_the_start_the_card_names_the_first_exercise_in_plain_words_and_how_to_start() {
        let v = view();
        let card = next_card(v.screen_state(&tick(0, 0, 0.0, true), &WindowState::default()));
        assert_eq!(card.title, of(1, 2, "exercise-sine-road"));
        assert_eq!(card.what, tr!("instruction-road"));
        assert_eq!(card.movement, Movement::Steer);
        assert_eq!(card.countdown_s, None);
        assert!(
            card.keys.contains(&i18n::tr!("controls-start")),
            "{:?}",
            card.keys
        );
        // The same while the patient has not started yet.
        let waiting = v.screen_state(&tick(500, 0, 0.0, true), &WindowState::default());
        assert_eq!(next_card(waiting).title, of(1, 2, "exercise-sine-road"));
    }

    #[test]
    fn a_prescribed_rest_shows_its_countdown_and_the_next_exercise_with_its_movement() {
        let w = WindowState {
            brk: BreakNow {
                kind: BreakKind::Prescribed,
                left_s: 17.2,
                ..BreakNow::default()
            },
            ..WindowState::default()
        };
        let card = next_card(view().screen_state(&tick(40_000, 1, 30.0, true), &w));
        assert_eq!(card.heading, tr!("card-rest-then-next"));
        assert_eq!(card.title, of(2, 2, "exercise-dial-sine"));
        assert_eq!(card.movement, Movement::Dial);
        assert_eq!(card.countdown_s, Some(17.2));
        assert!(
            card.keys.contains(&i18n::tr!("controls-go-on-now")),
            "{:?}",
            card.keys
        );
        // The short card between exercises says "Next", a rest the patient asked for says
        // they go back to the same exercise.
        let next = WindowState {
            brk: BreakNow {
                kind: BreakKind::Next,
                left_s: 3.0,
                ..BreakNow::default()
            },
            ..w
        };
        let card = next_card(view().screen_state(&tick(40_000, 1, 30.0, true), &next));
        assert_eq!(card.heading, tr!("card-next"));
        let asked = WindowState {
            brk: BreakNow {
                kind: BreakKind::Asked,
                left_s: 50.0,
                ..BreakNow::default()
            },
            ..w
        };
        let card = next_card(view().screen_state(&tick(20_000, 0, 12.0, true), &asked));
        assert_eq!(card.heading, tr!("card-rest-then-back"));
        assert_eq!(card.title, of(1, 2, "exercise-sine-road"));
    }

    #[test]
    fn esc_once_or_a_long_press_asks_before_ending_over_any_other_card_and_a_pause_is_its_choice_page()
     {
        let v = view();
        let id = |s: ScreenState| match s {
            ScreenState::Welcome(w) => w.id,
            other => panic!("{other:?}"),
        };
        let asking = WindowState {
            confirming_end: true,
            ..WindowState::default()
        };
        let held = WindowState {
            brk: BreakNow {
                end_asked: true,
                ..BreakNow::default()
            },
            ..WindowState::default()
        };
        for rec in [tick(0, 0, 0.0, true), tick(9000, 0, 8.0, false)] {
            assert_eq!(id(v.screen_state(&rec, &asking)), "end-now");
            assert_eq!(id(v.screen_state(&rec, &held)), "end-now");
        }
        let plain = WindowState::default();
        let paused = v.screen_state(&tick(9000, 0, 8.0, true), &plain);
        let ScreenState::Welcome(page) = paused else {
            panic!("{paused:?}")
        };
        assert_eq!(page.id, "paused");
        assert_eq!(page.picture, Some(render::Picture::Pause));
        assert_eq!(page.choices.len(), 3, "go on, rest, end");
        assert_eq!(
            v.screen_state(&tick(9000, 0, 8.0, false), &plain),
            ScreenState::Running
        );
    }

    #[test]
    fn an_unplugged_wheel_mid_exercise_shows_its_own_page_not_the_pause_card() {
        let w = WindowState {
            brk: BreakNow {
                wheel_away_left_s: Some(25.0),
                ..BreakNow::default()
            },
            ..WindowState::default()
        };
        match view().screen_state(&tick(9000, 0, 8.0, true), &w) {
            ScreenState::Welcome(page) => {
                assert_eq!(page.id, "wheel-unplugged");
                assert_eq!(page.picture, Some(render::Picture::Plug));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn after_a_rest_ready_waits_for_the_patient_or_counts_down() {
        let ready = |left_s| WindowState {
            brk: BreakNow {
                kind: BreakKind::Ready,
                left_s,
                ..BreakNow::default()
            },
            ..WindowState::default()
        };
        let card = next_card(view().screen_state(&tick(40_000, 1, 30.0, true), &ready(0.0)));
        assert_eq!(card.heading, i18n::tr!("controls-ready-title"));
        assert_eq!(card.countdown_s, None, "waits: no countdown");
        assert!(card.keys.contains(&i18n::tr!("controls-ready-press")));
        let card = next_card(view().screen_state(&tick(40_000, 1, 30.0, true), &ready(4.2)));
        assert_eq!(card.countdown_s, Some(4.2));
    }

    #[test]
    fn the_hud_names_exercises_and_devices_in_plain_words() {
        let v = view();
        let rec = tick(9000, 0, 8.0, false);
        let scene = v.scene(&rec, ScreenState::Running);
        assert_eq!(scene.hud.exercise, tr!("exercise-sine-road"));
        assert_eq!(plain_name("triangle-road"), "Triangle road");
        for line in &scene.hud.devices {
            assert!(!line.contains("N·m") && !line.contains('_'), "{line}");
        }
        let with_arm = TickRecord {
            arm: Some(record::ArmSample {
                setup: ArmSetup::Tracking,
                ..Default::default()
            }),
            ..rec
        };
        let devices = v.scene(&with_arm, ScreenState::Running).hud.devices;
        assert!(devices.contains(&tr!("hud-arm-working")), "{devices:?}");
    }
}

#[cfg(test)]
mod arm_inset_tests {
    use super::*;
    use record::ArmSample;

    fn tracked(setup: ArmSetup) -> TickRecord {
        TickRecord {
            arm: Some(ArmSample {
                setup,
                upper_axis: [0.6, 0.0, -0.8],
                fore_axis: [1.0, 0.0, 0.0],
                grip_m: [0.0, -0.14, 0.0],
                ..ArmSample::default()
            }),
            ..TickRecord::default()
        }
    }

    #[test]
    fn the_arm_inset_draws_the_configured_lengths_until_the_patients_own_are_measured() {
        let cfg = StationConfig::default();
        let view = CourseView::new(&cfg, None).unwrap();
        let configured = [cfg.arm.geometry.upper_arm_m, cfg.arm.geometry.forearm_m];
        let rec = tracked(ArmSetup::Tracking);
        let before = view
            .scene_with_arm(&rec, ScreenState::Running, None)
            .arm
            .expect("a tracked arm is drawn");
        assert_eq!([before.upper_arm_m, before.forearm_m], configured);
        assert!(!before.measured);
        let after = view
            .scene_with_arm(&rec, ScreenState::Running, Some([0.28, 0.35]))
            .arm
            .unwrap();
        assert_eq!([after.upper_arm_m, after.forearm_m], [0.28, 0.35]);
        assert!(after.measured);
        // The joints follow the lengths in use: the elbow one forearm behind the grip, the
        // shoulder one upper arm behind the elbow.
        let [ex, _, ez] = after.elbow_m();
        let [sx, _, sz] = after.shoulder_m();
        assert!((ex + 0.35).abs() < 1e-12 && ez.abs() < 1e-12, "{ex} {ez}");
        assert!((sx - (ex - 0.28 * 0.6)).abs() < 1e-12, "{sx}");
        assert!((sz - 0.28 * 0.8).abs() < 1e-12, "{sz}");
        assert!(view.scene(&rec, ScreenState::Running).validate().is_ok());
    }

    #[test]
    fn no_arm_inset_without_arm_sensing_or_while_the_arm_is_not_tracked() {
        let view = CourseView::new(&StationConfig::default(), None).unwrap();
        let none = TickRecord::default();
        assert_eq!(view.scene(&none, ScreenState::Running).arm, None);
        for setup in [
            ArmSetup::HoldStill,
            ArmSetup::TurnWheel,
            ArmSetup::Solving,
            ArmSetup::Failed,
            ArmSetup::SensorLost,
        ] {
            let rec = tracked(setup);
            assert_eq!(view.arm_inset(&rec, Some([0.3, 0.3])), None, "{setup:?}");
        }
        // Tracking but no pose yet (zero axes): nothing drawn rather than a collapsed arm.
        let mut rec = tracked(ArmSetup::Tracking);
        if let Some(a) = rec.arm.as_mut() {
            a.upper_axis = [0.0; 3];
        }
        assert_eq!(view.arm_inset(&rec, None), None);
    }
}
