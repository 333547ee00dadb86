//! Factory presets for the editor's menu: the engine's embedded `assets/presets/*.toml`
//! ([`Preset::factory`]) resolved to full parameter sets once, at plugin construction (main
//! thread). A preset whose values the engine refuses is left out and logged.

use nice_plug::prelude::*;
use noether_core::engine::{ParamValues, Preset};

/// A factory preset ready to apply.
#[derive(Debug, Clone)]
pub struct FactoryPreset {
    /// File stem in `assets/presets/`.
    pub stem: &'static str,
    /// Display name.
    pub name: String,
    /// What it is (shown as a tooltip).
    pub description: String,
    /// Every parameter's value (defaults where the file names none).
    pub values: ParamValues,
}

/// The factory presets in the engine's order.
pub fn factory_presets() -> Vec<FactoryPreset> {
    Preset::factory()
        .into_iter()
        .filter_map(|(stem, p)| match p.values() {
            Ok(values) => Some(FactoryPreset {
                stem,
                name: p.name.clone(),
                description: p.description.clone(),
                values,
            }),
            Err(e) => {
                nice_error!("factory preset {stem} refused: {e}");
                None
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use noether_core::engine::PARAMS;

    /// Every embedded factory preset resolves (none is dropped), includes the lecture's gong
    /// and both strings, and lies inside the host parameters' ranges.
    #[test]
    fn every_factory_preset_resolves() {
        let presets = factory_presets();
        assert_eq!(presets.len(), Preset::factory().len());
        for stem in ["gong-40N", "gong-80N", "rect-plate", "sitar", "tanpura"] {
            assert!(presets.iter().any(|p| p.stem == stem), "missing {stem}");
        }
        for p in &presets {
            for info in PARAMS {
                let v = p.values.get(info.id);
                assert!(
                    (info.min..=info.max).contains(&v),
                    "{}: {} = {v} outside [{}, {}]",
                    p.stem,
                    info.key,
                    info.min,
                    info.max
                );
            }
        }
    }
}
