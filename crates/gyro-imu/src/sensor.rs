//! Sensor error models: scale and quantisation (MG100, thesis §3.2.2 Table 3.1), bias, bias
//! random walk, white noise, saturation and sample-time jitter; seeded and deterministic.

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::error::{ImuError, check_range};

/// Error model of a 3-axis rate gyro.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GyroSpec {
    /// Analog scale (V·s/deg); the MG100 gives 1.1 mV·s/deg (Table 3.1). Quantisation happens
    /// on the voltage, so `resolution_deg_s · scale_v_s_per_deg` is the ADC step (V).
    pub scale_v_s_per_deg: f64,
    /// Smallest resolvable rate (deg/s); the MG100's is 0.15 deg/s (Table 3.1).
    pub resolution_deg_s: f64,
    /// Relative scale-factor error (e.g. 0.01 = +1 %), applied to every axis.
    pub scale_error: f64,
    /// Standard deviation of the turn-on bias per axis (deg/s), drawn once from the seed.
    pub bias_std_deg_s: f64,
    /// Bias random walk (deg/s/√s).
    pub bias_random_walk_deg_s_sqrt_s: f64,
    /// White rate noise density (deg/s/√Hz).
    pub noise_density_deg_s_sqrt_hz: f64,
    /// Full scale (deg/s): readings are clamped to ±this.
    pub saturation_deg_s: f64,
    /// Standard deviation of the sample-time jitter (s) added to reported timestamps.
    pub jitter_std_s: f64,
}

impl GyroSpec {
    /// The thesis's Gyration MG100 (Table 3.1: 1.1 mV·s/deg, 0.15 deg/s). The datasheet gives no
    /// noise or bias figures; the values here are typical of 2000s consumer vibrating gyros:
    /// 0.5 deg/s turn-on bias, 0.05 deg/s/√Hz noise, 0.01 deg/s/√s bias walk, ±300 deg/s.
    pub fn mg100() -> Self {
        Self {
            scale_v_s_per_deg: 1.1e-3,
            resolution_deg_s: 0.15,
            scale_error: 0.0,
            bias_std_deg_s: 0.5,
            bias_random_walk_deg_s_sqrt_s: 0.01,
            noise_density_deg_s_sqrt_hz: 0.05,
            saturation_deg_s: 300.0,
            jitter_std_s: 1e-4,
        }
    }

    /// A modern consumer MEMS gyro as in game controllers (BMI055/BMI270/LSM6DS-class,
    /// ±2000 deg/s 16-bit) read with the device's factory calibration: 0.061 deg/s LSB,
    /// 0.014 deg/s/√Hz, 0.5 deg/s turn-on bias, 0.003 deg/s/√s bias walk, 0.3 % residual
    /// scale error.
    pub fn consumer_mems() -> Self {
        Self {
            scale_v_s_per_deg: 1.0,
            resolution_deg_s: 2000.0 / 32768.0,
            scale_error: 0.003,
            bias_std_deg_s: 0.5,
            bias_random_walk_deg_s_sqrt_s: 0.003,
            noise_density_deg_s_sqrt_hz: 0.014,
            saturation_deg_s: 2000.0,
            jitter_std_s: 2e-4,
        }
    }

    /// An ideal gyro (no error at all).
    pub fn ideal() -> Self {
        Self {
            scale_v_s_per_deg: 1.0,
            resolution_deg_s: 0.0,
            scale_error: 0.0,
            bias_std_deg_s: 0.0,
            bias_random_walk_deg_s_sqrt_s: 0.0,
            noise_density_deg_s_sqrt_hz: 0.0,
            saturation_deg_s: 1e9,
            jitter_std_s: 0.0,
        }
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range(
            "scale_v_s_per_deg",
            self.scale_v_s_per_deg,
            1e-9,
            1e3,
            "[1e-9, 1e3] V·s/deg",
        )?;
        check_range(
            "resolution_deg_s",
            self.resolution_deg_s,
            0.0,
            10.0,
            "[0, 10] deg/s",
        )?;
        check_range("scale_error", self.scale_error, -0.5, 0.5, "[-0.5, 0.5]")?;
        check_range(
            "bias_std_deg_s",
            self.bias_std_deg_s,
            0.0,
            50.0,
            "[0, 50] deg/s",
        )?;
        check_range(
            "bias_random_walk_deg_s_sqrt_s",
            self.bias_random_walk_deg_s_sqrt_s,
            0.0,
            10.0,
            "[0, 10] deg/s/√s",
        )?;
        check_range(
            "noise_density_deg_s_sqrt_hz",
            self.noise_density_deg_s_sqrt_hz,
            0.0,
            10.0,
            "[0, 10] deg/s/√Hz",
        )?;
        check_range(
            "saturation_deg_s",
            self.saturation_deg_s,
            1.0,
            1e9,
            "[1, 1e9] deg/s",
        )?;
        check_range("jitter_std_s", self.jitter_std_s, 0.0, 0.01, "[0, 0.01] s")
    }
}

