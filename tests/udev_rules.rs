//! The udev rule shipped with the station (`packaging/udev/70-telerehab.rules`) gives the user
//! at the seat every device the station drives: the event node of every wheel with a built-in
//! profile and the hidraw node of every supported controller IMU, over USB and Bluetooth.

use std::path::Path;

/// One rule's match: the kernel node pattern and the vendor/product patterns (udev globs).
struct Rule {
    kernel: String,
    vendor: Option<String>,
    product: Option<String>,
    kernels: Option<String>,
    uaccess: bool,
}

fn rules() -> Vec<Rule> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../packaging/udev/70-telerehab.rules");
    let text = std::fs::read_to_string(path).unwrap();
    let value = |line: &str, key: &str| {
        let at = line.find(&format!("{key}==\""))? + key.len() + 3;
        Some(line[at..at + line[at..].find('"')?].to_owned())
    };
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| Rule {
            kernel: value(l, "KERNEL").unwrap_or_default(),
            vendor: value(l, "ATTRS{idVendor}"),
            product: value(l, "ATTRS{idProduct}"),
            kernels: value(l, "KERNELS"),
            uaccess: l.contains("TAG+=\"uaccess\""),
        })
        .collect()
}

/// udev's glob: `*`, `?`, `[a-f0-9]` classes and `|` between alternatives.
fn glob(pattern: &str, text: &str) -> bool {
    pattern
        .split('|')
        .any(|alt| glob_one(alt.as_bytes(), text.as_bytes()))
}

fn glob_one(p: &[u8], t: &[u8]) -> bool {
    match p.split_first() {
        None => t.is_empty(),
        Some((b'*', rest)) => (0..=t.len()).any(|i| glob_one(rest, &t[i..])),
        Some((b'?', rest)) => !t.is_empty() && glob_one(rest, &t[1..]),
        Some((b'[', rest)) => {
            let Some(end) = rest.iter().position(|&c| c == b']') else {
                return false;
            };
            let Some((&c, t_rest)) = t.split_first() else {
                return false;
            };
            let class = &rest[..end];
            let mut i = 0;
            let mut hit = false;
            while i < class.len() {
                if i + 2 < class.len() && class[i + 1] == b'-' {
                    hit |= (class[i]..=class[i + 2]).contains(&c);
                    i += 3;
                } else {
                    hit |= class[i] == c;
                    i += 1;
                }
            }
            hit && glob_one(&rest[end + 1..], t_rest)
        }
        Some((&c, rest)) => t.first() == Some(&c) && glob_one(rest, &t[1..]),
    }
}

/// Whether a USB device `vendor:product` gets `uaccess` on a node named like `node`.
fn usb_covered(rules: &[Rule], node: &str, vendor: u16, product: u16) -> bool {
    rules.iter().any(|r| {
        r.uaccess
            && glob(&r.kernel, node)
            && r.vendor
                .as_deref()
                .is_some_and(|v| glob(v, &format!("{vendor:04x}")))
            && r.product
                .as_deref()
                .is_none_or(|p| glob(p, &format!("{product:04x}")))
    })
}

#[test]
fn the_glob_matches_as_udev_does() {
    assert!(glob("c2[0-9a-f][0-9a-f]", "c24f"));
    assert!(!glob("c2[0-9a-f][0-9a-f]", "c34f"));
    assert!(glob("05c4|09cc", "09cc"));
    assert!(glob("*057E:2006*", "0005:057E:2006.0003"));
    assert!(!glob("event*", "hidraw3"));
}

#[test]
fn every_wheel_with_a_built_in_profile_gets_uaccess_on_its_event_node() {
    let rules = rules();
    let mut checked = 0;
    let mut missing = Vec::new();
    for profile in haptic_wheel::DeviceProfile::builtin() {
        let Some(vendor) = profile.usb_vendor else {
            continue;
        };
        for &product in &profile.usb_products {
            if !usb_covered(&rules, "event12", vendor, product) {
                missing.push(format!("{} ({vendor:04x}:{product:04x})", profile.name));
            }
            checked += 1;
        }
    }
    assert!(
        missing.is_empty(),
        "no uaccess rule for the event node of {missing:#?}"
    );
    assert!(checked >= 5, "only {checked} built-in wheels have USB ids");
}

#[test]
fn every_supported_controller_imu_gets_uaccess_on_its_hidraw_node_by_usb_and_bluetooth() {
    let rules = rules();
    for (vendor, product, _, name) in gyro_imu::device::KNOWN_DEVICES {
        assert!(
            usb_covered(&rules, "hidraw3", vendor, product),
            "{name} ({vendor:04x}:{product:04x}) over USB"
        );
        // Over Bluetooth the HID device's name carries the ids in upper case.
        let bt = format!("0005:{vendor:04X}:{product:04X}.0007");
        assert!(
            rules.iter().any(|r| r.uaccess
                && glob(&r.kernel, "hidraw3")
                && r.kernels.as_deref().is_some_and(|k| glob(k, &bt))),
            "{name} over Bluetooth"
        );
    }
}
