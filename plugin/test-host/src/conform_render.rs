//! The machinery of `conform`: one loaded plugin file, fresh instances of it, parameter values
//! set through `params.flush`, one activate-process-deactivate cycle with a given host rate and
//! block plan, and the audio checks every case applies to what came out.
//!
//! Threads: all on the test host's main thread, which also plays the audio thread (an offline
//! bounce); the plugin's own worker and voice-pool threads run inside it.

use clack_extensions::params::PluginParams;
use clack_extensions::state::PluginState;
use clack_host::events::event_types::{NoteOffEvent, NoteOnEvent, ParamValueEvent};
use clack_host::prelude::*;
use std::ffi::CString;
use std::path::Path;

use crate::host::{list_params, new_instance, process_stereo, values, Param, TestHost};

/// The value the host writes into every output sample before `process`: a quiet NaN with a
/// payload of its own, so a sample the plugin did not write is told apart from a NaN it wrote.
pub(crate) const UNWRITTEN: u32 = 0x7fc0_dead;

/// Peak below which a render counts as silent: -80 dBFS, as `check` (far below any struck or
/// plucked note at velocity 1 and 0 dB gain, far above the rounding floor of a silent engine).
pub(crate) const SILENT: f64 = 1e-4;

/// A loaded plugin file, its first plugin and its parameter list.
pub(crate) struct Session {
    pub(crate) entry: PluginEntry,
    pub(crate) id: CString,
    /// The parameters as the plugin describes them (CLAP ranges: nice-plug gives continuous
    /// parameters as normalised [0, 1] and stepped ones as 0..=steps).
    pub params: Vec<Param>,
}

impl Session {
    /// Loads `path` and lists the parameters of its first plugin.
    pub(crate) fn load(path: &Path) -> Result<Self, String> {
        // SAFETY: loading a shared library runs its initialisers; the path is the plugin under
        // test.
        let entry = unsafe { PluginEntry::load(path) }
            .map_err(|e| format!("loading {}: {e:?}", path.display()))?;
        let factory = entry
            .get_plugin_factory()
            .ok_or("the entry has no plugin factory")?;
        let id = factory
            .plugin_descriptors()
            .filter_map(|d| d.id().map(|s| s.to_owned()))
            .next()
            .ok_or("the factory lists no plugin")?;
        let mut s = Self {
            entry,
            id,
            params: Vec::new(),
        };
        let mut first = s.instance()?;
        s.params = list_params(&mut first)?;
        Ok(s)
    }

    /// A new instance of the plugin (inactive, default parameters).
    pub(crate) fn instance(&self) -> Result<PluginInstance<TestHost>, String> {
        new_instance(&self.entry, &self.id)
    }

    /// The index of the parameter whose display name is `name` (case-insensitive).
    pub(crate) fn index_of(&self, name: &str) -> Result<usize, String> {
        self.params
            .iter()
            .position(|p| p.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| format!("the plugin has no parameter named `{name}`"))
    }

    /// The default CLAP value of every parameter.
    pub(crate) fn defaults(&self) -> Vec<f64> {
        self.params.iter().map(|p| p.default).collect()
    }
}

/// Sets every parameter of the inactive `inst` to `values` (CLAP values, one per parameter in
/// [`Session::params`] order) with one `params.flush`.
pub(crate) fn set_values(
    inst: &mut PluginInstance<TestHost>,
    params: &[Param],
    values: &[f64],
) -> Result<(), String> {
    let ext: PluginParams = inst
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP params extension")?;
    let mut events = EventBuffer::new();
    for (p, &v) in params.iter().zip(values) {
        events.push(&ParamValueEvent::new(0, p.id, Pckn::match_all(), v));
    }
    let mut out = EventBuffer::new();
    let mut handle = inst
        .inactive_plugin_handle()
        .ok_or("set_values: the instance is active")?;
    ext.flush(
        &mut handle,
        &InputEvents::from_buffer(&events),
        &mut OutputEvents::from_buffer(&mut out),
    );
    Ok(())
}

/// Saves the state of `inst` through the CLAP state extension.
pub(crate) fn save_state(inst: &mut PluginInstance<TestHost>) -> Result<Vec<u8>, String> {
    let state: PluginState = inst
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP state extension")?;
    let mut blob = Vec::new();
    state
        .save(&inst.plugin_handle(), &mut blob)
        .map_err(|e| format!("state save: {e:?}"))?;
    Ok(blob)
}

/// Loads `blob` into `inst` through the CLAP state extension.
pub(crate) fn load_state(inst: &mut PluginInstance<TestHost>, blob: &[u8]) -> Result<(), String> {
    let state: PluginState = inst
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP state extension")?;
    state
        .load(&inst.plugin_handle(), &mut &blob[..])
        .map_err(|e| format!("state load: {e:?}"))
}

