//! The FIR low-pass against scipy (`firwin`, `freqz`), direct convolution and its own
//! properties (unit DC gain, symmetry, delay, attenuation, f32 vs f64, reset, NaN, bad
//! settings). The scipy reference values are in `data/firwin.csv`.
use pendtilt_core::filters::fir::{
    design_lowpass, magnitude_response, Fir, FirArray, FirBuffers, FirError, FirSlice, PaperFir,
    UnknownWindow, Window, PAPER_TAPS,
};

/// The scipy reference values (see the file's header).
const SCIPY: &str = include_str!("data/firwin.csv");

/// The rows `(x, value)` of one set of `data/firwin.csv`, in file order.
fn scipy_set(name: &str) -> Vec<(f64, f64)> {
    let rows: Vec<(f64, f64)> = SCIPY
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut cols = l.split(',');
            (cols.next()? == name).then(|| {
                let mut num = || cols.next().unwrap().trim().parse::<f64>().unwrap();
                (num(), num())
            })
        })
        .collect();
    assert!(!rows.is_empty(), "no set {name} in data/firwin.csv");
    rows
}

/// The taps of one set, checking that the rows are taps 0, 1, 2, ... in order.
fn scipy_taps(name: &str) -> Vec<f64> {
    let rows = scipy_set(name);
    for (i, (x, _)) in rows.iter().enumerate() {
        assert_eq!(*x, i as f64, "{name}: row {i} is tap {x}");
    }
    rows.into_iter().map(|(_, v)| v).collect()
}

