//! Clipping found in the readings themselves, for a sensor whose full scale nobody gave: a
//! sensor with noise never writes the very same value for many rows in a row, so a run of
//! identical readings well above the axis' own noise is a clip (the sensor at its range,
//! or a logger's integer limit). How long a run must be depends on how often the axis
//! repeats a reading by itself (its resolution against its noise, or the digits the log
//! keeps): with a share `p` of consecutive readings equal, a run of `n` happens by chance
//! with a probability of about `p^(n-1)`, held below `10^-`[`CHANCE_DIGITS`] per row, and
//! never shorter than [`MIN_PLATEAU_ROWS`] nor longer than [`PLATEAU_ROWS`]. The repeats
//! at the run's own value (of either sign) are left out of `p`: before its level is known,
//! a clip crossed by a vibration's crests a few rows at a time repeats it often enough to
//! keep raising the run it needs (the planar scooter's gyro clipped at 0.3 rad/s: runs of
//! 5 to 8 rows, each needing one more than the last). Its level is
//! then known for the rest of the log, and for the [`LOOK_AHEAD_ROWS`] rows before the run
//! (the reader finds clips that far ahead of the estimators): a reading exactly at it, on
//! any axis of the sensor and of either sign, is clipped too, however short its run.
//!
//! What must never trigger it, and how it is kept out (an axis is watched only after
//! [`MIN_PAIRS`] consecutive readings outside clips, and only while they show noise):
//! - a quantised sensor whose noise is below its step (at rest, or turning steadily): it
//!   repeats readings everywhere, so an axis is watched only while at most
//!   [`MAX_REPEAT_SHARE`] of its consecutive readings are equal;
//! - a noise-free (simulated) sensor, which repeats its reading whenever the body is
//!   still: its readings are smooth, so an axis is watched only while their second
//!   difference is at least [`MIN_ROUGHNESS`] times their first (white noise: sqrt 3), or
//!   under a vibration (second over first at least [`MIN_VIBRATION`]) their third at least
//!   that times their second (white noise: sqrt(10/3)). A smooth signal loses a factor of
//!   about `omega dt` at each difference, noise gains one; the third difference finds the
//!   noise under a strong vibration: the planar scooter's gyro (a 40 Hz vibration, its
//!   noise below it) has 0.27 and 0.92, its noise-free twin 0.25 and 0.25;
//! - a noisy sensor repeating a reading near zero (a stale value at rest): a clip must be
//!   at least [`NOISE_MULTIPLE`] times the axis' mean second difference (about twice its
//!   noise) from zero.

/// The longest run of identical readings a clip needs (20 ms at 1 kHz): the run needed at
/// the largest share of repeats an axis may have ([`MAX_REPEAT_SHARE`]).
pub const PLATEAU_ROWS: usize = 20;

/// How many rows ahead of the estimators the reader finds clips: a level found on a row
/// marks the readings at it from this many rows before (0.5 s at 1 kHz). Before a run long
/// enough, a vibration's crests pass a clip for a few rows each: on the scooter3d ride
/// with its gyro clipped at 0.1 rad/s the first run of 5 came 0.31 s into the clip, and
/// ekf3d and ukf3d, taking the clipped rate as true until then, moved their gyro bias by
/// 0.008 rad/s, which they took 8 s to forget.
pub const LOOK_AHEAD_ROWS: usize = 500;

/// The shortest run that makes a clip, however rarely the axis repeats a reading: a
/// vibration's crests above a clip last a few ms.
pub const MIN_PLATEAU_ROWS: usize = 5;

/// A run of identical readings makes a clip once chance would give it with a probability
/// below 10^-this per row.
pub const CHANCE_DIGITS: f64 = 12.0;

/// An axis is watched only while at most this share of its consecutive readings are
/// equal: a sensor whose noise is finer than its resolution repeats readings by itself.
pub const MAX_REPEAT_SHARE: f64 = 0.2;

/// Consecutive pairs of readings an axis needs before it is watched (0.5 s at 1 kHz).
pub const MIN_PAIRS: u64 = 500;

/// An axis is watched only while its mean absolute second difference is at least this
/// share of its mean absolute first difference, or its third of its second: noise makes
/// them sqrt 3 and sqrt(10/3), a smooth (noise-free) signal sampled finely much less (a
/// 40 Hz vibration at 1 kHz: 0.25).
pub const MIN_ROUGHNESS: f64 = 0.5;

