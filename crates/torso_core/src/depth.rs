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

/// Largest window radius: the window's readings are gathered on the stack.
pub const MAX_RADIUS: usize = 10;
const MAX_WINDOW: usize = (2 * MAX_RADIUS + 1) * (2 * MAX_RADIUS + 1);
/// The window radius of [`DepthLookup::default`].
const DEFAULT_RADIUS: usize = 3;
const DEFAULT_WINDOW: usize = (2 * DEFAULT_RADIUS + 1) * (2 * DEFAULT_RADIUS + 1);

/// A depth image in metres, borrowed, row-major (`data[row * width + column]`).
///
/// ```
/// use torso_core::depth::DepthImage;
/// let pixels = vec![1.5f32; 4 * 3];
/// let image = DepthImage::new(&pixels, 4, 3).unwrap();
/// assert_eq!((image.width(), image.height()), (4, 3));
/// assert!(DepthImage::new(&pixels, 5, 3).is_err()); // not 5 x 3 pixels
/// ```
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
}

/// How a keypoint's depth is read: the median of the valid readings in a `(2 radius + 1)²`
/// window around it after dropping those more than `band` behind the window's 25th percentile;
/// fewer than `min_valid` readings left gives NaN. Readings outside `min_depth..=max_depth` (m)
/// are invalid (holes read 0). Pixels past the image's border repeat its edge.
///
/// ```
/// use torso_core::depth::{DepthImage, DepthLookup};
/// let pixels = vec![2.0f32; 20 * 20];
/// let image = DepthImage::new(&pixels, 20, 20).unwrap();
/// let lookup = DepthLookup { radius: 2, ..DepthLookup::default() };
/// assert_eq!(lookup.depth_at(&image, [10.0, 10.0]), 2.0);
/// assert!(DepthLookup { radius: 50, ..lookup }.validate().is_err());
/// ```
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
            radius: DEFAULT_RADIUS,
            band: 0.15,
            min_valid: 4,
            min_depth: 0.2,
            max_depth: 10.0,
        }
    }
}

impl DepthLookup {
    /// Asks for the cache lines at both ends of every row of the windows around `pixels`: a
    /// depth image fresh from a sensor is not in the cache, and these requests fetch the rows
    /// in parallel, where [`depth_at`](Self::depth_at)'s window-by-window reads would wait for
    /// each in turn. Call it [`LOOKAHEAD`] keypoints ahead of their lookups (as the tracker
    /// does), so that the fetches of later windows overlap the work on earlier ones.
    pub fn prefetch(&self, image: &DepthImage<'_>, pixels: impl Iterator<Item = [f64; 2]>) {
        let r = self.radius.min(MAX_RADIUS) as isize;
        let (width, height) = (image.width as isize, image.height as isize);
        for [u, v] in pixels {
            if !(u >= -0.5 && v >= -0.5 && u < width as f64 - 0.5 && v < height as f64 - 0.5) {
                continue;
            }
            let (cu, cv) = (u.round_ties_even() as isize, v.round_ties_even() as isize);
            for row in (cv - r).max(0)..=(cv + r).min(height - 1) {
                for column in [(cu - r).max(0), (cu + r).min(width - 1)] {
                    fetch(&image.data[(row * width + column) as usize]);
                }
            }
        }
    }

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

    /// `min_depth..=max_depth` as the `f32` readings in it: the nearest and furthest `f32` whose
    /// value lies within the range, so that each reading is tested without widening it.
    fn valid_range(&self) -> (f32, f32) {
        // Positive finite `f32`s order as their bit patterns; `as` rounds to the nearest.
        let mut nearest = self.min_depth as f32;
        if f64::from(nearest) < self.min_depth {
            nearest = f32::from_bits(nearest.to_bits() + 1);
        }
        let mut furthest = self.max_depth as f32;
        if f64::from(furthest) > self.max_depth {
            furthest = f32::from_bits(furthest.to_bits() - 1);
        }
        (nearest, furthest)
    }

