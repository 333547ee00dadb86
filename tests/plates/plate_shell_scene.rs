//! Curved plates in scenes (`plate.imperfection`, `core/src/models/plate/rest_shape.rs`): the
//! projection of the rest shapes against independent computations, rise 0 as the flat plate
//! bit for bit, and the errors bad shapes get.

use noether::modal::circular::{CircularEdge, PlateModes};
use noether::modal::shell::Imperfection;
use noether::modal::CircularPlateSpec;
use noether::models::plate::basis::{BasisKey, ModalCache};
use noether::models::plate::rest_projection::project;
use noether::models::plate::rest_shape::ShapePart;
use noether::models::plate::voice::PlateVoice;
use noether::render::source::RenderSource;
use noether::scene::plate::{PlateShape, Symmetry};
use noether::scene::Scene;

/// A small gong scene (0.3 m, 1 mm steel, 40 × 12 strike-mirror modes, 32 kHz, mallet),
/// with `imperfection` as the TOML value of `plate.imperfection` (empty: none).
fn gong(imperfection: &str) -> Scene {
    let shape = if imperfection.is_empty() {
        String::new()
    } else {
        format!("imperfection = {imperfection}\n")
    };
    let text = format!(
        r#"
[output]
sample_rate = 32000
seconds = 0.05
[plate]
shape = "circular-free"
radius = 0.3
thickness = 0.001
n_phi = 40
n_psi = 12
symmetry = "strike-mirror"
sim_rate = 32000
scheme = "conservative-exact"
damping = {{ law = "power", a = 0.005, b = 0.6 }}
excitation = {{ kind = "mallet", at = {{ r = 0.3, angle = 0.0 }}, head = "hard-felt", speed = 3.0 }}
{shape}"#
    );
    Scene::from_toml(&text, "test", &[]).unwrap()
}

fn render(scene: &Scene, frames: usize) -> Vec<Vec<f64>> {
    let mut v = PlateVoice::build(scene.plate.as_ref().unwrap()).unwrap();
    let mut out = vec![vec![0.0; frames]; v.channels()];
    v.process(&mut out, frames);
    out
}