/// The third difference tells noise only where the second is at least this share of the
/// first (a smooth signal's share is about `omega dt`: 0.1 is 16 Hz at 1 kHz), that is
/// under a vibration: a noise-free move that stops has kinks, which the third difference
/// takes for noise (a sine's half period then still: second over first 0.003, third over
/// second 2).
pub const MIN_VIBRATION: f64 = 0.1;

/// A clip must be at least this many times the axis' mean absolute second difference
/// (about twice its noise) from zero: at rest a sensor's reading is its bias plus noise,
/// never a clip.
pub const NOISE_MULTIPLE: f64 = 5.0;

/// Most clip levels remembered (two signs of one full scale, with room for a second).
const MAX_LEVELS: usize = 4;

/// Magnitudes whose repeats an axis counts apart (the most repeated ones kept).
const COUNTED_VALUES: usize = 8;

/// Per-axis statistics of a sensor with `K` axes.
#[derive(Debug, Clone)]
pub struct PlateauWatch<const K: usize> {
    prev: [f64; K],
    // Rows, ending with the last one seen, with the same reading.
    run: [usize; K],
    pairs: [u64; K],
    repeats: [u64; K],
    // Sum of |change| over the counted pairs.
    change: [f64; K],
    // The last counted change, the number of counted changes of changes and their sum of
    // |change of change|.
    last_change: [f64; K],
    triples: [u64; K],
    change2: [f64; K],
    // Likewise one order up: the last change of change, and the sum of |third difference|
    // over `quads` of them.
    last_change2: [f64; K],
    quads: [u64; K],
    change3: [f64; K],
    // Repeats per reading magnitude, for the most repeated ones (NaN: a free entry).
    repeats_at: [[(f64, u64); COUNTED_VALUES]; K],
    levels: [f64; MAX_LEVELS],
    n_levels: usize,
}

/// A clip level found on a row: the axis and the level (a magnitude).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewLevel {
    /// The axis (0-based) whose run found it.
    pub axis: usize,
    /// The reading (signed) of that run.
    pub reading: f64,
    /// The run's length (rows).
    pub rows: usize,
}

impl<const K: usize> Default for PlateauWatch<K> {
    fn default() -> Self {
        Self {
            prev: [f64::NAN; K],
            run: [0; K],
            pairs: [0; K],
            repeats: [0; K],
            change: [0.0; K],
            last_change: [f64::NAN; K],
            triples: [0; K],
            change2: [0.0; K],
            last_change2: [f64::NAN; K],
            quads: [0; K],
            change3: [0.0; K],
            repeats_at: [[(f64::NAN, 0); COUNTED_VALUES]; K],
            levels: [f64::NAN; MAX_LEVELS],
            n_levels: 0,
        }
    }
}

impl<const K: usize> PlateauWatch<K> {
    /// Nothing seen yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The clip levels found so far (magnitudes).
    pub fn levels(&self) -> &[f64] {
        &self.levels[..self.n_levels]
    }

    fn at_level(&self, v: f64) -> bool {
        self.levels().contains(&v.abs())
    }

    /// The run of identical readings `v` that makes a clip on axis `k` (see the module):
    /// the share of repeats, those at `v` left out, is counted with one more of each (a few
    /// hundred readings without a repeat do not make repeats impossible).
    fn needed_run(&self, k: usize, v: f64) -> usize {
        let own = self.repeats_at[k]
            .iter()
            .find(|e| e.0 == v.abs())
            .map_or(0, |e| e.1);
        let p = (self.repeats[k] - own + 1) as f64 / (self.pairs[k] + 1) as f64;
        let n = 1.0 + (CHANCE_DIGITS / -p.log10()).ceil();
        (n as usize).clamp(MIN_PLATEAU_ROWS, PLATEAU_ROWS)
    }

