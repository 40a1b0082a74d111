//! A keypoint's depth from a registered depth image, robust to the edges of the body.
//!
//! A keypoint on a shoulder's edge sees half body, half wall, and the body is the nearer half;
//! so the window's readings further than a band behind its front (the 25th percentile, which
//! single flying pixels at depth edges cannot choose) are dropped, and the median of the rest is
//! the keypoint's depth.
//!
//! ```
//! use torso_core::depth::{DepthImage, DepthLookup};
//! // A 2 m wall with a person at 1 m on its left half.
//! let (w, h) = (20, 10);
//! let data: Vec<f32> = (0..w * h).map(|i| if i % w < 10 { 1.0 } else { 2.0 }).collect();
//! let image = DepthImage::new(&data, w, h).unwrap();
//! let lookup = DepthLookup::default();
//! assert_eq!(lookup.depth_at(&image, [9.5, 5.0]), 1.0); // on the edge: the body
//! assert_eq!(lookup.depth_at(&image, [15.0, 5.0]), 2.0);
//! assert!(lookup.depth_at(&image, [25.0, 5.0]).is_nan()); // off the image
//! ```

use crate::error::{Error, Result};

/// Largest window radius: the window's readings are sorted on the stack.
pub const MAX_RADIUS: usize = 10;
const MAX_WINDOW: usize = (2 * MAX_RADIUS + 1) * (2 * MAX_RADIUS + 1);

/// A depth image in metres, borrowed, row-major (`data[row * width + column]`).
#[derive(Clone, Copy, Debug)]
pub struct DepthImage<'a> {
    data: &'a [f32],
    width: usize,
    height: usize,
}

impl<'a> DepthImage<'a> {
    pub fn new(data: &'a [f32], width: usize, height: usize) -> Result<Self> {
        let expected = width.checked_mul(height).ok_or(Error::InvalidArgument {
            name: "depth",
            expected: "an image size whose pixel count fits in memory",
            value: width as f64 * height as f64,
        })?;
        if data.len() != expected {
            return Err(Error::LengthMismatch {
                name: "depth",
                expected,
                got: data.len(),
            });
        }
        Ok(Self {
            data,
            width,
            height,
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    fn at(&self, column: usize, row: usize) -> f64 {
        f64::from(self.data[row * self.width + column])
    }
}

/// How a keypoint's depth is read: the median of the valid readings in a `(2 radius + 1)²`
/// window around it after dropping those more than `band` behind the window's 25th percentile;
/// fewer than `min_valid` readings left gives NaN. Readings outside `min_depth..=max_depth` (m)
/// are invalid (holes read 0). Pixels past the image's border repeat its edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthLookup {
    pub radius: usize,
    pub band: f64,
    pub min_valid: usize,
    pub min_depth: f64,
    pub max_depth: f64,
}

impl Default for DepthLookup {
    fn default() -> Self {
        Self {
            radius: 3,
            band: 0.15,
            min_valid: 4,
            min_depth: 0.2,
            max_depth: 10.0,
        }
    }
}

impl DepthLookup {
    pub fn validate(&self) -> Result<()> {
        if self.radius > MAX_RADIUS {
            return Err(Error::InvalidArgument {
                name: "radius",
                expected: "a window radius from 0 to MAX_RADIUS (10) pixels",
                value: self.radius as f64,
            });
        }
        if !(self.band > 0.0 && self.band.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "band",
                expected: "a positive, finite depth band in metres",
                value: self.band,
            });
        }
        let window = (2 * self.radius + 1).pow(2);
        if !(1..=window).contains(&self.min_valid) {
            return Err(Error::InvalidArgument {
                name: "min_valid",
                expected: "from 1 to the window's pixel count",
                value: self.min_valid as f64,
            });
        }
        if !(self.min_depth >= 0.0 && self.min_depth < self.max_depth && self.max_depth.is_finite())
        {
            return Err(Error::InvalidArgument {
                name: "max_depth",
                expected: "a finite range with 0 <= min_depth < max_depth (m)",
                value: self.max_depth,
            });
        }
        Ok(())
    }

    /// Depth (m) at pixel `uv`; NaN off the image or without enough readings. The lookup is
    /// assumed valid ([`validate`](Self::validate)).
    pub fn depth_at(&self, image: &DepthImage<'_>, [u, v]: [f64; 2]) -> f64 {
        let (w, h) = (image.width as f64, image.height as f64);
        if !(u >= -0.5 && v >= -0.5 && u < w - 0.5 && v < h - 0.5) {
            return f64::NAN;
        }
        let r = self.radius.min(MAX_RADIUS) as isize;
        let (cu, cv) = (u.round_ties_even() as isize, v.round_ties_even() as isize);
        let mut window = [f64::INFINITY; MAX_WINDOW];
        let mut n = 0;
        for dv in -r..=r {
            let row = (cv + dv).clamp(0, image.height as isize - 1) as usize;
            for du in -r..=r {
                let column = (cu + du).clamp(0, image.width as isize - 1) as usize;
                let z = image.at(column, row);
                window[n] = if z >= self.min_depth && z <= self.max_depth {
                    z
                } else {
                    f64::INFINITY
                };
                n += 1;
            }
        }
        let window = &mut window[..n];
        window.sort_unstable_by(f64::total_cmp);
        let count = window.iter().take_while(|z| z.is_finite()).count();
        if count < self.min_valid {
            return f64::NAN;
        }
        // The 25th percentile with linear interpolation (NumPy's default).
        let position = 0.25 * (count - 1) as f64;
        let low = position.floor() as usize;
        let high = (low + 1).min(count - 1);
        let front = window[low] + (position - low as f64) * (window[high] - window[low]);
        let kept = window[..count]
            .iter()
            .take_while(|&&z| z <= front + self.band)
            .count();
        if kept < self.min_valid {
            return f64::NAN;
        }
        0.5 * (window[(kept - 1) / 2] + window[kept / 2])
    }
}
