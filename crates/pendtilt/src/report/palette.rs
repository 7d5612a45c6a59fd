//! Fixed colours per series name, so an estimator has the same colour in every figure.
use std::collections::BTreeMap;

use plotters::style::RGBColor;

/// The built-in name → colour map (names as in the estimates CSV).
///
/// Truth is black; the accelerometer grey and the Kalman filter fed by it orange; the
/// pendulum family blue/green/red; other filters in their own hues; the 3-D estimators
/// each their own.
pub const DEFAULT_COLOURS: &[(&str, RGBColor)] = &[
    ("theta", RGBColor(0, 0, 0)),
    ("truth", RGBColor(0, 0, 0)),
    ("accel", RGBColor(150, 150, 150)),
    ("kf_accel", RGBColor(255, 127, 14)),
    ("pendulum", RGBColor(140, 86, 75)),
    ("alg1", RGBColor(31, 119, 180)),
    ("alg2", RGBColor(44, 160, 44)),
    ("alg3", RGBColor(214, 39, 40)),
    // alg2's variants: a lighter alg2, and a hue of their own
    ("alg2_offset", RGBColor(152, 223, 138)),
    ("alg2_dc", RGBColor(90, 60, 160)),
    ("kf_pendulum", RGBColor(196, 156, 148)),
    ("kf_alg1", RGBColor(23, 190, 207)),
    ("kf_alg2", RGBColor(148, 103, 189)),
    ("kf_alg3", RGBColor(227, 119, 194)),
    // not the fallback's amber, which sat beside kf_accel's orange in one panel
    ("kf_fused", RGBColor(0, 128, 128)),
    ("ekf", RGBColor(188, 189, 34)),
    ("ukf", RGBColor(0, 90, 50)),
    ("madgwick", RGBColor(120, 0, 120)),
    ("mahony", RGBColor(0, 60, 140)),
    ("complementary", RGBColor(160, 90, 0)),
    // the 3-D estimators (a hash could give two of them one colour)
    ("pendulum3d", RGBColor(160, 100, 60)),
    ("accel3d", RGBColor(130, 130, 130)),
    ("inv3d", RGBColor(50, 170, 80)),
    ("ekf3d", RGBColor(200, 30, 30)),
    ("ukf3d", RGBColor(20, 170, 190)),
    ("vqf", RGBColor(240, 140, 0)),
    ("madgwick3d", RGBColor(130, 20, 140)),
    ("mahony3d", RGBColor(40, 90, 200)),
];

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
            colours: DEFAULT_COLOURS
                .iter()
                .map(|(n, c)| (n.to_string(), *c))
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
        let bank: Vec<&str> = crate::bank::REGISTRY.iter().map(|e| e.name).collect();
        let fixed = |n: &str| DEFAULT_COLOURS.iter().find(|(m, _)| *m == n).map(|c| c.1);
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
        for (i, (n1, c1)) in DEFAULT_COLOURS.iter().enumerate() {
            for (n2, c2) in &DEFAULT_COLOURS[i + 1..] {
                if !(*n1 == "theta" && *n2 == "truth") {
                    assert_ne!(c1, c2, "{n1} and {n2} share a colour");
                }
            }
        }
    }
}
