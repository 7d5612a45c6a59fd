// Scratch (not committed): can the log tell the gyro's bias walk?
use pendtilt::tune::kalman::{innovation_pass, KalmanData};
use pendtilt::tune::reference::integral;
use pendtilt::tune::search::Budget;
use pendtilt::tune::surrogate::{self, GyroErrors, Surrogate};
use pendtilt::tune::zoo::ride;
use pendtilt::tune::zoo::score::RideLog;
use pendtilt::tune::{tune, Options, Start};
use pendtilt_core::estimators::alg2::Alg2;
use pendtilt_core::kalman::tilt::UNUSABLE;
use pendtilt_core::kalman::KalmanSettings;
use pendtilt_core::Estimator;

fn slope(t: &[f64], y: &[f64]) -> f64 {
    let n = t.len() as f64;
    let (mt, my) = (t.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let stt: f64 = t.iter().map(|a| (a - mt).powi(2)).sum();
    t.iter()
        .zip(y)
        .map(|(a, b)| (a - mt) * (b - my))
        .sum::<f64>()
        / stt
}

fn main() {
    let a: Vec<u64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    for k in a[0]..=a[1] {
        let r = ride(k, 40.0);
        let log = RideLog::simulate(&r.scenario, k);
        let rig = r.scenario.rig().unwrap();
        let start = Start::from_rig(&rig);
        let t = tune(&log.samples, &start, &Options::default());
        let mut a2s = start.alg2;
        a2s.front_end.differentiator = t.differentiator;
        let mut a2 = Alg2::<f64>::new(a2s);
        let z: Vec<f64> = log
            .samples
            .iter()
            .map(|s| {
                let m = a2.update(s);
                if m.flags.intersects(UNUSABLE) {
                    f64::NAN
                } else {
                    m.theta
                }
            })
            .collect();
        let gb = t.gyro.as_ref().unwrap();
        let bias = gb.bias.unwrap();
        let reference = integral(&log.samples, bias);
        // one-second means of d = z - integral, after the burn-in
        let w = 1000;
        let mut tm = Vec::new();
        let mut dm = Vec::new();
        for (i, c) in z.chunks(w).enumerate().skip(2) {
            let rr = &reference[i * w..i * w + c.len()];
            let v: Vec<f64> = c
                .iter()
                .zip(rr)
                .map(|(a, b)| a - b)
                .filter(|x| x.is_finite())
                .collect();
            if v.len() * 2 > w {
                tm.push(i as f64 + 0.5);
                dm.push(v.iter().sum::<f64>() / v.len() as f64);
            }
        }
        let mut line = String::new();
        let mut ests = Vec::new();
        for seg in [6usize, tm.len() / 4, 12] {
            let sl: Vec<f64> = tm
                .chunks(seg)
                .zip(dm.chunks(seg))
                .filter(|(a, _)| a.len() == seg)
                .map(|(a, b)| slope(a, b))
                .collect();
            let diffs: Vec<f64> = sl.windows(2).map(|p| (p[1] - p[0]).powi(2)).collect();
            let west =
                (diffs.iter().sum::<f64>() / diffs.len() as f64 / (2.0 * seg as f64 / 3.0)).sqrt();
            ests.push(west);
            line += &format!(" L{seg}: {west:.1e}");
        }
        let dt: Vec<f64> = log.samples.iter().map(|s| s.dt).collect();
        let gyro: Vec<f64> = log.samples.iter().map(|s| s.gyro).collect();
        let d = KalmanData {
            dt: &dt,
            gyro: &gyro,
            z: &z,
        };
        let true_rms = |x: &[f64]| {
            let s = KalmanSettings {
                q_angle: x[0],
                q_bias: x[1],
                ..start.kalman
            };
            let (mut sum, mut n) = (0.0, 0usize);
            innovation_pass(&s, x[2], &d, |kk, th, _, _| {
                if kk >= log.skip && th.is_finite() {
                    sum += (th - log.truth[kk]).powi(2);
                    n += 1;
                }
            });
            (sum / n as f64).sqrt().to_degrees()
        };
        let def = start.ekf.sensors.gyro_bias_walk;
        let mut res = String::new();
        for wk in [def, ests[1].max(def), r.scenario.sensors.gyro.bias_walk] {
            let g = GyroErrors {
                bias,
                density: gb.density,
                bias_walk: wk,
            };
            let sur = Surrogate::new(&log.samples, &z, &g);
            let f = surrogate::fit(
                &start.kalman,
                start.kalman.r_pendulum,
                &sur,
                log.skip,
                &mut Budget::unlimited(),
            );
            res += &format!(" {:.4}", true_rms(&f.x));
        }
        println!(
            "ride {k:2}: true walk {:.1e} |{line} | kf_alg2 def-walk/est-walk/true-walk:{res}",
            r.scenario.sensors.gyro.bias_walk
        );
    }
}