/// Every parameter value of `inst` (CLAP values).
pub(crate) fn read_values(
    inst: &mut PluginInstance<TestHost>,
    params: &[Param],
) -> Result<Vec<f64>, String> {
    values(inst, params)
}

/// One render: host configuration, block plan and what is played.
#[derive(Debug, Clone)]
pub(crate) struct RenderSpec {
    /// Host sample rate given to `activate`, Hz.
    pub rate: f64,
    /// Maximum block size given to `activate`, frames.
    pub max_block: u32,
    /// The block sizes of the run, used in turn and repeated (each at most `max_block`; the
    /// last block is cut to the render's end).
    pub blocks: Vec<u32>,
    /// Length of the render, seconds.
    pub seconds: f64,
    /// Key and velocity (0..=1) of a note on at frame 0, off at 60 % of the render; `None`
    /// plays nothing.
    pub note: Option<(u8, f64)>,
    /// Process CPU seconds (all threads) the blocks may take: once past it the render stops
    /// at the end of the block (the checks apply to what came out). Activation is not counted.
    /// `None`: no limit.
    pub cpu_budget: Option<f64>,
}

impl RenderSpec {
    /// A note (key 60, velocity 1) of `seconds` at `rate` in fixed blocks of `block` frames.
    pub(crate) fn note(rate: f64, block: u32, seconds: f64) -> Self {
        Self {
            rate,
            max_block: block,
            blocks: vec![block],
            seconds,
            note: Some((60, 1.0)),
            cpu_budget: None,
        }
    }
}

/// What one render produced.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rendered {
    /// Left and right channels, one sample per frame asked for.
    pub left: Vec<f32>,
    /// See `left`.
    pub right: Vec<f32>,
    /// Frames the spec asked for.
    pub asked: usize,
    /// `process` calls made.
    pub blocks: usize,
    /// Frames the spec asked for before the CPU budget cut the render short (`asked` is then
    /// the frames rendered); `None` if it ran to the end.
    pub cut_from: Option<usize>,
    /// Process CPU seconds of `activate` (the first model build).
    pub activate_cpu: f64,
    /// Process CPU seconds of the blocks.
    pub process_cpu: f64,
}

/// Figures of one render's audio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AudioStats {
    /// Largest finite |sample|.
    pub peak: f64,
    /// Samples the plugin wrote as NaN or ±∞.
    pub non_finite: usize,
    /// Samples the plugin left as the host's sentinel ([`UNWRITTEN`]).
    pub unwritten: usize,
    /// Finite samples with |x| > 1 (above 0 dBFS).
    pub over: usize,
    /// First frame with any of the defects above, if any.
    pub first_bad: Option<usize>,
}

/// `peak` in dBFS, for the log.
pub(crate) fn dbfs(peak: f64) -> String {
    if peak > 0.0 {
        format!("{:+.1} dBFS", 20.0 * peak.log10())
    } else {
        "silent (0)".to_string()
    }
}

impl AudioStats {
    /// Scans stereo channels.
    pub(crate) fn of(left: &[f32], right: &[f32]) -> Self {
        let mut s = Self {
            peak: 0.0,
            non_finite: 0,
            unwritten: 0,
            over: 0,
            first_bad: None,
        };
        for (i, (&l, &r)) in left.iter().zip(right).enumerate() {
            for x in [l, r] {
                let bad = if x.to_bits() == UNWRITTEN {
                    s.unwritten += 1;
                    true
                } else if !x.is_finite() {
                    s.non_finite += 1;
                    true
                } else {
                    let a = f64::from(x.abs());
                    s.peak = s.peak.max(a);
                    if a > 1.0 {
                        s.over += 1;
                        true
                    } else {
                        false
                    }
                };
                if bad && s.first_bad.is_none() {
                    s.first_bad = Some(i);
                }
            }
        }
        s
    }

    /// Passes when every sample was written, finite and within ±1.0 (0 dBFS); with
    /// `need_sound`, also when the peak is above [`SILENT`]. The message gives the figures.
    pub(crate) fn verdict(&self, need_sound: bool) -> Result<String, String> {
        let figures = format!("peak {}", dbfs(self.peak));
        let mut faults = Vec::new();
        if self.unwritten > 0 {
            faults.push(format!("{} samples not written", self.unwritten));
        }
        if self.non_finite > 0 {
            faults.push(format!("{} samples NaN or infinite", self.non_finite));
        }
        if self.over > 0 {
            faults.push(format!("{} samples above 0 dBFS", self.over));
        }
        if need_sound && self.peak <= SILENT {
            faults.push(format!("silent (peak at most {})", dbfs(SILENT)));
        }
        if faults.is_empty() {
            Ok(figures)
        } else {
            let at = self
                .first_bad
                .map_or(String::new(), |f| format!(", first at frame {f}"));
            Err(format!("{}{at}; {figures}", faults.join(", ")))
        }
    }
}

