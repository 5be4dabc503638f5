//! Active motion and force assist (thesis Chapter 5), made safe under a real wheel's torque
//! ceiling and slew limit, plus assist-as-needed, difficulty adaptation, resistive modes and
//! the simulated human that the controllers are designed and tested against.
//!
//! Pure: controllers are structs with a `step(..., dt)` method; no I/O, threads or clocks.
//!
//! # Module map
//!
//! - [`runtime`]: [`Assist`], the one type the haptic loop calls, built from a [`spec`]
//!   ([`AssistSpec`], as a regimen carries it); [`limits`]: the torque ceiling and slew it
//!   must respect.
//! - [`motion`] and [`force`]: motion and force assist by input–output linearisation
//!   (§5.4.1–5.4.2) over the wheel + human [`model`] (eq. 5.5–5.32); [`governor`]: the
//!   reference governor that keeps a request deliverable.
//! - [`aan`]: assist-as-needed; [`resist`]: resistive modes; [`difficulty`]: session-to-session
//!   difficulty adaptation.
//! - [`human`]: the simulated human arm holding the wheel; [`sim`]: the RK4 plant simulator
//!   the tests and benchmarks use.
//! - [`effort`]: the patient's hand torque estimated from the wheel's dynamics and the
//!   motor's command (an extended-state observer, eq. E.1–E.2).
//! - [`error`]: the errors, [`AssistError`].
//!
//! The station's haptic loop uses [`Assist`]:
//!
//! ```
//! use assist::{Assist, AssistSpec, Limits, Measurement};
//! let spec: AssistSpec = toml::from_str("[mode]\nkind = \"motion\"\n").unwrap();
//! let mut assist = Assist::new(&spec).unwrap();
//! let limits = Limits { ceiling_nm: 1.87, slew_nm_per_s: 50.0 };
//! let out = assist.step(Measurement { angle_rad: 0.0, vel_rad_s: 0.0 }, 0.1, limits, 0.001);
//! assert!(out.torque_nm.abs() <= 1.87);
//! ```

pub mod aan;
pub mod difficulty;
pub mod effort;
pub mod error;
pub mod force;
pub mod governor;
pub mod human;
pub mod limits;
pub mod model;
pub mod motion;
pub mod resist;
pub mod runtime;
pub mod sim;
pub mod spec;

pub use difficulty::{DifficultyAdapter, DifficultyParams};
pub use effort::{
    BANDWIDTH_RAD_S, HAND_ESTIMATE_LAG_S, HandTorqueObserver, ObserverTuning, WheelDynamics,
};
pub use error::AssistError;
pub use governor::Infeasibility;
pub use human::{HumanArm, HumanArmParams};
pub use limits::Limits;
pub use model::PlantParams;
pub use runtime::{Assist, AssistOutput, AssistStatus, Measurement};
pub use spec::{
    AanParams, AssistMode, AssistSpec, ForceParams, HybridParams, ModelSpec, MotionParams,
    ResistParams,
};
