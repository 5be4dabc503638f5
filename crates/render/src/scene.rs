//! The plain data one frame is drawn from: road, car, camera, dial, HUD and which pictures
//! (`pictures` paints them).
//!
//! The renderer knows nothing about sessions, threads or devices; the station converts its
//! state snapshot into a [`Scene`] each frame. World frame: x and y on the ground plane in
//! metres, z up; yaw is measured counter-clockwise from +x (ISO 8855, as the exercise library's vehicle).

use super::RenderError;

/// One centre-line point of the road, thesis §3.3.4 (the patient drives near the centre).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadPoint {
    /// Centre-line x in the world frame, m.
    pub x_m: f64,
    /// Centre-line y in the world frame, m.
    pub y_m: f64,
    /// Width of the drivable lane at this point (edge line to edge line), m.
    pub lane_width_m: f64,
}

/// Road geometry of the current exercise.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Road {
    /// Centre-line polyline, in driving order; fewer than two points draws no road.
    pub centre: Vec<RoadPoint>,
    /// Barriers, each a polyline of ground points `[x_m, y_m]` drawn as a low wall.
    pub barriers: Vec<Vec<[f64; 2]>>,
    /// Traffic cones, ground points `[x_m, y_m]`.
    pub cones: Vec<[f64; 2]>,
}

/// Pose of the patient's car on the ground plane.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CarPose {
    /// Position of the car's centre, x, m.
    pub x_m: f64,
    /// Position of the car's centre, y, m.
    pub y_m: f64,
    /// Heading, counter-clockwise from +x, rad.
    pub yaw_rad: f64,
    /// Front-wheel steering angle, positive to the left, rad.
    pub steer_rad: f64,
}

/// Where the 3D camera sits.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum CameraMode {
    /// Behind and above the car, looking ahead over its roof.
    #[default]
    Chase,
    /// At the driver's eye; the car itself is not drawn.
    Driver,
}

/// The rotary dial tracking task, thesis §3.3.3 and Fig. 3-7(a): the red needle shows the
/// desired wheel angle, the black needle the wheel's actual angle.
///
/// Angles are wheel angles, positive counter-clockwise as the patient sees the wheel; 0 points
/// the needle straight up.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Dial {
    /// Desired wheel angle (red needle), rad.
    pub desired_rad: f64,
    /// Actual wheel angle (black needle), rad.
    pub actual_rad: f64,
}

/// The live score shown in the HUD.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum LiveScore {
    /// No score yet.
    #[default]
    None,
    /// Driving: RMS lateral deviation from the lane centre (m) and share of time in lane (%).
    Road {
        /// RMS distance from the lane centre so far, m.
        rms_lateral_m: f64,
        /// Share of time with the car inside the lane, 0–100 %.
        in_lane_pct: f64,
    },
    /// Dial tracking: RMS angle error between the needles so far, degrees.
    Dial {
        /// RMS difference between desired and actual angle, deg.
        rms_error_deg: f64,
    },
    /// The strength test: which way to push and how hard the patient pushes now.
    Strength {
        /// +1 push left, −1 push right, 0 rest.
        side: i8,
        /// The patient's torque the spring holds, N·m (≥ 0).
        push_nm: f64,
        /// The torque ceiling, N·m (the bar's full length).
        ceiling_nm: f64,
    },
}

/// Text and numbers for the heads-up display.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Hud {
    /// Name of the exercise, e.g. "Sine road".
    pub exercise: String,
    /// Time left in the exercise, s.
    pub time_left_s: f64,
    /// Live score.
    pub score: LiveScore,
    /// Car speed, m/s (shown in km/h).
    pub speed_m_s: f64,
    /// Assist level, 0 (patient does all the work) to 1 (full assist).
    pub assist_level: f64,
    /// One short line per device, e.g. "Wheel: connected".
    pub devices: Vec<String>,
    /// A short sentence for the patient on top of the running exercise (the gentle cue to
    /// sit up: "Sit back up straight."); `None` most of the time.
    pub notice: Option<String>,
}

