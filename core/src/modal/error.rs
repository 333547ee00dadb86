//! The typed errors of the modal bases: parameter problems (a [`ParamError`] naming the field,
//! value and allowed range), numerical failures of a build (which matrix or eigenproblem, which
//! parity class), rejected cache files and I/O failures (with the path).
//!
//! Plain data, built and read on worker threads.

use crate::error::ParamError;
use std::fmt;
use std::path::PathBuf;

/// Why a build, a cache read or a cache write of a modal basis failed.
#[derive(Debug, Clone, PartialEq)]
pub enum ModalError {
    /// A parameter out of its range: field, value and allowed range.
    Param(ParamError),
    /// A matrix of the build that must be symmetric positive definite is not (`class`: the
    /// parity class of a rectangle's Airy problem, `None` for the 1D beam problems).
    NotPositiveDefinite {
        /// Which matrix (for example `"Airy stiffness"`).
        matrix: &'static str,
        /// Parity class `0..4` (`2 px + py`), if the matrix belongs to one.
        class: Option<usize>,
    },
    /// A symmetric eigensolver failed (`detail`: the solver's own report).
    Eigensolver {
        /// Which eigenproblem (for example `"Airy"`, `"1D mass"`).
        problem: &'static str,
        /// Parity class `0..4`, if the problem belongs to one.
        class: Option<usize>,
        /// The solver's error, formatted.
        detail: String,
    },
    /// A cache file was not trusted (it is rebuilt).
    CacheRejected(CacheReject),
    /// A file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error's kind.
        kind: std::io::ErrorKind,
        /// The I/O error, formatted.
        message: String,
    },
}

/// Why a cache file was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum CacheReject {
    /// Shorter than its checksum.
    TooShort,
    /// The checksum over the contents does not match.
    Checksum,
    /// Magic, version or key fields differ from the requested basis.
    Header,
    /// The stored lengths overflow the address space.
    SizeOverflow,
    /// The payload length differs from the one the header implies.
    PayloadSize {
        /// Bytes found.
        got: usize,
        /// Bytes expected.
        expected: usize,
    },
    /// The stored tensor violates an invariant (the tensor's own check).
    Tensor(ParamError),
}

impl ModalError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, e: &std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            kind: e.kind(),
            message: e.to_string(),
        }
    }
}

impl From<ParamError> for ModalError {
    fn from(e: ParamError) -> Self {
        Self::Param(e)
    }
}

impl From<CacheReject> for ModalError {
    fn from(r: CacheReject) -> Self {
        Self::CacheRejected(r)
    }
}

impl fmt::Display for ModalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let class = |c: &Option<usize>| c.map(|c| format!(" in class {c}")).unwrap_or_default();
        match self {
            Self::Param(e) => e.fmt(f),
            Self::NotPositiveDefinite { matrix, class: c } => {
                write!(f, "{matrix} not positive definite{}", class(c))
            }
            Self::Eigensolver {
                problem,
                class: c,
                detail,
            } => write!(f, "{problem} eigensolver failed{}: {detail}", class(c)),
            Self::CacheRejected(r) => r.fmt(f),
            Self::Io { path, message, .. } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl fmt::Display for CacheReject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort => f.write_str("file too short"),
            Self::Checksum => f.write_str("checksum mismatch"),
            Self::Header => f.write_str("header does not match the requested basis"),
            Self::SizeOverflow => f.write_str("size overflow"),
            Self::PayloadSize { got, expected } => {
                write!(f, "payload is {got} bytes, expected {expected}")
            }
            Self::Tensor(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ModalError {}
