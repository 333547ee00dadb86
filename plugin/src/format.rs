//! Musical display and text entry of parameter values: one formatter and one parser per
//! parameter, used by the host (nice-plug's `value_to_string` / `string_to_value`), the
//! editor's sliders and the preset loader alike, so a value reads the same whatever set it.
//!
//! The stored (plain) value keeps the engine's SI unit (metres, pascals, radians, seconds, a
//! fraction); only the text changes: note names for keys (C4 = MIDI 60), mm / cm / m for
//! lengths chosen by magnitude, GPa for Young's modulus, degrees for angles, % for fractions,
//! Hz / kHz, dB, ms / s. The parser reads what the formatter writes, other units of the same
//! quantity ("30 deg", "0.5 rad", "2 m"), and plain numbers, which it takes in the parameter's
//! [`typing_unit`] (the engine's unit, degrees for angles). Any thread; allocates the string.

use noether_core::engine::{ParamId, Shown};

/// `v` with four significant digits: fixed notation from 0.01 to 99 999, scientific outside
/// (a relative rounding of at most 5e-4, inside the 0.1 % the round-trip tests allow).
pub fn four_significant(v: f32) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if (1e-2..1e5).contains(&a) {
        // Decimals from the magnitude after rounding to four digits, so 0.99999 reads
        // "1.000", not "1.0000".
        let digits = |m: f32| (3 - m.log10().floor() as i32).max(0);
        let d = digits(a);
        let rounded = (f64::from(a) * 10f64.powi(d)).round() / 10f64.powi(d);
        let decimals = digits(rounded as f32) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

const NOTE_NAMES: [&str; 12] = [
    "C", "C#", "D", "D#", "E", "F", "F#", "G", "G#", "A", "A#", "B",
];

/// The note name of MIDI key `key` (C4 = 60, so C-1 = 0 and G9 = 127).
pub fn note_name(key: i32) -> String {
    let k = key.clamp(0, 127);
    format!("{}{}", NOTE_NAMES[(k % 12) as usize], k / 12 - 1)
}

/// Reads a note name ("C4", "c#4", "Db3", "A-1") or a MIDI key number into a key 0..=127.
pub fn parse_note(s: &str) -> Option<i32> {
    let s = s.trim();
    if let Ok(k) = s.parse::<i32>() {
        return (0..=127).contains(&k).then_some(k);
    }
    let mut chars = s.chars();
    let letter = chars.next()?.to_ascii_uppercase();
    let base = match letter {
        'C' => 0,
        'D' => 2,
        'E' => 4,
        'F' => 5,
        'G' => 7,
        'A' => 9,
        'B' => 11,
        _ => return None,
    };
    let rest: &str = chars.as_str();
    let (shift, octave) = if let Some(r) = rest.strip_prefix('#').or(rest.strip_prefix('♯')) {
        (1, r)
    } else if let Some(r) = rest.strip_prefix('b').or(rest.strip_prefix('♭')) {
        (-1, r)
    } else {
        (0, rest)
    };
    let octave: i32 = octave.trim().parse().ok()?;
    let k = (octave + 1) * 12 + base + shift;
    (0..=127).contains(&k).then_some(k)
}

/// Singular or plural: `"1 voice"`, `"2 voices"`.
pub fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("1 {one}")
    } else {
        format!("{n} {many}")
    }
}

fn with_unit(number: f32, unit: &str) -> String {
    let n = four_significant(number);
    match unit {
        "" => n,
        "°" | "%" | "×" => format!("{n}{unit}"),
        _ => format!("{n} {unit}"),
    }
}

/// `a` rounded to the four significant digits the display shows: the unit is chosen from
/// it, so a value just below a unit's threshold that displays as the threshold ("1000 Hz")
/// takes the larger unit ("1.000 kHz"), as the value parsed back from that text does
/// (clap-validator's `param-conversions`: "1.000 kHz" read back as 999.99994 Hz printed
/// "1000 Hz").
fn as_displayed(a: f32) -> f32 {
    if a == 0.0 || !a.is_finite() {
        return a;
    }
    let scale = 10f64.powi(3 - f64::from(a).log10().floor() as i32);
    ((f64::from(a) * scale).round() / scale) as f32
}