    /// The axis' mean absolute second difference, when it is watched (see the module).
    fn noise(&self, k: usize) -> Option<f64> {
        let pairs = self.pairs[k] as f64;
        if self.pairs[k] < MIN_PAIRS || self.triples[k] == 0 {
            return None;
        }
        let d1 = self.change[k] / pairs;
        let d2 = self.change2[k] / self.triples[k] as f64;
        let d3 = self.change3[k] / self.quads[k].max(1) as f64;
        let rough = d2 >= MIN_ROUGHNESS * d1
            || (d2 >= MIN_VIBRATION * d1 && d3 > 0.0 && d3 >= MIN_ROUGHNESS * d2);
        let noisy = self.repeats[k] as f64 <= MAX_REPEAT_SHARE * pairs && rough;
        noisy.then_some(d2)
    }

    /// Counts a repeat of magnitude `a` on axis `k`: in its entry, else in a free one, else
    /// in place of the least repeated (the magnitudes repeated most stay).
    fn count_repeat(&mut self, k: usize, a: f64) {
        let t = &mut self.repeats_at[k];
        if let Some(e) = t.iter_mut().find(|e| e.0 == a) {
            e.1 += 1;
        } else if let Some(e) = t
            .iter_mut()
            .min_by_key(|e| if e.0.is_nan() { 0 } else { e.1 })
        {
            *e = (a, 1);
        }
    }

    /// Which axes of readings `x` are at a clip level found so far.
    pub fn clipped(&self, x: [f64; K]) -> [bool; K] {
        core::array::from_fn(|k| x[k] != 0.0 && self.at_level(x[k]))
    }

    /// Takes the next row's readings `x` (NaN: missing), in the order of the log; the
    /// level whose run this row completes, if it is a new one.
    #[allow(clippy::needless_range_loop)] // k indexes every per-axis array
    pub fn observe(&mut self, x: [f64; K]) -> Option<NewLevel> {
        let mut found = None;
        for k in 0..K {
            let v = x[k];
            let same = v == self.prev[k];
            self.run[k] = if same { self.run[k] + 1 } else { 1 };
            if !v.is_finite() {
                self.prev[k] = v;
                self.last_change[k] = f64::NAN;
                self.last_change2[k] = f64::NAN;
                continue;
            }
            // Zero is no clip level (a sensor at rest, or a logger's fill value).
            let mut at_level = v != 0.0 && self.at_level(v);
            // (A run shorter than the shortest clip needs no statistics.)
            let candidate = !at_level && v != 0.0 && self.run[k] >= MIN_PLATEAU_ROWS;
            if let Some(noise) = candidate.then(|| self.noise(k)).flatten() {
                let rows = self.run[k];
                if rows >= self.needed_run(k, v)
                    && v.abs() >= NOISE_MULTIPLE * noise
                    && self.n_levels < MAX_LEVELS
                {
                    at_level = true;
                    self.levels[self.n_levels] = v.abs();
                    self.n_levels += 1;
                    found = Some(NewLevel {
                        axis: k,
                        reading: v,
                        rows,
                    });
                }
            }
            // A clip's rows are not the sensor's own statistics.
            if !at_level && self.prev[k].is_finite() && !self.at_level(self.prev[k]) {
                let d = v - self.prev[k];
                self.pairs[k] += 1;
                self.repeats[k] += u64::from(same);
                if same {
                    self.count_repeat(k, v.abs());
                }
                self.change[k] += d.abs();
                if self.last_change[k].is_finite() {
                    let dd = d - self.last_change[k];
                    self.triples[k] += 1;
                    self.change2[k] += dd.abs();
                    if self.last_change2[k].is_finite() {
                        self.quads[k] += 1;
                        self.change3[k] += (dd - self.last_change2[k]).abs();
                    }
                    self.last_change2[k] = dd;
                } else {
                    self.last_change2[k] = f64::NAN;
                }
                self.last_change[k] = d;
            } else {
                self.last_change[k] = f64::NAN;
                self.last_change2[k] = f64::NAN;
            }
            self.prev[k] = v;
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic noise in [-1, 1) (xorshift).
    struct Noise(u64);
    impl Noise {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
        /// About unit variance (a sum of three uniforms).
        fn gauss(&mut self) -> f64 {
            (self.next() + self.next() + self.next()) * 1.0
        }
    }

    /// Runs `rows` through a watch as the reader does (found `LOOK_AHEAD_ROWS` ahead);
    /// the clipped flags per row and the levels found.
    fn run<const K: usize>(rows: &[[f64; K]]) -> (Vec<[bool; K]>, Vec<NewLevel>) {
        let mut w = PlateauWatch::<K>::new();
        let mut out = Vec::new();
        let mut found = Vec::new();
        for i in 0..rows.len() + LOOK_AHEAD_ROWS {
            if let Some(r) = rows.get(i) {
                found.extend(w.observe(*r));
            }
            if let Some(r) = i.checked_sub(LOOK_AHEAD_ROWS).map(|j| rows[j]) {
                out.push(w.clipped(r));
            }
        }
        (out, found)
    }

    /// A noisy rate whose 40 Hz vibration crests pass 0.1 for a few rows each, clipped at
    /// 0.1 from row 2000 to 4000 (before that and after it the crests reach 0.115): every
    /// clipped reading is found, the short runs before the first long one too (found
    /// ahead), and no other reading.
    #[test]
    fn a_clip_of_a_noisy_signal_is_found_from_its_first_row() {
        let mut n = Noise(7);
        let rows: Vec<[f64; 2]> = (0..6000)
            .map(|i| {
                let t = i as f64 * 1e-3;
                let w = 0.085 + 0.03 * (2.0 * core::f64::consts::PI * 40.0 * t).sin();
                let r = [
                    w + 0.003 * n.gauss(),
                    0.05 * (3.0 * t).cos() + 0.005 * n.gauss(),
                ];
                if (2000..4000).contains(&i) {
                    r.map(|v| v.clamp(-0.1, 0.1))
                } else {
                    r
                }
            })
            .collect();
        let (c, found) = run(&rows);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].axis == 0 && found[0].reading == 0.1, "{found:?}");
        let clipped = rows.iter().filter(|r| r[0] == 0.1).count();
        assert!(clipped > 500, "{clipped}");
        for i in 0..rows.len() {
            assert_eq!(c[i][0], rows[i][0] == 0.1, "row {i}: {:?}", rows[i]);
            assert!(!c[i][1], "row {i}");
        }
    }

