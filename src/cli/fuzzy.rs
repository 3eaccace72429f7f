//! `strider fuzzy …`: evaluate, export, plot and benchmark fuzzy engines given as FLL files or
//! Rhai scripts (seed 000 §3.1), and the built-in default scenario.

use std::fmt::Write as _;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, anyhow, bail};
use clap::{Subcommand, ValueEnum};

use crate::diagnostic::SourceError;
use crate::files::{self, write_atomic};
use crate::fuzzy::reference::Reference;
use crate::fuzzy::{Engine, Inference, Network, fll};
use crate::load::{Failure, Outcome};
use crate::render::plot::{self, SurfaceFigure, TermCurve, VariableFigure};
use crate::render::png::parse_size;
use crate::script::{self, Limits, ScriptLog};

/// The single-engine navigation rules (Fig 1's variables), built into the binary.
pub const SIMPLE_NAV_SCRIPT: &str = include_str!("../../scripts/simple_nav.rhai");

/// Fuzzy subcommands.
#[derive(Debug, Subcommand)]
pub enum FuzzyCommand {
    /// Evaluate an engine on input rows (CSV) or on a grid, print CSV.
    Eval {
        /// A `.fll` file or a `.rhai` script.
        engine: PathBuf,
        /// CSV whose header names input variables; without it, a grid of ⌊1024^(1/inputs)⌋
        /// points per input.
        #[arg(long)]
        inputs: Option<PathBuf>,
        /// Which engine of a script that builds several (default: all, layered).
        #[arg(long = "engine", value_name = "NAME")]
        only: Option<String>,
    },
    /// Print an engine in another format.
    Export {
        /// A `.fll` file or a `.rhai` script.
        engine: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Fll)]
        format: Format,
        /// Which engine of a script that builds several.
        #[arg(long = "engine", value_name = "NAME")]
        only: Option<String>,
    },
    /// Write PNG plots of every variable's terms and of each output's control surface.
    Plot {
        /// A `.fll` file or a `.rhai` script.
        engine: PathBuf,
        /// Directory for the PNG files (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Image size, WIDTHxHEIGHT.
        #[arg(long, default_value = "800x500", value_parser = parse_size)]
        size: (u32, u32),
        /// Which engine of a script that builds several (default: all, layered).
        #[arg(long = "engine", value_name = "NAME")]
        only: Option<String>,
    },
    /// Measure inferences per second on one core, on seeded random inputs.
    Bench {
        /// A `.fll` file or a `.rhai` script.
        engine: PathBuf,
        /// How long to measure, in seconds.
        #[arg(long, default_value_t = 2.0)]
        seconds: f64,
        /// Seed of the random inputs.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// How many inputs to check against the naive reference evaluation.
        #[arg(long, default_value_t = 2000)]
        check: usize,
        /// Which engine of a script that builds several.
        #[arg(long = "engine", value_name = "NAME")]
        only: Option<String>,
    },
}

/// Export formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The FuzzyLite Language.
    Fll,
}

/// Runs a fuzzy subcommand.
pub fn run(command: FuzzyCommand) -> Outcome {
    match command {
        FuzzyCommand::Eval { engine, inputs, only } => eval(&engine, inputs.as_deref(), only.as_deref()),
        FuzzyCommand::Export { engine, format: Format::Fll, only } => {
            let engines = load_engines(&engine, only.as_deref())?;
            if engines.len() > 1 {
                let names: Vec<&str> = engines.iter().map(|e| e.name.as_str()).collect();
                return Err(anyhow!(
                    "{} builds {} engines ({}); an FLL file holds one: choose with --engine NAME",
                    engine.display(),
                    engines.len(),
                    names.join(", ")
                )
                .into());
            }
            let mut out = io::stdout().lock();
            out.write_all(fll::export(&engines[0]).as_bytes())?;
            Ok(())
        }
        FuzzyCommand::Plot { engine, out, size, only } => plot_engines(&engine, &out, size, only.as_deref()),
        FuzzyCommand::Bench { engine, seconds, seed, check, only } => {
            if !(seconds > 0.0 && seconds <= 3600.0) {
                return Err(anyhow!("--seconds must be in (0, 3600], found {seconds}").into());
            }
            if check > MAX_CHECK {
                return Err(anyhow!("--check must be at most {MAX_CHECK}, found {check}").into());
            }
            let engines = load_engines(&engine, only.as_deref())?;
            let report = bench(&engines, seconds, seed, check)?;
            files::write_stdout(format_args!("{report}"))?;
            Ok(())
        }
    }
}

