//! One chunk of one bank: its sounding voices run as jobs of the voice pool (or on the audio
//! thread alone), then, on the audio thread and in voice order, their outputs are summed, the
//! divergence and silence checks and the energy bookkeeping applied, and the sum resampled to
//! the host rate.
//!
//! The sum runs in voice order whatever thread ran each voice, and each voice writes only its
//! own lane, so the output is bit-identical for any number of threads (as long as no job is
//! late; a late voice's chunk is left out of the mix, see [`super::pool`]).
//!
//! Threads: audio thread; the jobs run on the pool's workers and the audio thread.

use super::bank::Bank;
use super::governor::FADE_CHUNKS;
use super::pool::{Lanes, Pool};
use super::voice::Voice;
use std::time::Duration;

/// A voice ends when its stored energy falls below this fraction of its peak after the
/// excitation (1e-10: -100 dB in amplitude, since energy goes as amplitude squared).
pub const SILENCE_RATIO: f64 = 1e-10;

/// How the chunk's voice jobs are shared.
#[derive(Clone, Copy)]
pub(crate) struct Sharing<'a> {
    /// The worker pool (`None`: the audio thread alone).
    pub pool: Option<&'a Pool>,
    /// Workers invited besides the audio thread.
    pub helpers: usize,
    /// Longest wait for the jobs workers hold once the audio thread has run out of jobs.
    pub wait: Duration,
}

/// Counters a chunk adds to (the engine's totals).
#[derive(Default)]
pub(crate) struct Tally {
    /// Contact Newton solves that hit their cap.
    pub hits: u64,
    /// Voices silenced as diverged.
    pub diverged: u64,
    /// Voice jobs still running when the wait ended (their chunk left out of the mix).
    pub late: u64,
    /// Mallet contacts begun (strikes and re-strikes).
    pub impacts: u64,
}

/// Voice `i` of the bank whose voice list starts at `base`, if its lane is at rest.
///
/// # Safety
///
/// `base` comes from `Vec::as_mut_ptr` of the bank's voice list, obtained in the current
/// chunk, `i` is in range, and the caller holds the bank exclusively (`&mut Bank`) and makes
/// no other reference to this voice while the returned one lives.
unsafe fn voice_at<'a>(base: *mut Voice, lanes: &Lanes, i: usize) -> Option<&'a mut Voice> {
    // SAFETY: a lane at rest means no participant holds the voice (pool state diagram); the
    // rest is the caller's contract.
    lanes.is_idle(i).then(|| unsafe { &mut *base.add(i) })
}

/// Bookkeeping of voice `v` after a job (`ok`: it stayed finite and under the ceiling).
fn settle(v: &mut Voice, ok: bool, t: &mut Tally) {
    if !ok {
        v.reset();
        t.diverged += 1;
        return;
    }
    t.hits += v.take_cap_hits();
    t.impacts += v.take_impacts();
    let e = v.level_energy();
    v.energy = e;
    v.peak_energy = v.peak_energy.max(e);
    if !v.exciting() && (!e.is_finite() || e <= SILENCE_RATIO * v.peak_energy) {
        if !e.is_finite() {
            t.diverged += 1;
        }
        v.reset();
    }
}