/// Which screen the patient sees on top of the exercise.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum ScreenState {
    /// Before the exercise: a "get ready" card.
    #[default]
    Start,
    /// The exercise is running: HUD only.
    Running,
    /// Paused by the patient or the therapist.
    Paused,
    /// The patient is asked to do something before the exercise goes on: a card with a
    /// title and lines.
    Instruction {
        /// What to do, in a few words.
        title: String,
        /// How, and for how long.
        lines: Vec<String>,
    },
    /// A card with a picture and its caption (the pause), then a title and lines.
    Pictured {
        /// The picture; its caption is the card's main sentence.
        picture: Picture,
        /// What to do, in a few words.
        title: String,
        /// How (the keys or buttons).
        lines: Vec<String>,
    },
    /// Before an exercise (the first, or the next one after a break or rest): what comes
    /// next in plain words, with a picture of the movement and the rest's countdown.
    Next(NextCard),
    /// End of the session: a summary card with these lines.
    Summary(Vec<String>),
    /// Before any session (first run, pairing, today's session, device check): a full-screen
    /// page, drawn without the road or the car.
    Welcome(Welcome),
    /// After a session: its results, the check-in's questions on pictured scales, and the
    /// thanks or the page that says to stop and call the clinic.
    CheckIn(super::CheckInPage),
}

/// The movement an exercise asks for; each has its own picture.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum Movement {
    /// A winding road (the sine road): turn the wheel left and right.
    #[default]
    Steer,
    /// A straight road: hold the car in the middle.
    Straight,
    /// A zigzag road (the triangle road).
    Zigzag,
    /// A bend that gets tighter (the clothoid road).
    Tightening,
    /// Sharp corners.
    SharpTurns,
    /// One S-shaped bend.
    SBend,
    /// From one lane into the other.
    LaneChange,
    /// Between cones.
    Slalom,
    /// Following the red needle of the dial with the black one.
    Dial,
    /// Pushing against a wheel that does not move (the strength test).
    Strength,
}

impl Movement {
    /// The movement of the exercise with the stable short name `short` (`"sine-road"`,
    /// `"dial-step"`, …; see `exercises::ExerciseSpec::name`).
    pub fn of_exercise(short: &str) -> Movement {
        match short {
            "straight-road" => Movement::Straight,
            "triangle-road" => Movement::Zigzag,
            "clothoid-road" => Movement::Tightening,
            "sharp-turns" => Movement::SharpTurns,
            "s-bend" => Movement::SBend,
            "lane-change" => Movement::LaneChange,
            "slalom" => Movement::Slalom,
            "strength" | "assessment-strength" => Movement::Strength,
            // The standard assessment's other parts are dial tasks.
            s if s.starts_with("dial") || s == "haptic-sweep" || s.starts_with("assessment-") => {
                Movement::Dial
            }
            _ => Movement::Steer,
        }
    }

    /// Every movement.
    pub const ALL: [Movement; 10] = [
        Movement::Steer,
        Movement::Straight,
        Movement::Zigzag,
        Movement::Tightening,
        Movement::SharpTurns,
        Movement::SBend,
        Movement::LaneChange,
        Movement::Slalom,
        Movement::Dial,
        Movement::Strength,
    ];
}

/// A picture of the patient's pages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Picture {
    /// The movement of an exercise.
    Exercise(Movement),
    /// A rest: a cup of tea, the hands off the wheel.
    Rest,
    /// The exercise is paused.
    Pause,
    /// The wheel, its button lit: press it (`hold`: keep it pressed; `turn`: arrows to turn).
    Wheel {
        /// The button is held down (a long press).
        hold: bool,
        /// Arrows show the wheel turns to choose.
        turn: bool,
    },
    /// A cable's plug going into the wheel: plug it back in.
    Plug,
    /// The sensor strapped on the forearm, its cable's plug going back in.
    ArmSensorPlug,
    /// Yes: a tick.
    Yes,
    /// No: a cross.
    No,
    /// The session is over: a star.
    Done,
    /// Today's page: a calendar sheet.
    Today,
}

