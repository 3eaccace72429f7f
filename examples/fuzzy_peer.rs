//! Inference throughput of strider's compiled engine in the format of the fuzzylite harness
//! (`benches/peers/fuzzylite_bench.cpp`), on the same inputs, so both can be compared line by
//! line (`benches/peers/fuzzylite.sh` runs the two).
//!
//! ```sh
//! cargo run --release --example fuzzy_peer -- SECONDS RESOLUTIONS ENGINE...
//! cargo run --release --example fuzzy_peer -- --export ENGINE   # print the engine as FLL
//! ```
//!
//! `RESOLUTIONS` is a comma-separated list (e.g. `100,200,500`): every integral defuzzifier is
//! set to each in turn. `ENGINE` is a `.fll` file or a `.rhai` script ending with one engine.
//! Inputs: 4096 rows per engine from a 64-bit LCG seeded with 1 (state = state ·
//! 6364136223846793005 + 1442695040888963407, value = top 53 bits / 2^53), one value per input
//! variable in order, scaled to its range; the first rows' outputs are printed as `check` lines.

use std::hint::black_box;
use std::time::Instant;

use strider::fuzzy::{Defuzzifier, Engine, Inference, fll};
use strider::script::{Limits, ScriptLog, load_engines};

const ROWS: usize = 4096;
const CHECKS: usize = 4;

struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 * (1.0 / 9007199254740992.0)
    }
}

fn load(path: &str) -> Result<Engine, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    if path.ends_with(".rhai") {
        let mut engines = load_engines(&text, path, Limits::default(), &ScriptLog::new()).map_err(|e| e.to_string())?;
        if engines.len() != 1 {
            return Err(format!("{path}: one engine expected, found {}", engines.len()));
        }
        Ok(engines.remove(0))
    } else {
        fll::import(&text, path).map_err(|e| e.to_string())
    }
}

fn with_resolution(engine: &Engine, resolution: usize) -> Engine {
    let mut e = engine.clone();
    for out in &mut e.outputs {
        out.defuzzifier = out.defuzzifier.map(|d| match d {
            Defuzzifier::Centroid { .. } => Defuzzifier::Centroid { resolution },
            Defuzzifier::Bisector { .. } => Defuzzifier::Bisector { resolution },
            Defuzzifier::SmallestOfMaximum { .. } => Defuzzifier::SmallestOfMaximum { resolution },
            Defuzzifier::LargestOfMaximum { .. } => Defuzzifier::LargestOfMaximum { resolution },
            Defuzzifier::MeanOfMaximum { .. } => Defuzzifier::MeanOfMaximum { resolution },
            weighted => weighted,
        });
    }
    e
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, path] = args.as_slice()
        && flag == "--export"
    {
        print!("{}", fll::export(&load(path)?));
        return Ok(());
    }
    let [seconds, resolutions, files @ ..] = args.as_slice() else {
        return Err("usage: fuzzy_peer SECONDS RESOLUTIONS ENGINE... | fuzzy_peer --export ENGINE".into());
    };
    let seconds: f64 = seconds.parse().map_err(|_| format!("bad SECONDS '{seconds}'"))?;
    let resolutions: Vec<usize> = resolutions
        .split(',')
        .map(|r| r.parse().map_err(|_| format!("bad resolution '{r}'")))
        .collect::<Result<_, _>>()?;
    for path in files {
        let engine = load(path)?;
        let mut rng = Lcg(1);
        let rows: Vec<Vec<f64>> = (0..ROWS)
            .map(|_| engine.inputs.iter().map(|v| v.minimum + rng.next() * (v.maximum - v.minimum)).collect())
            .collect();
        for &resolution in &resolutions {
            let mut inf = Inference::new(&with_resolution(&engine, resolution)).map_err(|e| e.message)?;
            for (r, row) in rows.iter().take(CHECKS).enumerate() {
                inf.set_inputs(row);
                inf.process();
                let ins: Vec<String> = row.iter().map(|x| format!("{x:.17e}")).collect();
                let outs: Vec<String> = inf.outputs().iter().map(|y| format!("{y:.17e}")).collect();
                println!("check {} {resolution} {r} in {} out {}", engine.name, ins.join(" "), outs.join(" "));
            }
            let start = Instant::now();
            let (mut count, mut elapsed, mut sink) = (0u64, 0.0, 0.0);
            while elapsed < seconds {
                for row in &rows {
                    inf.set_inputs(black_box(row));
                    inf.process();
                    sink += inf.outputs()[0];
                }
                count += ROWS as u64;
                elapsed = start.elapsed().as_secs_f64();
            }
            black_box(sink);
            println!(
                "strider   {:<10} resolution {resolution:>4}: {:>10.0} inferences/s ({count} in {elapsed:.3} s)",
                engine.name,
                count as f64 / elapsed
            );
        }
    }
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("{e}");
        std::process::exit(2);
    }
}