    /// Depth (m) at pixel `uv`; NaN off the image or without enough readings. The lookup is
    /// assumed valid ([`validate`](Self::validate)).
    pub fn depth_at(&self, image: &DepthImage<'_>, [u, v]: [f64; 2]) -> f64 {
        let (w, h) = (image.width as f64, image.height as f64);
        if !(u >= -0.5 && v >= -0.5 && u < w - 0.5 && v < h - 0.5) {
            return f64::NAN;
        }
        let centre = (u.round_ties_even() as isize, v.round_ties_even() as isize);
        // The readings' buffer is zeroed on every call: the default window's own size, not the
        // largest window's, keeps that cheap.
        if self.radius <= DEFAULT_RADIUS {
            self.window_depth::<DEFAULT_WINDOW>(image, centre)
        } else {
            self.window_depth::<MAX_WINDOW>(image, centre)
        }
    }

    /// [`depth_at`](Self::depth_at) of the window around pixel `(cu, cv)`, its readings gathered
    /// in a buffer of `N` (at least the window's pixel count).
    fn window_depth<const N: usize>(
        &self,
        image: &DepthImage<'_>,
        (cu, cv): (isize, isize),
    ) -> f64 {
        let r = self.radius.min(MAX_RADIUS) as isize;
        let (width, height) = (image.width as isize, image.height as isize);
        // Valid readings are non-negative, so their bit patterns order as their values do, and
        // integer comparisons are the cheapest there are.
        let mut readings = [0u32; N];
        let mut count = 0;
        let (nearest, furthest) = self.valid_range();
        let mut take = |z: f32| {
            if z >= nearest && z <= furthest {
                readings[count] = (z + 0.0).to_bits(); // -0.0 as +0.0
                count += 1;
            }
        };
        if cu >= r && cv >= r && cu + r < width && cv + r < height {
            // Inside the image: whole rows of the window at once.
            for row in cv - r..=cv + r {
                let start = (row * width + cu - r) as usize;
                for &z in &image.data[start..=start + 2 * r as usize] {
                    take(z);
                }
            }
        } else {
            for dv in -r..=r {
                let row = (cv + dv).clamp(0, height - 1) as usize;
                for du in -r..=r {
                    let column = (cu + du).clamp(0, width - 1) as usize;
                    take(image.data[row * image.width + column]);
                }
            }
        }
        if count < self.min_valid {
            return f64::NAN;
        }
        let readings = &mut readings[..count];
        readings.sort_unstable();
        let metres = |i: usize| f64::from(f32::from_bits(readings[i]));
        // The 25th percentile with linear interpolation (NumPy's default).
        let position = 0.25 * (count - 1) as f64;
        let low = position.floor() as usize;
        let high = (low + 1).min(count - 1);
        let front = metres(low) + (position - low as f64) * (metres(high) - metres(low));
        // The median of the readings within the band to the front: a prefix of the sorted ones.
        let limit = front + self.band;
        let kept = readings.partition_point(|&b| f64::from(f32::from_bits(b)) <= limit);
        if kept < self.min_valid {
            return f64::NAN;
        }
        0.5 * (metres((kept - 1) / 2) + metres(kept / 2))
    }
}

/// Keypoints whose windows [`DepthLookup::prefetch`] is asked for ahead of the one looked up.
/// With a prefetch hint, eight: enough in flight that a depth image fresh from the sensor
/// arrives while the lookups before work, few enough that what arrives stays in the
/// first-level cache until it is read. Without one, every keypoint's before the first lookup:
/// reads then wait for their lines together, where between lookups each would wait alone.
pub const LOOKAHEAD: usize = if cfg!(target_arch = "x86_64") {
    8
} else {
    usize::MAX
};

