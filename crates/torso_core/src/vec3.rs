//! The few operations on `[f64; 3]` points that the per-frame chain needs, on plain arrays so
//! that joints stay `Copy` and the arithmetic is written out (and bit-for-bit reproducible).

pub(crate) fn finite(x: &[f64; 3]) -> bool {
    x.iter().all(|v| v.is_finite())
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}

/// Distance in the ground plane (x, y), the height left out.
pub(crate) fn horizontal_distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Whether [`horizontal_distance`] is under `limit`, without its square root: a test made for
/// every joint against every person nearer the camera, where `hypot` is a slow library call.
pub(crate) fn horizontally_within(a: [f64; 3], b: [f64; 3], limit: f64) -> bool {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    dx * dx + dy * dy < limit * limit
}

pub(crate) fn midpoint(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        0.5 * (a[0] + b[0]),
        0.5 * (a[1] + b[1]),
        0.5 * (a[2] + b[2]),
    ]
}
