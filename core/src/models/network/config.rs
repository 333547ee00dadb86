//! What a string network is built from: its strings, each with its seat and its place on the
//! bridge, the bridge's modes and the outputs.
//!
//! Plain data, read on the control thread by [`super::StringNetwork::new`].

use super::bridge::BridgeMode;
use crate::models::string::{Quantity, SeatSpec, StringConfig};

/// One string of the network.
///
/// Read on the control thread.
#[derive(Debug, Clone, PartialEq)]
pub struct SeatedString {
    /// The string (its obstacle is the jawari on the bridge, and moves with it).
    pub config: StringConfig,
    /// Where the string is tied to the bridge.
    pub seat: SeatSpec,
    /// `Φ_k` at the string's place on the bridge, one per bridge mode (dimensionless): the
    /// bridge under the string moves by `Σ_k Φ_k y_k`.
    pub bridge_shape: Vec<f64>,
    /// Highest mode frequency the string steps (Hz; `f64::INFINITY`: every mode). Below the
    /// Nyquist frequency its contact and seat are solved against the stepped modes'
    /// compliance ([`crate::models::string::StiffString::set_band_limit`]: a point jawari
    /// at most).
    pub band_limit: f64,
}

/// An output channel of the network.
///
/// Read on the control thread; resolved at build.
#[derive(Debug, Clone, PartialEq)]
pub enum NetworkOutput {
    /// Channel `channel` of string `string`'s own outputs ([`StringConfig::outputs`]).
    String {
        /// Index of the string.
        string: usize,
        /// Index of the channel in that string's outputs.
        channel: usize,
    },
    /// The bridge at a point: `Σ_k weights[k] y_k` (m) or its velocity (m/s, at `n + 1/2`).
    Bridge {
        /// Displacement or velocity.
        quantity: Quantity,
        /// One weight per bridge mode (the mode shapes at the point; dimensionless).
        weights: Vec<f64>,
    },
}

/// Everything needed to build a [`super::StringNetwork`].
///
/// Built on the control thread.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkConfig {
    /// The strings (at least one), all at the same sample rate.
    pub strings: Vec<SeatedString>,
    /// The bridge's modes (1 to [`super::MAX_BRIDGE_MODES`]).
    pub bridge: Vec<BridgeMode>,
    /// Output channels, in order.
    pub outputs: Vec<NetworkOutput>,
}