    /// A quantised gyro at rest (noise below its step: it repeats the bias for long runs)
    /// and turning steadily at 1 rad/s (likewise) is never clipped; nor is a noise-free
    /// reading standing still between moves.
    #[test]
    fn quantised_and_noise_free_sensors_repeating_readings_are_not_clips() {
        let lsb = 0.061f64.to_radians();
        let mut n = Noise(3);
        let q = |v: f64| (v / lsb).round() * lsb;
        let rest: Vec<[f64; 3]> = (0..20_000)
            .map(|_| {
                [
                    q(0.002 + 0.3 * lsb * n.gauss()),
                    q(-0.01 + 0.2 * lsb * n.gauss()),
                    q(0.0),
                ]
            })
            .collect();
        let (c, found) = run(&rest);
        assert!(found.is_empty() && c.iter().all(|r| r.iter().all(|x| !x)));
        let turning: Vec<[f64; 3]> = (0..20_000)
            .map(|i| {
                let w = if i < 5000 { 0.0 } else { 1.0 };
                [
                    q(w + 0.3 * lsb * n.gauss()),
                    q(0.0),
                    q(0.3 * lsb * n.gauss()),
                ]
            })
            .collect();
        let (c, found) = run(&turning);
        assert!(found.is_empty() && c.iter().all(|r| r.iter().all(|x| !x)));
        // Noise-free steps: a smooth move, then still at a constant reading (a bias).
        let steps: Vec<[f64; 1]> = (0..20_000)
            .map(|i| {
                let t = (i % 4000) as f64 * 1e-3;
                [if t < 1.0 {
                    0.3 * (core::f64::consts::PI * t).sin()
                } else {
                    0.02
                }]
            })
            .collect();
        let (c, found) = run(&steps);
        assert!(found.is_empty() && c.iter().all(|r| !r[0]));
    }

    /// A noisy gyro still at rest repeating its reading for a moment (a logger that
    /// wrote one stale value) is below the noise multiple: not a clip.
    #[test]
    fn a_stale_reading_near_zero_is_not_a_clip() {
        let mut n = Noise(11);
        let mut rows: Vec<[f64; 1]> = (0..5000).map(|_| [0.005 * n.gauss()]).collect();
        for r in rows.iter_mut().take(3050).skip(3000) {
            *r = [0.004];
        }
        let (c, found) = run(&rows);
        assert!(found.is_empty() && c.iter().all(|r| !r[0]));
    }
}