impl Rendered {
    /// The audio figures.
    pub(crate) fn stats(&self) -> AudioStats {
        AudioStats::of(&self.left, &self.right)
    }

    /// [`AudioStats::verdict`] plus the length check: one written frame per frame asked.
    pub(crate) fn verdict(&self, need_sound: bool) -> Result<String, String> {
        if self.left.len() != self.asked || self.right.len() != self.asked {
            return Err(format!(
                "{} frames asked, {} / {} came back",
                self.asked,
                self.left.len(),
                self.right.len()
            ));
        }
        let v = self.stats().verdict(need_sound)?;
        Ok(match self.cut_from {
            Some(total) => format!(
                "{v}; {} of {total} frames within the CPU budget",
                self.asked
            ),
            None => v,
        })
    }

    /// `activate X s, blocks Y s` for the log.
    pub(crate) fn cpu_line(&self) -> String {
        format!(
            "activate {:.2} s, blocks {:.2} s",
            self.activate_cpu, self.process_cpu
        )
    }

    /// Largest |a - b| over both channels (infinite if the lengths differ or a sample is not
    /// finite).
    pub(crate) fn max_diff(&self, other: &Rendered) -> f64 {
        if self.left.len() != other.left.len() {
            return f64::INFINITY;
        }
        let pairs = self
            .left
            .iter()
            .zip(&other.left)
            .chain(self.right.iter().zip(&other.right));
        pairs.fold(0.0f64, |m, (&a, &b)| {
            let d = f64::from(a) - f64::from(b);
            if d.is_finite() {
                m.max(d.abs())
            } else if a.to_bits() == b.to_bits() {
                m
            } else {
                f64::INFINITY
            }
        })
    }
}

/// Activates `inst` with `spec`'s rate and block range (`min_frames_count` 1), starts
/// processing, runs the block plan with the note, stops and deactivates. An `activate` that
/// returns false is an error naming the configuration. Every output sample is preset to the
/// [`UNWRITTEN`] sentinel before each `process`.
pub(crate) fn render(
    inst: &mut PluginInstance<TestHost>,
    spec: &RenderSpec,
) -> Result<Rendered, String> {
    let config = PluginAudioConfiguration {
        sample_rate: spec.rate,
        min_frames_count: 1,
        max_frames_count: spec.max_block,
    };
    let c0 = process_cpu_seconds();
    let stopped = inst.activate(|_, _| (), config).map_err(|e| {
        format!(
            "activate({} Hz, blocks 1..={}) failed: {e:?}",
            spec.rate, spec.max_block
        )
    })?;
    let mut proc = match stopped.start_processing() {
        Ok(p) => p,
        Err(e) => {
            inst.deactivate(e.into_stopped_processor());
            return Err("start_processing failed".to_string());
        }
    };
    let activate_cpu = process_cpu_seconds() - c0;
    let result = run_blocks(&mut proc, inst, spec);
    inst.deactivate(proc.stop_processing());
    result.map(|r| Rendered {
        activate_cpu,
        process_cpu: process_cpu_seconds() - c0 - activate_cpu,
        ..r
    })
}

fn run_blocks(
    proc: &mut StartedPluginAudioProcessor<TestHost>,
    inst: &mut PluginInstance<TestHost>,
    spec: &RenderSpec,
) -> Result<Rendered, String> {
    let total = (spec.seconds * spec.rate).round() as usize;
    let off = (0.6 * total as f64).round() as usize;
    let cap = spec.max_block as usize;
    let mut left = vec![0.0f32; cap];
    let mut right = vec![0.0f32; cap];
    let mut ports = AudioPorts::with_capacity(2, 1);
    let mut in_buf = EventBuffer::new();
    let mut out_buf = EventBuffer::new();
    let mut out = Rendered {
        left: Vec::with_capacity(total),
        right: Vec::with_capacity(total),
        asked: total,
        blocks: 0,
        cut_from: None,
        activate_cpu: 0.0,
        process_cpu: 0.0,
    };
    let c0 = process_cpu_seconds();
    let mut pos = 0usize;
    while pos < total {
        if spec
            .cpu_budget
            .is_some_and(|b| process_cpu_seconds() - c0 > b)
        {
            out.cut_from = Some(total);
            out.asked = pos;
            break;
        }
        let want = spec.blocks[out.blocks % spec.blocks.len()] as usize;
        if want == 0 || want > cap {
            return Err(format!("block plan: {want} frames outside 1..={cap}"));
        }
        let n = want.min(total - pos);
        in_buf.clear();
        if let Some((key, velocity)) = spec.note {
            let pckn = Pckn::new(0u16, 0u16, u16::from(key), u32::from(key));
            if pos == 0 {
                in_buf.push(&NoteOnEvent::new(0, pckn, velocity));
            }
            if (pos..pos + n).contains(&off) {
                in_buf.push(&NoteOffEvent::new((off - pos) as u32, pckn, 0.0));
            }
        }
        left[..n].fill(f32::from_bits(UNWRITTEN));
        right[..n].fill(f32::from_bits(UNWRITTEN));
        process_stereo(
            proc,
            &mut ports,
            &in_buf,
            &mut out_buf,
            [&mut left[..n], &mut right[..n]],
            pos as u64,
        )
        .map_err(|e| format!("process of {n} frames at frame {pos}: {e}"))?;
        out.left.extend_from_slice(&left[..n]);
        out.right.extend_from_slice(&right[..n]);
        out.blocks += 1;
        pos += n;
        inst.call_on_main_thread_callback();
    }
    Ok(out)
}

