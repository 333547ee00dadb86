//! The Noether standalone application: the plugin with its editor in a window, audio and MIDI
//! through JACK, ALSA (cpal/midir) or the dummy backend. `--help` lists the options
//! (`--backend jack|alsa|dummy`, `--sample-rate`, `--period-size`, `--midi-input`,
//! `--connect-jack-midi-input`, ...).

fn main() -> std::process::ExitCode {
    if nice_plug::nice_export_standalone::<noether_plugin::Noether>() {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
