//! The library alone, as the Python package's `estimate` runs it on a planar CSV: the
//! reader, every estimator, `pipeline::run_parallel`, and each estimate and flag kept in
//! memory, nothing written. Prints the rows and the wall time; `python/bench/overhead.py`
//! runs it as the peer the Python call is measured against, in the same run.
//!
//! `cargo run --release -p pendtilt --example estimate_in_memory -- LOG.csv [RIG.toml]`
use std::time::Instant;

use pendtilt::bank::planar::{Bank, BankSettings};
use pendtilt::config::RigConfig;
use pendtilt::io::{EstimatesWriter, LogReader, ReaderOptions};
use pendtilt::pipeline;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let log = args
        .next()
        .ok_or_else(|| anyhow::anyhow!("usage: LOG.csv [RIG.toml]"))?;
    let rig = match args.next() {
        Some(p) => RigConfig::load(std::path::Path::new(&p))?,
        None => RigConfig::default(),
    };
    let start = Instant::now();
    let mut reader = LogReader::open(&log, ReaderOptions::for_rig(&rig))?;
    let settings = BankSettings::from_rig(rig);
    let mut bank =
        Bank::new(&settings, pipeline::inputs_of(&reader), None).map_err(anyhow::Error::msg)?;
    let width = bank.names().len();
    let mut estimates: Vec<Vec<f64>> = vec![Vec::new(); width];
    let mut flags: Vec<Vec<u16>> = vec![Vec::new(); width];
    let each = |_: u64, _: &pendtilt::io::LogRecord, est: &[pendtilt_core::Estimate<f64>]| {
        for ((e, v), f) in est.iter().zip(&mut estimates).zip(&mut flags) {
            v.push(e.theta);
            f.push(e.flags.bits());
        }
    };
    let none = None::<&mut EstimatesWriter<std::io::Sink>>;
    let summary = pipeline::run_parallel(&mut reader, &mut bank, none, None, |_| {}, each)?;
    let elapsed = start.elapsed().as_secs_f64();
    assert_eq!(estimates[0].len() as u64, summary.rows);
    println!("{} rows, {width} estimators, {elapsed:.6} s", summary.rows);
    Ok(())
}