/// Most inputs `fuzzy bench --check` compares with the naive reference evaluation.
pub const MAX_CHECK: usize = 1_000_000;

/// Most variables `fuzzy plot` draws (one picture each).
pub const MAX_PLOTTED_VARIABLES: usize = 256;

/// Reads engines from a `.fll` file or a `.rhai` script; `only` keeps one by name.
pub fn load_engines(path: &Path, only: Option<&str>) -> Result<Vec<Engine>, Failure> {
    let file = path.display().to_string();
    let text = files::read_text(path)?;
    let engines = match path.extension().and_then(|e| e.to_str()) {
        Some("fll") => vec![fll::import(&text, &file)?],
        Some("rhai") => load_script(&text, &file)?,
        _ => return Err(anyhow!("{file}: expected a .fll file or a .rhai script").into()),
    };
    match only {
        None => Ok(engines),
        Some(name) => match engines.into_iter().find(|e| e.name == name) {
            Some(e) => Ok(vec![e]),
            None => Err(anyhow!("{file} builds no engine named '{name}'").into()),
        },
    }
}

fn load_script(text: &str, file: &str) -> Result<Vec<Engine>, SourceError> {
    let log = ScriptLog::new();
    let result = script::load_engines(text, file, Limits::default(), &log);
    for line in log.lines() {
        eprintln!("{file}: {line}");
    }
    result
}

/// Points per input of the default grid: ⌊1024^(1/inputs)⌋, at least 1.
pub fn grid_points(inputs: usize) -> usize {
    if inputs == 0 {
        return 1;
    }
    (1024f64.powf(1.0 / inputs as f64) as usize).max(1)
}

/// The default evaluation grid: each input from its minimum to its maximum in
/// [`grid_points`] steps, the last input varying fastest.
pub fn grid(ranges: &[(String, f64, f64)]) -> anyhow::Result<Vec<Vec<f64>>> {
    for (name, lo, hi) in ranges {
        if !(lo.is_finite() && hi.is_finite()) {
            bail!("input '{name}' has an unbounded range [{lo}, {hi}]; give input rows with --inputs");
        }
    }
    let n = grid_points(ranges.len());
    let total = n.pow(ranges.len() as u32);
    let mut rows = Vec::with_capacity(total);
    for k in 0..total {
        let mut row = vec![0.0; ranges.len()];
        let mut rest = k;
        for (i, (_, lo, hi)) in ranges.iter().enumerate().rev() {
            let step = rest % n;
            rest /= n;
            let dx = (hi - lo) / (n.max(2) - 1) as f64;
            row[i] = lo + step as f64 * dx;
        }
        rows.push(row);
    }
    Ok(rows)
}

fn input_ranges(engines: &[Engine], net: &Network) -> Vec<(String, f64, f64)> {
    net.input_names()
        .map(|name| {
            let var = engines.iter().flat_map(|e| &e.inputs).find(|v| v.name == name);
            let (lo, hi) = var.map_or((f64::NAN, f64::NAN), |v| (v.minimum, v.maximum));
            (name.to_string(), lo, hi)
        })
        .collect()
}

/// Reads input rows from CSV text whose header names the network inputs (any order). Inputs
/// without a column are NaN in every row; their names are returned with the rows.
pub fn read_inputs_csv(text: &str, file: &str, names: &[String]) -> Result<(Vec<Vec<f64>>, Vec<String>), SourceError> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((hl, header)) = lines.next() else {
        return Err(SourceError::new(file, 1, 1, "empty file: expected a header naming the input variables"));
    };
    let mut columns = Vec::new();
    let mut col = 1;
    for field in header.split(',') {
        let name = field.trim();
        let Some(index) = names.iter().position(|n| n == name) else {
            return Err(SourceError::new(
                file,
                hl + 1,
                col,
                format!("'{name}' is not an input variable (inputs: {})", names.join(", ")),
            ));
        };
        if columns.contains(&index) {
            return Err(SourceError::new(file, hl + 1, col, format!("column '{name}' appears twice")));
        }
        columns.push(index);
        col += field.chars().count() + 1;
    }
    let missing: Vec<String> = (0..names.len()).filter(|i| !columns.contains(i)).map(|i| names[i].clone()).collect();
    let mut rows = Vec::new();
    for (ln, line) in lines {
        let mut row = vec![f64::NAN; names.len()];
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != columns.len() {
            return Err(SourceError::new(
                file,
                ln + 1,
                1,
                format!("expected {} values, found {}", columns.len(), fields.len()),
            ));
        }
        let mut col = 1;
        for (field, &index) in fields.iter().zip(&columns) {
            let v = crate::lex::parse_number(field.trim())
                .ok_or_else(|| SourceError::new(file, ln + 1, col, format!("'{}' is not a number", field.trim())))?;
            row[index] = v;
            col += field.chars().count() + 1;
        }
        rows.push(row);
    }
    Ok((rows, missing))
}

