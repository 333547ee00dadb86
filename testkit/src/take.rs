//! The engine tests' one render loop and its measures: a [`Take`] is the stereo output of an
//! engine over a number of host samples, with the events of the first block (a note, an
//! expression) sent with that block ([`render`]), or a script of events at any host samples
//! with a look at the engine after every block ([`render_script`]), and its peak and RMS
//! levels.
//!
//! Test thread (allocates the take; the engine's blocks themselves allocate nothing).

use noether_core::engine::{Engine, Event, EventKind};

/// The stereo output of a render (host rate, the engine's output units).
#[derive(Debug, Clone, PartialEq)]
pub struct Take {
    /// Left channel.
    pub left: Vec<f32>,
    /// Right channel.
    pub right: Vec<f32>,
}

/// Renders `samples` host samples of `e` in blocks of `block` (the last one shorter if
/// `samples` is not a multiple), `first` sent with the first block.
pub fn render(e: &mut Engine, first: &[Event], samples: usize, block: usize) -> Take {
    let (mut left, mut right) = (vec![0.0f32; samples], vec![0.0f32; samples]);
    for (k, (l, r)) in left
        .chunks_mut(block.max(1))
        .zip(right.chunks_mut(block.max(1)))
        .enumerate()
    {
        e.process_events(if k == 0 { first } else { &[] }, l, r);
    }
    Take { left, right }
}

/// Renders `samples` host samples of `e` in blocks of `block` (the last one shorter if
/// `samples` is not a multiple), sending each `(sample, event)` of `script` (sorted by
/// sample) in the block that holds its sample, at its offset there, and calling `after(e,
/// end)` after each block with the host sample the block ended at. Events past the render are
/// not sent.
pub fn render_script(
    e: &mut Engine,
    script: &[(usize, EventKind)],
    samples: usize,
    block: usize,
    mut after: impl FnMut(&mut Engine, usize),
) -> Take {
    let (mut left, mut right) = (vec![0.0f32; samples], vec![0.0f32; samples]);
    let block = block.max(1);
    let mut next = 0;
    let mut events = Vec::with_capacity(script.len());
    for (k, (l, r)) in left
        .chunks_mut(block)
        .zip(right.chunks_mut(block))
        .enumerate()
    {
        let (start, end) = (k * block, k * block + l.len());
        events.clear();
        while next < script.len() && script[next].0 < end {
            let (at, kind) = script[next];
            events.push(Event::new(at.saturating_sub(start) as u32, kind));
            next += 1;
        }
        e.process_events(&events, l, r);
        after(e, end);
    }
    Take { left, right }
}

/// [`render`] of `seconds` at the engine's host rate (the sample count rounded down).
pub fn render_seconds(e: &mut Engine, first: &[Event], seconds: f64, block: usize) -> Take {
    let samples = (seconds * e.host_rate()) as usize;
    render(e, first, samples, block)
}

impl Take {
    /// The largest magnitude over both channels.
    pub fn peak(&self) -> f32 {
        peak(&self.left).max(peak(&self.right))
    }

    /// The left channel in `f64` (the analysis functions' input).
    pub fn left_f64(&self) -> Vec<f64> {
        self.left.iter().map(|&x| f64::from(x)).collect()
    }

    /// Left plus right in `f64` (the sum of both pickups).
    pub fn sum_f64(&self) -> Vec<f64> {
        self.left
            .iter()
            .zip(&self.right)
            .map(|(a, b)| f64::from(a + b))
            .collect()
    }
}

/// The largest magnitude of `x` (0 for an empty slice).
pub fn peak(x: &[f32]) -> f32 {
    x.iter().fold(0.0f32, |m, v| m.max(v.abs()))
}

/// The root mean square of `x` (NaN for an empty slice).
pub fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

/// The root mean square of `x` (NaN for an empty slice).
pub fn rms_f64(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// What [`run_blocks`] gave: the left output and the first voice's total energy after each
/// block.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockRun {
    /// Left channel (the engine's output units).
    pub left: Vec<f64>,
    /// Voice 0's total energy (J) after each block; 0 once the voice has ended.
    pub energy: Vec<f64>,
}

/// Plays `blocks` blocks of `block` host samples, each `(index, event)` of `events` at offset
/// 0 of the block of that index, each block inside `assert_no_alloc`; panics on a sample that
/// is not finite or over full scale. The loop of the tests of a voice that lives across notes
/// (the drone, the sitar), which look at the voice's energy after every block.
pub fn run_blocks(
    e: &mut Engine,
    events: &[(usize, EventKind)],
    blocks: usize,
    block: usize,
) -> BlockRun {
    let (mut l, mut r) = (vec![0.0f32; block], vec![0.0f32; block]);
    let mut out = BlockRun {
        left: Vec::with_capacity(blocks * block),
        energy: Vec::with_capacity(blocks),
    };
    for b in 0..blocks {
        let ev: Vec<Event> = events
            .iter()
            .filter(|(at, _)| *at == b)
            .map(|&(_, kind)| Event { offset: 0, kind })
            .collect();
        assert_no_alloc::assert_no_alloc(|| e.process_events(&ev, &mut l, &mut r));
        for &x in l.iter().chain(&r) {
            assert!(x.is_finite() && x.abs() <= 1.0, "block {b}: output {x}");
        }
        out.left.extend(l.iter().map(|&x| f64::from(x)));
        out.energy
            .push(e.voice_energy(0).map_or(0.0, |t| t.total()));
    }
    out
}
