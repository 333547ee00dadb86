//! The test host's `render` command: set parameters as display values, round-trip the state
//! through a second instance, play a scripted performance (with hostile automation if asked)
//! and write the output to a WAV file. The CLAP plumbing is `host.rs`.

use clack_extensions::params::PluginParams;
use clack_extensions::state::PluginState;
use clack_host::events::event_types::{MidiEvent, NoteOffEvent, NoteOnEvent, ParamValueEvent};
use clack_host::prelude::*;
use std::ffi::CString;
use std::path::PathBuf;

use crate::args::{parse_num, path_arg};
use crate::host::{
    list_params, new_instance, process_stereo, shows_value, text_of, values, Param, TestHost,
};
use crate::hostile::HostileAutomation;

/// What `render` does, from the command line.
#[derive(Debug)]
pub struct RenderOptions {
    /// The `.clap` bundle (on Linux a shared library file).
    pub plugin: PathBuf,
    /// Where the stereo 32-bit float WAV goes.
    pub out: PathBuf,
    /// Host sample rate in Hz.
    pub rate: f64,
    /// Block size in frames (the host's buffer size).
    pub block: u32,
    /// Total length of the render in seconds.
    pub seconds: f64,
    /// When the note-off events are sent, in seconds.
    pub note_off: f64,
    /// MIDI keys played together at t = 0.
    pub keys: Vec<u8>,
    /// Note-on velocity in [0, 1].
    pub velocity: f64,
    /// Parameters to set before activation: display name (case-insensitive) and the value as
    /// the plugin displays it (a number in the parameter's unit, or an enumeration name).
    pub sets: Vec<(String, String)>,
    /// Save the state of the first instance, load it into a second one, check every parameter
    /// came back, and render with the second instance.
    pub state_roundtrip: bool,
    /// A saved CLAP state stream to load before the `--set`s (see [`crate::state_load`]).
    pub load_state: Option<PathBuf>,
    /// Whether the plugin must accept (`ok`) or refuse (`refused`) `load_state`.
    pub expect_load: Option<bool>,
    /// Values the parameters must show after `load_state`: display name and display value.
    pub expects: Vec<(String, String)>,
    /// Send out-of-range and non-finite values to every parameter each block and check the
    /// values read back (see [`crate::hostile`]).
    pub hostile_automation: bool,
}

impl RenderOptions {
    /// Parses `PLUGIN OUT [options]`.
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut it = args.iter();
        let plugin = path_arg("PLUGIN.clap", it.next())?;
        let out = path_arg("OUT.wav", it.next())?;
        let mut o = Self {
            plugin,
            out,
            rate: 48_000.0,
            block: 256,
            seconds: 3.0,
            note_off: 1.0,
            keys: Vec::new(),
            velocity: 0.8,
            sets: Vec::new(),
            state_roundtrip: false,
            load_state: None,
            expect_load: None,
            expects: Vec::new(),
            hostile_automation: false,
        };
        while let Some(flag) = it.next() {
            match flag.as_str() {
                "--rate" => o.rate = parse_num(flag, it.next())?,
                "--block" => o.block = parse_num(flag, it.next())?,
                "--seconds" => o.seconds = parse_num(flag, it.next())?,
                "--note-off" => o.note_off = parse_num(flag, it.next())?,
                "--key" => o.keys.push(parse_num(flag, it.next())?),
                "--velocity" => o.velocity = parse_num(flag, it.next())?,
                "--state-roundtrip" => o.state_roundtrip = true,
                "--hostile-automation" => o.hostile_automation = true,
                "--load-state" => o.load_state = Some(path_arg(flag, it.next())?),
                "--expect-load" => {
                    o.expect_load = match it.next().map(String::as_str) {
                        Some("ok") => Some(true),
                        Some("refused") => Some(false),
                        other => return Err(format!("--expect-load {other:?}: ok or refused")),
                    }
                }
                "--expect" => {
                    let kv = it.next().ok_or("--expect needs NAME=VALUE")?;
                    let (k, v) = kv
                        .split_once('=')
                        .ok_or_else(|| format!("--expect: `{kv}` is not NAME=VALUE"))?;
                    o.expects.push((k.to_string(), v.to_string()));
                }
                "--set" => {
                    let kv = it.next().ok_or("--set needs NAME=VALUE")?;
                    let (k, v) = kv
                        .split_once('=')
                        .ok_or_else(|| format!("--set: `{kv}` is not NAME=VALUE"))?;
                    o.sets.push((k.to_string(), v.to_string()));
                }
                other => return Err(format!("unknown option `{other}`")),
            }
        }
        if o.keys.is_empty() {
            o.keys.push(60);
        }
        if !(8_000.0..=384_000.0).contains(&o.rate) {
            return Err(format!("--rate {} outside 8000..=384000 Hz", o.rate));
        }
        if !(1..=8192).contains(&o.block) {
            return Err(format!("--block {} outside 1..=8192", o.block));
        }
        if !(o.note_off > 0.0 && o.note_off < o.seconds) {
            return Err(format!(
                "--note-off {} must lie inside (0, --seconds {})",
                o.note_off, o.seconds
            ));
        }
        Ok(o)
    }
}

