//! Same seed, same bytes; different seed, different noise; streams independent per part.

use pendtilt::sim::planar::output::write_log;
use pendtilt::sim::planar::{simulate, Scenario, SimRow, Simulator};

fn scooter(duration: f64) -> Scenario {
    let mut s = Scenario::named("scooter").unwrap();
    s.duration = duration;
    s
}

fn bits(rows: &[SimRow]) -> Vec<[u64; 6]> {
    rows.iter()
        .map(|r| [r.t, r.phi, r.gyro, r.ax, r.ay, r.theta].map(f64::to_bits))
        .collect()
}

fn csv(s: &Scenario, seed: u64) -> Vec<u8> {
    let mut out = Vec::new();
    write_log(Simulator::new(s, seed).unwrap(), &mut out, |_, _| {}).unwrap();
    out
}

#[test]
fn same_seed_gives_identical_rows_and_bytes() {
    let s = scooter(3.0);
    assert_eq!(
        bits(&simulate(&s, 7).unwrap()),
        bits(&simulate(&s, 7).unwrap())
    );
    let a = csv(&s, 7);
    assert_eq!(a, csv(&s, 7));
    assert_ne!(a, csv(&s, 8));
    let text = String::from_utf8(a).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,phi,gyro,ax,ay,theta"));
    assert_eq!(lines.count(), 3000);
}

#[test]
fn different_seeds_change_noise_vibration_and_manoeuvres() {
    let s = scooter(2.0);
    let (a, b) = (simulate(&s, 1).unwrap(), simulate(&s, 2).unwrap());
    let differs = |f: fn(&SimRow) -> f64| a.iter().zip(&b).any(|(x, y)| f(x) != f(y));
    assert!(differs(|r| r.gyro));
    assert!(differs(|r| r.ax));
    assert!(differs(|r| r.truth.a_p1[1]));
    assert!(differs(|r| r.truth.theta));
    // Times are the convention t_k = k / rate, whatever the seed.
    assert!(a.iter().enumerate().all(|(k, r)| r.t == k as f64 / 1000.0));
}

#[test]
fn each_random_part_has_its_own_stream() {
    let s = scooter(1.0);
    let mut louder = s.clone();
    louder.sensors.gyro.noise_density *= 10.0;
    let (a, b) = (simulate(&s, 4).unwrap(), simulate(&louder, 4).unwrap());
    assert!(a.iter().zip(&b).any(|(x, y)| x.gyro != y.gyro));
    // Changing the gyro leaves every other column bit-identical.
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            [x.phi, x.ax, x.ay, x.theta].map(f64::to_bits),
            [y.phi, y.ax, y.ay, y.theta].map(f64::to_bits)
        );
    }
}

#[test]
fn iterator_streams_rows_with_an_exact_length() {
    let s = scooter(0.5);
    let mut sim = Simulator::new(&s, 1).unwrap();
    assert_eq!(sim.size_hint(), (500, Some(500)));
    assert_eq!(sim.total_rows(), 500);
    let first = sim.next().unwrap();
    assert_eq!(sim.rows_done(), 1);
    assert_eq!(sim.size_hint(), (499, Some(499)));
    let rest: Vec<SimRow> = sim.collect();
    assert_eq!(rest.len(), 499);
    let all = simulate(&s, 1).unwrap();
    assert_eq!(bits(&[first]), bits(&all[..1]));
    assert_eq!(bits(&rest), bits(&all[1..]));
}

#[test]
fn row_count_follows_the_convention() {
    let mut s = Scenario::named("sine").unwrap();
    for (duration, rate, rows) in [(1.0, 1000.0, 1000), (0.0015, 1000.0, 2), (2.5, 3.0, 8)] {
        s.duration = duration;
        s.rate = rate;
        // At 3 Hz the pendulum needs 10 RK4 steps a sample (sim::integrator::check_step).
        s.substeps = if rate < 10.0 { 10 } else { 2 };
        assert_eq!(simulate(&s, 1).unwrap().len(), rows);
    }
}

#[test]
fn threaded_writer_matches_row_by_row_formatting() {
    let s = scooter(2.5);
    let mut expected = b"t,phi,gyro,ax,ay,theta\n".to_vec();
    for r in simulate(&s, 9).unwrap() {
        pendtilt::sim::planar::output::write_row(&mut expected, &r).unwrap();
    }
    let mut calls = Vec::new();
    let mut got = Vec::new();
    let n = write_log(Simulator::new(&s, 9).unwrap(), &mut got, |d, t| {
        calls.push((d, t))
    })
    .unwrap();
    assert_eq!(n, 2500);
    assert_eq!(got, expected);
    assert_eq!(calls.last(), Some(&(2500, 2500)));
}

/// A sink that fails after `left` bytes.
struct Full {
    left: usize,
}

impl std::io::Write for Full {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.left < buf.len() {
            return Err(std::io::Error::other("disk full"));
        }
        self.left -= buf.len();
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn write_errors_stop_the_run_and_are_returned() {
    // A long run into a sink that fills up after about 100 rows: the error comes back
    // promptly (the simulating thread stops too) instead of simulating the whole hour.
    let s = scooter(3600.0);
    let t = std::time::Instant::now();
    let e = write_log(
        Simulator::new(&s, 1).unwrap(),
        Full { left: 10_000 },
        |_, _| {},
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "disk full");
    assert!(t.elapsed().as_secs_f64() < 2.0, "{:?}", t.elapsed());
}
