//! Estimator families: which panel of the small-multiple figures a series belongs to, so
//! that no panel carries more than a handful of lines (each estimator's family is in the
//! catalogue, [`crate::catalogue`]).

pub use crate::catalogue::Family;

/// `names` grouped by family, families in panel order, names in their given order.
pub fn group<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<(Family, Vec<&'a str>)> {
    let mut out: Vec<(Family, Vec<&'a str>)> = Vec::new();
    for n in names {
        let f = Family::of(n);
        match out.iter_mut().find(|(g, _)| *g == f) {
            Some((_, v)) => v.push(n),
            None => out.push((f, vec![n])),
        }
    }
    out.sort_by_key(|(f, _)| *f);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 17 outputs of `reproduce` fall into five panels, none with more than six lines.
    #[test]
    fn the_bank_splits_into_five_small_panels() {
        let names: Vec<&str> = crate::bank::planar::REGISTRY
            .iter()
            .map(|e| e.name)
            .collect();
        let g = group(names.iter().copied());
        let fams: Vec<Family> = g.iter().map(|(f, _)| *f).collect();
        assert_eq!(
            fams,
            [
                Family::Raw,
                Family::Paper,
                Family::Kalman,
                Family::ModelBased,
                Family::Peers
            ]
        );
        assert_eq!(g.iter().map(|(_, v)| v.len()).sum::<usize>(), 17);
        assert!(g.iter().all(|(_, v)| v.len() <= 6));
        assert_eq!(g[1].1, ["alg1", "alg2", "alg2_offset", "alg2_dc", "alg3"]);
        assert_eq!(Family::of("my_filter"), Family::Other);
    }
}
