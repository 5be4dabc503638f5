//! Write the simulated records behind the fusion error table (`fusion::tests`) to raw files, so
//! `scripts/compare_vqf.py --table DIR` can run the reference VQF on exactly the same samples.
//!
//! Usage: `cargo run -p gyro-imu --release --example fusion_table_data -- DIR`. For each row it
//! writes `DIR/<row>.f64`: little-endian f64, one record per sample of
//! `[gyr x y z (rad/s), acc x y z (m/s²), truth after the sample w x y z]`, 200 Hz, 5 minutes.
//! `DIR/rows.txt` lists `<row> <pauses> <config>` where config is `default`, `no_motion_bias`
//! or `no_bias`.

use std::io::Write;

use gyro_imu::sensor::{AccSpec, GyroSpec, SensorModel};
use gyro_imu::sim::motion::RandomMotion;
use nalgebra::Vector3;

fn main() -> std::io::Result<()> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "fusion-table".into());
    std::fs::create_dir_all(&dir)?;
    let dt = 1.0 / 200.0;
    let one_pct = GyroSpec {
        scale_error: 0.01,
        ..GyroSpec::consumer_mems()
    };
    let mems = GyroSpec::consumer_mems();
    // (name, seed, bias deg/s, gyro spec, rest s per 40 s, config): the rows of the table in
    // BENCHMARKS.md, in the same order and with the same seeds as the tests.
    let rows = [
        ("default_seed1", 1, None, mems, 6.0, "default"),
        ("default_seed2", 2, Some(1.0), mems, 6.0, "default"),
        ("default_seed3", 3, Some(-1.5), mems, 6.0, "default"),
        ("no_motion_bias", 2, Some(1.0), mems, 6.0, "no_motion_bias"),
        ("no_bias", 2, Some(1.0), mems, 6.0, "no_bias"),
        ("scale_1pct", 2, Some(1.0), one_pct, 6.0, "default"),
        ("no_pauses_seed2", 2, Some(1.0), mems, 0.0, "default"),
        (
            "no_pauses_no_motion_bias",
            2,
            Some(1.0),
            mems,
            0.0,
            "no_motion_bias",
        ),
        ("no_pauses_seed1", 1, None, mems, 0.0, "default"),
        ("no_pauses_seed3", 3, Some(-1.5), mems, 0.0, "default"),
    ];
    let mut list = std::fs::File::create(format!("{dir}/rows.txt"))?;
    for (name, seed, bias, spec, rest_s, cfg) in rows {
        let mut motion = RandomMotion::new(seed, 120.0, 0.15, 40.0, rest_s);
        let mut sensor = SensorModel::new(spec, Some(AccSpec::consumer_mems()), seed + 100)
            .map_err(std::io::Error::other)?;
        if let Some(b) = bias {
            sensor.set_gyro_bias_rad_s(Vector3::new(b, -0.8 * b, 0.6 * b).map(f64::to_radians));
        }
        let n = (5.0 * 60.0 / dt) as usize;
        let mut out = Vec::with_capacity(n * 10 * 8);
        let mut now = motion.next(dt);
        for _ in 0..n {
            let r = sensor.measure(&now.rate_rad_s, &now.specific_force_m_s2, dt);
            let acc = r.acc_m_s2.unwrap_or_default();
            now = motion.next(dt);
            let q = now.orientation;
            for x in [
                r.rate_rad_s.x,
                r.rate_rad_s.y,
                r.rate_rad_s.z,
                acc.x,
                acc.y,
                acc.z,
                q.w,
                q.i,
                q.j,
                q.k,
            ] {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        std::fs::write(format!("{dir}/{name}.f64"), out)?;
        writeln!(list, "{name} {} {cfg}", rest_s > 0.0)?;
    }
    Ok(())
}
