//! The paper's Table 5: the seven speed-up switches by the paper's letters and words,
//! their 2^7 combinations on top of the contact graph configuration, and the labels
//! the laboratory prints and parses (`C--ZDSF`).
//!
//! | bit | letter | paper's word | `SpeedUps` field |
//! |---|---|---|---|
//! | 0 | C | cache | `cache` |
//! | 1 | T | tweak | `fewer_iterations` |
//! | 2 | R | reduce | `deepest_contact_only` |
//! | 3 | Z | zero | `no_restitution_at_rest` |
//! | 4 | D | damp | `viscous_damping` |
//! | 5 | S | subgroup | `insulate_sleepy` |
//! | 6 | F | fixate | `hold` |
//!
//! ```
//! use rapier_contact_graph::speedups::SpeedUps;
//! use rcg_lab::table5;
//!
//! assert_eq!(table5::label(&SpeedUps::papers_fastest()), "C--ZDSF");
//! assert_eq!(table5::combination_bits("C-----F"), Some(0b100_0001));
//! assert_eq!(table5::combination_bits("65"), Some(65));
//! assert_eq!(table5::combination_bits("128"), None);
//! assert!(table5::combination(0b100_0001).hold);
//! ```

use rapier_contact_graph::speedups::SpeedUps;

/// The switches' letters, bit 0 first.
pub const LETTERS: [char; 7] = ['C', 'T', 'R', 'Z', 'D', 'S', 'F'];

/// The paper's words for the switches, bit 0 first (the CSV columns and the stability
/// suite's target names).
pub const WORDS: [&str; 7] = [
    "cache", "tweak", "reduce", "zero", "damp", "subgroup", "fixate",
];

/// The seven switches of `s`, bit 0 first.
pub fn switches(s: &SpeedUps) -> [bool; 7] {
    [
        s.cache,
        s.fewer_iterations,
        s.deepest_contact_only,
        s.no_restitution_at_rest,
        s.viscous_damping,
        s.insulate_sleepy,
        s.hold,
    ]
}

/// One of the 2^7 combinations of the seven switches (bit 0 = cache … bit 6 =
/// fixate), on top of the contact graph configuration, as in the paper's Table 5.
pub fn combination(bits: u8) -> SpeedUps {
    let on = |i: u8| bits & (1 << i) != 0;
    SpeedUps {
        cache: on(0),
        fewer_iterations: on(1),
        deepest_contact_only: on(2),
        no_restitution_at_rest: on(3),
        viscous_damping: on(4),
        insulate_sleepy: on(5),
        hold: on(6),
        ..SpeedUps::contact_graph()
    }
}

/// The seven switches as "CTRZDSF", with `-` for an off switch.
pub fn label(s: &SpeedUps) -> String {
    switches(s)
        .iter()
        .zip(LETTERS)
        .map(|(&on, c)| if on { c } else { '-' })
        .collect()
}

/// [`label`] preceded by the groups and sleepy switches (`G`, `S`, or `-`): the whole
/// configuration's switches in one word, as `GSC--ZDSF`.
pub fn full_label(s: &SpeedUps) -> String {
    format!(
        "{}{}{}",
        if s.groups { "G" } else { "-" },
        if s.sleepy { "S" } else { "-" },
        label(s)
    )
}

/// The combination bits (see [`combination`]) of a label like `"C-----F"` (as
/// [`label`] writes it) or of a number 0–127; `None` for anything else. O(1).
pub fn combination_bits(label: &str) -> Option<u8> {
    if let Ok(n) = label.parse::<u8>() {
        return (n < 128).then_some(n);
    }
    let bytes = label.as_bytes();
    if bytes.len() != LETTERS.len() {
        return None;
    }
    let mut bits = 0u8;
    for (i, (&got, on)) in bytes.iter().zip(LETTERS).enumerate() {
        match got {
            b'-' => {}
            g if g as char == on => bits |= 1 << i,
            _ => return None,
        }
    }
    Some(bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The presets are the DIKU table's rows their docs quote figures of, and keep
    /// Rapier's warm start (`cache`).
    #[test]
    fn presets_are_the_measured_combinations_and_keep_warm_start() {
        for (preset, name) in [
            (SpeedUps::reliable_sleep(), "C----SF"),
            (SpeedUps::papers_fastest(), "C--ZDSF"),
        ] {
            let bits = combination_bits(name).unwrap();
            assert_eq!(preset, combination(bits), "{name}");
            assert!(preset.cache, "{name} keeps warm start");
            preset.validate().unwrap();
        }
    }

    #[test]
    fn combination_bits_inverts_the_label() {
        for b in 0..128u8 {
            let name = label(&combination(b));
            assert_eq!(combination_bits(&name), Some(b), "{name}");
            assert_eq!(combination_bits(&b.to_string()), Some(b));
        }
        for bad in ["", "CTRZDSFX", "TCRZDSF", "c-----f", "ctrzdsf", "128", "-1"] {
            assert_eq!(combination_bits(bad), None, "{bad}");
        }
    }

    #[test]
    fn combinations_cover_the_seven_switches() {
        assert_eq!(label(&combination(0)), "-------");
        assert_eq!(label(&combination(127)), "CTRZDSF");
        assert_eq!(label(&combination(0b100_0001)), "C-----F");
        assert!(combination(5).groups && combination(5).sleepy);
        assert_eq!(full_label(&SpeedUps::default()), "GSC------");
    }
}
