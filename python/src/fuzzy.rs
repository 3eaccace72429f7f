//! `strider.fuzzy.Engine`: a fuzzy engine (FLL text, or the engines a Rhai script builds,
//! layered as `strider fuzzy eval` layers them) evaluated over whole NumPy arrays by strider's
//! compiled inference, with the GIL released.

use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use rayon::prelude::*;

use strider::diagnostic::SourceError;
use strider::fuzzy::{Engine as FuzzyEngine, Network, fll};

use crate::{StriderError, error};

/// Fewest inputs per parallel piece of a stateless engine's evaluation.
const PIECE: usize = 4096;

/// Pieces per thread of the pool: enough that rayon evens out threads that finish early (rows
/// cost more where more rules fire), few enough that what each piece costs besides its rows (a
/// copy of the network, scratch columns) stays small.
const PIECES_PER_THREAD: usize = 4;

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

/// Evaluates `network` on the rows of `inputs` (one column per network input) into `outputs`
/// (one column per output, all of the same length): [`PIECES_PER_THREAD`] pieces per thread
/// (of [`PIECE`] rows at least) in parallel, each on its own copy of the network, or in order on
/// `network` itself when `stateful`.
fn evaluate(network: &mut Network, inputs: &[&[f64]], outputs: &mut [&mut [f64]], stateful: bool) {
    let rows = outputs.first().map_or(0, |c| c.len());
    if stateful || rows <= PIECE {
        network.process_columns(inputs, outputs);
        return;
    }
    let piece = PIECE.max(rows.div_ceil(PIECES_PER_THREAD * rayon::current_num_threads()));
    // Rows are independent: each piece gets the same rows of every column.
    let mut pieces: Vec<Vec<&mut [f64]>> = (0..rows.div_ceil(piece)).map(|_| Vec::new()).collect();
    for column in outputs.iter_mut() {
        for (parts, part) in pieces.iter_mut().zip(column.chunks_mut(piece)) {
            parts.push(part);
        }
    }
    let template = &*network;
    pieces.into_par_iter().enumerate().for_each_init(
        || template.clone(),
        |network, (p, mut outs)| {
            let span = p * piece..((p + 1) * piece).min(rows);
            let ins: Vec<&[f64]> = inputs.iter().map(|c| c.get(span.clone()).unwrap_or(&[])).collect();
            network.process_columns(&ins, &mut outs);
        },
    );
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
        let slices = columns.iter().map(|c| c.as_slice()).collect::<Result<Vec<&[f64]>, _>>();
        let inputs = slices.map_err(|_| StriderError::new_err("the input columns must be contiguous"))?;
        let rows = inputs.first().map_or(0, |c| c.len());
        if inputs.iter().any(|c| c.len() != rows) {
            return Err(StriderError::new_err("the input columns differ in length"));
        }
        let arrays: Vec<Bound<'py, PyArray1<f64>>> =
            (0..self.outputs.len()).map(|_| PyArray1::zeros(py, rows, false)).collect();
        // SAFETY: the arrays were just made here and nothing else refers to them yet.
        let mut outputs: Vec<&mut [f64]> = arrays
            .iter()
            .map(|a| unsafe { a.as_slice_mut() })
            .collect::<Result<_, _>>()
            .map_err(|e| StriderError::new_err(e.to_string()))?;
        let stateful = self.stateful();
        let network = &mut self.network;
        py.detach(|| evaluate(network, &inputs, &mut outputs, stateful));
        Ok(arrays)
    }

    fn __repr__(&self) -> String {
        let names: Vec<&str> = self.engines.iter().map(|e| e.name.as_str()).collect();
        format!("Engine({}: inputs {:?}, outputs {:?})", names.join(" → "), self.inputs, self.outputs)
    }
}