/// The display text of `value` (plain, engine units) of parameter `id`.
pub fn format_value(id: ParamId, value: f32) -> String {
    let shown = as_displayed(value.abs());
    match id.info().shown {
        Shown::Length => {
            let a = shown;
            if a == 0.0 {
                "0 mm".to_string()
            } else if a < 1e-4 {
                with_unit(value * 1e6, "µm")
            } else if a < 1e-2 {
                with_unit(value * 1e3, "mm")
            } else if a < 1.0 {
                with_unit(value * 1e2, "cm")
            } else {
                with_unit(value, "m")
            }
        }
        Shown::Modulus => with_unit(value * 1e-9, "GPa"),
        Shown::Angle => with_unit(value.to_degrees(), "°"),
        Shown::Percent => with_unit(value * 100.0, "%"),
        Shown::Frequency if shown >= 1e3 => with_unit(value * 1e-3, "kHz"),
        Shown::Frequency => with_unit(value, "Hz"),
        Shown::Time if shown < 1.0 => with_unit(value * 1e3, "ms"),
        Shown::Time => with_unit(value, "s"),
        Shown::LinearDensity => with_unit(value * 1e3, "g/m"),
        Shown::Key => note_name(value.round() as i32),
        Shown::Count(one, many) => plural(value.round().max(0.0) as usize, one, many),
        Shown::Threads if value < 0.5 => "all cores".to_string(),
        Shown::Threads => plural(value.round() as usize, "thread", "threads"),
        Shown::Auto(_) if value <= 0.0 => "auto".to_string(),
        Shown::Auto(unit) => with_unit(value, unit),
        Shown::Plain("dB") => format!("{value:+.2} dB"),
        Shown::Plain(unit) => with_unit(value, unit),
    }
}

/// The unit a plain number typed for parameter `id` is read in: the engine table's unit (m,
/// Pa, s, Hz, kg/m; fractions as fractions, so presets, hosts and scripts can type what they
/// store), except angles, read in degrees (a player never types radians). Empty: the number
/// is taken as it is.
pub fn typing_unit(id: ParamId) -> &'static str {
    match id.info().shown {
        Shown::Length => "m",
        Shown::Modulus => "Pa",
        Shown::Angle => "°",
        Shown::Frequency => "Hz",
        Shown::Time => "s",
        Shown::LinearDensity => "kg/m",
        Shown::Plain(u) => u,
        Shown::Percent | Shown::Key | Shown::Count(..) | Shown::Threads | Shown::Auto(_) => "",
    }
}

/// Unit texts the parser accepts, with the factor to the engine's unit (the longest match
/// wins, so "ms" is not read as "s").
const UNITS: [(&str, f64); 24] = [
    ("µm", 1e-6),
    ("um", 1e-6),
    ("mm", 1e-3),
    ("cm", 1e-2),
    ("m", 1.0),
    ("GPa", 1e9),
    ("MPa", 1e6),
    ("Pa", 1.0),
    ("°", std::f64::consts::PI / 180.0),
    ("deg", std::f64::consts::PI / 180.0),
    ("rad", 1.0),
    ("%", 1e-2),
    ("kHz", 1e3),
    ("Hz", 1.0),
    ("ms", 1e-3),
    ("s", 1.0),
    ("g/m", 1e-3),
    ("kg/m", 1.0),
    ("kg/m³", 1.0),
    ("kg/m^3", 1.0),
    ("×", 1.0),
    ("x", 1.0),
    ("dB", 1.0),
    ("st", 1.0),
];

/// Which units belong to which quantity (a typed unit of another quantity is refused).
fn unit_fits(q: Shown, unit: &str) -> bool {
    match q {
        Shown::Length => matches!(unit, "µm" | "um" | "mm" | "cm" | "m"),
        Shown::Modulus => matches!(unit, "GPa" | "MPa" | "Pa"),
        Shown::Angle => matches!(unit, "°" | "deg" | "rad"),
        Shown::Percent => unit == "%",
        Shown::Frequency => matches!(unit, "kHz" | "Hz"),
        Shown::Time => matches!(unit, "ms" | "s"),
        Shown::LinearDensity => matches!(unit, "g/m" | "kg/m"),
        Shown::Key | Shown::Count(..) | Shown::Threads | Shown::Auto(_) => false,
        Shown::Plain(_) => false,
    }
}

