//! Physical models built on the schemes: [`plate`] (modal von Kármán plate, gongs).

pub mod plate;
