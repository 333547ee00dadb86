//! The CLAP side of the test host: load a plugin, make instances, list, read and show its
//! parameters, process stereo blocks and check their output events. The `render` command
//! built on it is `host_render.rs`.

use clack_extensions::params::{ParamInfoBuffer, ParamInfoFlags, PluginParams};
use clack_extensions::render::{PluginRender, RenderMode};
use clack_host::prelude::*;
use std::ffi::CString;

/// The host's shared handler: the test host runs everything on one thread, so restart, process
/// and callback requests need no action (main-thread callbacks are pumped between blocks).
pub(crate) struct Shared;

impl SharedHandler<'_> for Shared {
    fn request_restart(&self) {}
    fn request_process(&self) {}
    fn request_callback(&self) {}
}

/// The host type.
pub(crate) struct TestHost;

impl HostHandlers for TestHost {
    type Shared<'a> = Shared;
    type MainThread<'a> = ();
    type AudioProcessor<'a> = ();
}

/// One parameter as the plugin describes it.
#[derive(Debug, Clone)]
pub(crate) struct Param {
    pub id: ClapId,
    pub name: String,
    pub min: f64,
    pub max: f64,
    pub default: f64,
    /// Whether the parameter takes only whole CLAP values (`CLAP_PARAM_IS_STEPPED`).
    pub stepped: bool,
}

/// An activated instance and its audio processor, started (the set-up of the `expression`
/// and live `conform` cases). Main thread.
pub(crate) type Started = (
    PluginInstance<TestHost>,
    StartedPluginAudioProcessor<TestHost>,
);

/// Activates `inst` at `rate` for blocks of 1 to `max_frames` frames and starts processing
/// (the set-up of the `expression` and live `conform` cases). Main thread.
pub(crate) fn activate_started(
    mut inst: PluginInstance<TestHost>,
    rate: f64,
    max_frames: u32,
) -> Result<Started, String> {
    let config = PluginAudioConfiguration {
        sample_rate: rate,
        min_frames_count: 1,
        max_frames_count: max_frames,
    };
    let stopped = inst
        .activate(|_, _| (), config)
        .map_err(|e| format!("activate failed: {e:?}"))?;
    let proc = stopped
        .start_processing()
        .map_err(|e| format!("start_processing failed: {e:?}"))?;
    Ok((inst, proc))
}

/// A new instance of plugin `id` from `entry`, with the test host's identity, in CLAP's
/// offline render mode: the test host renders as a bounce does, so an activation waits for
/// the model and every render repeats bit for bit (a real-time activation returns at once and
/// plays silence until the model is built: [`new_realtime_instance`]).
pub(crate) fn new_instance(
    entry: &PluginEntry,
    id: &CString,
) -> Result<PluginInstance<TestHost>, String> {
    let mut instance = new_realtime_instance(entry, id)?;
    let render: PluginRender = instance
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP render extension")?;
    render
        .set(&instance.plugin_handle(), RenderMode::Offline)
        .map_err(|e| format!("setting the offline render mode: {e}"))?;
    Ok(instance)
}

/// A new instance of plugin `id` from `entry` in CLAP's default (real-time) render mode, as
/// a live host has it.
pub(crate) fn new_realtime_instance(
    entry: &PluginEntry,
    id: &CString,
) -> Result<PluginInstance<TestHost>, String> {
    let info = HostInfo::new(
        "noether-test-host",
        "Noether",
        "https://noether.invalid",
        "0.1.0",
    )
    .map_err(|e| format!("host info: {e:?}"))?;
    PluginInstance::<TestHost>::new(|_| Shared, |_| (), entry, id, &info)
        .map_err(|e| format!("creating the plugin instance: {e:?}"))
}

/// The parameters of `instance`, in the plugin's order.
pub(crate) fn list_params(instance: &mut PluginInstance<TestHost>) -> Result<Vec<Param>, String> {
    let handle = instance.plugin_handle();
    let params: PluginParams = handle
        .get_extension()
        .ok_or("the plugin has no CLAP params extension")?;
    let mut out = Vec::new();
    let mut buffer = ParamInfoBuffer::new();
    for i in 0..params.count(&handle) {
        let info = params
            .get_info(&handle, i, &mut buffer)
            .ok_or_else(|| format!("params.get_info({i}) failed"))?;
        out.push(Param {
            id: info.id,
            name: String::from_utf8_lossy(info.name).into_owned(),
            min: info.min_value,
            max: info.max_value,
            default: info.default_value,
            stepped: info.flags.contains(ParamInfoFlags::IS_STEPPED),
        });
    }
    Ok(out)
}

