//! What the station tells the hub of the patient's wheel in every `Hello`: its model, rated
//! torque and the ceiling the safety chain will allow at the motor in this configuration (the
//! clinic's prescribe form bounds every torque by it).

use haptic_wheel::wheel_config::CeilingReport;
use netlink::WheelInfo;
use session::config::StationConfig;

/// The wheel a session of `cfg` drives: the simulated one (`simulated`), else the first
/// force-feedback wheel plugged in (`None` when there is none). An unknown model is named as
/// such, with the conservative ceiling of unknown wheels.
pub fn for_hub(cfg: &StationConfig, simulated: bool) -> Option<WheelInfo> {
    if simulated {
        let max_nm = cfg.sim_wheel.max_torque_nm;
        // The chain's ceiling: the patient's, never above what the wheel gives.
        let ceiling_nm = cfg.haptic.safety.ceiling_nm.unwrap_or(max_nm).min(max_nm);
        return Some(WheelInfo {
            model: "simulated wheel".into(),
            rated_torque_nm: max_nm,
            ceiling_nm,
            unknown: false,
        });
    }
    let mut devices = wheel_devices::enumerate_devices();
    devices.apply_config(&cfg.wheel, cfg.haptic.safety.ceiling_nm);
    let wheel = devices.wheels.first()?;
    let model = wheel
        .profile
        .as_ref()
        .map_or(wheel.traits.name.as_str(), |p| p.name.as_str());
    from_ceiling(model, wheel.ceiling.as_ref()?)
}

/// The hub's view of a wheel named `model` whose ceiling is `ceiling` (`None` for a report
/// the hub would refuse: a ceiling above the motor's rating cannot be).
pub fn from_ceiling(model: &str, ceiling: &CeilingReport) -> Option<WheelInfo> {
    let model = if ceiling.assumed {
        format!("unknown wheel ({model})")
    } else {
        model.to_owned()
    };
    let info = WheelInfo {
        model: printable(&model),
        rated_torque_nm: ceiling.motor_nm,
        ceiling_nm: ceiling.ceiling_nm.min(ceiling.motor_nm),
        unknown: ceiling.assumed,
    };
    info.validate().ok().map(|()| info)
}

/// `text` without control characters, cut to the protocol's text length on a character
/// boundary (a driver's device name is not the station's to trust).
fn printable(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars().map(|c| if c.is_control() { ' ' } else { c }) {
        if out.len() + c.len_utf8() > netlink::frame::MAX_TEXT_LEN {
            break;
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use haptic_wheel::DeviceProfile;

    #[test]
    fn the_simulated_wheel_is_told_with_the_patient_ceiling_below_its_motor() {
        let mut cfg = StationConfig::default();
        let max = cfg.sim_wheel.max_torque_nm;
        let w = for_hub(&cfg, true).unwrap();
        assert_eq!((w.rated_torque_nm, w.ceiling_nm), (max, max));
        cfg.haptic.safety.ceiling_nm = Some(0.5);
        assert_eq!(for_hub(&cfg, true).unwrap().ceiling_nm, 0.5);
        assert!(w.validate().is_ok());
    }

    #[test]
    fn an_unknown_wheel_is_named_unknown_with_its_conservative_ceiling() {
        let profile = DeviceProfile::for_usb_id(0x1234, 0x5678);
        let ceiling = CeilingReport::new(&profile, 1.0, None);
        let w = from_ceiling("Acme Wheel", &ceiling).unwrap();
        assert!(w.unknown && w.model.contains("unknown"), "{w:?}");
        assert_eq!(
            w.ceiling_nm,
            haptic_wheel::profile::UNKNOWN_WHEEL_CEILING_NM.min(w.rated_torque_nm)
        );
    }
}
