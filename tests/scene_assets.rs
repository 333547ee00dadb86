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
    assert!(count >= 5, "{count} scenes");
    let gong = Scene::load(&dir.join("seed-gong-80N.toml"), &[]).unwrap();
    let p = gong.plate.unwrap();
    assert_eq!((p.n_phi, p.sim_rate), (1000, 40000.0));
}
