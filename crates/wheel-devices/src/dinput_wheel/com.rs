//! DirectInput 8 on the `windows` crate (Windows only): [`ComDevice`], the [`DiDevice`] of a
//! real wheel, [`ComFinder`], every force-feedback game controller present, and
//! [`DinputWheel::open_first`].
//!
//! - **The window DirectInput asks for.** `SetCooperativeLevel(DISCL_EXCLUSIVE |
//!   DISCL_BACKGROUND)` (exclusive: force feedback needs it; background: the wheel keeps
//!   working while the patient's window, another process, has the focus) wants a top-level
//!   window of this process. The station may have no console window (started from the Start
//!   menu) and the patient's window belongs to another process, so the backend makes its own:
//!   one hidden top-level window of the predefined `STATIC` class, never shown, made once per
//!   process on a thread of its own that serves its messages until the process ends
//!   ([`cooperative_window`]). A window dies with the thread that made it; on the session's or
//!   the haptic thread it would die with them while a device still used it.
//! - **The data format.** `c_dfDIJoystick2` is a data object of `dinput8.lib` that the
//!   `windows` crate does not bind; [`joystick2_format`] builds the same 164 objects
//!   (`DIJOYSTATE2`), as dinput.h's own table does.
//! - **Property ids.** DirectInput's `DIPROP_*` are small integers passed *as the GUID
//!   pointer* (`MAKEDIPROP`), not pointers to GUIDs: [`prop`] makes that pointer from the
//!   `windows` crate's constant.
//! - **Threads.** A [`ComDevice`] is made on the thread that opens the wheel and then moved to
//!   the haptic thread, which alone uses it from then on (`Send`, not `Sync`).

use std::ffi::c_void;
use std::sync::OnceLock;

use clock::Clock;
use windows::Win32::Devices::HumanInterfaceDevice as di;
use windows::Win32::Foundation::{HINSTANCE, HWND};
use windows::Win32::System::LibraryLoader::GetModuleHandleW;
use windows::Win32::UI::WindowsAndMessaging::{
    CreateWindowExW, DispatchMessageW, GetMessageW, MSG, WINDOW_EX_STYLE, WS_OVERLAPPED,
};
use windows::core::{BOOL, GUID, Interface, w};

use super::device::{DI_FFNOMINALMAX, DiDevice, DiError, DiFinder, DiIdentity, DiState, E_FAIL};
use super::{DinputWheel, REJOIN_RESCAN_EVERY};
use crate::devices::{DeviceClass, DeviceInfo, DeviceTraits};
use haptic_wheel::profile::DeviceProfile;
use haptic_wheel::wheel::WheelError;
use haptic_wheel::wheel_config::WheelConfig;

/// `DIDFT_OPTIONAL` (dinput.h): an object of the data format the device may lack.
const DIDFT_OPTIONAL: u32 = 0x8000_0000;
/// The steering axis's offset in `DIJOYSTATE2` (`DIJOFS_X`).
const DIJOFS_X: u32 = 0;

fn hr(e: windows::core::Error) -> DiError {
    DiError(e.code().0)
}

/// The pointer DirectInput takes for property `id` (`MAKEDIPROP`: the id itself).
fn prop(id: GUID) -> *const GUID {
    std::ptr::without_provenance(id.to_u128() as usize)
}

/// A property header for a `T` (`DIPROPDWORD`, `DIPROPRANGE`) on object `obj` found `how`.
fn header<T>(obj: u32, how: u32) -> di::DIPROPHEADER {
    di::DIPROPHEADER {
        dwSize: size_of::<T>() as u32,
        dwHeaderSize: size_of::<di::DIPROPHEADER>() as u32,
        dwObj: obj,
        dwHow: how,
    }
}

