//! Tests of the user preset store, each in its own temporary folder.

use super::*;
use noether_core::engine::{ParamKind, PARAMS};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh folder under the system's temporary folder, removed on drop.
pub(crate) struct TempDir(pub PathBuf);

impl TempDir {
    pub(crate) fn new(tag: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "noether-presets-{tag}-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&dir);
        Self(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

fn bits(v: &ParamValues) -> Vec<u32> {
    v.0.iter().map(|x| x.to_bits()).collect()
}

/// Random parameter sets inside the table's ranges (integers integral), from a xorshift64*
/// generator with a fixed seed.
pub(crate) fn random_values(n: usize, seed: u64) -> Vec<ParamValues> {
    let mut s = seed | 1;
    let mut next = move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        (s.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let mut v = ParamValues::defaults();
            for p in PARAMS {
                let (lo, hi) = (f64::from(p.min), f64::from(p.max));
                // Half the draws spread over decades for log parameters, to get values with
                // many significant digits at every scale.
                let x = match p.kind {
                    ParamKind::Float { log: true } if lo > 0.0 => {
                        (lo.ln() + next() * (hi.ln() - lo.ln())).exp()
                    }
                    ParamKind::Float { .. } => lo + next() * (hi - lo),
                    _ => (lo + next() * (hi - lo)).round(),
                };
                let x = (x as f32).clamp(p.min, p.max);
                v.set(p.id, x).unwrap();
            }
            v
        })
        .collect()
}

/// Every factory preset and 200 random parameter sets come back bit for bit through
/// save → list → load (exact: the file stores each f32 widened to f64 in the shortest text
/// that reads back the same f64).
#[test]
fn save_list_load_round_trip_is_bit_exact() {
    let t = TempDir::new("round-trip");
    let store = UserPresetStore::at(&t.0);
    let mut expected = vec![];
    for (stem, p) in Preset::factory() {
        let v = p.values().unwrap();
        let name = format!("factory {stem}");
        store.save(&name, &p.description, &v, false).unwrap();
        expected.push((name, v));
    }
    for (i, v) in random_values(200, 0x5eed).into_iter().enumerate() {
        let name = format!("random {i:03}");
        store.save(&name, "", &v, false).unwrap();
        expected.push((name, v));
    }
    let listing = store.list();
    assert!(listing.broken.is_empty(), "{:?}", listing.broken);
    assert_eq!(listing.presets.len(), expected.len());
    for (name, v) in &expected {
        let listed = listing.presets.iter().find(|p| &p.name == name).unwrap();
        assert_eq!(bits(&listed.values), bits(v), "{name} (listed)");
        let loaded = store.load(&listed.stem).unwrap();
        assert_eq!(bits(&loaded.values), bits(v), "{name} (loaded)");
    }
    // The file is a factory-format preset: the engine's own loader reads it.
    let p = Preset::load(&t.0.join("factory gong-40N.toml")).unwrap();
    assert_eq!(p.name, "factory gong-40N");
    assert!(p.description.contains("gong"));
    assert_eq!(p.params.len(), PARAMS.len());
}

/// Listing is sorted ignoring case; hidden and non-TOML files are ignored.
#[test]
fn list_is_sorted_ignoring_case() {
    let t = TempDir::new("sorted");
    let store = UserPresetStore::at(&t.0);
    assert_eq!(
        store.list(),
        Listing::default(),
        "a missing folder lists empty"
    );
    let v = ParamValues::defaults();
    for name in ["beta", "Alpha", "gamma", "Delta", "alpha 2"] {
        store.save(name, "", &v, false).unwrap();
    }
    fs::write(t.0.join("notes.txt"), "not a preset").unwrap();
    fs::write(t.0.join(".hidden.toml.tmp"), "x").unwrap();
    fs::write(t.0.join(".hidden.toml"), "x").unwrap();
    let names: Vec<String> = store.list().presets.into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["Alpha", "alpha 2", "beta", "Delta", "gamma"]);
}

/// Files that do not parse or hold refused values are listed as broken with the error naming
/// the field, and never loaded; the good ones still load.
#[test]
fn broken_files_are_listed_not_loaded() {
    let t = TempDir::new("broken");
    let store = UserPresetStore::at(&t.0);
    store
        .save("good", "", &ParamValues::defaults(), false)
        .unwrap();
    fs::write(t.0.join("garbage.toml"), "name = \n[[[").unwrap();
    fs::write(
        t.0.join("range.toml"),
        "name = \"range\"\n[params]\nsize = 99.0\n",
    )
    .unwrap();
    fs::write(
        t.0.join("unknown.toml"),
        "name = \"u\"\n[params]\nnope = 1\n",
    )
    .unwrap();
    fs::write(t.0.join("binary.toml"), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    let l = store.list();
    assert_eq!(l.presets.len(), 1);
    assert_eq!(l.presets[0].name, "good");
    let stems: Vec<&str> = l.broken.iter().map(|b| b.stem.as_str()).collect();
    assert_eq!(stems, ["binary", "garbage", "range", "unknown"]);
    let range = &l.broken[2].error;
    assert!(
        range.contains("params.size") && range.contains("99"),
        "{range}"
    );
    assert!(
        l.broken[3].error.contains("params.nope"),
        "{}",
        l.broken[3].error
    );
    assert!(store.load("range").is_err());
    assert!(store.load("garbage").is_err());
    // A broken file can be deleted.
    store.delete("garbage").unwrap();
    assert_eq!(store.list().broken.len(), 3);
}

/// Bad names are refused with an error naming the field, the value and what is allowed;
/// nothing is written.
#[test]
fn bad_names_are_refused() {
    let t = TempDir::new("names");
    let store = UserPresetStore::at(&t.0);
    let v = ParamValues::defaults();
    let long = "x".repeat(MAX_NAME_CHARS + 1);
    for bad in [
        "",
        "   ",
        "a/b",
        "a\\b",
        "../up",
        ".hidden",
        " lead",
        "tab\there",
        "c:d",
        "what?",
        &long,
    ] {
        let e = store.save(bad, "", &v, false).unwrap_err();
        assert_eq!(e.field, "preset name", "{bad:?}");
        assert_eq!(e.value, format!("{bad:?}"));
        assert!(e.allowed.contains("1 to 64 characters"), "{e}");
        assert!(e.to_string().contains("preset name"), "{e}");
    }
    assert!(!t.0.exists(), "a refused save created the folder");
    // The longest name allowed, non-ASCII, and a trailing space trimmed.
    let ok = "é".repeat(MAX_NAME_CHARS);
    assert_eq!(store.save(&ok, "", &v, false).unwrap(), ok);
    assert_eq!(store.save("gong ", "", &v, false).unwrap(), "gong");
}

/// Saving over an existing name (ignoring case) needs `overwrite`; with it the folder keeps one
/// file, under the new spelling, holding the new values.
#[test]
fn overwrite_needs_confirmation() {
    let t = TempDir::new("overwrite");
    let store = UserPresetStore::at(&t.0);
    let [a, b] = [random_values(1, 1)[0], random_values(1, 2)[0]];
    store.save("Bell", "first", &a, false).unwrap();
    let e = store.save("bell", "", &b, false).unwrap_err();
    assert_eq!(e.field, "preset name");
    assert!(e.allowed.contains("confirm"), "{e}");
    assert_eq!(bits(&store.load("Bell").unwrap().values), bits(&a));
    assert_eq!(store.existing("BELL").as_deref(), Some("Bell"));
    store.save("bell", "second", &b, true).unwrap();
    let l = store.list();
    assert_eq!(l.presets.len(), 1);
    assert_eq!(l.presets[0].stem, "bell");
    assert_eq!(l.presets[0].description, "second");
    assert_eq!(bits(&l.presets[0].values), bits(&b));
}

/// Rename moves the file and its name, keeps the values, refuses a taken name unless
/// confirmed, and handles a change of case only.
#[test]
fn rename_and_delete() {
    let t = TempDir::new("rename");
    let store = UserPresetStore::at(&t.0);
    let [a, b] = [random_values(1, 3)[0], random_values(1, 4)[0]];
    store.save("one", "d1", &a, false).unwrap();
    store.save("two", "d2", &b, false).unwrap();
    assert_eq!(store.rename("one", "uno", false).unwrap(), "uno");
    let l = store.list();
    let names: Vec<&str> = l.presets.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["two", "uno"]);
    let uno = store.load("uno").unwrap();
    assert_eq!((uno.name.as_str(), uno.description.as_str()), ("uno", "d1"));
    assert_eq!(bits(&uno.values), bits(&a));
    assert!(store.load("one").is_err());
    // Case only.
    store.rename("uno", "Uno", false).unwrap();
    assert_eq!(store.list().presets[1].stem, "Uno");
    // A taken name, a bad name, a missing preset.
    let e = store.rename("Uno", "TWO", false).unwrap_err();
    assert!(e.allowed.contains("confirm"), "{e}");
    assert_eq!(
        store.rename("Uno", "a/b", false).unwrap_err().field,
        "preset name"
    );
    assert_eq!(
        store.rename("nope", "x", false).unwrap_err().field,
        "preset file"
    );
    // Confirmed: the other preset is replaced.
    store.rename("Uno", "TWO", true).unwrap();
    let l = store.list();
    assert_eq!(l.presets.len(), 1);
    assert_eq!(bits(&l.presets[0].values), bits(&a));
    store.delete("TWO").unwrap();
    assert!(store.list().presets.is_empty());
    let e = store.delete("TWO").unwrap_err();
    assert_eq!(e.field, "preset file");
}

/// The folder: the override when set and not empty, else `noether/presets` in the data folder.
#[test]
fn folder_resolution() {
    let data = Some(PathBuf::from("/home/u/.local/share"));
    assert_eq!(
        resolve_dir(None, data.clone()),
        Some(PathBuf::from("/home/u/.local/share/noether/presets"))
    );
    assert_eq!(
        resolve_dir(Some("/tmp/p".into()), data.clone()),
        Some(PathBuf::from("/tmp/p"))
    );
    assert_eq!(
        resolve_dir(Some("".into()), data),
        Some(PathBuf::from("/home/u/.local/share/noether/presets"))
    );
    assert_eq!(resolve_dir(None, None), None);
}
