//! Noether as an instrument: a nice-plug CLAP and VST3 plugin and a standalone application
//! around the `noether` engine ([`noether_core::engine`]), with an egui editor.
//!
//! This crate is glue only. The engine owns the physics, the voice pool, the worker thread that
//! builds voice banks and the resampling to the host rate; this crate
//! - mirrors the engine's parameter table as host parameters ([`params`]),
//! - translates host note and MIDI events into sample-accurate engine events ([`midi`]),
//! - connects the editor to the engine's telemetry and command queues ([`link`]),
//! - ships the factory presets ([`presets`]), keeps the user's presets ([`user_presets`]), the
//!   current preset and the A/B compare slots ([`preset_state`], [`preset_ops`]), and the editor
//!   ([`editor`]),
//! - makes any saved state it is given load to a defined, reported state ([`state`]),
//! - saves the Scala tuning with the state and publishes its key table ([`tuning`]).
//!
//! Threads: `process` runs on the host's audio thread (no allocation, lock or I/O: parameters
//! are copied into atomics, events into a preallocated buffer); `activate` and the editor run
//! on the host's main and GUI threads.

pub mod bypass;
pub mod editor;
#[cfg(test)]
pub(crate) mod fake_host;
pub mod format;
pub mod link;
pub mod midi;
pub mod params;
pub mod poly;
pub mod preset_ops;
pub mod preset_state;
pub mod presets;
pub mod remote;
pub mod state;
pub mod tuning;
pub mod user_presets;

use editor::EditorApp;
use link::EngineLink;
use nice_plug::prelude::*;
use nice_plug_egui::{create_egui_editor, EguiEditor, EguiNiceSettings, RepaintNotifier};
use noether_core::engine::{Engine, Event, SharedParams};
use params::NoetherParams;
use std::num::NonZeroU32;
use std::sync::Arc;
use std::time::Duration;

/// Longest wait per chunk for the voice pool's jobs in an offline bounce (the engine's offline
/// renders use the same bound): long enough for any job, bounded all the same.
const OFFLINE_JOB_WAIT: Duration = Duration::from_secs(10);

/// nice-plug's input event queues (note events, and every parameter change in VST3), sized
/// at the plugin's creation: 8192 events in one (sub-)block, eight times nice-plug's default
/// of 1024, which pluginval's automation tests overflowed (the queue then grows on the audio
/// thread). The test host's `conform` case `load` sends 6000 in a block and fails on any
/// overflow nice-plug logs. About 0.5 MB per instance.
const INPUT_EVENTS: usize = 8192;

/// Engine events one (sub-)block can produce: a note's event and its per-note modulation for
/// every input event; beyond it, events are dropped, never reallocated (`midi`, `poly`).
const EVENT_CAPACITY: usize = 2 * INPUT_EVENTS;
/// The most voices a bank holds (the `polyphony` parameter's maximum): the host's voice
/// capacity for polyphonic modulation.
const MAX_VOICES: u32 = 16;

/// The plugin instance (one per host instance).
pub struct Noether {
    /// Host parameters mirroring the engine's table (host, GUI and audio threads).
    params: Arc<NoetherParams>,
    /// The engine's parameter atomics; the audio thread writes them from `params` every block.
    shared: Arc<SharedParams>,
    /// The editor application until the host asks for the editor (then moved into it).
    editor_app: Option<EditorApp>,
    /// Wakes the editor when a telemetry frame is ready (audio thread: an atomic store).
    repaint: RepaintNotifier,
    /// The engine (audio thread; `activate`/`deactivate` on the main thread). It makes no
    /// sound before the first `activate`.
    engine: Engine,
    /// Engine events of the current block, preallocated to [`EVENT_CAPACITY`].
    events: Vec<Event>,
    /// Which key sounds on which MIDI channel, MPE zones and bends (audio thread).
    midi: midi::MidiMap,
    /// The host's notes, their polyphonic modulation and their ends (audio thread).
    poly: poly::PolyVoices,
    /// The bypass fade (audio thread; its rate set in `activate`).
    bypass: bypass::BypassFade,
}

impl Default for Noether {
    fn default() -> Self {
        let params = Arc::new(NoetherParams::default());
        let shared = params.engine.clone();
        params.sync_to_engine(&shared);
        let (engine, handle) = Engine::new(shared.clone());
        let link = Arc::new(EngineLink::new(handle));
        let presets = Arc::new(presets::factory_presets());
        let editor_app = Some(EditorApp::new(params.clone(), link, presets));
        Self {
            params,
            shared,
            editor_app,
            repaint: RepaintNotifier::new(),
            engine,
            events: Vec::with_capacity(EVENT_CAPACITY),
            midi: midi::MidiMap::default(),
            poly: poly::PolyVoices::default(),
            bypass: bypass::BypassFade::default(),
        }
    }
}

impl Plugin for Noether {
    const NAME: &'static str = "Noether";
    const VENDOR: &'static str = "Noether";
    const URL: &'static str = "https://noether.invalid";
    const EMAIL: &'static str = "noether@noether.invalid";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");

