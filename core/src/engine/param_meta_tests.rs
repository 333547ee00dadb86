//! Tests of the parameter table's metadata columns (`param_meta.rs`, `params.rs`): what each
//! instrument reads, the groups, the help texts.

use super::param_meta::{ParamGroup, Reads};
use super::params::{ParamId, ParamValues, PARAMS};

fn with(pairs: &[(ParamId, f32)]) -> ParamValues {
    let mut v = ParamValues::defaults();
    for &(id, x) in pairs {
        v.set(id, x).unwrap();
    }
    v
}

/// The choices that decide what an instrument reads, case by case (the editor's rows).
#[test]
fn each_instrument_reads_its_own_parameters() {
    use ParamId::*;
    let reads = |id: ParamId, v: &ParamValues| v.reads(id);
    let gong = ParamValues::defaults();
    assert!(!reads(ContactStiffness, &gong));
    assert!(!reads(PluckPosition, &gong));
    assert!(!reads(YoungsModulus, &gong));
    let custom = with(&[(Material, 4.0)]);
    assert!(reads(YoungsModulus, &custom));
    let sitar = with(&[(Model, 3.0)]);
    assert!(reads(BridgeCurvature, &sitar));
    assert!(!reads(StrikeDuration, &sitar));
    assert!(!reads(BridgeCurvature, &with(&[(Model, 4.0)])));
    assert!(reads(StrikeDuration, &gong));
    assert!(!reads(MalletSpeed, &gong));
    let mallet = with(&[(Exciter, 1.0)]);
    assert!(!reads(StrikeForce, &mallet));
    assert!(reads(MalletSpeed, &mallet));
    assert!(reads(MalletMass, &mallet));
    let wood = with(&[(Exciter, 1.0), (MalletHead, 4.0)]);
    assert!(!reads(MalletMass, &wood) && !reads(MalletHardness, &wood));
    assert!(reads(MalletHead, &wood));
    assert!(reads(Dome, &gong) && reads(Boss, &gong));
    let rect = with(&[(Model, 2.0)]);
    assert!(reads(Dome, &rect) && !reads(BossRadius, &rect) && reads(Aspect, &rect));
    assert!(!reads(Dome, &sitar) && !reads(Boss, &sitar) && !reads(Aspect, &gong));
    // A string's mallet choice is not a mallet.
    let plucked = with(&[(Model, 4.0), (Exciter, 1.0)]);
    assert!(!reads(MalletSpeed, &plucked) && !reads(StrikeForce, &plucked));
    // The drone reads its own rows, not a single string's nor a plate's, nor a point of a
    // body (its output is the bridge).
    let drone = with(&[(Model, 5.0)]);
    assert!(reads(Jivari, &drone) && reads(DroneLatch, &drone) && reads(Modes, &drone));
    assert!(!reads(Tension, &drone) && !reads(PluckPosition, &drone));
    assert!(reads(PluckAmplitude, &drone) && reads(PluckAmplitude, &sitar));
    assert!(!reads(StrikeForce, &drone) && !reads(Size, &drone));
    assert!(!reads(PickupLeftPos, &drone) && reads(PickupLeftPos, &sitar));
    assert!(!reads(Jivari, &sitar) && !reads(DroneCycle, &gong));
    // The sitar with its taraf: its own rows, the pluck's amplitude and tuning by ear, not the
    // drone's cycle nor a single string's.
    let taraf = with(&[(Model, 6.0)]);
    assert!(reads(SitarThaat, &taraf) && reads(TarafStrings, &taraf));
    assert!(reads(ChikariStroke, &taraf) && reads(DroneEar, &taraf) && reads(DroneEar, &drone));
    assert!(reads(PluckAmplitude, &taraf) && !reads(DroneCycle, &taraf));
    assert!(!reads(Tension, &taraf) && !reads(PickupLeftPos, &taraf) && !reads(Size, &taraf));
    assert!(!reads(SitarThaat, &drone) && !reads(SitarThaat, &sitar));
}

/// Every group has parameters, and the row's help names what it reads where it is not
/// read by every model (a cheap consistency check of the two columns).
#[test]
fn groups_and_help_agree_with_the_rows() {
    for g in ParamGroup::ALL {
        assert!(PARAMS.iter().any(|p| p.group == g), "{}", g.title());
    }
    for p in PARAMS {
        let help = p.help.to_lowercase();
        let named = match p.reads {
            Reads::All | Reads::Bodies => true,
            Reads::Drone => help.contains("drone"),
            Reads::Plates | Reads::CustomMaterial | Reads::Pulse => help.contains("plate"),
            Reads::CircularPlates => help.contains("circular"),
            Reads::RectPlate => help.contains("rectang"),
            Reads::Strings | Reads::Plucked => help.contains("string"),
            Reads::Sitar => help.contains("sitar"),
            Reads::SitarTaraf => help.contains("sitar with taraf"),
            Reads::Networks => help.contains("drone") && help.contains("sitar with taraf"),
            Reads::Mallet | Reads::CustomMallet => help.contains("mallet"),
        };
        assert!(
            named,
            "{}: {:?} but its help says {:?}",
            p.key, p.reads, p.help
        );
    }
}