/// Sets parameters given as display values in their units (`Damping=2`, `Model=sitar`): the
/// plugin's `text_to_value` gives the CLAP value (nice-plug exposes continuous parameters
/// normalised to [0, 1] and integers as steps), `params.flush` on the inactive instance sets
/// it, and `value_to_text` of the value read back must show the requested value.
fn apply_sets(
    instance: &mut PluginInstance<TestHost>,
    params: &[Param],
    sets: &[(String, String)],
) -> Result<(), String> {
    let ext: PluginParams = instance
        .plugin_handle()
        .get_extension()
        .ok_or("no params extension")?;
    let mut events = EventBuffer::new();
    let mut targets = Vec::new();
    for (name, text) in sets {
        let p = params
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| format!("--set: the plugin has no parameter named `{name}`"))?;
        let c = CString::new(text.as_str()).map_err(|_| format!("--set {name}: bad text"))?;
        let value = ext
            .text_to_value(&instance.plugin_handle(), p.id, &c)
            .ok_or_else(|| format!("--set {name}={text}: the plugin cannot parse `{text}`"))?;
        if !(p.min..=p.max).contains(&value) {
            return Err(format!(
                "--set {name}={text}: CLAP value {value} outside {}..={}",
                p.min, p.max
            ));
        }
        events.push(&ParamValueEvent::new(0, p.id, Pckn::match_all(), value));
        targets.push((p.clone(), text.clone()));
    }
    let mut out_buffer = EventBuffer::new();
    {
        let mut handle = instance
            .inactive_plugin_handle()
            .ok_or("instance is active")?;
        ext.flush(
            &mut handle,
            &InputEvents::from_buffer(&events),
            &mut OutputEvents::from_buffer(&mut out_buffer),
        );
    }
    for (p, want) in targets {
        let got = ext
            .get_value(&instance.plugin_handle(), p.id)
            .ok_or("get_value failed")?;
        let shown = text_of(&ext, instance, p.id, got)?;
        if !shows_value(&ext, instance, p.id, &want, &shown) {
            return Err(format!(
                "parameter `{}` set to `{want}` reads back `{shown}` (CLAP value {got})",
                p.name
            ));
        }
        println!("set {} = {want} (reads back `{shown}`)", p.name);
    }
    Ok(())
}

/// Saves `from`'s state, loads it into `to`, and checks every parameter value matches.
fn roundtrip_state(
    from: &mut PluginInstance<TestHost>,
    to: &mut PluginInstance<TestHost>,
    params: &[Param],
) -> Result<(), String> {
    let state: PluginState = from
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP state extension")?;
    let mut blob = Vec::new();
    state
        .save(&from.plugin_handle(), &mut blob)
        .map_err(|e| format!("state save: {e:?}"))?;
    let state_to: PluginState = to.plugin_handle().get_extension().ok_or("no state ext")?;
    state_to
        .load(&to.plugin_handle(), &mut blob.as_slice())
        .map_err(|e| format!("state load: {e:?}"))?;
    let a = values(from, params)?;
    let b = values(to, params)?;
    for ((p, x), y) in params.iter().zip(&a).zip(&b) {
        // The state holds the f32 values nice-plug keeps; the CLAP values (normalised or
        // steps) come back to within f32 rounding: 1e-6 of the CLAP range is a few ulps.
        let tol = 1e-6 * (p.max - p.min).abs().max(1e-12);
        if (x - y).abs() > tol {
            return Err(format!(
                "state round trip: `{}` was {x}, restored {y} (tolerance {tol:e})",
                p.name
            ));
        }
    }
    println!(
        "state round trip: {} bytes, {} parameters restored",
        blob.len(),
        params.len()
    );
    Ok(())
}

