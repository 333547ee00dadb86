//! Modal data of thin plates for the von Kármán modal model (SEED §3.1).
pub mod angular;
pub mod assemble;
pub mod basis;
pub mod bessel;
pub mod circular;
pub mod coupling;
pub mod quadrature;