impl Picture {
    /// Every picture, the exercises' first.
    pub fn all() -> Vec<Picture> {
        let mut all: Vec<Picture> = Movement::ALL
            .iter()
            .map(|m| Picture::Exercise(*m))
            .collect();
        all.extend([
            Picture::Rest,
            Picture::Pause,
            Picture::Wheel {
                hold: false,
                turn: false,
            },
            Picture::Wheel {
                hold: true,
                turn: true,
            },
            Picture::Plug,
            Picture::ArmSensorPlug,
            Picture::Yes,
            Picture::No,
            Picture::Done,
            Picture::Today,
        ]);
        all
    }

    /// The id of the picture's caption in the `pictures` catalogue.
    pub fn caption_id(self) -> &'static str {
        match self {
            Picture::Exercise(m) => match m {
                Movement::Steer => "picture-road-winding",
                Movement::Straight => "picture-road-straight",
                Movement::Zigzag => "picture-road-zigzag",
                Movement::Tightening => "picture-road-tightening",
                Movement::SharpTurns => "picture-road-sharp-turns",
                Movement::SBend => "picture-road-s-bend",
                Movement::LaneChange => "picture-road-lane-change",
                Movement::Slalom => "picture-road-slalom",
                Movement::Dial => "picture-dial",
                Movement::Strength => "picture-strength",
            },
            Picture::Rest => "picture-rest",
            Picture::Pause => "picture-pause",
            Picture::Wheel { turn: true, .. } => "picture-wheel-turn",
            Picture::Wheel { .. } => "picture-buttons",
            Picture::Plug => "picture-plug",
            Picture::ArmSensorPlug => "picture-arm-sensor-plug",
            Picture::Yes => "picture-yes",
            Picture::No => "picture-no",
            Picture::Done => "picture-done",
            Picture::Today => "picture-today",
        }
    }

    /// The caption in the language in force.
    pub fn caption(self) -> String {
        i18n::tr!(self.caption_id())
    }
}

/// The card before an exercise: "Exercise 2 of 4", its name, what to do, the movement, and
/// the rest's countdown if one is in progress.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NextCard {
    /// Above the title, e.g. "Rest" or "Next: exercise 2 of 4".
    pub heading: String,
    /// The exercise's name for the patient, e.g. "Exercise 2 of 4: Sine road".
    pub title: String,
    /// What to do, in plain words.
    pub what: String,
    /// The picture of the movement.
    pub movement: Movement,
    /// Time left of the rest or break, s (drawn as a large countdown).
    pub countdown_s: Option<f64>,
    /// The keys, e.g. "Space: start".
    pub keys: Vec<String>,
    /// The picture's animation time, s (any clock that moves on).
    pub anim_s: f64,
    /// A message from the therapist, shown on the session's start card in large plain type.
    pub message: Option<String>,
}

/// A line of a [`Welcome`] page, with how it stands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StatusLine {
    /// `Some(true)`: ready (a green tick); `Some(false)`: needs doing (a red cross, the line
    /// says what); `None`: plain text.
    pub ok: Option<bool>,
    /// What to say, in plain words.
    pub text: String,
}

/// A full-screen page before a session: a title, lines, an optional field being typed in and
/// the keys the patient can press.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Welcome {
    /// The page's title, e.g. "Welcome".
    pub title: String,
    /// What the page says, one line each.
    pub lines: Vec<StatusLine>,
    /// A field being typed: its label and what was typed so far.
    pub field: Option<(String, String)>,
    /// Something went wrong, in plain words (drawn in red under the field).
    pub error: Option<String>,
    /// The keys and what they do, e.g. "Space: start".
    pub keys: Vec<String>,
    /// The page's stable name for logs and tests (`language`, `pairing`, `today`, …).
    pub id: &'static str,
    /// A picture beside the words (the wheel's button to press, the plug).
    pub picture: Option<Picture>,
    /// Large choices in a row, chosen by turning the wheel (the chosen one is framed).
    pub choices: Vec<String>,
    /// Which of [`Welcome::choices`] is chosen.
    pub chosen: usize,
}

