//! On-disk cache of circular-plate bases, keyed by (geometry, ν, N_Φ, N_Ψ, quadrature order,
//! format version).
//!
//! Only the coupling tensor is stored (the modes take a fraction of a second to recompute and
//! are recomputed on load). File layout, little-endian:
//! `b"NTHMODAL"`, format version (u32), edge (u8: 0 free, 1 clamped), ν (f64), N_Φ, N_Ψ,
//! Q, fingerprint of the recomputed modes, nnz (u64 each), `row_start` (u32 × (N_Ψ+1)), `i`,
//! `j` (u32 × nnz), `value` (f64 × nnz), checksum (u64 over everything before it).
//! A file whose header, lengths, fingerprint, checksum or tensor invariants do not match is
//! not trusted: the basis is rebuilt and the file rewritten (atomically: temporary file, then
//! rename). Runs on the worker thread that builds the basis; allocates and does file I/O.

use super::assemble::assemble;
use super::basis::{CircularPlateSpec, Mode, PlateModes};
use super::radial::CircularEdge;
use crate::error::ParamError;
use crate::modal::error::{CacheReject, ModalError};
use crate::modal::tensor::CouplingTensor;
use std::path::{Path, PathBuf};

/// Version of the file layout and of the numerical method; bump it when either changes.
pub const CACHE_FORMAT_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"NTHMODAL";

/// What [`PlateModes::load_or_build`] did.
///
/// Plain data returned to the worker thread.
#[derive(Debug, Clone, PartialEq)]
pub enum CacheOutcome {
    /// A valid cache file was found and used.
    Hit,
    /// No cache file existed; the basis was built and saved.
    Built,
    /// A cache file existed but was rejected (the reason is given: a
    /// [`ModalError::CacheRejected`], or [`ModalError::Io`] if it could not be read); rebuilt
    /// and saved.
    Rebuilt(ModalError),
    /// Built, but saving failed (the [`ModalError::Io`] is given, with the path); the basis is
    /// still valid.
    NotSaved(ModalError),
}

/// Default cache directory: `$NOETHER_CACHE` if set, else `$HOME/.cache/noether`, else
/// `target/noether-cache` (relative to the working directory).
pub fn default_cache_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("NOETHER_CACHE") {
        return PathBuf::from(d);
    }
    if let Some(h) = std::env::var_os("HOME") {
        return PathBuf::from(h).join(".cache").join("noether");
    }
    PathBuf::from("target").join("noether-cache")
}

/// File name of the cache entry of `spec` (every key field appears in it).
pub fn cache_file_name(spec: &CircularPlateSpec) -> String {
    format!(
        "circular-{}{}-nu{:016x}-phi{}-psi{}-q{}-v{}.bin",
        spec.edge.name(),
        if spec.mirror { "-mirror" } else { "" },
        spec.nu.to_bits(),
        spec.n_phi,
        spec.n_psi,
        spec.quad_points,
        CACHE_FORMAT_VERSION
    )
}

