//! Assist-as-needed: an error-based feedforward learned per phase bin across repetitions,
//! with a forgetting factor so that the robot's help decays whenever the patient no longer
//! needs it.
//!
//! Update, once per repetition for each phase bin `i` (Emken, Bobrow & Reinkensmeyer 2005,
//! "Robotic movement training as an optimization problem: designing a controller that
//! assists only as needed", ICORR; the human's own trial-to-trial adaptation has the same
//! form, Emken et al. 2007, "Motor adaptation as a greedy optimization of error and effort",
//! J. Neurophysiol. 97):
//!
//! `u_{k+1}[i − L] = f · u_k[i − L] + g · ē_k[i]`
//!
//! with `ē_k[i]` the mean angle error `r − θ` (rad) over bin `i` in repetition `k`, forgetting
//! factor `0 ≤ f < 1`, learning gain `g` (N·m/rad) and a phase lead of `L` bins (the torque
//! applied in a bin shows up as position error a little later; phase-lead learning is the
//! standard remedy in iterative learning control, Bristow, Tharayil & Alleyne 2006, "A survey
//! of iterative learning control", IEEE Control Systems 26(3)). With a constant error the
//! help settles at `g·ē/(1 − f)`; with no error it decays as `fᵏ` — the robot must "relax"
//! faster than the patient forgets (`f` below the human's retention factor) so that the
//! patient, not the robot, takes over the task. Every learned value is clamped to the torque
//! ceiling so the learning law cannot wind up.
//!
//! The applied torque is `τ = u(phase) + K_fb (r − θ)`, `u(phase)` linearly interpolated
//! between bin centres; `K_fb` is a small optional compliant feedback (Wolbrecht et al. 2008,
//! "Optimizing compliant, model-based robotic assistance to promote neurorehabilitation",
//! IEEE TNSRE 16(3)).
//!
//! The phase is `(t mod T)/T` with `t` accumulated from `dt` since the controller started,
//! so the station must start the assist with the exercise's first repetition.

/// Largest number of phase bins.
pub const MAX_BINS: usize = 256;

/// The assist-as-needed learner.
#[derive(Clone, Debug)]
pub struct AssistAsNeeded {
    period_s: f64,
    forgetting: f64,
    gain_nm_per_rad: f64,
    lead_bins: usize,
    feedback_nm_per_rad: f64,
    bins_nm: Vec<f64>,
    err_sum: f64,
    err_count: u32,
    current_bin: usize,
    t_s: f64,
    repetitions: u64,
}

impl AssistAsNeeded {
    /// A learner with `bins` phase bins (1 ..= [`MAX_BINS`]) over a repetition of `period_s`.
    /// Allocates its bins once here; [`AssistAsNeeded::torque_nm`] never allocates.
    pub fn new(
        period_s: f64,
        bins: usize,
        forgetting: f64,
        gain_nm_per_rad: f64,
        lead_bins: usize,
        feedback_nm_per_rad: f64,
    ) -> Self {
        let bins = bins.clamp(1, MAX_BINS);
        Self {
            period_s,
            forgetting,
            gain_nm_per_rad,
            lead_bins: lead_bins % bins,
            feedback_nm_per_rad,
            bins_nm: vec![0.0; bins],
            err_sum: 0.0,
            err_count: 0,
            current_bin: 0,
            t_s: 0.0,
            repetitions: 0,
        }
    }

    /// Completed repetitions.
    pub fn repetitions(&self) -> u64 {
        self.repetitions
    }

    /// The learned feedforward per bin, N·m.
    pub fn bins_nm(&self) -> &[f64] {
        &self.bins_nm
    }

    /// Mean magnitude of the learned help, N·m.
    pub fn mean_help_nm(&self) -> f64 {
        self.bins_nm.iter().map(|u| u.abs()).sum::<f64>() / self.bins_nm.len() as f64
    }

    /// Let `dt_s` pass without learning or output (the station's reference keeps moving
    /// while the assist sits in its safe state), so the phase stays aligned.
    pub fn skip(&mut self, dt_s: f64) {
        self.t_s += dt_s;
        self.err_sum = 0.0;
        self.err_count = 0;
    }

    fn phase(&self) -> f64 {
        (self.t_s / self.period_s).fract()
    }

    fn close_bin(&mut self, ceiling_nm: f64) {
        let n = self.bins_nm.len();
        if self.err_count > 0 {
            let e = self.err_sum / f64::from(self.err_count);
            let target = (self.current_bin + n - self.lead_bins) % n;
            let u = self.forgetting * self.bins_nm[target] + self.gain_nm_per_rad * e;
            self.bins_nm[target] = u.clamp(-ceiling_nm, ceiling_nm);
        }
        self.err_sum = 0.0;
        self.err_count = 0;
    }

    /// Feedforward at the current phase, interpolated between bin centres, N·m.
    fn feedforward_nm(&self) -> f64 {
        let n = self.bins_nm.len();
        let x = self.phase() * n as f64 - 0.5;
        let i0 = x.floor();
        let w = x - i0;
        let i0 = (i0 as isize).rem_euclid(n as isize) as usize;
        let i1 = (i0 + 1) % n;
        (1.0 - w) * self.bins_nm[i0] + w * self.bins_nm[i1]
    }

    /// One tick: learn from the error `reference_rad − angle_rad` and return the assist
    /// torque (unclamped; the caller applies the limits), N·m.
    pub fn torque_nm(
        &mut self,
        angle_rad: f64,
        reference_rad: f64,
        ceiling_nm: f64,
        dt_s: f64,
    ) -> f64 {
        let n = self.bins_nm.len();
        let err = reference_rad - angle_rad;
        let bin = ((self.phase() * n as f64) as usize).min(n - 1);
        if bin != self.current_bin {
            self.close_bin(ceiling_nm);
            if bin < self.current_bin {
                self.repetitions += 1;
            }
            self.current_bin = bin;
        }
        self.err_sum += err;
        self.err_count += 1;
        let tau = self.feedforward_nm() + self.feedback_nm_per_rad * err;
        self.t_s += dt_s;
        tau
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_error_settles_at_g_e_over_one_minus_f() {
        let mut a = AssistAsNeeded::new(1.0, 10, 0.8, 2.0, 0, 0.0);
        for _ in 0..100_000 {
            a.torque_nm(0.0, 0.05, 10.0, 0.001);
        }
        for u in a.bins_nm() {
            assert!((u - 2.0 * 0.05 / 0.2).abs() < 1e-9, "{u}");
        }
        assert!(a.repetitions() >= 99);
    }

    #[test]
    fn help_decays_geometrically_without_error() {
        let mut a = AssistAsNeeded::new(1.0, 4, 0.5, 2.0, 0, 0.0);
        for _ in 0..20_000 {
            a.torque_nm(0.0, 0.1, 10.0, 0.001);
        }
        let before = a.mean_help_nm();
        for _ in 0..3_000 {
            a.torque_nm(0.0, 0.0, 10.0, 0.001);
        }
        let after = a.mean_help_nm();
        assert!(after < before * 0.5f64.powi(2), "{before} -> {after}");
    }

    #[test]
    fn learned_help_never_exceeds_the_ceiling() {
        let mut a = AssistAsNeeded::new(0.5, 8, 0.99, 100.0, 1, 0.0);
        for _ in 0..10_000 {
            a.torque_nm(0.0, 3.0, 1.5, 0.001);
        }
        assert!(a.bins_nm().iter().all(|u| u.abs() <= 1.5));
    }
}