/// One scheduled input event.
#[derive(Debug, Clone, Copy)]
enum Scheduled {
    NoteOn(u8),
    NoteOff(u8),
    /// Raw MIDI 1.0 bytes (pitch bend, control change).
    Midi([u8; 3]),
}

/// The performance: notes on at 0, MIDI expression while they sound, notes off at `note_off`.
fn schedule(o: &RenderOptions) -> Vec<(u64, Scheduled)> {
    let at = |s: f64| (s * o.rate).round() as u64;
    let off = o.note_off;
    let mut ev = Vec::new();
    for &k in &o.keys {
        ev.push((0, Scheduled::NoteOn(k)));
        ev.push((at(off), Scheduled::NoteOff(k)));
    }
    // Sustain pedal down and up again before the note-off (so the release still happens at
    // `note_off`), a pitch bend up and back to centre, the mod wheel half way.
    ev.push((at(0.1 * off), Scheduled::Midi([0xB0, 64, 127])));
    ev.push((at(0.2 * off), Scheduled::Midi([0xE0, 0x00, 0x50])));
    ev.push((at(0.3 * off), Scheduled::Midi([0xB0, 1, 64])));
    ev.push((at(0.6 * off), Scheduled::Midi([0xE0, 0x00, 0x40])));
    ev.push((at(0.8 * off), Scheduled::Midi([0xB0, 64, 0])));
    ev.sort_by_key(|(t, _)| *t);
    ev
}

/// Renders the performance with an activated instance; returns interleaved stereo frames.
fn perform(
    instance: &mut PluginInstance<TestHost>,
    params: &[Param],
    o: &RenderOptions,
) -> Result<Vec<f32>, String> {
    let mut hostile = if o.hostile_automation {
        Some(HostileAutomation::new(params, values(instance, params)?))
    } else {
        None
    };
    let config = PluginAudioConfiguration {
        sample_rate: o.rate,
        min_frames_count: 1,
        max_frames_count: o.block,
    };
    let stopped = instance
        .activate(|_, _| (), config)
        .map_err(|e| format!("activate: {e:?}"))?;
    let mut proc = stopped
        .start_processing()
        .map_err(|e| format!("start_processing: {e:?}"))?;

    let total = (o.seconds * o.rate).round() as u64;
    let block = o.block as usize;
    let events = schedule(o);
    let mut next_event = 0;
    let mut left = vec![0.0f32; block];
    let mut right = vec![0.0f32; block];
    let mut ports = AudioPorts::with_capacity(2, 1);
    let mut in_buf = EventBuffer::new();
    let mut out_buf = EventBuffer::new();
    let mut out = Vec::with_capacity(2 * total as usize);
    let mut pos = 0u64;
    while pos < total {
        let n = block.min((total - pos) as usize);
        in_buf.clear();
        while next_event < events.len() && events[next_event].0 < pos + n as u64 {
            let (t, e) = events[next_event];
            let time = (t - pos) as u32;
            match e {
                Scheduled::NoteOn(k) => in_buf.push(&NoteOnEvent::new(
                    time,
                    Pckn::new(0u16, 0u16, k as u16, k as u32),
                    o.velocity,
                )),
                Scheduled::NoteOff(k) => in_buf.push(&NoteOffEvent::new(
                    time,
                    Pckn::new(0u16, 0u16, k as u16, k as u32),
                    0.0,
                )),
                Scheduled::Midi(data) => in_buf.push(&MidiEvent::new(time, 0, data)),
            }
            next_event += 1;
        }
        if let Some(h) = hostile.as_mut() {
            h.push_events(&mut in_buf);
        }
        process_stereo(
            &mut proc,
            &mut ports,
            &in_buf,
            &mut out_buf,
            [&mut left[..n], &mut right[..n]],
            pos,
        )
        .map_err(|e| format!("process at frame {pos}: {e}"))?;
        for i in 0..n {
            out.push(left[i]);
            out.push(right[i]);
        }
        pos += n as u64;
        if let Some(h) = hostile.as_mut() {
            h.check(instance)?;
        }
        // The plugin may ask for main-thread callbacks (GUI-free here); run them between blocks.
        instance.call_on_main_thread_callback();
    }
    let stopped = proc.stop_processing();
    instance.deactivate(stopped);
    if let Some(h) = &hostile {
        println!("{}", h.summary());
    }
    Ok(out)
}

