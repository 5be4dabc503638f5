//! Rest detection and gyro-bias estimation at rest.
//!
//! Bias is the dominant source of gyro drift (0.15 deg/s held for 10 minutes is 90°). When the
//! sensor is still, the reading *is* the bias: detect rest, average, subtract.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{ImuError, check_range};

/// First-order low-pass gain for time constant `tau_s` at step `dt_s`.
#[inline]
pub(crate) fn lp_gain(tau_s: f64, dt_s: f64) -> f64 {
    if tau_s <= 0.0 {
        1.0
    } else {
        1.0 - (-dt_s / tau_s).exp()
    }
}

/// Rest-detector settings (defaults follow Laidig & Seel 2023).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestConfig {
    /// Low-pass time constant of the reference signals (s).
    pub filter_tau_s: f64,
    /// Max deviation of the rate from its low-passed value at rest (deg/s).
    pub rate_threshold_deg_s: f64,
    /// Max deviation of the acceleration from its low-passed value at rest (m/s²).
    pub acc_threshold_m_s2: f64,
    /// Max magnitude of the low-passed rate at rest (deg/s): the largest bias we believe in.
    pub max_bias_deg_s: f64,
    /// Max rate at which the gravity direction may turn in the sensor frame at rest (deg/s),
    /// from the lag between a fast and a slow low-pass of the acceleration. This rejects slow
    /// real rotations (a drifting elbow) that the rate-deviation test cannot see, and that
    /// would otherwise be averaged into the bias.
    pub tilt_rate_threshold_deg_s: f64,
    /// How long the conditions must hold before rest is declared (s).
    pub min_duration_s: f64,
}

impl Default for RestConfig {
    fn default() -> Self {
        Self {
            filter_tau_s: 0.5,
            rate_threshold_deg_s: 2.0,
            acc_threshold_m_s2: 0.5,
            max_bias_deg_s: 5.0,
            tilt_rate_threshold_deg_s: 0.3,
            min_duration_s: 1.5,
        }
    }
}

impl RestConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range(
            "filter_tau_s",
            self.filter_tau_s,
            0.01,
            10.0,
            "[0.01, 10] s",
        )?;
        check_range(
            "rate_threshold_deg_s",
            self.rate_threshold_deg_s,
            0.01,
            50.0,
            "[0.01, 50] deg/s",
        )?;
        check_range(
            "acc_threshold_m_s2",
            self.acc_threshold_m_s2,
            0.001,
            10.0,
            "[0.001, 10] m/s²",
        )?;
        check_range(
            "max_bias_deg_s",
            self.max_bias_deg_s,
            0.1,
            50.0,
            "[0.1, 50] deg/s",
        )?;
        check_range(
            "tilt_rate_threshold_deg_s",
            self.tilt_rate_threshold_deg_s,
            0.01,
            50.0,
            "[0.01, 50] deg/s",
        )?;
        check_range(
            "min_duration_s",
            self.min_duration_s,
            0.0,
            60.0,
            "[0, 60] s",
        )
    }
}

/// Detects when a sensor is still from its rate (and, if present, acceleration) stream.
#[derive(Debug, Clone, Copy)]
pub struct RestDetector {
    cfg: RestConfig,
    rate_lp: Option<Vector3<f64>>,
    acc_lp: Option<Vector3<f64>>,
    acc_tilt: Option<(Vector3<f64>, Vector3<f64>)>,
    dev_rate2: f64,
    dev_acc2: f64,
    still_s: f64,
}

impl RestDetector {
    /// A detector with validated settings.
    pub fn new(cfg: RestConfig) -> Result<Self, ImuError> {
        cfg.validate()?;
        Ok(Self {
            cfg,
            rate_lp: None,
            acc_lp: None,
            acc_tilt: None,
            dev_rate2: 0.0,
            dev_acc2: 0.0,
            still_s: 0.0,
        })
    }