/// Error model of a 3-axis accelerometer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AccSpec {
    /// Quantisation step (m/s²).
    pub resolution_m_s2: f64,
    /// Standard deviation of the constant bias per axis (m/s²), drawn once from the seed.
    pub bias_std_m_s2: f64,
    /// White noise density (m/s²/√Hz).
    pub noise_density_m_s2_sqrt_hz: f64,
    /// Full scale (m/s²): readings are clamped to ±this.
    pub saturation_m_s2: f64,
}

impl AccSpec {
    /// A consumer MEMS accelerometer after the device's factory calibration (±8 g, 16 bit, 180 µg/√Hz, 5 mg residual bias per axis; every 1 mg of bias tilts the gravity estimate by 0.057°, which no filter can observe).
    pub fn consumer_mems() -> Self {
        Self {
            resolution_m_s2: 16.0 * 9.81 / 65536.0,
            bias_std_m_s2: 0.05,
            noise_density_m_s2_sqrt_hz: 180e-6 * 9.81,
            saturation_m_s2: 8.0 * 9.81,
        }
    }

    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range(
            "resolution_m_s2",
            self.resolution_m_s2,
            0.0,
            1.0,
            "[0, 1] m/s²",
        )?;
        check_range("bias_std_m_s2", self.bias_std_m_s2, 0.0, 5.0, "[0, 5] m/s²")?;
        check_range(
            "noise_density_m_s2_sqrt_hz",
            self.noise_density_m_s2_sqrt_hz,
            0.0,
            1.0,
            "[0, 1] m/s²/√Hz",
        )?;
        check_range(
            "saturation_m_s2",
            self.saturation_m_s2,
            10.0,
            1e4,
            "[10, 1e4] m/s²",
        )
    }
}

/// A seeded sensor: turns true rates (and specific force) into what the device reports.
#[derive(Debug, Clone)]
pub struct SensorModel {
    gyro: GyroSpec,
    acc: Option<AccSpec>,
    rng: ChaCha8Rng,
    gyro_bias_rad_s: Vector3<f64>,
    acc_bias_m_s2: Vector3<f64>,
}

/// One simulated reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    /// Measured body rate (rad/s).
    pub rate_rad_s: Vector3<f64>,
    /// Measured specific force (m/s²), if the sensor has an accelerometer.
    pub acc_m_s2: Option<Vector3<f64>>,
    /// Timestamp error added by jitter (s): the reported time minus the true sample time.
    pub time_error_s: f64,
}

