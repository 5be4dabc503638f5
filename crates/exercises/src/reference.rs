//! Test-only reference solution of eq. C.1–C.15: written again from the paper, independently
//! of `model.rs` (linear tyres, forward motion, drive force only), and integrated with an
//! adaptive Dormand–Prince 5(4) method at tight tolerances.

/// Table C.1 constants, restated here on purpose.
const CF: f64 = 145_000.0;
const CR: f64 = 145_000.0;
const A: f64 = 1.37;
const B: f64 = 1.43;
const D: f64 = 1.5;
const M: f64 = 1860.0;
const IZ: f64 = 3100.0;

/// `y = [X, Y, θ, Ux, Uy, r]`; `delta` and `fad` are the driver inputs at time `t`.
fn rhs(y: &[f64; 6], delta: f64, fad: f64) -> [f64; 6] {
    let [_, _, th, ux, uy, r] = *y;
    // eq. C.12 with Fbd = 0: [δ, 0, 0, Fad/2, Fad/2].
    let (fxrf, fxlf, fxrr, fxlr) = (0.0, 0.0, fad / 2.0, fad / 2.0);
    let fxf = fxrf + fxlf; // C.4
    let fxr = fxrr + fxlr; // C.5
    let dfxf = fxrf - fxlf; // C.6
    let dfxr = fxrr - fxlr; // C.7
    let fyf = -CF * ((uy + r * A) / ux - delta); // C.13
    let fyr = -CR * ((uy - r * B) / ux); // C.14
    let ux_dot = (fxr + fxf * delta.cos() - fyf * delta.sin() + M * r * uy) / M; // C.1
    let uy_dot = (fyr + fxf * delta.sin() + fyf * delta.cos() - M * r * ux) / M; // C.2
    let r_dot = (A * fxf * delta.sin() + A * fyf * delta.cos() - B * fyr
        + dfxr * D / 2.0
        + dfxf * delta.cos() * D / 2.0)
        / IZ; // C.3
    // C.15
    [
        th.cos() * ux - th.sin() * uy,
        th.sin() * ux + th.cos() * uy,
        r,
        ux_dot,
        uy_dot,
        r_dot,
    ]
}

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const AM: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const B5: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
const B4: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// Integrate from `t0` to `t1` with inputs `inputs(t) -> (δ, Fad)` that are smooth on the
/// interval (split the interval at input discontinuities).
pub fn integrate<F: Fn(f64) -> (f64, f64)>(y0: [f64; 6], t0: f64, t1: f64, inputs: &F) -> [f64; 6] {
    let (rtol, atol) = (1e-12, 1e-12);
    let mut t = t0;
    let mut y = y0;
    let mut h: f64 = 1e-3;
    while t < t1 {
        h = h.min(t1 - t);
        let mut k = [[0.0; 6]; 7];
        for s in 0..7 {
            let mut ys = y;
            for (j, kj) in k.iter().enumerate().take(s) {
                for i in 0..6 {
                    ys[i] += h * AM[s][j] * kj[i];
                }
            }
            let (delta, fad) = inputs(t + C[s] * h);
            k[s] = rhs(&ys, delta, fad);
        }
        let mut y5 = y;
        let mut err: f64 = 0.0;
        for i in 0..6 {
            let (mut d5, mut d4) = (0.0, 0.0);
            for s in 0..7 {
                d5 += B5[s] * k[s][i];
                d4 += B4[s] * k[s][i];
            }
            y5[i] += h * d5;
            let scale = atol + rtol * y[i].abs().max(y5[i].abs());
            err = err.max((h * (d5 - d4)).abs() / scale);
        }
        if err <= 1.0 {
            t += h;
            y = y5;
        }
        h *= (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_reproduces_circle_of_steady_state_yaw_rate() {
        // After the transient, r = U δ / (L + K U²) at the current speed.
        let delta = 0.01;
        let y = integrate([0.0, 0.0, 0.0, 15.0, 0.0, 0.0], 0.0, 10.0, &|_| {
            (delta, 0.0)
        });
        let (l, k) = (A + B, M * (B * CR - A * CF) / ((A + B) * CF * CR));
        let expect = y[3] * delta / (l + k * y[3] * y[3]);
        assert!((y[5] - expect).abs() / expect < 2e-3, "{y:?} vs {expect}");
    }
}
