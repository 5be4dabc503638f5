//! What the hub's services answer a station with: a boxed future (so their traits can be
//! trait objects) and a refusal sent as an `Error` frame. Shared by the hub's protocol server
//! ([`crate::therapist`]) and pairing ([`crate::pairing`]), which both answer stations.

use std::future::Future;
use std::pin::Pin;

/// A boxed future, so the store traits can be used as trait objects.
pub type BoxFuture<'a, T> = Pin<Box<dyn Future<Output = T> + Send + 'a>>;

/// A refusal the hub sends to the station as an `Error` frame before closing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// Why, for humans (names the problem).
    pub message: String,
    /// A machine-readable code, e.g. [`crate::frame::UPDATE_REQUIRED`]; `None` for ordinary
    /// refusals.
    pub code: Option<&'static str>,
}

impl Refusal {
    /// A refusal without a code.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            code: None,
        }
    }
}