/// A cap of rise 0 is the flat plate bit for bit (the model runs the flat arithmetic when the
/// rest shape is zero); a cap of 2 thicknesses changes the sound (so the comparison can fail).
#[test]
fn rise_zero_is_the_flat_plate_bit_for_bit() {
    let flat = render(&gong(""), 1600);
    let zero = render(&gong(r#"{ kind = "spherical", rise = 0.0 }"#), 1600);
    assert_eq!(flat, zero);
    let curved = render(&gong(r#"{ kind = "spherical", rise = 0.002 }"#), 1600);
    let diff = flat[0]
        .iter()
        .zip(&curved[0])
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let peak = flat[0].iter().fold(0.0f64, |m, a| m.max(a.abs()));
    println!(
        "cap of 2 mm vs flat: largest difference {:.3} of the peak",
        diff / peak
    );
    assert!(diff > 0.05 * peak, "{diff} vs {peak}");
}

/// The scene's projection of a spherical cap equals `Imperfection::project` of the shell
/// module (a separate radial quadrature, in thickness units: `a = L h ã`) to 1e-12 relative
/// (two Gauss-Legendre rules of different sizes on a smooth integrand: round-off). Radius
/// 0.3 m, h = 1 mm, rise 5 mm (κ = 10).
#[test]
fn cap_projection_matches_the_shell_modules() {
    let key = BasisKey::new(
        PlateShape::CircularFree,
        0.3,
        1.0,
        40,
        12,
        Symmetry::StrikeMirror,
    )
    .unwrap();
    let basis = ModalCache::default().basis(&key).unwrap();
    let cap = [ShapePart::Spherical {
        rise: Some(0.005),
        curvature_radius: None,
    }];
    let a = project(&cap, &basis, PlateShape::CircularFree, 0.3, 1.0);
    let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 40, 12, None)
        .unwrap()
        .mirror_symmetric();
    let modes = PlateModes::build(&spec).unwrap();
    let shell = Imperfection::from_rise(0.005, 0.3, 0.001)
        .unwrap()
        .project(&modes);
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(&shell)
        .fold(0.0f64, |m, (x, y)| m.max((x - 0.3 * 0.001 * y).abs()));
    println!(
        "cap projection vs the shell module: {:.2e} of the largest",
        worst / scale
    );
    assert!(scale > 1e-6 && worst < 1e-12 * scale, "{worst} / {scale}");
    // The same cap given by its curvature radius R = a²/2H = 9 m.
    let by_r = project(
        &[ShapePart::Spherical {
            rise: None,
            curvature_radius: Some(9.0),
        }],
        &basis,
        PlateShape::CircularFree,
        0.3,
        1.0,
    );
    for (x, y) in a.iter().zip(&by_r) {
        assert!((x - y).abs() <= 1e-14 * scale);
    }
}

/// A boss (`cos²` bump of radius 0.25) against the same shape given as a 201-point linear
/// profile: linear interpolation errs by at most `Δr²/8 · max|w0''| = Δr²/8 · (H/2)(π/b)²`
/// = 2.5e-4 H (Δr = 0.005, b = 0.25), so the projections agree to 3e-4 of the largest
/// coefficient (measured 1.4e-4); a boss of the wrong radius (0.26) is off by 6.8e-2.
#[test]
fn boss_projection_matches_a_fine_profile() {
    let key = BasisKey::new(PlateShape::CircularFree, 0.3, 1.0, 60, 12, Symmetry::Full).unwrap();
    let basis = ModalCache::default().basis(&key).unwrap();
    let (rise, b) = (0.004, 0.25);
    let boss = ShapePart::Boss { rise, radius: b };
    let points: Vec<[f64; 2]> = (0..=200)
        .map(|i| {
            let r = i as f64 / 200.0;
            [r, boss.height(r, 0.3)]
        })
        .collect();
    let profile = ShapePart::Profile { points };
    let a = project(&[boss], &basis, PlateShape::CircularFree, 0.3, 1.0);
    let p = project(&[profile], &basis, PlateShape::CircularFree, 0.3, 1.0);
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(&p)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let wrong = project(
        &[ShapePart::Boss { rise, radius: 0.26 }],
        &basis,
        PlateShape::CircularFree,
        0.3,
        1.0,
    );
    let off = a
        .iter()
        .zip(&wrong)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    println!(
        "boss vs 201-point profile: {:.2e}; boss of radius 0.26: {:.2e} (of the largest)",
        worst / scale,
        off / scale
    );
    assert!(worst < 3e-4 * scale && off > 1e-2 * scale);
    // Axisymmetric: only modes without nodal diameters get a coefficient.
    for (k, x) in a.iter().enumerate() {
        if basis.cosine_order(k) != Some(0) {
            assert_eq!(*x, 0.0, "mode {k}");
        }
    }
}

/// Bad shapes are refused with the field, the value and what is allowed.
#[test]
fn bad_shapes_are_refused_with_the_field_named() {
    let scene = |shape: &str| {
        let text = gong("").plate.unwrap();
        let mut t = toml::Table::try_from(Scene {
            plate: Some(text),
            ..gong("")
        })
        .unwrap();
        let v: toml::Value = toml::from_str(&format!("x = {shape}")).unwrap();
        let plate = t.get_mut("plate").unwrap().as_table_mut().unwrap();
        plate.insert("imperfection".into(), v.get("x").unwrap().clone());
        Scene::from_toml(&toml::to_string(&t).unwrap(), "test", &[])
            .unwrap_err()
            .to_string()
    };
    let cases = [
        (r#"{ kind = "spherical" }"#, "plate.imperfection[0].rise"),
        (
            r#"{ kind = "spherical", rise = 0.01, curvature_radius = 3.0 }"#,
            "exactly one of rise",
        ),
        (
            r#"{ kind = "spherical", rise = 0.6 }"#,
            "plate.imperfection[0].rise",
        ),
        (
            r#"{ kind = "boss", rise = 0.01, radius = 0.0 }"#,
            "plate.imperfection[0].radius",
        ),
        (r#"{ kind = "dome", rise = 0.01 }"#, "on circular plates"),
        (
            r#"[{ kind = "spherical", rise = 0.01 }, { kind = "profile", points = [[0.0, 0.0], [0.5, 0.1], [0.4, 0.0], [1.0, 0.0]] }]"#,
            "plate.imperfection[1].points[2].r",
        ),
        (
            r#"{ kind = "profile", points = [[0.1, 0.0], [1.0, 0.0]] }"#,
            "r from 0 (the centre) to 1",
        ),
        (
            r#"{ kind = "modal", coefficients = [] }"#,
            "1 to n_phi = 40",
        ),
        (r#"{ kind = "wobbly" }"#, "imperfection"),
    ];
    for (shape, want) in cases {
        let e = scene(shape);
        assert!(e.contains(want), "{shape}: {e}");
    }
}
