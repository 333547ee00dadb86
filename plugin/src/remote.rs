//! CLAP remote-control pages: what a hardware controller's eight knobs reach
//! (`clap.remote-controls`, nice-plug's [`ClapPlugin::remote_controls`]).
//!
//! The first section holds the knobs a player reaches for while playing, one page per
//! instrument family (a gong's strike and mallet, a string's pluck and bridge), eight each, in
//! the order of musical use; the second gives every host parameter a page, by the editor's
//! groups (the table's `group` column, [`ParamGroup`]), in the table's order (nice-plug splits a panel of more than eight
//! into numbered pages). Built on the main thread when the host asks; no state.

use crate::params::{NoetherParams, Slot};
use nice_plug::prelude::*;
use noether_core::engine::{ParamGroup, ParamId, PARAMS};

/// The playing pages: name and eight parameters each.
pub const PLAYING_PAGES: [(&str, [ParamId; 8]); 3] = [
    (
        "Gong and plate",
        [
            ParamId::Gain,
            ParamId::DampingScale,
            ParamId::ReleaseT60,
            ParamId::StrikeRadius,
            ParamId::MalletHardness,
            ParamId::MalletMass,
            ParamId::VelocityCurve,
            ParamId::ModWheelDepth,
        ],
    ),
    (
        "String",
        [
            ParamId::Gain,
            ParamId::DampingScale,
            ParamId::ReleaseT60,
            ParamId::PluckPosition,
            ParamId::PluckAmplitude,
            ParamId::Tension,
            ParamId::BridgePosition,
            ParamId::ContactStiffness,
        ],
    ),
    (
        "Pickups and band",
        [
            ParamId::PickupLeftPos,
            ParamId::PickupLeftAngle,
            ParamId::PickupRightPos,
            ParamId::PickupRightAngle,
            ParamId::LowCut,
            ParamId::BandLimit,
            ParamId::BandAbove,
            ParamId::Closure,
        ],
    ),
];

/// Defines the pages on `context` (main thread).
pub fn define(params: &NoetherParams, context: &mut impl RemoteControlsContext) {
    let add = |page: &mut _, id: ParamId| add_slot(page, params.slot(id));
    context.add_section("Play", |section| {
        for (name, ids) in PLAYING_PAGES {
            section.add_page(name, |page| {
                for id in ids {
                    add(page, id);
                }
            });
        }
    });
    context.add_section("All parameters", |section| {
        for g in ParamGroup::ALL {
            section.add_page(g.title(), |page| {
                for info in PARAMS.iter().filter(|i| i.group == g) {
                    add(page, info.id);
                }
            });
        }
    });
}

fn add_slot(page: &mut impl RemoteControlsPage, slot: &Slot) {
    match slot {
        Slot::Float(p) => page.add_param(p),
        Slot::Int(p) => page.add_param(p),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records the pages as `(section, page, parameter names)`.
    #[derive(Default)]
    struct Pages(Vec<(String, String, Vec<String>)>);
    struct Page(Vec<String>);

    impl RemoteControlsContext for Pages {
        type Section = Self;
        fn add_section(&mut self, name: impl Into<String>, f: impl FnOnce(&mut Self)) {
            let before = self.0.len();
            f(self);
            let name = name.into();
            for p in &mut self.0[before..] {
                p.0 = name.clone();
            }
        }
    }
    impl RemoteControlsSection for Pages {
        type Page = Page;
        fn add_page(&mut self, name: impl Into<String>, f: impl FnOnce(&mut Page)) {
            let mut page = Page(Vec::new());
            f(&mut page);
            self.0.push((String::new(), name.into(), page.0));
        }
    }
    impl RemoteControlsPage for Page {
        fn add_param(&mut self, param: &impl Param) {
            self.0.push(param.name().to_string());
        }
        fn add_spacer(&mut self) {
            self.0.push(String::new());
        }
    }
    /// Three playing pages of eight, each parameter once per page; every engine parameter on
    /// exactly one page of the second section.
    #[test]
    fn pages_reach_every_parameter() {
        let params = NoetherParams::default();
        let mut pages = Pages::default();
        define(&params, &mut pages);
        let play: Vec<_> = pages.0.iter().filter(|p| p.0 == "Play").collect();
        assert_eq!(play.len(), 3);
        for (_, name, ps) in &play {
            assert_eq!(ps.len(), 8, "{name}");
            let mut unique = ps.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), 8, "{name}: {ps:?}");
        }
        let mut all: Vec<String> = pages
            .0
            .iter()
            .filter(|p| p.0 == "All parameters")
            .flat_map(|p| p.2.clone())
            .collect();
        assert_eq!(all.len(), PARAMS.len());
        all.sort();
        all.dedup();
        assert_eq!(all.len(), PARAMS.len(), "each parameter once");
    }
}