/// A small seeded generator (SplitMix64, Steele, Lea and Flood 2014): the same seed gives the
/// same parameter sets on every machine.
#[derive(Debug, Clone)]
pub(crate) struct Rng(u64);

impl Rng {
    /// Seeds the generator.
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A CLAP value of `p` drawn uniformly: a whole number in `min..=max` for stepped
    /// parameters (integers, enumerations), else a real in `[min, max]`.
    pub(crate) fn value_of(&mut self, p: &Param) -> f64 {
        let u = self.unit();
        if p.stepped {
            let steps = (p.max - p.min).round();
            (p.min + (u * (steps + 1.0)).floor()).min(p.max)
        } else {
            p.min + u * (p.max - p.min)
        }
    }
}

/// CPU time of the whole process (every thread: the plugin's workers and voice pool count),
/// seconds, from `CLOCK_PROCESS_CPUTIME_ID`; NaN where it cannot be read.
pub(crate) fn process_cpu_seconds() -> f64 {
    noether_core::clock::process_cpu_time().map_or(f64::NAN, |t| t.as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rendered(left: Vec<f32>, asked: usize) -> Rendered {
        Rendered {
            right: left.clone(),
            left,
            asked,
            blocks: 1,
            cut_from: None,
            activate_cpu: 0.0,
            process_cpu: 0.0,
        }
    }

    #[test]
    fn a_bounded_written_sounding_render_passes() {
        let r = rendered(vec![0.0, 0.5, -1.0, 0.25], 4);
        assert_eq!(r.verdict(true), Ok("peak +0.0 dBFS".to_string()));
    }

    #[test]
    fn each_defect_fails_the_verdict() {
        // Exactly 1.0 passes (0 dBFS is the bound); the next float above does not.
        let over = rendered(vec![0.1, f32::from_bits(1.0f32.to_bits() + 1)], 2);
        assert!(over.verdict(false).unwrap_err().contains("above 0 dBFS"));
        let nan = rendered(vec![0.1, f32::NAN], 2);
        assert!(nan.verdict(false).unwrap_err().contains("NaN or infinite"));
        let inf = rendered(vec![f32::INFINITY, 0.1], 2);
        let e = inf.verdict(false).unwrap_err();
        assert!(
            e.contains("NaN or infinite") && e.contains("frame 0"),
            "{e}"
        );
        let hole = rendered(vec![0.1, f32::from_bits(UNWRITTEN)], 2);
        assert!(hole.verdict(false).unwrap_err().contains("not written"));
        let short = rendered(vec![0.1, 0.2], 3);
        assert!(short.verdict(false).unwrap_err().contains("3 frames asked"));
        let quiet = rendered(vec![1e-5, -1e-5], 2);
        assert!(quiet.verdict(false).is_ok());
        assert!(quiet.verdict(true).unwrap_err().contains("silent"));
    }

    #[test]
    fn max_diff_sees_differences_and_non_finite_mismatches() {
        let a = rendered(vec![0.0, 0.5, f32::NAN], 3);
        let b = rendered(vec![0.0, 0.25, f32::NAN], 3);
        assert_eq!(a.max_diff(&a), 0.0);
        assert_eq!(a.max_diff(&b), 0.25);
        let c = rendered(vec![0.0, 0.5, 0.0], 3);
        assert_eq!(a.max_diff(&c), f64::INFINITY);
    }

    #[test]
    fn stepped_draws_cover_every_step_and_stay_in_range() {
        let p = Param {
            id: ClapId::new(1),
            name: "k".into(),
            min: 0.0,
            max: 4.0,
            default: 0.0,
            stepped: true,
        };
        let mut rng = Rng::new(7);
        let mut seen = [false; 5];
        for _ in 0..200 {
            let v = rng.value_of(&p);
            assert!(v.fract() == 0.0 && (0.0..=4.0).contains(&v), "{v}");
            seen[v as usize] = true;
        }
        assert!(seen.iter().all(|&s| s), "{seen:?}");
    }
}
