//! Fixed colours per series name, so an estimator has the same colour in every figure.
use std::collections::BTreeMap;

use plotters::style::RGBColor;

/// The series that are not estimators: the truth, black under both its names. The
/// estimators' colours are in the catalogue ([`crate::catalogue::Listing::colour`]).
const TRUTH_COLOURS: &[(&str, RGBColor)] =
    &[("theta", RGBColor(0, 0, 0)), ("truth", RGBColor(0, 0, 0))];

/// The built-in name → colour map: the truth's and every catalogued estimator's.
pub fn default_colours() -> Vec<(&'static str, RGBColor)> {
    let estimators = crate::catalogue::CATALOGUE
        .iter()
        .map(|l| (l.name, RGBColor(l.colour[0], l.colour[1], l.colour[2])));
    TRUTH_COLOURS.iter().copied().chain(estimators).collect()
}

/// Colours for names not in the map, picked by a stable hash of the name.
const FALLBACK: &[RGBColor] = &[
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(204, 121, 167),
    RGBColor(100, 100, 0),
    RGBColor(90, 60, 160),
];

/// Name → colour map used by every figure.
#[derive(Debug, Clone)]
pub struct Palette {
    colours: BTreeMap<String, RGBColor>,
}

impl Default for Palette {
    fn default() -> Self {
        Self {
            colours: default_colours()
                .into_iter()
                .map(|(n, c)| (n.to_string(), c))
                .collect(),
        }
    }
}

impl Palette {
    /// A palette with no fixed names: every colour comes from the hash fallback.
    pub fn empty() -> Self {
        Self {
            colours: BTreeMap::new(),
        }
    }

    /// Sets (or overrides) the colour of `name`.
    pub fn set(&mut self, name: &str, colour: RGBColor) -> &mut Self {
        self.colours.insert(name.to_string(), colour);
        self
    }

    /// Whether `name` has a fixed colour (built in or set).
    pub fn has(&self, name: &str) -> bool {
        self.colours.contains_key(name)
    }

    /// The colour of `name`: its fixed colour, or a fallback chosen by a stable hash of the
    /// name (the same name always gets the same colour, across runs and figures).
    pub fn colour(&self, name: &str) -> RGBColor {
        if let Some(c) = self.colours.get(name) {
            return *c;
        }
        // FNV-1a: stable across Rust versions, unlike DefaultHasher.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in name.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        FALLBACK[(h % FALLBACK.len() as u64) as usize]
    }

    /// The colour as a CSS hex string (`#rrggbb`), for HTML swatches.
    pub fn css(&self, name: &str) -> String {
        let RGBColor(r, g, b) = self.colour(name);
        format!("#{r:02x}{g:02x}{b:02x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_names_have_fixed_colours_and_others_are_stable() {
        let p = Palette::default();
        assert_eq!(p.colour("theta"), RGBColor(0, 0, 0));
        assert_eq!(p.css("alg2"), "#2ca02c");
        assert_eq!(p.colour("my_filter"), p.colour("my_filter"));
        let mut q = Palette::empty();
        q.set("alg2", RGBColor(1, 2, 3));
        assert_eq!(q.colour("alg2"), RGBColor(1, 2, 3));
    }

    /// Every series of one panel of the small multiples (`super::super::families`) has a
    /// fixed colour at least 80 apart (RGB distance) from the others: kf_fused had the
    /// fallback's amber, 37 from kf_accel's orange in the Kalman panel.
    #[test]
    fn each_panel_s_series_have_fixed_colours_far_apart() {
        use crate::report::families::group;
        // Every series of the planar bank, as `reproduce` draws them.
        let bank: Vec<&str> = crate::bank::planar::REGISTRY
            .iter()
            .map(|e| e.name)
            .collect();
        let all = default_colours();
        let fixed = |n: &str| all.iter().find(|(m, _)| *m == n).map(|c| c.1);
        for (family, names) in group(bank.iter().copied()) {
            for (i, a) in names.iter().enumerate() {
                let ca = fixed(a).unwrap_or_else(|| panic!("{a} has no fixed colour"));
                for b in &names[i + 1..] {
                    let cb = fixed(b).unwrap();
                    let d = ((ca.0 as f64 - cb.0 as f64).powi(2)
                        + (ca.1 as f64 - cb.1 as f64).powi(2)
                        + (ca.2 as f64 - cb.2 as f64).powi(2))
                    .sqrt();
                    assert!(d >= 80.0, "{family:?}: {a} and {b} are {d:.0} apart");
                }
            }
        }
    }

    #[test]
    fn built_in_names_are_distinct_except_truth_aliases() {
        let all = default_colours();
        for (i, (n1, c1)) in all.iter().enumerate() {
            for (n2, c2) in &all[i + 1..] {
                if !(*n1 == "theta" && *n2 == "truth") {
                    assert_ne!(c1, c2, "{n1} and {n2} share a colour");
                }
            }
        }
    }
}