/// Reads a value of parameter `id` typed by a user or a host: the display text, another unit
/// of the same quantity, or a plain number in [`typing_unit`]. Returns the plain value in
/// engine units (not clamped: nice-plug clamps to the range).
pub fn parse_value(id: ParamId, text: &str) -> Option<f32> {
    let q = id.info().shown;
    match q {
        Shown::Key => return parse_note(text).map(|k| k as f32),
        Shown::Threads if text.trim().starts_with("all") => return Some(0.0),
        Shown::Count(..) | Shown::Threads => {
            let first = text.split_whitespace().next()?;
            return first.parse::<f32>().ok();
        }
        Shown::Auto(_) if text.trim().starts_with("auto") => return Some(0.0),
        _ => {}
    }
    // A budget reads as a plain number in its unit.
    let q = match q {
        Shown::Auto(unit) => Shown::Plain(unit),
        q => q,
    };
    let t = text.trim().replace('−', "-");
    let split = t
        .char_indices()
        .find(|&(i, c)| {
            let numeric = c.is_ascii_digit() || matches!(c, '.' | '-' | '+');
            // An exponent: 'e' followed by a digit or a sign ("1e13", "2.5e-3").
            let exponent = matches!(c, 'e' | 'E')
                && t[i + 1..]
                    .chars()
                    .next()
                    .is_some_and(|n| n.is_ascii_digit() || n == '-' || n == '+');
            !numeric && !exponent
        })
        .map_or(t.len(), |(i, _)| i);
    let number: f64 = t[..split].trim().parse().ok()?;
    let unit = t[split..].trim();
    let unit = if unit.is_empty() {
        typing_unit(id)
    } else {
        unit
    };
    if unit.is_empty() {
        return Some(number as f32);
    }
    // Plain units with a fixed text (N, 1/m, N/m^α, s^(b−1)) may be typed in full or left out.
    if let Shown::Plain(u) = q {
        let u = u.replace('−', "-");
        if unit == u || u.starts_with(unit) || (u == "×" && unit == "x") {
            return Some(number as f32);
        }
        return None;
    }
    let (_, factor) = UNITS.iter().find(|(u, _)| *u == unit)?;
    unit_fits(q, unit).then_some((number * factor) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use noether_core::engine::{ParamKind, PARAMS};

    /// Every float and integer parameter at its min, default, max and the geometric or
    /// arithmetic middle reads back within 0.1 % of the range's larger end (the display keeps
    /// four significant digits: a relative rounding of at most 5e-4).
    #[test]
    fn every_parameter_round_trips() {
        for info in PARAMS {
            if matches!(info.kind, ParamKind::Enum { .. }) {
                continue;
            }
            let mid = if info.min > 0.0 {
                (info.min * info.max).sqrt()
            } else {
                0.5 * (info.min + info.max)
            };
            for v in [info.min, info.default, info.max, mid] {
                let v = if matches!(info.kind, ParamKind::Int) {
                    v.round()
                } else {
                    v
                };
                let s = format_value(info.id, v);
                let back = parse_value(info.id, &s)
                    .unwrap_or_else(|| panic!("{}: cannot read back {s:?}", info.key));
                let tol = 1e-3 * v.abs().max(1e-30);
                assert!(
                    (back - v).abs() <= tol,
                    "{}: {v} -> {s:?} -> {back}",
                    info.key
                );
            }
        }
    }

    /// Every parameter the engine gives a unit shows one in the editor (a bare number for a
    /// dome rise in plate thicknesses or a boss radius as a fraction of the plate's reads as
    /// metres or as anything).
    #[test]
    fn every_parameter_with_a_unit_shows_it() {
        for info in PARAMS {
            if info.unit.is_empty() || matches!(info.kind, ParamKind::Enum { .. }) {
                continue;
            }
            let s = format_value(info.id, info.max);
            let unit = s.trim_start_matches(|c: char| c.is_ascii_digit() || "+-.e ".contains(c));
            assert!(!unit.is_empty(), "{} ({}) shows {s:?}", info.key, info.unit);
        }
        assert_eq!(format_value(ParamId::Dome, 12.0), "12.00 × thickness");
        assert_eq!(parse_value(ParamId::Dome, "12"), Some(12.0));
        assert_eq!(parse_value(ParamId::Boss, "3 × thickness"), Some(3.0));
        assert_eq!(format_value(ParamId::BossRadius, 0.2), "20.00%");
        assert_eq!(parse_value(ParamId::BossRadius, "20%"), Some(0.2));
    }

    #[test]
    fn musical_texts() {
        assert_eq!(format_value(ParamId::RootKey, 60.0), "C4");
        assert_eq!(format_value(ParamId::RootKey, 69.0), "A4");
        assert_eq!(format_value(ParamId::Thickness, 1.0e-3), "1.000 mm");
        assert_eq!(format_value(ParamId::Thickness, 0.99999e-3), "1.000 mm");
        assert_eq!(format_value(ParamId::StrikeDuration, 0.0099999), "10.00 ms");
        assert_eq!(format_value(ParamId::Size, 0.4), "40.00 cm");
        assert_eq!(format_value(ParamId::Size, 1.2), "1.200 m");
        assert_eq!(format_value(ParamId::YoungsModulus, 2.0e11), "200.0 GPa");
        assert_eq!(format_value(ParamId::Density, 7860.0), "7860 kg/m³");
        assert_eq!(
            format_value(ParamId::StrikeAngle, std::f32::consts::FRAC_PI_6),
            "30.00°"
        );
        assert_eq!(format_value(ParamId::StrikeRadius, 0.92), "92.00%");
        assert_eq!(format_value(ParamId::SimRate, 8000.0), "8.000 kHz");
        // Just below a unit's threshold, shown as the threshold: the larger unit, as the
        // value read back from that text (clap-validator's round trip, Band limit).
        for (id, v, text) in [
            (ParamId::BandLimit, 999.99994, "1.000 kHz"),
            (ParamId::BandLimit, 999.9, "999.9 Hz"),
            (ParamId::ReleaseT60, 0.99999, "1.000 s"),
            (ParamId::Size, 0.0099999, "1.000 cm"),
        ] {
            assert_eq!(format_value(id, v), text);
            let back = parse_value(id, text).unwrap();
            assert_eq!(format_value(id, back), text);
        }
        assert_eq!(format_value(ParamId::StrikeDuration, 0.01), "10.00 ms");
        assert_eq!(format_value(ParamId::ReleaseT60, 2.0), "2.000 s");
        assert_eq!(format_value(ParamId::Gain, -6.0), "-6.00 dB");
        assert_eq!(format_value(ParamId::LinearDensity, 1.17e-3), "1.170 g/m");
    }

    #[test]
    fn text_entry_reads_units_and_plain_numbers() {
        let deg = std::f32::consts::PI / 180.0;
        let close = |a: Option<f32>, b: f32| a.is_some_and(|a| (a - b).abs() <= 1e-6 * b.abs());
        assert!(close(parse_value(ParamId::StrikeAngle, "30°"), 30.0 * deg));
        assert!(close(
            parse_value(ParamId::StrikeAngle, "30 deg"),
            30.0 * deg
        ));
        assert!(close(parse_value(ParamId::StrikeAngle, "30"), 30.0 * deg));
        assert!(close(parse_value(ParamId::StrikeAngle, "0.5 rad"), 0.5));
        assert!(close(parse_value(ParamId::Thickness, "2 mm"), 2.0e-3));
        assert!(close(parse_value(ParamId::Thickness, "0.002"), 2.0e-3));
        assert!(close(parse_value(ParamId::StrikeRadius, "0.5"), 0.5));
        assert!(close(parse_value(ParamId::StrikeRadius, "50%"), 0.5));
        assert!(close(parse_value(ParamId::Thickness, "0.2 cm"), 2.0e-3));
        assert!(close(parse_value(ParamId::Size, "1.5 m"), 1.5));
        assert!(close(parse_value(ParamId::YoungsModulus, "70 GPa"), 7.0e10));
        assert!(close(parse_value(ParamId::YoungsModulus, "7e10"), 7.0e10));
        assert!(close(parse_value(ParamId::SimRate, "8000"), 8000.0));
        assert!(close(parse_value(ParamId::StrikeDuration, "5 ms"), 5.0e-3));
        assert!(close(parse_value(ParamId::StrikeDuration, "0.5 s"), 0.5));
        assert!(close(parse_value(ParamId::SimRate, "44.1 kHz"), 44_100.0));
        assert!(close(
            parse_value(ParamId::ContactStiffness, "1e13"),
            1.0e13
        ));
        assert!(close(
            parse_value(ParamId::ContactStiffness, "1.000e13 N/m^α"),
            1.0e13
        ));
        assert_eq!(parse_value(ParamId::RootKey, "C#4"), Some(61.0));
        assert_eq!(parse_value(ParamId::RootKey, "Db4"), Some(61.0));
        assert_eq!(parse_value(ParamId::RootKey, "A-1"), Some(9.0));
        assert_eq!(parse_value(ParamId::RootKey, "72"), Some(72.0));
        // A unit of another quantity or garbage is refused, not misread.
        assert_eq!(parse_value(ParamId::StrikeAngle, "30 mm"), None);
        assert_eq!(parse_value(ParamId::Thickness, "loud"), None);
        assert_eq!(parse_value(ParamId::RootKey, "H4"), None);
    }

    #[test]
    fn plurals_and_note_names() {
        assert_eq!(plural(1, "voice", "voices"), "1 voice");
        assert_eq!(plural(0, "voice", "voices"), "0 voices");
        assert_eq!(format_value(ParamId::Polyphony, 1.0), "1 voice");
        assert_eq!(format_value(ParamId::Threads, 0.0), "all cores");
        assert_eq!(parse_value(ParamId::Threads, "all cores"), Some(0.0));
        assert_eq!(note_name(0), "C-1");
        assert_eq!(note_name(127), "G9");
        for k in 0..=127 {
            assert_eq!(parse_note(&note_name(k)), Some(k));
        }
    }
}
