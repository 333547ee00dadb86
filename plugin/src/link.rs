//! The editor's side of the engine: the [`EngineHandle`] (telemetry and GUI commands, build
//! status) behind a mutex that only the GUI and main threads take; the audio thread never
//! touches it (it talks to the handle through the engine's lock-free queues).

use noether_core::engine::{EngineHandle, EventKind, GuiCommand, Telemetry};
use std::sync::Mutex;

/// Shared between the plugin (which created the engine) and the editor.
pub struct EngineLink {
    handle: Mutex<EngineHandle>,
}

impl EngineLink {
    /// Wraps the handle returned by `Engine::new`.
    pub fn new(handle: EngineHandle) -> Self {
        Self {
            handle: Mutex::new(handle),
        }
    }

    /// Updates `into` with the newest telemetry frame if one arrived, and its `rebuilding`
    /// flag from the worker's status (immediate, even when the audio thread is idle).
    /// Returns the last model-build error, if any. GUI thread.
    pub fn latest_telemetry(&self, into: &mut Telemetry) -> Option<String> {
        let Ok(mut h) = self.handle.lock() else {
            return Some("engine link poisoned".to_string());
        };
        if let Some(t) = h.telemetry() {
            *into = t;
        }
        into.rebuilding = h.is_rebuilding();
        h.last_error()
    }

    /// Stops every voice at once (the editor's panic button). GUI thread.
    pub fn all_sound_off(&self) {
        if let Ok(mut h) = self.handle.lock() {
            // A full queue (256 commands pending) means the audio thread is not running;
            // dropping the command then is harmless.
            let _ = h.send(GuiCommand::Event(EventKind::AllSoundOff));
        }
    }

    /// Sends a note event from the editor's keyboard (applied at the audio thread's
    /// next block start). GUI thread.
    pub fn note(&self, kind: EventKind) {
        if let Ok(mut h) = self.handle.lock() {
            let _ = h.send(GuiCommand::Event(kind));
        }
    }

    /// Chooses the voice shown by the spectrum and displacement views (`None`: the loudest).
    pub fn watch(&self, voice: Option<u8>) {
        if let Ok(mut h) = self.handle.lock() {
            let _ = h.send(GuiCommand::Watch(voice));
        }
    }
}