/// The objects of `c_dfDIJoystick2` (dinput.h's `DIJOYSTATE2` format), in its order:
/// six axes and two sliders for position, four POVs, 128 buttons, then the axes and sliders
/// again for velocity, acceleration and force. Every object is optional.
fn joystick2_objects() -> Vec<di::DIOBJECTDATAFORMAT> {
    static AXES: [GUID; 6] = [
        di::GUID_XAxis,
        di::GUID_YAxis,
        di::GUID_ZAxis,
        di::GUID_RxAxis,
        di::GUID_RyAxis,
        di::GUID_RzAxis,
    ];
    static SLIDER: GUID = di::GUID_Slider;
    static POV: GUID = di::GUID_POV;
    let axis_type = di::DIDFT_AXIS | DIDFT_OPTIONAL | di::DIDFT_ANYINSTANCE;
    let mut objs = Vec::with_capacity(164);
    let axes_at = |objs: &mut Vec<di::DIOBJECTDATAFORMAT>, base: u32, aspect: u32| {
        for (i, g) in AXES.iter().enumerate() {
            objs.push(di::DIOBJECTDATAFORMAT {
                pguid: g,
                dwOfs: base + 4 * i as u32,
                dwType: axis_type,
                dwFlags: aspect,
            });
        }
        for i in 0..2 {
            objs.push(di::DIOBJECTDATAFORMAT {
                pguid: &SLIDER,
                dwOfs: base + 24 + 4 * i,
                dwType: axis_type,
                dwFlags: aspect,
            });
        }
    };
    axes_at(&mut objs, 0, di::DIDOI_ASPECTPOSITION);
    for i in 0..4 {
        objs.push(di::DIOBJECTDATAFORMAT {
            pguid: &POV,
            dwOfs: 32 + 4 * i,
            dwType: di::DIDFT_POV | DIDFT_OPTIONAL | di::DIDFT_ANYINSTANCE,
            dwFlags: 0,
        });
    }
    for i in 0..128 {
        objs.push(di::DIOBJECTDATAFORMAT {
            pguid: std::ptr::null(),
            dwOfs: 48 + i,
            dwType: di::DIDFT_BUTTON | DIDFT_OPTIONAL | di::DIDFT_ANYINSTANCE,
            dwFlags: 0,
        });
    }
    // After the 128 button bytes at 48: velocity, acceleration, force (8 values each).
    for (k, aspect) in [
        di::DIDOI_ASPECTVELOCITY,
        di::DIDOI_ASPECTACCEL,
        di::DIDOI_ASPECTFORCE,
    ]
    .into_iter()
    .enumerate()
    {
        axes_at(&mut objs, 176 + 32 * k as u32, aspect);
    }
    objs
}

/// `c_dfDIJoystick2` over `objects` (which must outlive the `SetDataFormat` call).
fn joystick2_format(objects: &mut [di::DIOBJECTDATAFORMAT]) -> di::DIDATAFORMAT {
    di::DIDATAFORMAT {
        dwSize: size_of::<di::DIDATAFORMAT>() as u32,
        dwObjSize: size_of::<di::DIOBJECTDATAFORMAT>() as u32,
        dwFlags: di::DIDF_ABSAXIS,
        dwDataSize: size_of::<di::DIJOYSTATE2>() as u32,
        dwNumObjs: objects.len() as u32,
        rgodf: objects.as_mut_ptr(),
    }
}

/// The process's hidden top-level window for `SetCooperativeLevel`, made on first use on a
/// thread of its own that serves its messages for the life of the process.
pub fn cooperative_window() -> Result<HWND, DiError> {
    static WINDOW: OnceLock<Result<usize, DiError>> = OnceLock::new();
    let made = WINDOW.get_or_init(|| {
        let (tx, rx) = std::sync::mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("dinput-window".into())
            .spawn(move || {
                // SAFETY: a plain call with no pointer arguments (None: this executable).
                let module = unsafe { GetModuleHandleW(None) };
                let made = module.and_then(|m| {
                    // SAFETY: the class and title are static wide strings; no parent, menu or
                    // creation data; the predefined STATIC class needs no registration.
                    unsafe {
                        CreateWindowExW(
                            WINDOW_EX_STYLE(0),
                            w!("STATIC"),
                            w!("telerehab wheel"),
                            WS_OVERLAPPED,
                            0,
                            0,
                            0,
                            0,
                            None,
                            None,
                            Some(HINSTANCE::from(m)),
                            None,
                        )
                    }
                });
                let ok = made.is_ok();
                let _ = tx.send(made.map(|h| h.0 as usize).map_err(hr));
                if ok {
                    let mut msg = MSG::default();
                    // SAFETY: `msg` is a valid MSG for the call to fill; this thread owns the
                    // window, so its messages come here.
                    while unsafe { GetMessageW(&mut msg, None, 0, 0) }.as_bool() {
                        // SAFETY: `msg` was filled by GetMessageW just above.
                        unsafe { DispatchMessageW(&msg) };
                    }
                }
            });
        match spawned {
            Ok(_) => rx.recv().unwrap_or(Err(DiError(E_FAIL))),
            Err(_) => Err(DiError(E_FAIL)),
        }
    });
    made.map(|h| HWND(h as *mut c_void))
}

