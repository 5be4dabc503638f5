//! `telerehab devices`: list wheels, pedals, gamepads and arm IMUs (and what to check when
//! there are none), with the torque ceiling each wheel would get in N·m and as a share of its
//! motor under the station's configuration.

use std::fmt::Write as _;
use std::path::PathBuf;

use session::config::StationConfig;

/// `telerehab devices`.
#[derive(Debug, clap::Args)]
pub struct DevicesArgs {
    /// Station configuration (TOML): its `[wheel]` section and patient ceiling
    /// (`[haptic.safety] ceiling_nm`) decide the torque ceiling shown for each wheel.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// The IMU part of the device list.
fn imu_report() -> String {
    let mut s = String::new();
    match gyro_imu::device::enumerate() {
        Ok(list) if list.is_empty() => {
            let _ = writeln!(
                s,
                "IMUs: 0\nNo arm IMU found (DualShock 4, DualSense, Joy-Con or Pro Controller over USB or \
                 Bluetooth). Check that it is paired or plugged in and that this user can read \
                 /dev/hidraw* (install the udev rule in packaging/udev/)."
            );
        }
        Ok(list) => {
            let _ = writeln!(s, "IMUs: {}", list.len());
            for d in list {
                let _ = writeln!(
                    s,
                    "  {} ({:?}, {:04x}:{:04x}{}) at {}",
                    d.name,
                    d.kind,
                    d.vendor_id,
                    d.product_id,
                    if d.bluetooth { ", Bluetooth" } else { "" },
                    d.path
                );
            }
        }
        Err(e) => {
            let _ = writeln!(s, "IMUs: cannot list HID devices: {e}");
        }
    }
    s
}

/// Print the devices found; exits successfully when there are none (that is an answer).
pub fn run(args: &DevicesArgs) -> anyhow::Result<()> {
    let cfg = match &args.config {
        Some(p) => StationConfig::load(p)?,
        None => StationConfig::default(),
    };
    let mut report = wheel_devices::enumerate_devices();
    report.apply_config(&cfg.wheel, cfg.haptic.safety.ceiling_nm);
    println!("{report}");
    print!("{}", imu_report());
    Ok(())
}
