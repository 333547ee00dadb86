//! `render --load-state FILE`: load a saved state stream into the plugin through the CLAP
//! `state` extension, as a host restoring a project does, and check the instance is in a
//! defined state afterwards.
//!
//! `FILE` holds the bytes a host stores for the plugin: for nice-plug an 8-byte little-endian
//! length followed by the JSON state (`plugin/ci/state_blobs.sh` writes good and bad ones).
//! Checks: every parameter value finite and inside its CLAP range; a refused load leaves every
//! value as it was; the `--expect NAME=VALUE` display values hold. The plugin's own log
//! (stderr) names what it repaired.

use crate::host::{shows_value, text_of, values, Param, TestHost};
use clack_extensions::params::PluginParams;
use clack_extensions::state::PluginState;
use clack_host::prelude::*;
use std::path::Path;

/// Loads `path` into `instance` (inactive), prints the parameters that changed, runs the
/// checks above; returns whether the plugin accepted the state.
pub fn load_state(
    instance: &mut PluginInstance<TestHost>,
    params: &[Param],
    path: &Path,
    expects: &[(String, String)],
) -> Result<bool, String> {
    let blob = std::fs::read(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let before = values(instance, params)?;
    let state: PluginState = instance
        .plugin_handle()
        .get_extension()
        .ok_or("the plugin has no CLAP state extension")?;
    let accepted = state
        .load(&instance.plugin_handle(), &mut blob.as_slice())
        .is_ok();
    let after = values(instance, params)?;
    let ext: PluginParams = instance
        .plugin_handle()
        .get_extension()
        .ok_or("no params extension")?;
    let mut changed = 0;
    for ((p, x), y) in params.iter().zip(&before).zip(&after) {
        if !(y.is_finite() && (p.min..=p.max).contains(y)) {
            return Err(format!(
                "after loading {}: `{}` = {y} outside its CLAP range {}..={}",
                path.display(),
                p.name,
                p.min,
                p.max
            ));
        }
        if x != y {
            if !accepted {
                return Err(format!(
                    "{} was refused but changed `{}` from {x} to {y}",
                    path.display(),
                    p.name
                ));
            }
            changed += 1;
            let shown = text_of(&ext, instance, p.id, *y)?;
            println!("  {} -> {shown}", p.name);
        }
    }
    for (name, want) in expects {
        let (p, y) = params
            .iter()
            .zip(&after)
            .find(|(p, _)| p.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| format!("--expect: no parameter named `{name}`"))?;
        let shown = text_of(&ext, instance, p.id, *y)?;
        if !shows_value(&ext, instance, p.id, want, &shown) {
            return Err(format!(
                "after loading {}: `{name}` shows `{shown}`, expected `{want}`",
                path.display()
            ));
        }
    }
    println!(
        "state {}: {} bytes, {}, {changed} parameters changed, all {} finite and in range",
        path.display(),
        blob.len(),
        if accepted { "loaded" } else { "refused" },
        params.len()
    );
    Ok(accepted)
}
