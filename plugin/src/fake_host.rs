//! A fake host for the tests: a [`GuiContextInner`] that records every gesture and stores each
//! normalized value into the parameter the way nice-plug's wrappers do with a GUI change.

use nice_plug::context::gui::GuiContextInner;
use nice_plug::context::PluginApi;
use nice_plug::params::internals::ParamPtr;
use nice_plug::plugin::PluginState;
use std::sync::Mutex;

/// A host: applies normalized values at once and logs `(gesture, parameter name)`.
#[derive(Default)]
pub(crate) struct FakeHost {
    log: Mutex<Vec<(char, String)>>,
}

impl FakeHost {
    fn record(&self, kind: char, param: ParamPtr) {
        // SAFETY: the parameters outlive the host in every test.
        let name = unsafe { param.name() }.to_string();
        self.log.lock().unwrap().push((kind, name));
    }

    /// The gestures since the last call, as `(b|s|e, parameter name)`.
    pub(crate) fn take(&self) -> Vec<(char, String)> {
        std::mem::take(&mut *self.log.lock().unwrap())
    }
}

impl GuiContextInner for FakeHost {
    fn plugin_api(&self) -> PluginApi {
        PluginApi::Clap
    }
    unsafe fn raw_begin_set_parameter(&self, param: ParamPtr) {
        self.record('b', param);
    }
    unsafe fn raw_set_parameter_normalized(&self, param: ParamPtr, normalized: f32) {
        self.record('s', param);
        // SAFETY: as above; this is what the wrappers do with a GUI change.
        unsafe { param._internal_set_normalized_value(normalized) };
    }
    unsafe fn raw_end_set_parameter(&self, param: ParamPtr) {
        self.record('e', param);
    }
    fn get_state(&self) -> PluginState {
        PluginState {
            version: String::new(),
            params: Default::default(),
            fields: Default::default(),
        }
    }
    fn set_state(&self, _state: PluginState) {}
    fn request_restart(&self) {}
}