    /// Feed one sample; returns whether the sensor is at rest now.
    pub fn update(
        &mut self,
        rate_rad_s: &Vector3<f64>,
        acc_m_s2: Option<&Vector3<f64>>,
        dt_s: f64,
    ) -> bool {
        let k = lp_gain(self.cfg.filter_tau_s, dt_s);
        let rlp = self.rate_lp.get_or_insert(*rate_rad_s);
        *rlp += (rate_rad_s - *rlp) * k;
        // Squared deviation from the low-passed value, smoothed over a short window (a fifth
        // of `filter_tau_s`) so a noisy gyro's single samples do not break rest.
        let kd = lp_gain(0.2 * self.cfg.filter_tau_s, dt_s);
        self.dev_rate2 += ((rate_rad_s - *rlp).norm_squared() - self.dev_rate2) * kd;
        let rate_ok = self.dev_rate2.sqrt() < self.cfg.rate_threshold_deg_s.to_radians()
            && rlp.norm() < self.cfg.max_bias_deg_s.to_radians();
        let acc_ok = match acc_m_s2 {
            Some(a) => {
                let alp = self.acc_lp.get_or_insert(*a);
                *alp += (a - *alp) * k;
                self.dev_acc2 += ((a - *alp).norm_squared() - self.dev_acc2) * kd;
                // Two short low-passes (0.2 and 0.7 × filter_tau_s): under a steady tilt rate
                // r their directions differ by r·Δτ, Δτ = 0.5 × filter_tau_s.
                let (fast, slow) = self.acc_tilt.get_or_insert((*a, *a));
                *fast += (a - *fast) * lp_gain(0.2 * self.cfg.filter_tau_s, dt_s);
                *slow += (a - *slow) * lp_gain(0.7 * self.cfg.filter_tau_s, dt_s);
                let tilt = fast.angle(slow) / (0.5 * self.cfg.filter_tau_s);
                self.dev_acc2.sqrt() < self.cfg.acc_threshold_m_s2
                    && tilt < self.cfg.tilt_rate_threshold_deg_s.to_radians()
            }
            None => true,
        };
        if rate_ok && acc_ok {
            self.still_s += dt_s;
        } else {
            self.still_s = 0.0;
        }
        self.is_rest()
    }

    /// Whether the last update declared rest.
    pub fn is_rest(&self) -> bool {
        self.still_s >= self.cfg.min_duration_s && self.still_s > 0.0
    }

    /// The low-passed rate (rad/s): at rest, an estimate of the bias.
    pub fn rate_lowpass(&self) -> Vector3<f64> {
        self.rate_lp.unwrap_or_default()
    }
}

/// Gyro-bias estimator: averages the rate during detected rest and subtracts it.
#[derive(Debug, Clone, Copy)]
pub struct GyroBiasEstimator {
    rest: RestDetector,
    bias_rad_s: Vector3<f64>,
    /// Averaging time constant at rest (s).
    tau_s: f64,
    rest_time_s: f64,
}

impl GyroBiasEstimator {
    /// An estimator with rest settings `cfg` and averaging time constant `tau_s` (s).
    pub fn new(cfg: RestConfig, tau_s: f64) -> Result<Self, ImuError> {
        check_range("tau_s", tau_s, 0.1, 600.0, "[0.1, 600] s")?;
        Ok(Self {
            rest: RestDetector::new(cfg)?,
            bias_rad_s: Vector3::zeros(),
            tau_s,
            rest_time_s: 0.0,
        })
    }

    /// Feed a sample; returns the bias-corrected rate (rad/s).
    pub fn update(
        &mut self,
        rate_rad_s: &Vector3<f64>,
        acc_m_s2: Option<&Vector3<f64>>,
        dt_s: f64,
    ) -> Vector3<f64> {
        if self.rest.update(rate_rad_s, acc_m_s2, dt_s) {
            self.rest_time_s += dt_s;
            // A running mean at first, then an exponential average with time constant tau.
            let k = (dt_s / self.rest_time_s.min(self.tau_s)).min(1.0);
            self.bias_rad_s += (rate_rad_s - self.bias_rad_s) * k;
        }
        rate_rad_s - self.bias_rad_s
    }

    /// The current bias estimate (rad/s).
    pub fn bias_rad_s(&self) -> Vector3<f64> {
        self.bias_rad_s
    }

    /// Whether the sensor is at rest now.
    pub fn is_rest(&self) -> bool {
        self.rest.is_rest()
    }
}

