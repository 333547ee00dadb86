//! The sitar with its taraf: the played string with the curved jawari of the main bridge, and
//! 11 to 13 sympathetic strings on the taraf's small bridge, tuned to a thaat ([`thaat`]), all
//! on the bridges' shared modes ([`crate::models::network`]), tuned by ear
//! ([`tuning`]), playing a phrase of frets and meends ([`phrase`]).

pub mod instrument;
pub mod phrase;
pub mod spec;
pub mod thaat;
pub mod tuning;

pub use instrument::Sitar;
pub use phrase::SitarStroke;
pub use spec::SitarSpec;
pub use thaat::Thaat;