impl SensorModel {
    /// A sensor with the given specs, its random turn-on biases drawn from `seed`.
    pub fn new(gyro: GyroSpec, acc: Option<AccSpec>, seed: u64) -> Result<Self, ImuError> {
        gyro.validate()?;
        if let Some(a) = &acc {
            a.validate()?;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let gyro_bias_rad_s = normal3(&mut rng) * gyro.bias_std_deg_s.to_radians();
        let acc_bias_m_s2 = normal3(&mut rng) * acc.map_or(0.0, |a| a.bias_std_m_s2);
        Ok(Self {
            gyro,
            acc,
            rng,
            gyro_bias_rad_s,
            acc_bias_m_s2,
        })
    }

    /// The gyro's full scale (rad/s): readings are clamped to ± this.
    pub fn gyro_full_scale_rad_s(&self) -> f64 {
        self.gyro.saturation_deg_s.to_radians()
    }

    /// The current true gyro bias (rad/s), for tests and tables.
    pub fn gyro_bias_rad_s(&self) -> Vector3<f64> {
        self.gyro_bias_rad_s
    }

    /// Override the gyro bias (rad/s).
    pub fn set_gyro_bias_rad_s(&mut self, bias: Vector3<f64>) {
        self.gyro_bias_rad_s = bias;
    }

    /// Measure the true body rate `rate_rad_s` and specific force `specific_force_m_s2` (both
    /// in the sensor frame) for a sample of period `dt_s`.
    pub fn measure(
        &mut self,
        rate_rad_s: &Vector3<f64>,
        specific_force_m_s2: &Vector3<f64>,
        dt_s: f64,
    ) -> Reading {
        let g = self.gyro;
        let dt = dt_s.max(1e-6);
        self.gyro_bias_rad_s +=
            normal3(&mut self.rng) * (g.bias_random_walk_deg_s_sqrt_s.to_radians() * dt.sqrt());
        let noise =
            normal3(&mut self.rng) * (g.noise_density_deg_s_sqrt_hz.to_radians() / dt.sqrt());
        let w = rate_rad_s * (1.0 + g.scale_error) + self.gyro_bias_rad_s + noise;
        // Through the analog scale and the ADC step (Table 3.1), then back to rad/s.
        let lsb_v = g.resolution_deg_s * g.scale_v_s_per_deg;
        let sat = g.saturation_deg_s;
        let rate = w.map(|x| {
            let volts = x.to_degrees().clamp(-sat, sat) * g.scale_v_s_per_deg;
            let q = if lsb_v > 0.0 {
                (volts / lsb_v).round() * lsb_v
            } else {
                volts
            };
            (q / g.scale_v_s_per_deg).to_radians()
        });
        let acc = self.acc.map(|a| {
            let n = normal3(&mut self.rng) * (a.noise_density_m_s2_sqrt_hz / dt.sqrt());
            (specific_force_m_s2 + self.acc_bias_m_s2 + n).map(|x| {
                let x = x.clamp(-a.saturation_m_s2, a.saturation_m_s2);
                if a.resolution_m_s2 > 0.0 {
                    (x / a.resolution_m_s2).round() * a.resolution_m_s2
                } else {
                    x
                }
            })
        });
        let jitter: f64 = StandardNormal.sample(&mut self.rng);
        Reading {
            rate_rad_s: rate,
            acc_m_s2: acc,
            time_error_s: jitter * g.jitter_std_s,
        }
    }
}

fn normal3(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::new(
        StandardNormal.sample(rng),
        StandardNormal.sample(rng),
        StandardNormal.sample(rng),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mg100_quantises_to_its_resolution_and_saturates() {
        let mut spec = GyroSpec::ideal();
        spec.scale_v_s_per_deg = 1.1e-3;
        spec.resolution_deg_s = 0.15;
        spec.saturation_deg_s = 300.0;
        let mut s = SensorModel::new(spec, None, 1).unwrap();
        let r = s.measure(
            &Vector3::new(
                0.07f64.to_radians(),
                0.08f64.to_radians(),
                500f64.to_radians(),
            ),
            &Vector3::zeros(),
            0.0035,
        );
        let d = r.rate_rad_s.map(f64::to_degrees);
        assert!((d.x - 0.0).abs() < 1e-9 && (d.y - 0.15).abs() < 1e-9, "{d}");
        assert!((d.z - 300.0).abs() < 0.15, "{d}");
    }

    #[test]
    fn noise_has_the_specified_density_and_is_seeded() {
        let mut spec = GyroSpec::ideal();
        spec.noise_density_deg_s_sqrt_hz = 0.1;
        let dt = 0.01;
        let mut a = SensorModel::new(spec, None, 7).unwrap();
        let mut b = SensorModel::new(spec, None, 7).unwrap();
        let n = 20000;
        let mut sum2 = 0.0;
        for _ in 0..n {
            let ra = a.measure(&Vector3::zeros(), &Vector3::zeros(), dt);
            let rb = b.measure(&Vector3::zeros(), &Vector3::zeros(), dt);
            assert_eq!(ra, rb);
            sum2 += ra.rate_rad_s.x.to_degrees().powi(2);
        }
        let std = (sum2 / n as f64).sqrt();
        let expect = 0.1 / dt.sqrt();
        assert!((std / expect - 1.0).abs() < 0.03, "{std} vs {expect}");
    }

    #[test]
    fn validate_names_the_bad_field() {
        let mut spec = GyroSpec::mg100();
        spec.noise_density_deg_s_sqrt_hz = f64::NAN;
        let e = spec.validate().unwrap_err().to_string();
        assert!(e.contains("noise_density_deg_s_sqrt_hz"), "{e}");
        let toml_err =
            toml::from_str::<GyroSpec>("scale_v_s_per_deg = 1.0\nbogus = 2").unwrap_err();
        assert!(toml_err.to_string().contains("bogus"));
    }
}