/// A DirectInput 8 interface for this process.
fn directinput() -> Result<di::IDirectInput8W, DiError> {
    // SAFETY: a plain call with no pointer arguments (None: this executable).
    let module = unsafe { GetModuleHandleW(None) }.map_err(hr)?;
    let mut out: *mut c_void = std::ptr::null_mut();
    // SAFETY: the IID is IDirectInput8W's and `out` receives an interface of that type; no
    // aggregation.
    unsafe {
        di::DirectInput8Create(
            HINSTANCE::from(module),
            di::DIRECTINPUT_VERSION,
            &di::IDirectInput8W::IID,
            &mut out,
            None,
        )
    }
    .map_err(hr)?;
    if out.is_null() {
        return Err(DiError(E_FAIL));
    }
    // SAFETY: DirectInput8Create succeeded and gave an owned IDirectInput8W reference.
    Ok(unsafe { di::IDirectInput8W::from_raw(out) })
}

unsafe extern "system" fn collect_instance(
    instance: *mut di::DIDEVICEINSTANCEW,
    list: *mut c_void,
) -> BOOL {
    // SAFETY: `list` is the `Vec` `instances` passes, alive and not otherwise borrowed for
    // the whole EnumDevices call; `instance` is valid for this callback.
    let (list, instance) = unsafe {
        (
            &mut *list.cast::<Vec<di::DIDEVICEINSTANCEW>>(),
            instance.as_ref(),
        )
    };
    if let Some(i) = instance {
        list.push(*i);
    }
    BOOL(di::DIENUM_CONTINUE as i32)
}

/// Every attached game controller with force feedback.
fn instances(dinput: &di::IDirectInput8W) -> Result<Vec<di::DIDEVICEINSTANCEW>, DiError> {
    let mut list: Vec<di::DIDEVICEINSTANCEW> = Vec::new();
    // SAFETY: the callback's context is `list`, which outlives the synchronous call.
    unsafe {
        dinput.EnumDevices(
            di::DI8DEVCLASS_GAMECTRL,
            Some(collect_instance),
            (&mut list as *mut Vec<di::DIDEVICEINSTANCEW>).cast(),
            di::DIEDFL_ATTACHEDONLY | di::DIEDFL_FORCEFEEDBACK,
        )
    }
    .map_err(hr)?;
    Ok(list)
}

fn wide(s: &[u16]) -> String {
    let end = s.iter().position(|&c| c == 0).unwrap_or(s.len());
    String::from_utf16_lossy(&s[..end])
}

/// A real DirectInput wheel.
pub struct ComDevice {
    // Field order is drop order: the effect before its device, the device before DirectInput.
    effect: Option<di::IDirectInputEffect>,
    dev: di::IDirectInputDevice8W,
    _dinput: di::IDirectInput8W,
    identity: DiIdentity,
}

// SAFETY: DirectInput objects made through DirectInput8Create are not bound to a COM
// apartment (no CoInitialize is involved); a ComDevice is owned by one thread at a time (moved
// to the haptic thread, never shared: it is not Sync), and its window lives on a thread of its
// own for the life of the process.
unsafe impl Send for ComDevice {}

impl std::fmt::Debug for ComDevice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ComDevice")
            .field("identity", &self.identity)
            .finish_non_exhaustive()
    }
}