/// The patient's arm on the wheel, drawn small in a corner as seen from the patient's right
/// (only with arm sensing): shoulder, elbow and the hand on the rim, with the segment lengths
/// the station uses now. Wheel frame: origin at the wheel centre, x forward (away from the
/// patient), y left, z up.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ArmInset {
    /// The hand's grip point on the rim, m.
    pub grip_m: [f64; 3],
    /// Unit direction of the upper arm (shoulder → elbow).
    pub upper_axis: [f64; 3],
    /// Unit direction of the forearm (elbow → grip).
    pub fore_axis: [f64; 3],
    /// Upper-arm length drawn, m: the configured one, or the patient's own once measured.
    pub upper_arm_m: f64,
    /// Elbow-to-grip length drawn, m: the configured one, or the patient's own once measured.
    pub forearm_m: f64,
    /// Radius of the rim where the hand grips, m.
    pub rim_radius_m: f64,
    /// Tilt of the wheel's top toward the patient from vertical, rad.
    pub wheel_tilt_rad: f64,
    /// The lengths are the patient's own, measured during this session (a discreet tick).
    pub measured: bool,
}

impl ArmInset {
    /// The elbow: the grip less the forearm along its axis, m.
    pub fn elbow_m(&self) -> [f64; 3] {
        std::array::from_fn(|i| self.grip_m[i] - self.forearm_m * self.fore_axis[i])
    }

    /// The shoulder: the elbow less the upper arm along its axis, m.
    pub fn shoulder_m(&self) -> [f64; 3] {
        let e = self.elbow_m();
        std::array::from_fn(|i| e[i] - self.upper_arm_m * self.upper_axis[i])
    }
}

/// Everything one frame shows. Plain data: build it from a snapshot, never share it mutably.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Road of the current exercise (empty for the dial task).
    pub road: Road,
    /// The car.
    pub car: CarPose,
    /// Camera placement.
    pub camera: CameraMode,
    /// The dial task; drawn full-screen when there is no road, as an inset otherwise.
    pub dial: Option<Dial>,
    /// Heads-up display data.
    pub hud: Hud,
    /// Start / running / paused / summary screen.
    pub screen: ScreenState,
    /// The patient's arm, drawn as a small inset (only with arm sensing, while tracked).
    pub arm: Option<ArmInset>,
}

fn finite(field: &str, value: f64) -> Result<(), RenderError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(RenderError::InvalidScene(format!(
            "{field} must be finite, got {value}"
        )))
    }
}

fn in_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<(), RenderError> {
    finite(field, value)?;
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(RenderError::InvalidScene(format!(
            "{field} must be in [{lo}, {hi}], got {value}"
        )))
    }
}

/// Largest coordinate accepted, m: beyond this f32 vertex positions lose centimetres.
pub const MAX_COORD_M: f64 = 1.0e5;