/// `sin(x)`, short for the signals below.
fn sin(x: f64) -> f64 {
    x.sin()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Deterministic pseudo-random numbers in [-1, 1) (no rand in a no_std crate's tests).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[test]
fn hamming_51_matches_scipy_firwin() {
    let mut taps = [0.0f64; 51];
    design_lowpass(20.0, 1000.0, Window::Hamming, &mut taps).unwrap();
    let err = max_abs_diff(&taps, &scipy_taps("hamming_51_20hz_1khz"));
    assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
    // The paper's constructor designs the same thing.
    let paper = PaperFir::<f64>::paper(1000.0).unwrap();
    assert_eq!(paper.taps(), &taps[..]);
}

#[test]
fn hann_16_matches_scipy_firwin() {
    let mut taps = [0.0f64; 16];
    design_lowpass(100.0, 500.0, Window::Hann, &mut taps).unwrap();
    let err = max_abs_diff(&taps, &scipy_taps("hann_16_100hz_500hz"));
    assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
}

#[test]
fn blackman_21_matches_scipy_firwin() {
    let mut taps = [0.0f64; 21];
    design_lowpass(60.0, 200.0, Window::Blackman, &mut taps).unwrap();
    let err = max_abs_diff(&taps, &scipy_taps("blackman_21_60hz_200hz"));
    assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
}

#[test]
fn rectangular_9_matches_scipy_firwin() {
    let mut taps = [0.0f64; 9];
    design_lowpass(10.0, 100.0, Window::Rectangular, &mut taps).unwrap();
    let err = max_abs_diff(&taps, &scipy_taps("boxcar_9_10hz_100hz"));
    assert!(err < 1e-12, "max |ours - scipy| = {err:e}");
}

#[test]
fn one_tap_design_is_identity() {
    let mut taps = [0.0f64; 1];
    design_lowpass(20.0, 1000.0, Window::Hamming, &mut taps).unwrap();
    assert_eq!(taps, [1.0]);
}

#[test]
fn dc_gain_is_one_and_constant_in_gives_constant_out() {
    for window in Window::ALL {
        let mut fir = FirArray::<f64, 33>::lowpass(45.0, 400.0, window).unwrap();
        let sum: f64 = fir.taps().iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "{window}: DC gain {sum}");
        assert!((magnitude_response(fir.taps(), 0.0, 400.0) - 1.0).abs() < 1e-12);
        for k in 0..100 {
            let y = fir.update(0.25);
            assert!((y - 0.25).abs() < 1e-12, "{window}: sample {k} gave {y}");
        }
    }
}

#[test]
fn designs_are_symmetric() {
    let mut taps = [0.0f64; 40];
    for window in Window::ALL {
        design_lowpass(7.0, 90.0, window, &mut taps).unwrap();
        for i in 0..taps.len() {
            let j = taps.len() - 1 - i;
            assert!(
                (taps[i] - taps[j]).abs() < 1e-15,
                "{window}: tap {i} vs {j}"
            );
        }
    }
}

#[test]
fn magnitude_response_matches_scipy_freqz() {
    let hamming = scipy_taps("hamming_51_20hz_1khz");
    for (f, g) in scipy_set("gain_hamming_51") {
        let ours = magnitude_response(&hamming, f, 1000.0);
        assert!((ours - g).abs() < 1e-12, "{f} Hz: {ours} vs scipy {g}");
    }
    let hann = scipy_taps("hann_16_100hz_500hz");
    for (f, g) in scipy_set("gain_hann_16") {
        let ours = magnitude_response(&hann, f, 500.0);
        assert!((ours - g).abs() < 1e-12, "{f} Hz: {ours} vs scipy {g}");
    }
    assert!(magnitude_response(&[1.0f64], 1.0, 0.0).is_nan());
}

/// Runs `fir` over a sine of `freq` Hz at `rate` Hz and returns the largest deviation,
/// once the window holds only real samples, from `gain * sin(w (k - delay))`.
fn sine_error<B: FirBuffers<Sample = f64>>(
    fir: &mut Fir<B>,
    freq: f64,
    rate: f64,
    gain: f64,
) -> f64 {
    let w = 2.0 * core::f64::consts::PI * freq / rate;
    let delay = fir.group_delay();
    let mut worst = 0.0f64;
    for k in 0..2000 {
        let y = fir.update(sin(w * k as f64));
        if fir.is_filled() {
            let expected = gain * sin(w * (k as f64 - delay));
            worst = worst.max((y - expected).abs());
        }
    }
    worst
}

#[test]
fn passband_sine_keeps_its_amplitude_and_is_delayed_by_half_the_order() {
    // 2 Hz through the paper's filter at 1 kHz: scipy's gain 0.99498, 25 samples late.
    let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
    assert_eq!(fir.group_delay(), 25.0);
    let (f, g) = scipy_set("gain_hamming_51")[1];
    assert!(g > 0.99);
    let err = sine_error(&mut fir, f, 1000.0, g);
    assert!(err < 1e-12, "deviation from 0.995 sin(w (k - 25)): {err:e}");
    // The same delay is wrong by one sample: the test can tell.
    let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
    let w = 2.0 * core::f64::consts::PI * f / 1000.0;
    let mut off = 0.0f64;
    for k in 0..2000 {
        let y = fir.update(sin(w * k as f64));
        if fir.is_filled() {
            off = off.max((y - g * sin(w * (k as f64 - 24.0))).abs());
        }
    }
    assert!(off > 1e-3);
}

#[test]
fn even_length_delays_by_a_half_sample() {
    let mut taps = [0.0f64; 16];
    design_lowpass(100.0, 500.0, Window::Hann, &mut taps).unwrap();
    let mut fir = FirArray::new(taps);
    assert_eq!(FirArray::<f64, 16>::GROUP_DELAY, 7.5);
    let (f, g) = scipy_set("gain_hann_16")[0];
    let err = sine_error(&mut fir, f, 500.0, g);
    assert!(err < 1e-12, "deviation from g sin(w (k - 7.5)): {err:e}");
}

#[test]
fn stopband_sine_is_attenuated_as_predicted() {
    for &(f, g) in &scipy_set("gain_hamming_51")[4..6] {
        assert!(g < 3e-4, "{f} Hz should be at least 70 dB down");
        let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
        let w = 2.0 * core::f64::consts::PI * f / 1000.0;
        // Amplitude from the RMS over 3000 filled samples: a whole number of periods of
        // both 100 Hz (10 samples) and 150 Hz (20 samples for 3 periods), where the
        // RMS of a sampled sine is exactly amplitude / sqrt(2).
        let (mut sum_sq, mut n) = (0.0f64, 0usize);
        for k in 0..(PAPER_TAPS + 3000) {
            let y = fir.update(sin(w * k as f64));
            if k >= PAPER_TAPS {
                sum_sq += y * y;
                n += 1;
            }
        }
        assert_eq!(n, 3000);
        let amplitude = (2.0 * sum_sq / n as f64).sqrt();
        assert!(
            (amplitude - g).abs() < 1e-6 * g,
            "{f} Hz: amplitude {amplitude} vs {g}"
        );
        let mut fir = PaperFir::<f64>::paper(1000.0).unwrap();
        assert!(sine_error(&mut fir, f, 1000.0, g) < 1e-13);
    }
}

/// Direct convolution with the pre-fill convention: x[k] = x[0] for k < 0.
fn direct(taps: &[f64], x: &[f64], k: usize) -> f64 {
    taps.iter()
        .enumerate()
        .map(|(i, h)| h * if i <= k { x[k - i] } else { x[0] })
        .sum()
}

fn check_streaming_equals_direct<const N: usize>(seed: u64) {
    let mut rng = Lcg(seed);
    let mut taps = [0.0f64; N];
    // Arbitrary, asymmetric taps: the tap order must be right, not just the symmetry.
    for t in taps.iter_mut() {
        *t = rng.next();
    }
    let mut x = [0.0f64; 300];
    for v in x.iter_mut() {
        *v = rng.next() * 5.0;
    }
    let mut fir = FirArray::new(taps);
    let mut hist = [9.0f64; N];
    let mut slice = FirSlice::new(&taps, &mut hist).unwrap();
    for k in 0..x.len() {
        let want = direct(&taps, &x, k);
        let y = fir.update(x[k]);
        let ys = slice.update(x[k]);
        assert!((y - want).abs() < 1e-12, "N={N} k={k}: {y} vs {want}");
        assert_eq!(y.to_bits(), ys.to_bits(), "Fir and FirSlice differ");
        assert_eq!(fir.is_filled(), k + 1 >= N);
        assert_eq!(slice.is_filled(), k + 1 >= N);
    }
}

#[test]
fn streaming_equals_direct_convolution() {
    check_streaming_equals_direct::<1>(1);
    check_streaming_equals_direct::<2>(2);
    check_streaming_equals_direct::<3>(3);
    check_streaming_equals_direct::<4>(4);
    check_streaming_equals_direct::<7>(5);
    check_streaming_equals_direct::<51>(6);
    check_streaming_equals_direct::<64>(7);
}

#[test]
fn f32_and_f64_agree() {
    let mut t64 = [0.0f64; 51];
    let mut t32 = [0.0f32; 51];
    design_lowpass(20.0, 1000.0, Window::Hamming, &mut t64).unwrap();
    design_lowpass(20.0, 1000.0, Window::Hamming, &mut t32).unwrap();
    for (a, b) in t64.iter().zip(&t32) {
        // The f32 design is the f64 one, correctly rounded.
        assert_eq!(*b, *a as f32);
    }
    let mut f64_fir = FirArray::new(t64);
    let mut f32_fir = FirArray::new(t32);
    let mut rng = Lcg(42);
    let mut worst = 0.0f64;
    for k in 0..5000 {
        // A tilt-like signal in radians: slow swing plus vibration and noise.
        let t = k as f64 / 1000.0;
        let x = 0.2 * sin(2.0 * t)
            + 0.05 * sin(2.0 * core::f64::consts::PI * 80.0 * t)
            + 0.01 * rng.next();
        let y64 = f64_fir.update(x);
        let y32 = f32_fir.update(x as f32);
        worst = worst.max((y64 - y32 as f64).abs());
    }
    assert!(worst < 1e-6, "f32 vs f64: {worst:e}");
}

#[test]
fn reset_restarts_like_new() {
    let mut fir = PaperFir::<f64>::paper(500.0).unwrap();
    for k in 0..100 {
        fir.update(k as f64);
    }
    assert!(fir.is_filled());
    fir.reset();
    assert!(!fir.is_filled());
    let mut fresh = PaperFir::<f64>::paper(500.0).unwrap();
    for k in 0..60 {
        let x = sin(k as f64 * 0.3);
        assert_eq!(fir.update(x).to_bits(), fresh.update(x).to_bits());
    }
    let taps: [f64; PAPER_TAPS] = fresh.taps().try_into().unwrap();
    let mut hist = [0.0; PAPER_TAPS];
    let mut slice = FirSlice::new(&taps, &mut hist).unwrap();
    for k in 0..80 {
        slice.update(k as f64);
    }
    slice.reset();
    assert!(!slice.is_filled());
    assert_eq!(slice.update(3.0), fresh_constant(&taps, 3.0));
}

fn fresh_constant(taps: &[f64; PAPER_TAPS], x: f64) -> f64 {
    let mut fir = FirArray::new(*taps);
    fir.update(x)
}

#[test]
fn nan_input_spoils_one_window_then_recovers() {
    let mut fir = FirArray::<f64, 11>::lowpass(10.0, 100.0, Window::Hamming).unwrap();
    for _ in 0..20 {
        fir.update(1.0);
    }
    assert!(fir.update(f64::NAN).is_nan());
    for _ in 0..10 {
        assert!(fir.update(1.0).is_nan());
    }
    let y = fir.update(1.0);
    assert!((y - 1.0).abs() < 1e-12, "after the window: {y}");
}

#[test]
fn bad_settings_are_errors_not_panics() {
    let mut taps = [7.0f64; 5];
    let cases = [
        (20.0, 1000.0, FirError::NoTaps),
        (0.0, 1000.0, FirError::CutoffNotPositive { cutoff_hz: 0.0 }),
        (
            -1.0,
            1000.0,
            FirError::CutoffNotPositive { cutoff_hz: -1.0 },
        ),
        (
            500.0,
            1000.0,
            FirError::CutoffAboveNyquist {
                cutoff_hz: 500.0,
                nyquist_hz: 500.0,
            },
        ),
        (
            f64::INFINITY,
            1000.0,
            FirError::CutoffAboveNyquist {
                cutoff_hz: f64::INFINITY,
                nyquist_hz: 500.0,
            },
        ),
        (20.0, 0.0, FirError::InvalidRate { rate_hz: 0.0 }),
        (20.0, -5.0, FirError::InvalidRate { rate_hz: -5.0 }),
        (
            20.0,
            f64::INFINITY,
            FirError::InvalidRate {
                rate_hz: f64::INFINITY,
            },
        ),
    ];
    for (i, (cutoff, rate, want)) in cases.into_iter().enumerate() {
        let out: &mut [f64] = if i == 0 { &mut [] } else { &mut taps };
        assert_eq!(
            design_lowpass(cutoff, rate, Window::Hamming, out),
            Err(want)
        );
    }
    // NaN settings are rejected too (compared by variant: NaN != NaN).
    assert!(matches!(
        design_lowpass(f64::NAN, 1000.0, Window::Hann, &mut taps),
        Err(FirError::CutoffNotPositive { .. })
    ));
    assert!(matches!(
        design_lowpass(20.0, f64::NAN, Window::Hann, &mut taps),
        Err(FirError::InvalidRate { .. })
    ));
    // The output is untouched on error.
    assert_eq!(taps, [7.0; 5]);
    // 20 Hz is not a low-pass at 40 Hz.
    assert!(matches!(
        PaperFir::<f32>::paper(40.0),
        Err(FirError::CutoffAboveNyquist { .. })
    ));
    assert!(PaperFir::<f32>::paper(40.001).is_ok());
    let mut hist = [0.0f64; 4];
    assert_eq!(
        FirSlice::new(&taps, &mut hist).err(),
        Some(FirError::LengthMismatch {
            taps: 5,
            history: 4
        })
    );
    assert_eq!(
        FirSlice::<f64>::new(&[], &mut []).err(),
        Some(FirError::NoTaps)
    );
}

#[test]
fn window_names_round_trip() {
    for w in Window::ALL {
        assert_eq!(w.name().parse::<Window>(), Ok(w));
    }
    assert_eq!("Hanning".parse::<Window>(), Ok(Window::Hann));
    assert_eq!("boxcar".parse::<Window>(), Ok(Window::Rectangular));
    assert_eq!("kaiser".parse::<Window>(), Err(UnknownWindow));
    assert_eq!(Window::default(), Window::Hamming);
    // Hamming ends at 0.08 and peaks at 1; out of range is 0.
    assert!((Window::Hamming.value(0, 51) - 0.08).abs() < 1e-15);
    assert!((Window::Hamming.value(25, 51) - 1.0).abs() < 1e-15);
    assert_eq!(Window::Hamming.value(51, 51), 0.0);
}