impl ComDevice {
    /// Open the device `instance` enumerated: the `DIJOYSTATE2` format, exclusive background
    /// access with the hidden window, its identity read (not acquired yet).
    pub fn open(
        dinput: &di::IDirectInput8W,
        instance: &di::DIDEVICEINSTANCEW,
    ) -> Result<Self, DiError> {
        let mut dev: Option<di::IDirectInputDevice8W> = None;
        // SAFETY: the GUID is the enumerated instance's; `dev` receives the interface.
        unsafe { dinput.CreateDevice(&instance.guidInstance, &mut dev, None) }.map_err(hr)?;
        let dev = dev.ok_or(DiError(E_FAIL))?;
        let mut objects = joystick2_objects();
        let mut format = joystick2_format(&mut objects);
        // SAFETY: `format` and the objects it points to live across the call, which copies
        // them.
        unsafe { dev.SetDataFormat(&mut format) }.map_err(hr)?;
        let window = cooperative_window()?;
        // SAFETY: `window` is a live top-level window of this process.
        unsafe { dev.SetCooperativeLevel(window, di::DISCL_EXCLUSIVE | di::DISCL_BACKGROUND) }
            .map_err(hr)?;
        let mut range = di::DIPROPRANGE {
            diph: header::<di::DIPROPRANGE>(DIJOFS_X, di::DIPH_BYOFFSET),
            lMin: 0,
            lMax: 0,
        };
        // SAFETY: `range` is a DIPROPRANGE whose header says so; the property id is passed as
        // DirectInput expects (`prop`).
        unsafe { dev.GetProperty(prop(di::DIPROP_RANGE), &mut range.diph) }.map_err(hr)?;
        let mut info = di::DIEFFECTINFOW {
            dwSize: size_of::<di::DIEFFECTINFOW>() as u32,
            ..Default::default()
        };
        // SAFETY: `info` has its size set; the GUID is a static constant.
        let constant_force =
            unsafe { dev.GetEffectInfo(&mut info, &di::GUID_ConstantForce) }.is_ok();
        let product = instance.guidProduct.data1;
        let identity = DiIdentity {
            product_name: wide(&instance.tszProductName),
            instance_name: wide(&instance.tszInstanceName),
            instance_guid: instance.guidInstance.to_u128(),
            usb_id: ((product & 0xffff) as u16, (product >> 16) as u16),
            axis_range: (range.lMin, range.lMax),
            constant_force,
        };
        Ok(Self {
            effect: None,
            dev,
            _dinput: dinput.clone(),
            identity,
        })
    }

    fn set_dword(&mut self, id: GUID, value: u32) -> Result<(), DiError> {
        let mut p = di::DIPROPDWORD {
            diph: header::<di::DIPROPDWORD>(0, di::DIPH_DEVICE),
            dwData: value,
        };
        // SAFETY: `p` is a DIPROPDWORD whose header says so, for the whole device.
        unsafe { self.dev.SetProperty(prop(id), &mut p.diph) }.map_err(hr)
    }
}

impl DiDevice for ComDevice {
    fn identity(&self) -> &DiIdentity {
        &self.identity
    }

    fn acquire(&mut self) -> Result<(), DiError> {
        // SAFETY: plain calls on a live device.
        unsafe {
            self.dev.Acquire().map_err(hr)?;
            self.dev
                .SendForceFeedbackCommand(di::DISFFC_RESET)
                .map_err(hr)?;
            self.dev
                .SendForceFeedbackCommand(di::DISFFC_SETACTUATORSON)
                .map_err(hr)
        }
    }

    fn unacquire(&mut self) {
        // SAFETY: a plain call on a live device.
        let _ = unsafe { self.dev.Unacquire() };
    }

    fn set_autocenter(&mut self, on: bool) -> Result<(), DiError> {
        let value = if on {
            di::DIPROPAUTOCENTER_ON
        } else {
            di::DIPROPAUTOCENTER_OFF
        };
        self.set_dword(di::DIPROP_AUTOCENTER, value)
    }

    fn set_gain(&mut self, gain: u32) -> Result<(), DiError> {
        self.set_dword(di::DIPROP_FFGAIN, gain.min(DI_FFNOMINALMAX as u32))
    }