/// Estimate a constant bias from a whole record: the mean rate over the samples a
/// [`RestDetector`] marks as rest. Returns `(bias_rad_s, rest_fraction)`; an error if no
/// sample is at rest.
pub fn estimate_bias(
    rates_rad_s: &[Vector3<f64>],
    acc_m_s2: Option<&[Vector3<f64>]>,
    dt_s: f64,
    cfg: RestConfig,
) -> Result<(Vector3<f64>, f64), ImuError> {
    check_range("dt_s", dt_s, 1e-6, 1.0, "[1e-6, 1] s")?;
    if let Some(a) = acc_m_s2
        && a.len() != rates_rad_s.len()
    {
        return Err(ImuError::InvalidInput(format!(
            "acc has {} samples, rates has {}",
            a.len(),
            rates_rad_s.len()
        )));
    }
    let mut det = RestDetector::new(cfg)?;
    let mut sum = Vector3::zeros();
    let mut n = 0usize;
    for (i, w) in rates_rad_s.iter().enumerate() {
        if !(w.x.is_finite() && w.y.is_finite() && w.z.is_finite()) {
            return Err(ImuError::InvalidInput(format!(
                "rate sample {i} is not finite"
            )));
        }
        if det.update(w, acc_m_s2.map(|a| &a[i]), dt_s) {
            sum += w;
            n += 1;
        }
    }
    if n == 0 {
        return Err(ImuError::Calibration(format!(
            "no rest found in {} samples (need {} s still)",
            rates_rad_s.len(),
            cfg.min_duration_s
        )));
    }
    Ok((sum / n as f64, n as f64 / rates_rad_s.len() as f64))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::{GyroSpec, SensorModel};

    #[test]
    fn rest_is_detected_only_after_stillness_and_not_during_motion() {
        let mut d = RestDetector::new(RestConfig::default()).unwrap();
        let dt = 0.01;
        for k in 0..300 {
            let w = Vector3::new((k as f64 * 0.1).sin() * 1.0, 0.0, 0.0);
            assert!(!d.update(&w, None, dt), "motion declared rest at {k}");
        }
        let mut first_rest = None;
        for k in 0..400 {
            if d.update(&Vector3::new(0.01, 0.0, 0.0), None, dt) && first_rest.is_none() {
                first_rest = Some(k);
            }
        }
        let k = first_rest.expect("rest never detected");
        assert!((150..=400).contains(&k), "rest after {k} samples");
    }

    #[test]
    fn estimate_bias_recovers_mg100_bias_from_a_still_record() {
        let mut s = SensorModel::new(GyroSpec::mg100(), None, 3).unwrap();
        let truth = Vector3::new(0.4, -0.3, 0.2).map(f64::to_radians);
        s.set_gyro_bias_rad_s(truth);
        let dt = 1.0 / 286.0;
        let rates: Vec<_> = (0..286 * 10)
            .map(|_| {
                s.measure(&Vector3::zeros(), &Vector3::zeros(), dt)
                    .rate_rad_s
            })
            .collect();
        let (b, frac) = estimate_bias(&rates, None, dt, RestConfig::default()).unwrap();
        assert!(frac > 0.8);
        assert!(
            (b - truth).norm().to_degrees() < 0.03,
            "{}",
            (b - truth).norm().to_degrees()
        );
    }

    #[test]
    fn estimate_bias_rejects_nan_and_all_motion() {
        let dt = 0.01;
        let mut rates = vec![Vector3::zeros(); 500];
        rates[7].y = f64::NAN;
        assert!(
            estimate_bias(&rates, None, dt, RestConfig::default())
                .unwrap_err()
                .to_string()
                .contains("sample 7")
        );
        let moving: Vec<_> = (0..500)
            .map(|k| Vector3::new((k as f64 * 0.2).sin() * 2.0, 0.0, 0.0))
            .collect();
        assert!(matches!(
            estimate_bias(&moving, None, dt, RestConfig::default()),
            Err(ImuError::Calibration(_))
        ));
    }

    /// Orientation drift of gyro-only integration over 10 minutes of arm-like motion with a
    /// 6 s pause every 40 s, with and without rest-bias estimation (the BENCHMARKS.md table).
    #[test]
    fn drift_with_and_without_rest_bias_estimation_table() {
        use crate::integrate::QuatIntegrator;
        use crate::sim::motion::RandomMotion;
        use crate::so3;
        let dt = 1.0 / 286.0;
        let n = 600 * 286;
        println!(
            "| sensor | bias (deg/s) | raw: end / RMS (deg) | rest-bias estimated: end / RMS (deg) |\n|---|---|---|---|"
        );
        for (name, spec, bias) in [
            ("MG100", GyroSpec::mg100(), 0.15),
            ("MG100", GyroSpec::mg100(), 0.5),
            ("consumer MEMS", GyroSpec::consumer_mems(), 0.5),
        ] {
            let mut motion = RandomMotion::new(9, 90.0, 0.1, 40.0, 6.0);
            let mut sensor = SensorModel::new(spec, None, 77).unwrap();
            sensor.set_gyro_bias_rad_s(
                Vector3::new(bias, -bias, bias).map(f64::to_radians) / 3f64.sqrt(),
            );
            let mut est = GyroBiasEstimator::new(RestConfig::default(), 10.0).unwrap();
            let mut now = motion.next(dt);
            let q0 = now.orientation;
            let (mut raw, mut cor) = (QuatIntegrator::new(q0), QuatIntegrator::new(q0));
            let (mut s_raw, mut s_cor) = (0.0, 0.0);
            let (mut e_raw, mut e_cor) = (0.0, 0.0);
            for _ in 0..n {
                let r = sensor.measure(&now.rate_rad_s, &Vector3::zeros(), dt);
                raw.step(&r.rate_rad_s, dt);
                cor.step(&est.update(&r.rate_rad_s, None, dt), dt);
                now = motion.next(dt);
                e_raw = so3::angle_between(&raw.orientation(), &now.orientation).to_degrees();
                e_cor = so3::angle_between(&cor.orientation(), &now.orientation).to_degrees();
                s_raw += e_raw * e_raw;
                s_cor += e_cor * e_cor;
            }
            let (r_raw, r_cor) = ((s_raw / n as f64).sqrt(), (s_cor / n as f64).sqrt());
            println!("| {name} | {bias} | {e_raw:.2} / {r_raw:.2} | {e_cor:.2} / {r_cor:.2} |");
            assert!(r_cor * 3.0 < r_raw, "{name}: {r_cor} vs {r_raw}");
        }
    }
}
