//! `strider.fuzzy.Engine`: a fuzzy engine (FLL text, or the engines a Rhai script builds,
//! layered as `strider fuzzy eval` layers them) evaluated over whole NumPy arrays by strider's
//! compiled inference, with the GIL released.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use rayon::prelude::*;

use strider::diagnostic::SourceError;
use strider::fuzzy::{Engine as FuzzyEngine, Network, fll};

use crate::{StriderError, error};

/// Inputs per parallel piece of a stateless engine's evaluation.
const PIECE: usize = 4096;

/// A fuzzy engine, or several layered into one network.
#[pyclass(module = "strider._strider")]
pub struct Engine {
    engines: Vec<FuzzyEngine>,
    network: Network,
    inputs: Vec<String>,
    outputs: Vec<String>,
}

impl Engine {
    fn of(py: Python<'_>, engines: Vec<FuzzyEngine>, file: &str) -> PyResult<Engine> {
        let network = Network::new(&engines).map_err(|e| error(py)(SourceError::new(file, 0, 0, e.message)))?;
        let inputs = network.input_names().map(str::to_string).collect();
        let outputs = network.output_names().map(str::to_string).collect();
        Ok(Engine { engines, network, inputs, outputs })
    }

    /// True when an output keeps its previous value when no rule fires: then each input row
    /// depends on the rows before it and rows are evaluated in order.
    fn stateful(&self) -> bool {
        self.engines.iter().flat_map(|e| &e.outputs).any(|o| o.lock_previous)
    }
}

/// Evaluates `network` on the rows of `columns` (one column per input, equal lengths) and
/// returns one column per output.
fn evaluate(network: &mut Network, columns: &[Vec<f64>], outputs: usize) -> Vec<Vec<f64>> {
    let rows = columns.first().map_or(0, Vec::len);
    let mut out = vec![vec![0.0; rows]; outputs];
    let mut row = vec![0.0; columns.len()];
    for r in 0..rows {
        for (x, c) in row.iter_mut().zip(columns) {
            *x = c[r];
        }
        network.process(&row);
        for (o, column) in out.iter_mut().enumerate() {
            column[r] = network.output_at(o);
        }
    }
    out
}

#[pymethods]
impl Engine {
    /// An engine from FuzzyLite Language text; `file` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, file="<fll>"))]
    fn from_fll(py: Python<'_>, text: &str, file: &str) -> PyResult<Engine> {
        let engine = fll::import(text, file).map_err(error(py))?;
        Engine::of(py, vec![engine], file)
    }

    /// The engines a Rhai script (or an `.fll` file) builds, layered in order (outputs feed
    /// later inputs of the same name); `engine` keeps only the one of that name.
    #[staticmethod]
    #[pyo3(signature = (path, engine=None))]
    fn from_rhai(py: Python<'_>, path: PathBuf, engine: Option<&str>) -> PyResult<Engine> {
        let engines = py.detach(|| strider::cli::fuzzy::load_engines(&path, engine)).map_err(error(py))?;
        Engine::of(py, engines, &path.display().to_string())
    }

    /// The names of the inputs, in order.
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.inputs.clone()
    }

    /// The names of the outputs, in order.
    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.outputs.clone()
    }

    /// The engine as FLL text (an engine only, not a layered network).
    fn to_fll(&self) -> PyResult<String> {
        match self.engines.as_slice() {
            [one] => Ok(fll::export(one)),
            many => Err(StriderError::new_err(format!(
                "this network layers {} engines; an FLL file holds one (load one with engine=NAME)",
                many.len()
            ))),
        }
    }

    /// Evaluates the engine on one row per index of the input columns (in `inputs` order,
    /// equal lengths) and returns the output columns (in `outputs` order).
    fn _process<'py>(
        &mut self,
        py: Python<'py>,
        columns: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        if columns.len() != self.inputs.len() {
            return Err(StriderError::new_err(format!(
                "expected {} input columns, found {}",
                self.inputs.len(),
                columns.len()
            )));
        }
        let columns: Vec<Vec<f64>> = columns.iter().map(|c| c.as_array().to_vec()).collect();
        let rows = columns.first().map_or(0, Vec::len);
        if columns.iter().any(|c| c.len() != rows) {
            return Err(StriderError::new_err("the input columns differ in length"));
        }
        let outputs = self.outputs.len();
        let stateful = self.stateful();
        let network = &mut self.network;
        let out = py.detach(|| {
            if stateful || rows <= PIECE {
                return evaluate(network, &columns, outputs);
            }
            // Rows are independent: evaluate pieces in parallel, each on its own copy.
            let pieces: Vec<Vec<Vec<f64>>> = (0..rows.div_ceil(PIECE))
                .into_par_iter()
                .map(|p| {
                    let span = p * PIECE..((p + 1) * PIECE).min(rows);
                    let piece: Vec<Vec<f64>> = columns.iter().map(|c| c[span.clone()].to_vec()).collect();
                    evaluate(&mut network.clone(), &piece, outputs)
                })
                .collect();
            (0..outputs).map(|o| pieces.iter().flat_map(|p| p[o].iter().copied()).collect()).collect()
        });
        Ok(out.into_iter().map(|c| c.into_pyarray(py)).collect())
    }

    fn __repr__(&self) -> String {
        let names: Vec<&str> = self.engines.iter().map(|e| e.name.as_str()).collect();
        format!("Engine({}: inputs {:?}, outputs {:?})", names.join(" → "), self.inputs, self.outputs)
    }
}
