//! Python arguments to engine values, each bad one a `ValueError` that names it.
//!
//! PyO3's own extraction raises `TypeError` ("argument 'dim': 'float' object cannot be
//! interpreted as an integer"); the API promises a `ValueError` naming the field and the
//! value for every bad argument, so the entry points take `PyAny` and convert here.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict, PyString};

/// `ValueError("invalid {field} = {repr}: must be {expected}")`.
pub(crate) fn invalid(field: &str, value: &Bound<'_, PyAny>, expected: &str) -> PyErr {
    let text = value.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
    PyValueError::new_err(format!(
        "invalid {field} = {}: must be {expected}",
        physstep::error::one_line(&text)
    ))
}

/// A real number (int, float, numpy scalar; not bool or str).
pub(crate) fn float(o: &Bound<'_, PyAny>, field: &str) -> PyResult<f64> {
    if o.is_instance_of::<PyString>() || o.is_instance_of::<pyo3::types::PyBool>() {
        return Err(invalid(field, o, "a number"));
    }
    o.extract::<f64>().map_err(|_| invalid(field, o, "a number"))
}

/// A whole number in `[lo, hi]` (int or numpy integer; not float or bool).
pub(crate) fn whole(o: &Bound<'_, PyAny>, field: &str, lo: i64, hi: i64) -> PyResult<i64> {
    let expected = || format!("a whole number from {lo} to {hi}");
    if o.is_instance_of::<pyo3::types::PyBool>() {
        return Err(invalid(field, o, &expected()));
    }
    match o.extract::<i64>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        // A handle's `__index__` refusing (its entity was removed, or it is another World's)
        // says so itself, naming it.
        Err(e) if e.is_instance_of::<pyo3::exceptions::PyValueError>(o.py()) => Err(e),
        _ => Err(invalid(field, o, &expected())),
    }
}

/// A count `>= 0` that fits the engine's u64.
pub(crate) fn count(o: &Bound<'_, PyAny>, field: &str) -> PyResult<u64> {
    whole(o, field, 0, i64::MAX).map(|v| v as u64)
}

/// A particle index.
pub(crate) fn index(o: &Bound<'_, PyAny>, field: &str) -> PyResult<usize> {
    whole(o, field, 0, i64::MAX).map(|v| v as usize).map_err(|e| {
        if crate::entity_handle::is_handle(o) {
            e
        } else {
            invalid(field, o, "a particle index >= 0")
        }
    })
}

/// A flag (bool or numpy bool).
pub(crate) fn flag(o: &Bound<'_, PyAny>, field: &str) -> PyResult<bool> {
    o.extract::<bool>().map_err(|_| invalid(field, o, "True or False"))
}

/// A string (a name).
pub(crate) fn text(o: &Bound<'_, PyAny>, field: &str) -> PyResult<String> {
    o.extract::<String>().map_err(|_| invalid(field, o, "a string"))
}

/// Bytes from `bytes`, `bytearray` or `memoryview`.
pub(crate) fn bytes(o: &Bound<'_, PyAny>, field: &str) -> PyResult<Vec<u8>> {
    if let Ok(b) = o.cast::<PyBytes>() {
        return Ok(b.as_bytes().to_vec());
    }
    if let Ok(b) = o.cast::<PyByteArray>() {
        return Ok(b.to_vec());
    }
    if let Ok(b) = o.call_method0("tobytes") {
        if let Ok(b) = b.cast::<PyBytes>() {
            return Ok(b.as_bytes().to_vec());
        }
    }
    Err(invalid(field, o, "bytes (from World.snapshot())"))
}

/// Scene parameters: a dict `{name: number}` or pairs `[(name, number), ...]`; `None` is none.
pub(crate) fn params(o: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, f64)>> {
    let Some(o) = o.filter(|o| !o.is_none()) else { return Ok(Vec::new()) };
    let pairs: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)> = if let Ok(d) = o.cast::<PyDict>() {
        d.iter().collect()
    } else {
        o.try_iter()
            .and_then(|it| it.map(|p| p.and_then(|p| p.extract())).collect::<PyResult<Vec<_>>>())
            .map_err(|_| invalid("params", o, "a dict of name: number"))?
    };
    pairs
        .iter()
        .map(|(k, v)| {
            let name = text(k, "params key")?;
            let value = float(v, &format!("params['{}']", physstep::error::one_line(&name)))?;
            Ok((name, value))
        })
        .collect()
}

/// A vector argument of `dim` finite components, named `field` in errors.
pub(crate) fn vector(o: &Bound<'_, PyAny>, field: &str, dim: usize) -> PyResult<[f64; 3]> {
    let v = array(o, field, Some(dim), None)?;
    if let Some(i) = v.iter().position(|c| !c.is_finite()) {
        return Err(PyValueError::new_err(format!("invalid {field}[{i}] = {}: must be finite", v[i])));
    }
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(&v);
    Ok(out)
}

