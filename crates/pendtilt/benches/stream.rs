//! `pendtilt stream` latency: the time from one log line written to the command's standard
//! input to its estimate line read back from its standard output, through real pipes, one
//! line at a time (nothing else queued), planar (every planar estimator) and 3-D (every 3-D
//! estimator). The peer in the same run is `cat` on the same pipes: the floor the pipes and
//! the process switches set.
//!
//! `cargo bench -p pendtilt --bench stream`; criterion reports the time per line (the
//! median is the figure to compare with the 0.1 ms target, docs/performance.md).
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};

/// A running filter process and its pipes.
struct Piped {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
    line: String,
}

impl Piped {
    fn spawn(program: &str, args: &[&str], header: &str) -> Self {
        let mut child = Command::new(program)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn");
        let input = child.stdin.take().expect("stdin");
        let output = BufReader::new(child.stdout.take().expect("stdout"));
        let mut p = Self {
            child,
            input,
            output,
            line: String::new(),
        };
        p.round_trip(header);
        p
    }

    /// Writes one line and waits for the line it gives back.
    fn round_trip(&mut self, line: &str) {
        self.input.write_all(line.as_bytes()).expect("write");
        self.input.flush().expect("flush");
        self.line.clear();
        self.output.read_line(&mut self.line).expect("read");
        assert!(self.line.ends_with('\n'), "the command stopped");
    }
}

impl Drop for Piped {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Line `k` of a planar log at 1 kHz: a slow swing, as a rig would send it.
fn planar(k: u64) -> String {
    let t = k as f64 * 1e-3;
    let th = 0.1 * (2.0 * t).sin();
    format!(
        "{t},{},{},{},{},{th}\n",
        0.9 * th,
        0.2 * (2.0 * t).cos(),
        9.8 * th.sin(),
        9.8 * th.cos()
    )
}

/// Line `k` of a 3-D log at 1 kHz: a slow roll.
fn spatial(k: u64) -> String {
    let t = k as f64 * 1e-3;
    let r = 0.1 * (2.0 * t).sin();
    format!(
        "{t},{},0,{},0,0,0,{},{},{r},0\n",
        -0.9 * r,
        0.2 * (2.0 * t).cos(),
        9.8 * r.sin(),
        9.8 * r.cos()
    )
}

fn bench(c: &mut Criterion) {
    let exe = env!("CARGO_BIN_EXE_pendtilt");
    let mut g = c.benchmark_group("stream latency per line");
    g.measurement_time(Duration::from_secs(5));
    type Line = fn(u64) -> String;
    let cases: [(&str, &str, Vec<&str>, &str, Line); 3] = [
        (
            "cat (the floor of the pipes)",
            "cat",
            vec![],
            "t,phi,gyro,ax,ay,theta\n",
            planar,
        ),
        (
            "planar, every estimator",
            exe,
            vec!["stream", "-q"],
            "t,phi,gyro,ax,ay,theta\n",
            planar,
        ),
        (
            "3-D, every estimator",
            exe,
            vec!["stream", "-q"],
            "t,phi_x,phi_y,gyro_x,gyro_y,gyro_z,ax,ay,az,roll,pitch\n",
            spatial,
        ),
    ];
    for (name, program, args, header, line) in cases {
        let mut p = Piped::spawn(program, &args, header);
        let mut k = 0u64;
        g.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let lines: Vec<String> = (0..iters).map(|i| line(k + i)).collect();
                k += iters;
                let start = Instant::now();
                for l in &lines {
                    p.round_trip(l);
                }
                start.elapsed()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