/// Runs every sounding voice of `b` for the chunk and resamples into `left`/`right`.
/// Returns whether a voice job is still running (a late worker): the caller must then not
/// touch the bank's voice list until a later call returns `false` (then every lane is at
/// rest). Never touches a voice whose lane is not at rest.
pub(crate) fn run_bank(
    b: &mut Bank,
    share: Sharing,
    left: &mut [f32],
    right: &mut [f32],
    t: &mut Tally,
) -> bool {
    let m = b.resampler.input_needed(left.len());
    let m_above = b.above.input_needed(left.len());
    let n = b.voices.len().min(b.lanes.len());
    // Raw pointer into the voice list: the voices are reached one by one, never through a
    // slice that would cover a voice a worker still holds.
    let base = b.voices.as_mut_ptr();
    let lanes = &*b.lanes;
    // Results of late jobs that have finished since: bookkeeping, samples dropped.
    for i in 0..n {
        if let Some((ok, ..)) = lanes.take(i) {
            // SAFETY: `take` returned the voice to this thread; `base` is this chunk's.
            settle(unsafe { &mut *base.add(i) }, ok, t);
        }
    }
    let (mut queued, mut assist) = (0u64, false);
    for i in 0..n {
        // SAFETY: `base` is this chunk's, `i < n`, the bank is held exclusively; the reference
        // ends within the iteration.
        if let Some(v) = unsafe { voice_at(base, lanes, i) } {
            if v.active {
                assist |= v.offers_step_halves();
                lanes.queue(i, v, (m, m_above), b.norm);
                queued |= 1 << i;
            }
        }
    }
    if queued == 0 && b.resampler.is_silent() && b.above.is_silent() {
        b.resampler.advance_silent(left.len(), m);
        left.fill(0.0);
        right.fill(0.0);
        record_sounding(base, lanes, n);
        return lanes.any_busy();
    }
    match share.pool {
        Some(p) if share.helpers > 0 && (queued.count_ones() > 1 || assist) => {
            p.run(lanes, queued, share.helpers, share.wait, assist)
        }
        _ => {
            lanes.claim(0);
        }
    }
    let (sl, sr) = (&mut b.sim_l[..m], &mut b.sim_r[..m]);
    sl.fill(0.0);
    sr.fill(0.0);
    b.above.clear(m_above);
    for i in (0..n).filter(|i| queued >> i & 1 == 1) {
        match lanes.take(i) {
            Some((ok, [vl, vr], above)) => {
                // SAFETY: `take` returned the voice to this thread; `base` is this chunk's.
                let v = unsafe { &mut *base.add(i) };
                if ok {
                    b.cost.observe(v.price(), m, v.job_seconds);
                    // The note's key-tracked level, volume and pan expressions, outside the
                    // voice's ceiling check (which bounds the physics, not the mix); a voice
                    // the governor ends fades out over its last chunks.
                    let fade = match v.fading {
                        0 => 1.0,
                        k => f32::from(k - 1) / f32::from(FADE_CHUNKS),
                    };
                    let g = fade * (v.level * f64::from(v.note_volume)) as f32;
                    let p = v.note_pan;
                    let (gl, gr) = (g * (2.0 * (1.0 - p)).min(1.0), g * (2.0 * p).min(1.0));
                    for k in 0..m {
                        sl[k] += gl * vl[k];
                        sr[k] += gr * vr[k];
                    }
                    b.above.add((gl, gr), above);
                }
                settle(v, ok, t);
                if v.fading > 0 {
                    v.fading -= 1;
                    if v.fading == 0 {
                        v.reset();
                    }
                }
            }
            None => t.late += 1,
        }
    }
    b.resampler.push(sl, sr);
    b.resampler.produce(left, right);
    b.above.mix_into(left, right);
    let hold = lanes.any_busy();
    if !hold {
        // A late job may have ended since its lane was looked at: settle it now, so the
        // bank's voices all rest with the audio thread between chunks.
        for i in 0..n {
            if let Some((ok, ..)) = lanes.take(i) {
                // SAFETY: `take` returned the voice to this thread; `base` is this chunk's.
                settle(unsafe { &mut *base.add(i) }, ok, t);
            }
        }
    }
    record_sounding(base, lanes, n);
    hold
}

/// Records in the lanes which voices sound (a voice whose job still runs keeps its record:
/// it was sounding when queued).
fn record_sounding(base: *mut Voice, lanes: &Lanes, n: usize) {
    for i in 0..n {
        // SAFETY: as in `run_bank`: this chunk's `base`, `i < n`, the reference ends here.
        if let Some(v) = unsafe { voice_at(base, lanes, i) } {
            lanes.set_sounding(i, v.active);
        }
    }
}
