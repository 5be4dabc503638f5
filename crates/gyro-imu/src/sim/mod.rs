//! Simulated motion and devices: a generic random motion, the patient's arm on the wheel and
//! trunk in the chair, and simulated IMUs with the sensor model of [`crate::sensor`].

pub mod arm;
pub mod motion;
pub mod trunk;