    const AUDIO_IO_LAYOUTS: &'static [AudioIOLayout] = &[AudioIOLayout {
        main_input_channels: None,
        main_output_channels: NonZeroU32::new(2),
        aux_input_ports: &[],
        aux_output_ports: &[],
        names: PortNames::const_default(),
    }];

    const MIDI_INPUT: MidiConfig = MidiConfig::MidiCCs;
    const SAMPLE_ACCURATE_AUTOMATION: bool = true;
    const INPUT_EVENT_CAPACITY: usize = INPUT_EVENTS;

    type Editor = EguiEditor<EditorApp>;
    type SysExMessage = ();
    type BackgroundTask = ();

    fn params(&self) -> Arc<dyn Params> {
        self.params.clone()
    }

    /// Runs before nice-plug loads a parsed state (main thread): [`state::repair`] fills,
    /// clamps, converts or drops every bad value and each change is logged as an error.
    fn filter_state(state: &mut PluginState) {
        for issue in state::repair(state, Self::VERSION) {
            nice_error!("{issue}");
        }
    }

    fn editor(&mut self, _async_executor: AsyncExecutor<Self>) -> Option<Self::Editor> {
        let app = self.editor_app.take()?;
        create_egui_editor(
            self.params.editor_state.clone(),
            self.repaint.clone(),
            EguiNiceSettings::new().with_tile("Noether"),
            app,
        )
    }

    fn activate(
        &mut self,
        _audio_io_layout: &AudioIOLayout,
        buffer_config: &BufferConfig,
        context: &mut impl ActivateContext<Self>,
    ) -> bool {
        // The host may have restored a state since the last block: build the first bank for it.
        self.params.sync_to_engine(&self.shared);
        let max_block = buffer_config.max_buffer_size.max(1) as usize;
        // An offline bounce (the host's freewheeling render) waits for every voice job, so no
        // voice's chunk is left out as late and a bounce repeats bit for bit; in real time the
        // wait is the chunk's duration (the engine's default).
        self.engine.set_job_wait(
            (buffer_config.process_mode == ProcessMode::Offline).then_some(OFFLINE_JOB_WAIT),
        );
        let rate = f64::from(buffer_config.sample_rate);
        self.bypass.set_rate(rate);
        // A real-time activation never waits for a model build (it runs on the host's main
        // thread): the worker builds in the background and the last good model of this
        // instance plays meanwhile, or silence (the editor says which). An offline bounce waits
        // for the model, so it repeats bit for bit.
        // The CPU governor keeps a live host's blocks in time; a bounce keeps every note's
        // full band (and repeats).
        let offline = buffer_config.process_mode == ProcessMode::Offline;
        self.engine.set_governor(!offline);
        let activated = if offline {
            self.engine.activate(rate, max_block).map(|refused| {
                if let Some(e) = refused {
                    // The editor shows the same message (the engine handle's last error).
                    nice_error!("{e}: the last model that could be built keeps playing");
                }
            })
        } else {
            self.engine.activate_realtime(rate, max_block)
        };
        match activated {
            Ok(()) => {
                context.set_latency_samples(self.engine.latency_samples());
                true
            }
            Err(e) => {
                nice_error!("the engine refused the host configuration: {e}");
                false
            }
        }
    }

    fn deactivate(&mut self) {
        self.engine.deactivate();
    }

    fn reset(&mut self) {
        self.engine.reset();
        self.midi.reset();
        self.poly.reset();
        self.bypass.reset(self.params.bypass.value());
    }

    fn process(
        &mut self,
        buffer: &mut Buffer,
        _aux: &mut AuxiliaryBuffers,
        context: &mut impl ProcessContext<Self>,
    ) -> ProcessStatus {
        self.params.sync_to_engine(&self.shared);
        // The host's tempo, for a drone whose cycle follows it (none: its own period).
        self.engine.set_host_tempo(context.transport().tempo);
        self.events.clear();
        // Output events must leave in time order (CLAP requires it): each note end is sent at
        // its input event's time or the latest time already sent, whichever is later (a host
        // may deliver input events out of order).
        let mut sent_at = 0u32;
        while let Some(event) = context.next_event() {
            self.midi.translate(&event, &mut self.events);
            self.poly
                .observe(&event, &self.params, &mut self.events, |e| {
                    sent_at = sent_at.max(event.timing());
                    // A host with no output event list gets no note ends.
                    let _ = context.try_send_event(poly::terminated(sent_at, e));
                });
        }
        let [left, right] = buffer.as_slice() else {
            return ProcessStatus::Error("the plugin needs a stereo output");
        };
        self.engine.process_events(&self.events, left, right);
        self.bypass.apply(self.params.bypass.value(), left, right);
        let last = (left.len() as u32).saturating_sub(1).max(sent_at);
        self.poly.end_voices(self.engine.sounding_keys(), |e| {
            let _ = context.try_send_event(poly::terminated(last, e));
        });
        if self.params.editor_state.is_open() {
            self.repaint.request_repaint();
        }
        ProcessStatus::KeepAlive
    }
}

impl ClapPlugin for Noether {
    const CLAP_ID: &'static str = "org.noether.noether";
    const CLAP_DESCRIPTION: Option<&'static str> =
        Some("Physical-model gongs, plates, sitar and tanpura with energy-conserving schemes");
    const CLAP_MANUAL_URL: Option<&'static str> = None;
    const CLAP_SUPPORT_URL: Option<&'static str> = None;
    /// One voice per key (`crate::poly`): a new note on a sounding key takes its voice over.
    const CLAP_POLY_MODULATION_CONFIG: Option<PolyModulationConfig> = Some(PolyModulationConfig {
        max_voice_capacity: MAX_VOICES,
        supports_overlapping_voices: false,
    });
    const CLAP_FEATURES: &'static [ClapFeature] = &[
        ClapFeature::Instrument,
        ClapFeature::Synthesizer,
        ClapFeature::Stereo,
    ];

    fn remote_controls(&self, context: &mut impl RemoteControlsContext) {
        remote::define(&self.params, context);
    }
}

impl Vst3Plugin for Noether {
    const VST3_CLASS_ID: [u8; 16] = *b"NoetherPhysModel";
    const VST3_SUBCATEGORIES: &'static [Vst3SubCategory] =
        &[Vst3SubCategory::Instrument, Vst3SubCategory::Synth];
}

nice_export_clap!(Noether);
nice_export_vst3!(Noether);
