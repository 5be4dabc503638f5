//! The seam under [`DinputWheel`](super::DinputWheel): the DirectInput 8 calls the backend
//! makes ([`DiDevice`]), implemented on Windows by `com::ComDevice` (the `windows` crate) and,
//! for tests on any system, by [`FakeDiDevice`](super::fake::FakeDiDevice); and what makes a
//! device the session's wheel ([`DiIdentity`]).

/// DirectInput's full scale of a constant force's magnitude and of the device gain
/// (`DI_FFNOMINALMAX`, dinput.h): the thesis's ±10 000 effect units (eq. 3.3).
pub const DI_FFNOMINALMAX: i32 = 10_000;

/// `DIERR_INPUTLOST` (dinput.h): access to the device was lost (unplugged, or taken by
/// another application's exclusive access); it must be acquired again.
pub const DIERR_INPUTLOST: i32 = 0x8007_001E_u32 as i32;
/// `DIERR_NOTACQUIRED` (dinput.h): the device is not acquired (any more).
pub const DIERR_NOTACQUIRED: i32 = 0x8007_000C_u32 as i32;
/// `DIERR_UNPLUGGED` (dinput.h): the device is not plugged in.
pub const DIERR_UNPLUGGED: i32 = 0x8004_0209_u32 as i32;
/// `E_FAIL`: an unspecified failure (what a driver answers for a refused effect update).
pub const E_FAIL: i32 = 0x8000_4005_u32 as i32;

/// A failed DirectInput call: its `HRESULT`. `Copy` and heap-free, as the 1 kHz path makes
/// them while a fault lasts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DiError(pub i32);

impl DiError {
    /// The device went away: [`DIERR_INPUTLOST`], [`DIERR_NOTACQUIRED`] or
    /// [`DIERR_UNPLUGGED`]. The backend reports these as
    /// [`WheelFault::Unplugged`](haptic_wheel::WheelFault::Unplugged), as the evdev backend reports
    /// the kernel's ENODEV.
    pub fn is_device_loss(self) -> bool {
        matches!(
            self.0,
            DIERR_INPUTLOST | DIERR_NOTACQUIRED | DIERR_UNPLUGGED
        )
    }
}

impl std::fmt::Display for DiError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = match self.0 {
            DIERR_INPUTLOST => " (DIERR_INPUTLOST: access to the device was lost)",
            DIERR_NOTACQUIRED => " (DIERR_NOTACQUIRED: the device is not acquired)",
            DIERR_UNPLUGGED => " (DIERR_UNPLUGGED: the device is not plugged in)",
            E_FAIL => " (E_FAIL)",
            _ => "",
        };
        write!(f, "DirectInput error 0x{:08X}{what}", self.0 as u32)
    }
}

impl std::error::Error for DiError {}

/// What makes a DirectInput device the session's wheel, read once when it is opened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DiIdentity {
    /// The product's name (`DIDEVICEINSTANCEW::tszProductName`).
    pub product_name: String,
    /// This instance's name (`tszInstanceName`; Windows numbers a second unit of a model).
    pub instance_name: String,
    /// The instance GUID (`guidInstance`): stable for one unit on one port of one computer.
    pub instance_guid: u128,
    /// USB vendor and product id (the low and high words of `guidProduct.Data1`): the model,
    /// hence the profile.
    pub usb_id: (u16, u16),
    /// The steering axis's declared raw range (`DIPROP_RANGE` of the X axis): the angle scale.
    pub axis_range: (i32, i32),
    /// The device can play a constant force (`GUID_ConstantForce` is among its effects).
    pub constant_force: bool,
}

/// How closely a device found after an unplug matches the lost wheel, best last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Likeness {
    /// The same model (USB id and steering range).
    SameModel,
    /// The same model with the lost wheel's instance name.
    SameName,
    /// The very unit on the same port (the instance GUID).
    SameUnit,
}

/// Why a device found is not taken for the lost wheel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// It cannot play a constant force.
    NoConstantForce,
    /// Another USB id: another profile, hence other torque and angle scales.
    OtherModel,
    /// Another steering range: another angle scale.
    OtherRange,
}

impl DiIdentity {
    /// Whether `found` can stand for this wheel, and how closely it matches: the same model
    /// only (a units hazard otherwise), the same unit, then the same instance name, preferred.
    pub fn likeness(&self, found: &DiIdentity) -> Result<Likeness, Refusal> {
        if !found.constant_force {
            return Err(Refusal::NoConstantForce);
        }
        if found.usb_id != self.usb_id {
            return Err(Refusal::OtherModel);
        }
        if found.axis_range != self.axis_range {
            return Err(Refusal::OtherRange);
        }
        Ok(if found.instance_guid == self.instance_guid {
            Likeness::SameUnit
        } else if found.instance_name == self.instance_name {
            Likeness::SameName
        } else {
            Likeness::SameModel
        })
    }
}

/// One `GetDeviceState` of the wheel (`DIJOYSTATE2`): what the backend reads of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DiState {
    /// The steering axis (`lX`), raw.
    pub x: i32,
    /// The first 128 buttons (`rgbButtons`), bit `i` set when button `i` is down.
    pub buttons: u128,
}

/// The DirectInput 8 calls [`DinputWheel`](super::DinputWheel) makes on one wheel. Every
/// method the haptic loop calls (`state`, `set_magnitude`) must not allocate. A device owns
/// what it holds (`'static`).
pub trait DiDevice: 'static {
    /// What the device is (read at open).
    fn identity(&self) -> &DiIdentity;
    /// Acquire it exclusively in the background (`SetCooperativeLevel(DISCL_EXCLUSIVE |
    /// DISCL_BACKGROUND)`, set when opened; `Acquire`; force feedback reset and actuators on).
    fn acquire(&mut self) -> Result<(), DiError>;
    /// Give it back (`Unacquire`: DirectInput stops its effects). Best effort.
    fn unacquire(&mut self);
    /// The wheel's own spring towards the centre on or off (`DIPROP_AUTOCENTER`).
    fn set_autocenter(&mut self, on: bool) -> Result<(), DiError>;
    /// The device-wide force-feedback gain, 0..=[`DI_FFNOMINALMAX`] (`DIPROP_FFGAIN`).
    fn set_gain(&mut self, gain: u32) -> Result<(), DiError>;
    /// Create the one constant-force effect (`GUID_ConstantForce`, `DIEFF_CARTESIAN` on the X
    /// axis, magnitude 0, not started) that plays for `duration_us` µs each time it is started.
    fn create_constant_force(&mut self, duration_us: u32) -> Result<(), DiError>;
    /// Its new magnitude, −[`DI_FFNOMINALMAX`]..=[`DI_FFNOMINALMAX`], started again at once
    /// (`SetParameters` with `DIEP_TYPESPECIFICPARAMS | DIEP_START`).
    fn set_magnitude(&mut self, magnitude: i32) -> Result<(), DiError>;
    /// Stop the effect (`IDirectInputEffect::Stop`).
    fn stop_effect(&mut self) -> Result<(), DiError>;
    /// `Poll` and `GetDeviceState` (`DIJOYSTATE2`).
    fn state(&mut self) -> Result<DiState, DiError>;
}

/// Where a lost wheel is looked for: every force-feedback game controller present now,
/// opened.
pub trait DiFinder<D>: Send + 'static {
    /// The devices present now that may be the wheel.
    fn candidates(&mut self) -> Vec<D>;
}

impl<D, F> DiFinder<D> for F
where
    F: FnMut() -> Vec<D> + Send + 'static,
{
    fn candidates(&mut self) -> Vec<D> {
        self()
    }
}