/// A shape as Python prints it: `(4,)`, `(3, 2)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// Any array-like (numpy array, nested lists) as float64 data of the wanted shape: `cols =
/// Some(dim)` for an `(n, dim)` matrix, `None` for a vector; `rows` fixes `n` (the length of
/// a vector).
pub(crate) fn array(
    obj: &Bound<'_, PyAny>,
    field: &str,
    rows: Option<usize>,
    cols: Option<usize>,
) -> PyResult<Vec<f64>> {
    let py = obj.py();
    let want = match (rows, cols) {
        (Some(r), Some(c)) => format!("({r}, {c})"),
        (None, Some(c)) => format!("(n, {c})"),
        (Some(r), None) => format!("({r},)"),
        (None, None) => "(n,)".into(),
    };
    // Only real numbers: numpy would cast a complex array to its real part with a warning.
    // One conversion: `asarray` keeps the dtype so that only real numbers pass (numpy
    // would cast a complex array to its real part with a mere warning), then float64.
    let not_numbers = || {
        PyValueError::new_err(format!("invalid {field}: must be an array of real numbers of shape {want}"))
    };
    let np = py.import("numpy")?;
    let raw = np.call_method1("asarray", (obj,)).map_err(|_| not_numbers())?;
    let kind: String = raw.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u" | "f") && raw.getattr("size")?.extract::<usize>()? > 0 {
        return Err(not_numbers());
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let arr = np.call_method("ascontiguousarray", (raw,), Some(&kwargs)).map_err(|_| not_numbers())?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let ok = match cols {
        Some(c) => shape.len() == 2 && shape[1] == c,
        None => shape.len() == 1,
    } && rows.is_none_or(|r| shape[0] == r);
    if !ok {
        return Err(PyValueError::new_err(format!(
            "invalid {field} shape {}: must be {want}",
            shape_text(&shape)
        )));
    }
    let data = if cols.is_some() {
        arr.extract::<PyReadonlyArray2<'_, f64>>()?.as_array().iter().copied().collect()
    } else {
        arr.extract::<PyReadonlyArray1<'_, f64>>()?.as_array().iter().copied().collect()
    };
    Ok(data)
}

/// `rows x cols` numpy array from a flat row-major vector.
pub(crate) fn matrix(py: Python<'_>, data: Vec<f64>, cols: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let rows = data.len().checked_div(cols).unwrap_or(0);
    let arr = Array2::from_shape_vec((rows, cols), data).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(arr.into_pyarray(py))
}

/// Solids' orientations, flat as the engine gives them, shaped for Python: the angles (n,)
/// in 2D, the quaternions (n, 4) as (w, x, y, z) in 3D.
pub(crate) fn orientations(py: Python<'_>, q: Vec<f64>, dim: usize) -> PyResult<Bound<'_, PyAny>> {
    if dim == 3 {
        Ok(matrix(py, q, 4)?.into_any())
    } else {
        Ok(q.into_pyarray(py).into_any())
    }
}

/// Rows of `cols` indices from any array-like of whole numbers (numpy integer arrays, nested
/// lists of ints), shape `(m, cols)`; a negative entry names its place (`triangles[4][1]`).
/// The engine checks them against what they index.
pub(crate) fn indices<const N: usize>(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<Vec<[usize; N]>> {
    let py = obj.py();
    let not_indices = || {
        PyValueError::new_err(format!("invalid {field}: must be an array of whole numbers of shape (m, {N})"))
    };
    let np = py.import("numpy")?;
    let raw = np.call_method1("asarray", (obj,)).map_err(|_| not_indices())?;
    let kind: String = raw.getattr("dtype")?.getattr("kind")?.extract()?;
    let size: usize = raw.getattr("size")?.extract()?;
    let unsigned = kind == "u";
    if !(kind == "i" || unsigned || size == 0) {
        return Err(not_indices());
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", if unsigned { "uint64" } else { "int64" })?;
    let arr = np.call_method("ascontiguousarray", (raw,), Some(&kwargs)).map_err(|_| not_indices())?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let rows = shape.len() == 2 && shape[1] == N;
    if !(rows || (size == 0 && shape.len() == 1)) {
        return Err(PyValueError::new_err(format!(
            "invalid {field} shape {}: must be (m, {N})",
            shape_text(&shape)
        )));
    }
    let flat: Vec<usize> = if size == 0 {
        Vec::new()
    } else if unsigned {
        let a = arr.extract::<numpy::PyReadonlyArray2<'_, u64>>()?;
        let flat: Vec<u64> = a.as_array().iter().copied().collect();
        flat.into_iter().map(|v| usize::try_from(v).unwrap_or(usize::MAX)).collect()
    } else {
        let a = arr.extract::<numpy::PyReadonlyArray2<'_, i64>>()?;
        let flat: Vec<i64> = a.as_array().iter().copied().collect();
        if let Some(at) = flat.iter().position(|v| *v < 0) {
            return Err(PyValueError::new_err(format!(
                "invalid {field}[{}][{}] = {}: must be an index >= 0",
                at / N,
                at % N,
                flat[at]
            )));
        }
        flat.into_iter().map(|v| v as usize).collect()
    };
    Ok(flat.chunks_exact(N).map(|c| std::array::from_fn(|k| c[k])).collect())
}