/// Starts bringing `x`'s cache line in without waiting for it: on x86-64 a prefetch hint, so
/// the requests of [`DepthLookup::prefetch`] stay in flight while the lookups that follow work;
/// elsewhere a read (stable Rust has no portable prefetch), which holds the requests to the
/// processor's window of reads in flight.
#[inline(always)]
fn fetch(x: &f32) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint: it never faults and changes no memory, and `x` is a live
    // reference. SSE, which it needs, is part of every x86-64 processor.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (x as *const f32).cast(),
        )
    };
    #[cfg(not(target_arch = "x86_64"))]
    std::hint::black_box(*x);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lookup written out plainly: every window pixel (edges repeated), sorted as floats.
    fn reference(lookup: &DepthLookup, data: &[f32], w: usize, h: usize, [u, v]: [f64; 2]) -> f64 {
        if !(u >= -0.5 && v >= -0.5 && u < w as f64 - 0.5 && v < h as f64 - 0.5) {
            return f64::NAN;
        }
        let r = lookup.radius as isize;
        let (cu, cv) = (u.round_ties_even() as isize, v.round_ties_even() as isize);
        let mut valid = Vec::new();
        for dv in -r..=r {
            for du in -r..=r {
                let row = (cv + dv).clamp(0, h as isize - 1) as usize;
                let col = (cu + du).clamp(0, w as isize - 1) as usize;
                let z = f64::from(data[row * w + col]);
                if z >= lookup.min_depth && z <= lookup.max_depth {
                    valid.push(z);
                }
            }
        }
        valid.sort_by(f64::total_cmp);
        if valid.len() < lookup.min_valid {
            return f64::NAN;
        }
        let p = 0.25 * (valid.len() - 1) as f64;
        let (lo, hi) = (
            p.floor() as usize,
            (p.floor() as usize + 1).min(valid.len() - 1),
        );
        let front = valid[lo] + (p - lo as f64) * (valid[hi] - valid[lo]);
        let kept: Vec<f64> = valid
            .into_iter()
            .filter(|&z| z <= front + lookup.band)
            .collect();
        if kept.len() < lookup.min_valid {
            return f64::NAN;
        }
        0.5 * (kept[(kept.len() - 1) / 2] + kept[kept.len() / 2])
    }

    #[test]
    fn a_reading_is_valid_exactly_where_its_value_lies_in_the_range() {
        let next = |z: f32, step: i32| f32::from_bits((z.to_bits() as i32 + step) as u32);
        // Ends no f32 holds exactly, rounded by `as` into the range (0.7, 1.1) and out of it (0.2,
        // 0.7); ends f32 holds (0, 10); ends beyond f32's range.
        for (min_depth, max_depth) in [(0.7, 1.1), (0.2, 0.7), (0.0, 10.0), (1e-50, 1e300)] {
            let lookup = DepthLookup {
                radius: 0,
                min_valid: 1,
                min_depth,
                max_depth,
                ..DepthLookup::default()
            };
            let ends = [min_depth as f32, max_depth as f32, 0.0, f32::MAX];
            for z in ends
                .into_iter()
                .flat_map(|z| (-2..=2).map(move |k| next(z, k)))
            {
                let image = DepthImage::new(std::slice::from_ref(&z), 1, 1).unwrap();
                let valid = (min_depth..=max_depth).contains(&f64::from(z));
                let got = lookup.depth_at(&image, [0.0, 0.0]);
                assert_eq!(got.is_nan(), !valid, "{z:e} in {min_depth}..={max_depth}");
            }
        }
    }

    #[test]
    fn the_lookup_matches_its_plain_definition_inside_at_the_borders_and_on_holes() {
        let (w, h) = (37usize, 23usize);
        let mut next = crate::testing::uniform(7);
        let levels = [0.0, f32::NAN, 1.0, 1.05, 1.1, 1.3, 2.5, 11.0];
        // Readings spread about each level, and readings exactly on them (ties).
        for jitter in [0.01f32, 0.0] {
            let data: Vec<f32> = (0..w * h)
                .map(|_| levels[(next() * levels.len() as f64) as usize] + jitter * next() as f32)
                .collect();
            let image = DepthImage::new(&data, w, h).unwrap();
            // Radii up to the default's gather in its small buffer, larger ones in the largest.
            for radius in [0, 1, 2, 3, 4, 7] {
                let lookup = DepthLookup {
                    radius,
                    min_valid: 1.max(radius),
                    ..DepthLookup::default()
                };
                for _ in 0..400 {
                    let uv = [next() * 40.0 - 2.0, next() * 26.0 - 2.0];
                    let got = lookup.depth_at(&image, uv);
                    let want = reference(&lookup, &data, w, h, uv);
                    assert!(
                        got == want || (got.is_nan() && want.is_nan()),
                        "{uv:?}: {got} {want}"
                    );
                }
            }
            assert!(DepthImage::new(&data, w, h + 1).is_err());
        }
    }
}
