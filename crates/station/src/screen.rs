//! The patient's screen for a session: the static geometry of each exercise of the course,
//! and the conversion of a tick's record into a [`render::Scene`].

use crate::config::StationConfig;
use crate::render::{self, CarPose, Dial, Hud, LiveScore, RoadPoint, Scene, ScreenState};
use record::{ArmSetup, TickRecord};
use regimen::Regimen;

/// Centre-line sample spacing for the screen's road mesh, m.
const ROAD_SAMPLE_M: f64 = 2.0;

/// What the screen needs of one exercise.
struct ExerciseView {
    name: String,
    road: Option<render::Road>,
}

/// The screen's view of a course: one entry per exercise, in course order.
pub struct CourseView {
    exercises: Vec<ExerciseView>,
    duration_s: f64,
}

impl CourseView {
    /// The view of the course a session of `cfg` (and `regimen`) runs.
    pub fn new(cfg: &StationConfig, regimen: Option<&Regimen>) -> anyhow::Result<Self> {
        let entries = crate::session::course::entries(cfg, regimen)?;
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
                name: ex.name.clone(),
                road,
            });
        }
        Ok(Self {
            exercises,
            // The session ends when its exercises are done, or at its duration cap.
            duration_s: course_s.min(cfg.session.duration_s),
        })
    }

    /// The scene for the tick `rec`.
    pub fn scene(&self, rec: &TickRecord, screen: ScreenState) -> Scene {
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
                devices: std::iter::once(if rec.wheel.motor_rating_known {
                    format!("wheel: {}", rec.wheel.watchdog)
                } else {
                    format!(
                        "wheel: {} · UNKNOWN motor: force capped at {:.1} N·m",
                        rec.wheel.watchdog, rec.wheel.ceiling_nm
                    )
                })
                .chain(
                    rec.arm
                        .map(|a| format!("arm sensors: {}", a.setup.as_str())),
                )
                .collect(),
            },
            screen,
        }
    }
}

/// Which screen a live session shows for the tick `rec`: a set-up instruction from the arm
/// sensing, the start card (until the patient first presses Space), the pause card, or the
/// running exercise.
pub fn live_screen_state(rec: &TickRecord) -> ScreenState {
    let seconds = |s: f64| format!("{} s", s.ceil().max(0.0));
    match rec.arm.map(|a| (a.setup, a.setup_remaining_s)) {
        _ if rec.tick == 0 => ScreenState::Start,
        Some((ArmSetup::HoldStill, left)) => ScreenState::Instruction {
            title: "Hold the wheel still".into(),
            lines: vec![
                "Rest both hands on the wheel, centred, and relax.".into(),
                seconds(left),
            ],
        },
        Some((ArmSetup::TurnWheel, left)) => ScreenState::Instruction {
            title: "Turn the wheel slowly".into(),
            lines: vec![
                "Left and right, as far as is comfortable.".into(),
                seconds(left),
            ],
        },
        Some((ArmSetup::Solving, _)) => ScreenState::Instruction {
            title: "Thank you".into(),
            lines: vec!["Setting up the arm sensors…".into()],
        },
        // Not started yet: the patient starts the exercise with Space.
        _ if rec.score.paused && rec.score.active_s == 0.0 => ScreenState::Start,
        _ if rec.score.paused => ScreenState::Paused,
        _ => ScreenState::Running,
    }
}