pub(crate) fn values(
    instance: &mut PluginInstance<TestHost>,
    params: &[Param],
) -> Result<Vec<f64>, String> {
    let handle = instance.plugin_handle();
    let ext: PluginParams = handle.get_extension().ok_or("no params extension")?;
    params
        .iter()
        .map(|p| {
            ext.get_value(&handle, p.id)
                .ok_or_else(|| format!("get_value({}) failed", p.name))
        })
        .collect()
}

/// The plugin's display text for `value` of parameter `id`.
pub(crate) fn text_of(
    ext: &PluginParams,
    instance: &mut PluginInstance<TestHost>,
    id: ClapId,
    value: f64,
) -> Result<String, String> {
    let mut buf = [0u8; 256];
    let text = ext
        .value_to_text(&instance.plugin_handle(), id, value, &mut buf)
        .map_err(|_| format!("value_to_text({}) failed", id.get()))?;
    Ok(String::from_utf8_lossy(text).into_owned())
}

/// Whether the plugin's display text `shown` of parameter `id` shows the requested `want`:
/// [`same_display_value`], or both texts read by the plugin's own `text_to_value` give the
/// same CLAP value within a relative 1e-3 (the display may use another unit than the request:
/// `Size=0.5` shows "50.00 cm", `Release T60=0.5` shows "500.0 ms").
pub(crate) fn shows_value(
    ext: &PluginParams,
    instance: &mut PluginInstance<TestHost>,
    id: ClapId,
    want: &str,
    shown: &str,
) -> bool {
    if same_display_value(want, shown) {
        return true;
    }
    let mut parse = |t: &str| {
        let c = CString::new(t).ok()?;
        ext.text_to_value(&instance.plugin_handle(), id, &c)
    };
    match (parse(want), parse(shown)) {
        (Some(a), Some(b)) => (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-9,
        _ => false,
    }
}

/// Whether the display text `shown` (first word, the number or the enumeration name) matches
/// the requested `want`: equal names, or numbers within a relative 1e-3 (the plugin prints four
/// significant digits, a rounding of at most 5e-4 relative; f32 storage adds 1e-7).
pub(crate) fn same_display_value(want: &str, shown: &str) -> bool {
    let w = want.trim();
    let s = shown.trim();
    match (
        w.parse::<f64>(),
        s.split_whitespace()
            .next()
            .and_then(|t| t.parse::<f64>().ok()),
    ) {
        (Ok(a), Some(b)) => (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-12,
        _ => s.eq_ignore_ascii_case(w) || s.to_lowercase().starts_with(&w.to_lowercase()),
    }
}

/// `Ok` if the plugin's output events of one `process` call are in time order (CLAP requires
/// it; clap-validator's `param-fuzz-modulation` caught note ends out of order), else an error
/// naming the two times.
pub(crate) fn events_in_order(out_buf: &EventBuffer) -> Result<(), String> {
    let mut last = 0;
    for e in out_buf.iter() {
        let t = e.header().time();
        if t < last {
            return Err(format!(
                "the plugin output an event at sample {t} after one at sample {last}"
            ));
        }
        last = t;
    }
    Ok(())
}

/// One `process` call of a started instance with no audio input, the events of `in_buf` and
/// the stereo output `out` (the output events buffer is cleared first), at steady time `pos`; fails if the output events are out of
/// time order ([`events_in_order`]).
/// Main thread, which plays the host's audio thread.
pub(crate) fn process_stereo(
    proc: &mut StartedPluginAudioProcessor<TestHost>,
    ports: &mut AudioPorts,
    in_buf: &EventBuffer,
    out_buf: &mut EventBuffer,
    out: [&mut [f32]; 2],
    pos: u64,
) -> Result<(), String> {
    out_buf.clear();
    let mut outputs = ports.with_output_buffers([AudioPortBuffer {
        latency: 0,
        channels: AudioPortBufferType::f32_output_only(out.into_iter()),
    }]);
    proc.process(
        &InputAudioBuffers::empty(),
        &mut outputs,
        &InputEvents::from_buffer(in_buf),
        &mut OutputEvents::from_buffer(out_buf),
        Some(pos),
        None,
    )
    .map_err(|e| format!("{e:?}"))?;
    events_in_order(out_buf)
}
