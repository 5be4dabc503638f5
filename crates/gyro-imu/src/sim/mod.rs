//! Simulated motion and devices: a generic random motion, the patient's arm on the wheel, and
//! simulated IMUs with the sensor model of [`crate::sensor`].

pub mod arm;
pub mod motion;