/// `render`: the whole session.
pub fn render(o: &RenderOptions) -> Result<(), String> {
    // SAFETY: loading a shared library runs its initialisers; the path is the plugin under test.
    let entry = unsafe { PluginEntry::load(&o.plugin) }
        .map_err(|e| format!("loading {}: {e:?}", o.plugin.display()))?;
    let factory = entry
        .get_plugin_factory()
        .ok_or("the entry has no plugin factory")?;
    let mut ids = Vec::new();
    for d in factory.plugin_descriptors() {
        let id = d.id().map(|s| s.to_owned()).unwrap_or_default();
        let name = d.name().map(|s| s.to_string_lossy().into_owned());
        println!("plugin {id:?} name {name:?}");
        ids.push(id);
    }
    let id = ids.first().ok_or("the factory lists no plugin")?.clone();

    let mut first = new_instance(&entry, &id)?;
    let params = list_params(&mut first)?;
    let now = values(&mut first, &params)?;
    let ext: PluginParams = first
        .plugin_handle()
        .get_extension()
        .ok_or("no params extension")?;
    println!(
        "{} parameters (CLAP id, name, CLAP range and default, current value as shown):",
        params.len()
    );
    for (p, v) in params.iter().zip(&now) {
        let shown = text_of(&ext, &mut first, p.id, *v)?;
        println!(
            "  {:>10} {:<24} [{}, {}] default {:.4} value {shown}",
            p.id.get(),
            p.name,
            p.min,
            p.max,
            p.default,
        );
    }
    if let Some(path) = &o.load_state {
        let ok = crate::state_load::load_state(&mut first, &params, path, &o.expects)?;
        if o.expect_load.is_some_and(|want| want != ok) {
            return Err(format!(
                "{}: the plugin {} the state, expected {}",
                path.display(),
                if ok { "accepted" } else { "refused" },
                if ok { "a refusal" } else { "it to load" }
            ));
        }
    }
    apply_sets(&mut first, &params, &o.sets)?;

    let mut instance = if o.state_roundtrip {
        let mut second = new_instance(&entry, &id)?;
        roundtrip_state(&mut first, &mut second, &params)?;
        drop(first);
        second
    } else {
        first
    };
    let t0 = std::time::Instant::now();
    let frames = perform(&mut instance, &params, o)?;
    let wall = t0.elapsed().as_secs_f64();
    println!(
        "rendered {:.3} s at {} Hz in blocks of {} in {:.3} s wall (real-time factor {:.2})",
        o.seconds,
        o.rate,
        o.block,
        wall,
        o.seconds / wall
    );
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: o.rate.round() as u32,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(&o.out, spec)
        .map_err(|e| format!("creating {}: {e}", o.out.display()))?;
    for &s in &frames {
        w.write_sample(s).map_err(|e| format!("writing WAV: {e}"))?;
    }
    w.finalize().map_err(|e| format!("writing WAV: {e}"))?;
    println!("wrote {}", o.out.display());
    if o.hostile_automation {
        // After the WAV is written, so a failing render can be inspected.
        println!("{}", crate::hostile::check_output(&frames, 2, o.rate)?);
    }
    Ok(())
}