/// 64-bit hash (FNV-1a over 8-byte words, then a final avalanche); not cryptographic. Also
/// names the drone's tuning files (`models::tanpura::tuning_cache`).
pub(crate) fn hash_words(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut chunks = bytes.chunks_exact(8);
    for c in &mut chunks {
        h ^= u64::from_le_bytes(c.try_into().expect("8-byte chunk"));
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    for &b in chunks.remainder() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^ (h >> 33)
}

/// Fingerprint of two mode lists (labels and eigenvalue bits).
fn fingerprint(phi: &[Mode], psi: &[Mode]) -> u64 {
    let mut b = Vec::with_capacity(24 * (phi.len() + psi.len()));
    for m in phi.iter().chain(psi) {
        b.extend_from_slice(&m.n.to_le_bytes());
        b.extend_from_slice(&m.k.to_le_bytes());
        b.extend_from_slice(&(m.parity as u64).to_le_bytes());
        b.extend_from_slice(&m.radial.lambda.to_bits().to_le_bytes());
    }
    hash_words(&b)
}

fn header(spec: &CircularPlateSpec, fp: u64, nnz: usize) -> Vec<u8> {
    let mut b = Vec::with_capacity(64);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&CACHE_FORMAT_VERSION.to_le_bytes());
    b.push(match spec.edge {
        CircularEdge::Free => 0,
        CircularEdge::Clamped => 1,
    });
    b.extend_from_slice(&spec.nu.to_bits().to_le_bytes());
    for v in [
        spec.n_phi as u64,
        spec.n_psi as u64,
        spec.quad_points as u64,
        fp,
        nnz as u64,
    ] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

/// Serialises the tensor of `spec` with the mode fingerprint `fp`.
fn encode(spec: &CircularPlateSpec, fp: u64, t: &CouplingTensor) -> Vec<u8> {
    let (rs, vi, vj, vv) = t.parts();
    let mut b = header(spec, fp, t.nnz());
    b.reserve(4 * (rs.len() + 2 * vi.len()) + 8 * vv.len() + 8);
    for x in rs.iter().chain(vi).chain(vj) {
        b.extend_from_slice(&x.to_le_bytes());
    }
    for x in vv {
        b.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    let h = hash_words(&b);
    b.extend_from_slice(&h.to_le_bytes());
    b
}

/// Parses and checks a cache file; `Err` carries the reason for rejecting it.
fn decode(spec: &CircularPlateSpec, fp: u64, bytes: &[u8]) -> Result<CouplingTensor, CacheReject> {
    if bytes.len() < 8 {
        return Err(CacheReject::TooShort);
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    let stored = u64::from_le_bytes(tail.try_into().expect("8 bytes"));
    if hash_words(body) != stored {
        return Err(CacheReject::Checksum);
    }
    let probe = header(spec, fp, 0);
    let hl = probe.len();
    if body.len() < hl || body[..hl - 8] != probe[..hl - 8] {
        return Err(CacheReject::Header);
    }
    let nnz = u64::from_le_bytes(body[hl - 8..hl].try_into().expect("8 bytes")) as usize;
    let nrow = spec.n_psi + 1;
    let need = nrow
        .checked_add(nnz.checked_mul(2).ok_or(CacheReject::SizeOverflow)?)
        .and_then(|w| w.checked_mul(4))
        .and_then(|w| w.checked_add(nnz.checked_mul(8)?))
        .ok_or(CacheReject::SizeOverflow)?;
    if body.len() - hl != need {
        return Err(CacheReject::PayloadSize {
            got: body.len() - hl,
            expected: need,
        });
    }
    let u32s = |off: usize, n: usize| -> Vec<u32> {
        body[off..off + 4 * n]
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect()
    };
    let rs = u32s(hl, nrow);
    let vi = u32s(hl + 4 * nrow, nnz);
    let vj = u32s(hl + 4 * (nrow + nnz), nnz);
    let off = hl + 4 * (nrow + 2 * nnz);
    let vv: Vec<f64> = body[off..off + 8 * nnz]
        .chunks_exact(8)
        .map(|c| f64::from_bits(u64::from_le_bytes(c.try_into().expect("8 bytes"))))
        .collect();
    CouplingTensor::from_parts(spec.n_phi, spec.n_psi, rs, vi, vj, vv).map_err(CacheReject::Tensor)
}

/// Writes `bytes` to `path` atomically (temporary file in the same directory, then rename).
/// Also writes the drone's tuning files (`models::tanpura::tuning_cache`).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    // One temporary name per write (process and a counter): two threads of a process (two
    // plugin instances, parallel renders) saving the same basis must not write one file.
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = path.with_extension(format!("tmp{}-{n}", std::process::id()));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

impl PlateModes {
    /// Loads the basis of `spec` from `cache_dir` (see [`default_cache_dir`]) or builds it and
    /// saves it there. Corrupt or mismatching files are rebuilt and overwritten, never
    /// trusted. I/O failures while saving are reported in the outcome, not as errors.
    /// Worker thread.
    pub fn load_or_build(
        spec: &CircularPlateSpec,
        cache_dir: &Path,
    ) -> Result<(Self, CacheOutcome), ParamError> {
        spec.validate()?;
        let (phi, psi) = Self::modes(spec);
        let fp = fingerprint(&phi, &psi);
        let path = cache_dir.join(cache_file_name(spec));
        let mut outcome = CacheOutcome::Built;
        match std::fs::read(&path) {
            Ok(bytes) => match decode(spec, fp, &bytes) {
                Ok(t) => return Ok((Self::from_parts(*spec, phi, psi, t), CacheOutcome::Hit)),
                Err(reason) => outcome = CacheOutcome::Rebuilt(reason.into()),
            },
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => outcome = CacheOutcome::Rebuilt(ModalError::io(&path, &e)),
        }
        let t = assemble(&phi, &psi, spec.quad_points)?;
        if let Err(e) = write_atomic(&path, &encode(spec, fp, &t)) {
            outcome = CacheOutcome::NotSaved(ModalError::io(&path, &e));
        }
        Ok((Self::from_parts(*spec, phi, psi, t), outcome))
    }
}