/// Formats a value for CSV output: shortest exact decimal, `nan`, `inf`, `-inf`.
fn csv_number(x: f64) -> String {
    crate::lex::number(x)
}

fn eval(path: &Path, inputs: Option<&Path>, only: Option<&str>) -> Outcome {
    let engines = load_engines(path, only)?;
    let mut net = Network::new(&engines).map_err(|e| anyhow!("{}: {}", path.display(), e.message))?;
    let names: Vec<String> = net.input_names().map(str::to_string).collect();
    let rows = match inputs {
        Some(csv) => {
            let file = csv.display().to_string();
            let text = files::read_text(csv)?;
            let (rows, missing) = read_inputs_csv(&text, &file, &names)?;
            for name in missing {
                eprintln!("warning: {file} has no column for input '{name}'; it is NaN in every row");
            }
            rows
        }
        None => grid(&input_ranges(&engines, &net))?,
    };
    let outputs: Vec<String> = net.output_names().map(str::to_string).collect();
    let mut out = BufWriter::new(io::stdout().lock());
    let header: Vec<&str> = names.iter().chain(&outputs).map(String::as_str).collect();
    writeln!(out, "{}", header.join(","))?;
    let mut line = String::new();
    for row in rows {
        net.process(&row);
        line.clear();
        for (i, v) in row.iter().copied().chain(outputs.iter().map(|o| net.output(o).unwrap_or(f64::NAN))).enumerate() {
            if i > 0 {
                line.push(',');
            }
            line.push_str(&csv_number(v));
        }
        writeln!(out, "{line}")?;
    }
    out.flush()?;
    Ok(())
}

/// Samples every term of a variable for plotting.
fn curves(terms: &[crate::fuzzy::NamedTerm], lo: f64, hi: f64) -> Vec<TermCurve> {
    let n = 400;
    terms
        .iter()
        .map(|t| TermCurve {
            name: t.name.clone(),
            points: (0..=n)
                .map(|i| {
                    let x = lo + (hi - lo) * i as f64 / n as f64;
                    (x, t.term.membership(x))
                })
                .collect(),
        })
        .collect()
}

