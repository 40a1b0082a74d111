//! NumPy in, NumPy out: shape checks and conversions shared by the bindings. Inputs arrive as
//! `PyArrayLike` with type change allowed, so float32 arrays and plain lists work too; outputs
//! are always float64.

use crate::errors::shape_error;
use numpy::ndarray::{ArrayView, ArrayView2, ArrayView3, Dimension};
use numpy::{PyArray1, PyArray2, PyArray3, ToPyArray};
use pyo3::prelude::*;
use std::borrow::Cow;
use torso_core::coco::{Joints, N_JOINTS};

/// Two arrays returned together, as a Python tuple.
pub type ArrayPair<'py, A, B> = PyResult<(Bound<'py, A>, Bound<'py, B>)>;

/// The array's elements in C (row-major) order, copied (small arrays: joints, scores).
pub fn contiguous<D: Dimension>(view: ArrayView<'_, f64, D>) -> Vec<f64> {
    c_order(&view).into_owned()
}

/// The array's elements in C (row-major) order: borrowed when the array is laid out so, copied
/// otherwise. A Fortran-ordered or transposed array is contiguous too, but in the other order,
/// so its memory is never read as it lies.
pub fn c_order<'a, T: Copy, D: Dimension>(view: &'a ArrayView<'_, T, D>) -> Cow<'a, [T]> {
    match view.as_slice() {
        Some(s) => Cow::Borrowed(s),
        None => Cow::Owned(view.iter().copied().collect()),
    }
}

/// A fixed number of values from an argument's flat buffer of shape `shape`: a `ShapeError`
/// naming the argument otherwise.
pub fn fixed<T: Copy, const N: usize>(name: &str, flat: &[T], shape: &[usize]) -> PyResult<[T; N]> {
    flat.try_into()
        .map_err(|_| shape_error(name, &format!("{N} values"), shape))
}

/// A fixed number of values from a Python sequence argument (a pose, a camera's intrinsics): a
/// `ShapeError` naming the argument for any other length (extracted as an array, PyO3 raises a
/// plain `ValueError` that names none).
pub fn sequence<T: Copy, const N: usize>(name: &str, values: &[T]) -> PyResult<[T; N]> {
    fixed(name, values, &[values.len()])
}

/// Rows of three (points) from an `(n, 3)`-shaped flat buffer.
pub fn points(flat: &[f64]) -> Vec<[f64; 3]> {
    flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Checks the number of dimensions of an argument's shape; arguments arrive with any number, so
/// that a wrong one is a `ShapeError` naming the argument (a fixed-dimension extraction raises
/// a `TypeError` that names none).
pub fn expect_ndim(name: &str, shape: &[usize], ndim: usize, expected: &str) -> PyResult<()> {
    if shape.len() == ndim {
        Ok(())
    } else {
        Err(shape_error(name, expected, shape))
    }
}

/// Checks the trailing dimension of an array shape.
pub fn expect_last(name: &str, shape: &[usize], last: usize, expected: &str) -> PyResult<()> {
    if shape.last() == Some(&last) {
        Ok(())
    } else {
        Err(shape_error(name, expected, shape))
    }
}

/// A float64 `(rows, cols)` array from row arrays.
pub fn matrix<'py, const C: usize>(
    py: Python<'py>,
    rows: &[[f64; C]],
) -> Bound<'py, PyArray2<f64>> {
    // Copied into a new array as it is made, without the borrow checks of writing into one.
    ArrayView2::from_shape((rows.len(), C), rows.as_flattened())
        .expect("rows of C values")
        .to_pyarray(py)
}

/// Joints as a new `(people, 17, 3)` array.
pub fn joints_array<'py>(py: Python<'py>, joints: &[Joints]) -> Bound<'py, PyArray3<f64>> {
    ArrayView3::from_shape(
        (joints.len(), N_JOINTS, 3),
        joints.as_flattened().as_flattened(),
    )
    .expect("17 joints of 3 coordinates")
    .to_pyarray(py)
}

/// A float64 vector.
pub fn vector<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, values)
}

/// Checks that `depth` is a `(height, width)` image and gives its `(height, width)`.
pub fn depth_size(shape: &[usize]) -> PyResult<(usize, usize)> {
    expect_ndim("depth", shape, 2, "(height, width) in metres")?;
    Ok((shape[0], shape[1]))
}
