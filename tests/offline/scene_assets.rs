//! Every shipped scene parses and validates, and its modal counts are the lecture's.

use noether::scene::Scene;

#[test]
fn every_asset_scene_is_valid() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes"));
    let mut count = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let s = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert!(!s.name.is_empty());
            count += 1;
        }
    }
    assert!(count >= 9, "{count} scenes");
    let gong = Scene::load(&dir.join("seed-gong-80N.toml"), &[]).unwrap();
    let p = gong.plate.unwrap();
    assert_eq!((p.n_phi, p.sim_rate), (1000, 40000.0));
    // The lecture's string scenes: L = 1 m, d = 0.43 mm, T = 180.5 N, mu = 1.17e-3 kg/m,
    // B = 2e-5 (0 for -b0), K = 1e13, alpha = 1.5, fs = 2 MHz, damped.
    for (file, b) in [
        ("seed-sitar.toml", 2e-5),
        ("seed-tanpura.toml", 2e-5),
        ("seed-tanpura-b0.toml", 0.0),
    ] {
        let s = Scene::load(&dir.join(file), &[]).unwrap().string.unwrap();
        assert_eq!(
            (s.length, s.diameter, s.tension, s.linear_density),
            (1.0, 0.43e-3, 180.5, 1.17e-3),
            "{file}"
        );
        assert_eq!(s.inharmonicity, Some(b), "{file}");
        assert_eq!((s.contact.stiffness, s.contact.exponent), (1e13, 1.5));
        assert_eq!(s.sim_rate, 2e6);
        assert!(s.losses != Default::default(), "{file} is lossless");
    }
    let musical = Scene::load(&dir.join("sitar.toml"), &[]).unwrap();
    assert_eq!(musical.string.unwrap().sim_rate, 8.0 * 48_000.0);
}