fn plot_engines(path: &Path, out: &Path, (w, h): (u32, u32), only: Option<&str>) -> Outcome {
    let engines = load_engines(path, only)?;
    let variables: usize = engines.iter().map(|e| e.inputs.len() + e.outputs.len()).sum();
    if variables > MAX_PLOTTED_VARIABLES {
        return Err(anyhow!(
            "{}: {variables} variables to plot, one picture each; at most {MAX_PLOTTED_VARIABLES} are drawn \
             (choose an engine with --engine NAME)",
            path.display()
        )
        .into());
    }
    let mut net = Network::new(&engines).map_err(|e| anyhow!("{}: {}", path.display(), e.message))?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut written = Vec::new();
    let mut save = |name: String, pixmap: tiny_skia::Pixmap| -> Outcome {
        let file = out.join(name);
        let png = pixmap.encode_png().map_err(|e| anyhow!("cannot encode {}: {e}", file.display()))?;
        write_atomic(&file, &png).with_context(|| format!("cannot write {}", file.display()))?;
        written.push(file);
        Ok(())
    };
    for e in &engines {
        for v in &e.inputs {
            let (lo, hi) = finite_range(v.minimum, v.maximum);
            let fig = VariableFigure {
                title: format!("{}: input {}", e.name, v.name),
                range: (lo, hi),
                curves: curves(&v.terms, lo, hi),
            };
            save(format!("{}_input_{}.png", e.name, v.name), plot::plot_variable(&fig, w, h))?;
        }
        for v in &e.outputs {
            let fig = VariableFigure {
                title: format!("{}: output {}", e.name, v.name),
                range: (v.minimum, v.maximum),
                curves: curves(&v.terms, v.minimum, v.maximum),
            };
            save(format!("{}_output_{}.png", e.name, v.name), plot::plot_variable(&fig, w, h))?;
        }
    }
    // Control surfaces over the first two network inputs (others at mid-range).
    let ranges: Vec<(String, f64, f64)> = input_ranges(&engines, &net)
        .into_iter()
        .map(|(n, lo, hi)| {
            let (lo, hi) = finite_range(lo, hi);
            (n, lo, hi)
        })
        .collect();
    let outputs: Vec<String> = net.output_names().map(str::to_string).collect();
    if ranges.len() >= 2 {
        let (nx, ny) = (81, 81);
        let mid: Vec<f64> = ranges.iter().map(|(_, lo, hi)| 0.5 * (lo + hi)).collect();
        let mut values = vec![Vec::with_capacity(nx * ny); outputs.len()];
        for j in 0..ny {
            for i in 0..nx {
                let mut row = mid.clone();
                row[0] = ranges[0].1 + (ranges[0].2 - ranges[0].1) * i as f64 / (nx - 1) as f64;
                row[1] = ranges[1].1 + (ranges[1].2 - ranges[1].1) * j as f64 / (ny - 1) as f64;
                net.process(&row);
                for (k, o) in outputs.iter().enumerate() {
                    values[k].push(net.output(o).unwrap_or(f64::NAN));
                }
            }
        }
        for (o, values) in outputs.iter().zip(values) {
            let fig = SurfaceFigure {
                title: format!("{o} over {} and {}", ranges[0].0, ranges[1].0),
                x_name: ranges[0].0.clone(),
                x_range: (ranges[0].1, ranges[0].2),
                nx,
                y_name: ranges[1].0.clone(),
                y_range: (ranges[1].1, ranges[1].2),
                ny,
                z_name: o.clone(),
                values,
            };
            save(format!("surface_{o}.png"), plot::plot_surface(&fig, w, h))?;
        }
    } else if ranges.len() == 1 {
        let (name, lo, hi) = &ranges[0];
        let n = 400;
        let mut curves: Vec<TermCurve> =
            outputs.iter().map(|o| TermCurve { name: o.clone(), points: Vec::new() }).collect();
        for i in 0..=n {
            let x = lo + (hi - lo) * i as f64 / n as f64;
            net.process(&[x]);
            for (c, o) in curves.iter_mut().zip(&outputs) {
                c.points.push((x, net.output(o).unwrap_or(f64::NAN)));
            }
        }
        for c in curves {
            let v = engines.iter().flat_map(|e| &e.outputs).find(|v| v.name == c.name);
            let (ylo, yhi) = v.map_or((0.0, 1.0), |v| finite_range(v.minimum, v.maximum));
            let scaled = TermCurve {
                name: c.name.clone(),
                points: c.points.iter().map(|&(x, y)| (x, (y - ylo) / (yhi - ylo))).collect(),
            };
            let fig = VariableFigure {
                title: format!("{} over {name} (scaled to its range [{ylo}, {yhi}])", c.name),
                range: (*lo, *hi),
                curves: vec![scaled],
            };
            save(format!("surface_{}.png", c.name), plot::plot_variable(&fig, w, h))?;
        }
    }
    for f in written {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

/// A finite plotting range for a variable whose range may be unbounded.
fn finite_range(lo: f64, hi: f64) -> (f64, f64) {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (lo, hi),
        (true, false) => (lo, lo + 10.0),
        (false, true) => (hi - 10.0, hi),
        (false, false) => (-10.0, 10.0),
    }
}

/// Benchmarks inference on seeded random inputs and checks the compiled engine against the
/// naive reference. Returns the report text.
pub fn bench(engines: &[Engine], seconds: f64, seed: u64, check: usize) -> Result<String, Failure> {
    let mut net = Network::new(engines).map_err(|e| anyhow!("{}", e.message))?;
    let ranges = input_ranges(engines, &net);
    let mut rng = crate::rng::stream(seed, 0, 0);
    let samples: Vec<Vec<f64>> = (0..4096)
        .map(|_| {
            ranges
                .iter()
                .map(|(_, lo, hi)| {
                    let (lo, hi) = finite_range(*lo, *hi);
                    crate::rng::uniform(&mut rng, lo, hi)
                })
                .collect()
        })
        .collect();
    // Agreement with the naive evaluation (single-engine files; layered ones stage by stage).
    let mut max_diff: f64 = 0.0;
    let mut compared = 0usize;
    if engines.len() == 1 {
        let mut fast = Inference::new(&engines[0]).map_err(|e| anyhow!("{}", e.message))?;
        let mut naive = Reference::new(&engines[0]).map_err(|e| anyhow!("{}", e.message))?;
        for row in samples.iter().cycle().take(check) {
            fast.set_inputs(row);
            fast.process();
            let expected = naive.process(row);
            for (a, b) in fast.outputs().iter().zip(expected) {
                if a.is_nan() != b.is_nan() {
                    max_diff = f64::INFINITY;
                } else if !a.is_nan() {
                    max_diff = max_diff.max((a - b).abs());
                }
            }
            compared += 1;
        }
    }
    // Throughput on one thread.
    let start = Instant::now();
    let mut count: u64 = 0;
    let mut sink = 0.0;
    while start.elapsed().as_secs_f64() < seconds {
        for row in &samples {
            net.process(row);
        }
        sink += net.stages().last().map_or(0.0, |s| s.outputs().first().copied().unwrap_or(0.0));
        count += samples.len() as u64;
    }
    let elapsed = start.elapsed().as_secs_f64();
    std::hint::black_box(sink);
    let rate = count as f64 / elapsed;
    let e = &engines[0];
    let mut report = String::new();
    let rules: usize = engines.iter().map(Engine::rule_count).sum();
    let _ = writeln!(
        report,
        "engine: {} ({:?}, {} inputs, {} outputs, {rules} rules, {} stage(s))",
        e.name,
        e.kind(),
        ranges.len(),
        net.output_names().count(),
        engines.len()
    );
    let _ = writeln!(report, "inferences: {count} in {elapsed:.3} s on one thread");
    let _ = writeln!(report, "inferences per second: {rate:.0}");
    if compared > 0 {
        let _ = writeln!(report, "max |compiled - reference| over {compared} inputs: {max_diff:e}");
        if max_diff > 1e-9 {
            return Err(Failure::Task(anyhow!("{report}compiled engine disagrees with the reference evaluation")));
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_matches_the_dataset_convention() {
        assert_eq!(grid_points(1), 1024);
        assert_eq!(grid_points(2), 32);
        assert_eq!(grid_points(3), 10);
        let rows = grid(&[("a".into(), 0.0, 31.0), ("b".into(), -1.0, 1.0)]).unwrap();
        assert_eq!(rows.len(), 1024);
        assert_eq!(rows[0], vec![0.0, -1.0]);
        assert_eq!(rows[1][0], 0.0);
        assert_eq!(rows[31], vec![0.0, 1.0]);
        assert_eq!(rows[32][0], 1.0);
        assert!(grid(&[("a".into(), f64::NEG_INFINITY, 0.0)]).is_err());
    }

    #[test]
    fn csv_inputs_are_checked() {
        let names = vec!["a".to_string(), "b".to_string()];
        let (rows, missing) = read_inputs_csv("b,a\n1,2\nnan,3\n", "in.csv", &names).unwrap();
        assert!(missing.is_empty());
        assert_eq!(rows[0], vec![2.0, 1.0]);
        assert!(rows[1][1].is_nan());
        let err = read_inputs_csv("a,c\n1,2\n", "in.csv", &names).unwrap_err();
        assert_eq!((err.line, err.col), (1, 3));
        let err = read_inputs_csv("a,b\n1,x\n", "in.csv", &names).unwrap_err();
        assert_eq!((err.line, err.col), (2, 3));
        let (rows, missing) = read_inputs_csv("a\n1\n", "in.csv", &names).unwrap();
        assert!(rows[0][1].is_nan());
        assert_eq!(missing, vec!["b".to_string()]);
        assert!(read_inputs_csv("a\n1,2\n", "in.csv", &names).is_err());
        assert!(read_inputs_csv("", "in.csv", &names).is_err());
    }

    #[test]
    fn default_script_builds_the_benchmark_shaped_engine() {
        let engines = load_script(SIMPLE_NAV_SCRIPT, "simple_nav.rhai").unwrap();
        let e = &engines[0];
        assert_eq!((e.inputs.len(), e.outputs.len(), e.rule_count()), (2, 2, 15));
        assert!(Inference::new(e).is_ok());
    }
}