    fn create_constant_force(&mut self, duration_us: u32) -> Result<(), DiError> {
        let mut axes = [DIJOFS_X];
        let mut direction = [0i32];
        let mut force = di::DICONSTANTFORCE { lMagnitude: 0 };
        let mut effect = di::DIEFFECT {
            dwSize: size_of::<di::DIEFFECT>() as u32,
            dwFlags: di::DIEFF_CARTESIAN | di::DIEFF_OBJECTOFFSETS,
            dwDuration: duration_us,
            dwSamplePeriod: 0,
            dwGain: DI_FFNOMINALMAX as u32,
            dwTriggerButton: di::DIEB_NOTRIGGER,
            dwTriggerRepeatInterval: 0,
            cAxes: 1,
            rgdwAxes: axes.as_mut_ptr(),
            rglDirection: direction.as_mut_ptr(),
            lpEnvelope: std::ptr::null_mut(),
            cbTypeSpecificParams: size_of::<di::DICONSTANTFORCE>() as u32,
            lpvTypeSpecificParams: (&mut force as *mut di::DICONSTANTFORCE).cast(),
            dwStartDelay: 0,
        };
        let mut made: Option<di::IDirectInputEffect> = None;
        // SAFETY: `effect` and the arrays and force it points to live across the call;
        // `made` receives the interface.
        unsafe {
            self.dev
                .CreateEffect(&di::GUID_ConstantForce, &mut effect, &mut made, None)
        }
        .map_err(hr)?;
        self.effect = Some(made.ok_or(DiError(E_FAIL))?);
        Ok(())
    }

    fn set_magnitude(&mut self, magnitude: i32) -> Result<(), DiError> {
        let Some(effect) = self.effect.as_ref() else {
            return Err(DiError(E_FAIL));
        };
        let mut force = di::DICONSTANTFORCE {
            lMagnitude: magnitude.clamp(-DI_FFNOMINALMAX, DI_FFNOMINALMAX),
        };
        let mut params = di::DIEFFECT {
            dwSize: size_of::<di::DIEFFECT>() as u32,
            cbTypeSpecificParams: size_of::<di::DICONSTANTFORCE>() as u32,
            lpvTypeSpecificParams: (&mut force as *mut di::DICONSTANTFORCE).cast(),
            ..Default::default()
        };
        // SAFETY: `params` and the force it points to live across the call; only the
        // type-specific parameters are read (and the effect restarted).
        unsafe { effect.SetParameters(&mut params, di::DIEP_TYPESPECIFICPARAMS | di::DIEP_START) }
            .map_err(hr)
    }

    fn stop_effect(&mut self) -> Result<(), DiError> {
        match self.effect.as_ref() {
            // SAFETY: a plain call on a live effect.
            Some(effect) => unsafe { effect.Stop() }.map_err(hr),
            None => Ok(()),
        }
    }

    fn state(&mut self) -> Result<DiState, DiError> {
        let mut s = di::DIJOYSTATE2::default();
        // SAFETY: plain calls on a live device; `s` is the DIJOYSTATE2 the data format says,
        // its size passed with it.
        unsafe {
            self.dev.Poll().map_err(hr)?;
            self.dev
                .GetDeviceState(
                    size_of::<di::DIJOYSTATE2>() as u32,
                    (&mut s as *mut di::DIJOYSTATE2).cast(),
                )
                .map_err(hr)?;
        }
        let buttons = s
            .rgbButtons
            .iter()
            .enumerate()
            .filter(|(_, b)| **b & 0x80 != 0)
            .fold(0u128, |acc, (i, _)| acc | (1u128 << i));
        Ok(DiState { x: s.lX, buttons })
    }
}

impl Drop for ComDevice {
    fn drop(&mut self) {
        // SAFETY: plain calls on a live device and effect; the interfaces are released after.
        unsafe {
            if let Some(e) = self.effect.take() {
                let _ = e.Stop();
                let _ = e.Unload();
            }
            let _ = self.dev.Unacquire();
        }
    }
}

/// Every force-feedback game controller attached now, opened (those that cannot be opened are
/// left out, with a debug log line).
#[derive(Clone, Copy, Debug, Default)]
pub struct ComFinder;

impl ComFinder {
    /// The controllers present, opened; an error when DirectInput itself cannot be had.
    pub fn devices(&self) -> Result<Vec<ComDevice>, DiError> {
        let dinput = directinput()?;
        Ok(instances(&dinput)?
            .iter()
            .filter_map(|i| match ComDevice::open(&dinput, i) {
                Ok(d) => Some(d),
                Err(e) => {
                    tracing::debug!(
                        "cannot open DirectInput device '{}': {e}",
                        wide(&i.tszInstanceName)
                    );
                    None
                }
            })
            .collect())
    }
}