impl Scene {
    /// Checks every number the renderer uses; the error names the offending field.
    pub fn validate(&self) -> Result<(), RenderError> {
        for (i, p) in self.road.centre.iter().enumerate() {
            in_range(
                &format!("road.centre[{i}].x_m"),
                p.x_m,
                -MAX_COORD_M,
                MAX_COORD_M,
            )?;
            in_range(
                &format!("road.centre[{i}].y_m"),
                p.y_m,
                -MAX_COORD_M,
                MAX_COORD_M,
            )?;
            in_range(
                &format!("road.centre[{i}].lane_width_m"),
                p.lane_width_m,
                0.5,
                50.0,
            )?;
        }
        for (b, line) in self.road.barriers.iter().enumerate() {
            for (i, p) in line.iter().enumerate() {
                in_range(
                    &format!("road.barriers[{b}][{i}].x"),
                    p[0],
                    -MAX_COORD_M,
                    MAX_COORD_M,
                )?;
                in_range(
                    &format!("road.barriers[{b}][{i}].y"),
                    p[1],
                    -MAX_COORD_M,
                    MAX_COORD_M,
                )?;
            }
        }
        for (i, p) in self.road.cones.iter().enumerate() {
            in_range(
                &format!("road.cones[{i}].x"),
                p[0],
                -MAX_COORD_M,
                MAX_COORD_M,
            )?;
            in_range(
                &format!("road.cones[{i}].y"),
                p[1],
                -MAX_COORD_M,
                MAX_COORD_M,
            )?;
        }
        in_range("car.x_m", self.car.x_m, -MAX_COORD_M, MAX_COORD_M)?;
        in_range("car.y_m", self.car.y_m, -MAX_COORD_M, MAX_COORD_M)?;
        finite("car.yaw_rad", self.car.yaw_rad)?;
        in_range("car.steer_rad", self.car.steer_rad, -1.5, 1.5)?;
        if let Some(d) = &self.dial {
            finite("dial.desired_rad", d.desired_rad)?;
            finite("dial.actual_rad", d.actual_rad)?;
        }
        if let Some(a) = &self.arm {
            for (field, xyz) in [
                ("arm.grip_m", a.grip_m),
                ("arm.upper_axis", a.upper_axis),
                ("arm.fore_axis", a.fore_axis),
            ] {
                for (i, x) in xyz.iter().enumerate() {
                    in_range(&format!("{field}[{i}]"), *x, -10.0, 10.0)?;
                }
            }
            in_range("arm.upper_arm_m", a.upper_arm_m, 0.0, 2.0)?;
            in_range("arm.forearm_m", a.forearm_m, 0.0, 2.0)?;
            in_range("arm.rim_radius_m", a.rim_radius_m, 0.0, 2.0)?;
            in_range("arm.wheel_tilt_rad", a.wheel_tilt_rad, -1.6, 1.6)?;
        }
        let h = &self.hud;
        finite("hud.time_left_s", h.time_left_s)?;
        finite("hud.speed_m_s", h.speed_m_s)?;
        in_range("hud.assist_level", h.assist_level, 0.0, 1.0)?;
        match h.score {
            LiveScore::None => {}
            LiveScore::Road {
                rms_lateral_m,
                in_lane_pct,
            } => {
                finite("hud.score.rms_lateral_m", rms_lateral_m)?;
                in_range("hud.score.in_lane_pct", in_lane_pct, 0.0, 100.0)?;
            }
            LiveScore::Dial { rms_error_deg } => finite("hud.score.rms_error_deg", rms_error_deg)?,
            LiveScore::Strength {
                push_nm,
                ceiling_nm,
                ..
            } => {
                finite("hud.score.push_nm", push_nm)?;
                finite("hud.score.ceiling_nm", ceiling_nm)?;
            }
        }
        Ok(())
    }

    /// True when the scene has a road to draw in 3D.
    pub fn has_road(&self) -> bool {
        self.road.centre.len() >= 2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_scene_is_valid() {
        assert!(Scene::default().validate().is_ok());
    }

    #[test]
    fn nan_car_position_is_rejected_with_field_name() {
        let mut s = Scene::default();
        s.car.x_m = f64::NAN;
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains("car.x_m"), "{err}");
    }

    #[test]
    fn narrow_lane_is_rejected_with_index() {
        let mut s = Scene::default();
        s.road.centre = vec![
            RoadPoint {
                x_m: 0.0,
                y_m: 0.0,
                lane_width_m: 3.5,
            },
            RoadPoint {
                x_m: 1.0,
                y_m: 0.0,
                lane_width_m: 0.1,
            },
        ];
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains("road.centre[1].lane_width_m"), "{err}");
    }

    #[test]
    fn assist_level_above_one_is_rejected() {
        let mut s = Scene::default();
        s.hud.assist_level = 1.5;
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains("hud.assist_level"), "{err}");
    }

    #[test]
    fn infinite_dial_angle_is_rejected() {
        let s = Scene {
            dial: Some(Dial {
                desired_rad: f64::INFINITY,
                actual_rad: 0.0,
            }),
            ..Scene::default()
        };
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains("dial.desired_rad"), "{err}");
    }
}
