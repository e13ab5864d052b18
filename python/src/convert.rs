//! Reports to Python without JSON text or lists of numbers: a serde value becomes dicts, lists
//! and scalars, and every array of numbers a float64 `numpy.ndarray` — 1-D for a list of numbers,
//! (N, k) for a list of equal-length number lists (points are (N, 2), mm).
use ncgear::math::Point;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString};
use serde_json::Value;

/// Points `[x, y]` (mm) as a float64 array of shape (N, 2), without a list between.
pub fn points<'py>(py: Python<'py>, pts: &[Point]) -> Bound<'py, PyAny> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    Array2::from_shape_vec((pts.len(), 2), flat)
        .expect("N × 2 values")
        .into_pyarray(py)
        .into_any()
}

/// The numbers of `a`, when every element is one.
fn numbers(a: &[Value]) -> Option<Vec<f64>> {
    a.iter().map(Value::as_f64).collect()
}

/// The rows of `a` as one (N, k) array, when every element is a list of k numbers (k ≥ 1).
fn matrix(a: &[Value]) -> Option<Array2<f64>> {
    let k = a.first()?.as_array()?.len();
    let mut flat = Vec::with_capacity(a.len() * k);
    for row in a {
        let row = row.as_array().filter(|r| r.len() == k && k > 0)?;
        flat.extend(numbers(row)?);
    }
    Array2::from_shape_vec((a.len(), k), flat).ok()
}

/// A JSON array: a numpy array when it holds numbers (see the module doc), else a list.
fn array<'py>(py: Python<'py>, a: &[Value]) -> PyResult<Bound<'py, PyAny>> {
    if !a.is_empty() {
        if let Some(v) = numbers(a) {
            return Ok(PyArray1::from_vec(py, v).into_any());
        }
        if let Some(m) = matrix(a) {
            return Ok(m.into_pyarray(py).into_any());
        }
    }
    let items = a
        .iter()
        .map(|x| to_py(py, x))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(PyList::new(py, items)?.into_any())
}

/// `v` as Python objects (`null` is `None`: serde writes a non-finite number as `null`).
pub fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match n.as_i64() {
            Some(i) => i.into_pyobject(py)?.into_any(),
            None => PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => array(py, a)?,
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}