/// What `telerehab devices` says of a DirectInput device: a wheel when it has constant force,
/// with the profile its USB id gives.
pub fn describe(d: &ComDevice) -> DeviceInfo {
    let id = d.identity();
    DeviceInfo {
        path: format!("DirectInput:{{{:032x}}}", id.instance_guid),
        class: if id.constant_force {
            DeviceClass::Wheel
        } else {
            DeviceClass::Gamepad
        },
        traits: DeviceTraits {
            name: id.product_name.clone(),
            ff_effects: if id.constant_force {
                vec!["constant", "gain", "autocenter"]
            } else {
                Vec::new()
            },
            abs_axes: vec!["x"],
            gamepad_buttons: false,
        },
        usb_id: Some(id.usb_id),
        profile: id
            .constant_force
            .then(|| DeviceProfile::for_usb_id(id.usb_id.0, id.usb_id.1)),
        ceiling: None,
        expected_update_rate_hz: None,
        max_ff_effects: 1,
    }
}

impl DiFinder<ComDevice> for ComFinder {
    fn candidates(&mut self) -> Vec<ComDevice> {
        self.devices().unwrap_or_default()
    }
}

impl DinputWheel<ComDevice> {
    /// Open the first force-feedback wheel DirectInput finds (one with constant force), and
    /// look for it again every [`REJOIN_RESCAN_EVERY`] once it has gone away.
    pub fn open_first(config: WheelConfig, clock: Clock) -> Result<Self, WheelError> {
        let found = ComFinder.devices().map_err(|e| WheelError::Io {
            device: "DirectInput".into(),
            source: std::io::Error::other(e),
        })?;
        let dev = found
            .into_iter()
            .find(|d| d.identity().constant_force)
            .ok_or_else(|| {
                WheelError::Disconnected(
                    "DirectInput found no force-feedback wheel with constant force; check that \
                     it is plugged in and that its maker's driver is installed"
                        .into(),
                )
            })?;
        Ok(Self::with_device(dev, config, clock)?.reopen_with(ComFinder, REJOIN_RESCAN_EVERY))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_joystick2_format_has_dinputs_164_objects_within_dijoystate2() {
        let objs = joystick2_objects();
        assert_eq!(objs.len(), 164);
        let size = size_of::<di::DIJOYSTATE2>() as u32;
        assert_eq!(size, 272);
        assert!(objs.iter().all(|o| o.dwOfs < size));
        assert_eq!(objs[0].dwOfs, DIJOFS_X);
        assert_eq!(objs.last().map(|o| o.dwOfs), Some(size - 4));
    }

    /// Wine (and a computer without a wheel) has no force-feedback device: enumerating must
    /// still work, find none, and opening the first wheel must say so in words.
    #[test]
    fn enumerating_force_feedback_devices_works_and_no_wheel_is_a_clear_error() {
        let found = ComFinder.devices().expect("DirectInput 8 is available");
        eprintln!(
            "DirectInput force-feedback controllers found: {}",
            found.len()
        );
        for d in &found {
            eprintln!("  {:?}", d.identity());
        }
        if found.iter().any(|d| d.identity().constant_force) {
            eprintln!("SKIPPED: a real wheel is attached; the no-wheel message is not checked");
            return;
        }
        let err = DinputWheel::open_first(WheelConfig::default(), Clock::real()).unwrap_err();
        assert!(err.to_string().contains("no force-feedback wheel"), "{err}");
    }

    /// Whether this runs under Wine (its ntdll exports `wine_get_version`).
    fn under_wine() -> bool {
        use windows::Win32::System::LibraryLoader::GetProcAddress;
        use windows::core::s;
        // SAFETY: plain calls with static strings; ntdll is loaded in every process.
        unsafe {
            GetModuleHandleW(w!("ntdll.dll"))
                .is_ok_and(|m| GetProcAddress(m, s!("wine_get_version")).is_some())
        }
    }

    #[test]
    fn the_hidden_window_is_made_once_per_process() {
        if under_wine() && std::env::var_os("DISPLAY").is_none() {
            eprintln!("SKIPPED: Wine without an X display makes no windows (run under xvfb-run)");
            return;
        }
        let a = cooperative_window().expect("a hidden window");
        let b = cooperative_window().expect("the same window");
        assert_eq!(a, b);
        assert!(!a.is_invalid());
    }
}
