//! NumPy arrays in and out: shape checks that name the argument, and results handed over without copies.

use crate::errors::invalid;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{Element, IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// The array's data as one slice: the Python layer passes C-contiguous arrays; anything else is refused
/// with a message, never read out of order.
pub fn slice<'a, T: Element>(name: &str, a: &'a PyReadonlyArrayDyn<'_, T>) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| invalid(format!("{name}: expected a C-contiguous array")))
}

/// Checks the array's shape against `expected` (None: any length), naming the argument.
pub fn shape(name: &str, a: &PyReadonlyArrayDyn<'_, impl Element>, expected: &[Option<usize>]) -> PyResult<Vec<usize>> {
    let s = a.shape().to_vec();
    let fits = s.len() == expected.len() && s.iter().zip(expected).all(|(&n, e)| e.is_none_or(|e| e == n));
    if !fits {
        let want: Vec<String> = expected.iter().map(|e| e.map_or("N".to_string(), |n| n.to_string())).collect();
        return Err(invalid(format!("{name}: expected shape ({}), got {:?}", want.join(", "), s)));
    }
    if s.contains(&0) {
        return Err(invalid(format!("{name}: the array is empty (shape {s:?})")));
    }
    Ok(s)
}

/// A result of `shape` from its values in C order.
pub fn output<'py, T: Element>(py: Python<'py>, shape: &[usize], values: Vec<T>) -> Bound<'py, PyArrayDyn<T>> {
    ArrayD::from_shape_vec(IxDyn(shape), values).expect("the values fill the shape").into_pyarray(py)
}

/// Interleaved pixels as one flat vector.
pub fn flatten<const N: usize>(pixels: Vec<[f32; N]>) -> Vec<f32> {
    pixels.into_iter().flatten().collect()
}
