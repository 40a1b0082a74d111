//! A recorded stream of detections and depth images through the engine, printing each frame's
//! tracks and their forecasts: what a Rust robot's loop looks like.
//!
//! ```text
//! cargo run --release --example replay -p torso_core [-- path/to/recording]
//! ```
//!
//! The recording (default: `examples/walk`, see its README) is a folder with `camera.txt`,
//! `detections.txt` and `depth/NNNN.pgm`. A robot replaces the reading with its keypoint model's
//! output and its depth camera's frames; the loop stays the same.

use std::collections::BTreeMap;
use std::error::Error;
use std::fs;
use std::path::{Path, PathBuf};
use torso_core::camera::{Camera, Intrinsics, Rigid};
use torso_core::depth::DepthImage;
use torso_core::tracker::Keypoints;
use torso_core::{Tracker, TrackerConfig};

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// The numbers of a text file's lines, comments (`#`) and blank lines left out.
fn number_lines(path: &Path) -> Result<Vec<Vec<f64>>> {
    let text = fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            l.split_whitespace()
                .map(|v| v.parse::<f64>())
                .collect::<std::result::Result<Vec<_>, _>>()
                .map_err(|e| format!("{}: {e} in {l:?}", path.display()).into())
        })
        .collect()
}

fn read_camera(path: &Path) -> Result<Camera> {
    let lines = number_lines(path)?;
    let [k, d, r0, r1, r2] = lines.as_slice() else {
        return Err(format!("{}: expected 5 lines of numbers", path.display()).into());
    };
    let intrinsics = Intrinsics::new(k[0], k[1], k[2], k[3], d[..5].try_into()?)?;
    let rows = [r0, r1, r2].map(|r| [r[0], r[1], r[2], r[3]]);
    Ok(Camera::new(intrinsics, Rigid::from_rows(rows)?))
}

/// A 16-bit binary PGM (P5, big-endian) of millimetres as metres.
fn read_depth(path: &Path) -> Result<(Vec<f32>, usize, usize)> {
    let bytes = fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    // The header: magic, width, height, maxval, each followed by whitespace.
    let mut fields = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while fields.len() < 4 && i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            if i > start {
                fields.push(std::str::from_utf8(&bytes[start..i])?.to_string());
            }
            start = i + 1;
        }
        i += 1;
    }
    if fields.len() < 4 || fields[0] != "P5" || fields[3] != "65535" {
        return Err(format!("{}: not a 16-bit binary PGM", path.display()).into());
    }
    let (width, height): (usize, usize) = (fields[1].parse()?, fields[2].parse()?);
    let pixels = &bytes[start..];
    if pixels.len() != 2 * width * height {
        return Err(format!("{}: truncated", path.display()).into());
    }
    let metres = pixels
        .chunks_exact(2)
        .map(|b| f32::from(u16::from_be_bytes([b[0], b[1]])) / 1000.0)
        .collect();
    Ok((metres, width, height))
}

/// Per frame: its time and the detections' keypoints, by frame index.
fn read_detections(path: &Path) -> Result<BTreeMap<usize, (f64, Vec<Keypoints>)>> {
    let mut frames: BTreeMap<usize, (f64, Vec<Keypoints>)> = BTreeMap::new();
    for line in number_lines(path)? {
        if line.len() != 3 + 17 * 3 {
            return Err(format!("{}: a line of {} numbers", path.display(), line.len()).into());
        }
        let keypoints: Keypoints = std::array::from_fn(|j| {
            let p = &line[3 + 3 * j..6 + 3 * j];
            [p[0], p[1], p[2]]
        });
        let entry = frames
            .entry(line[0] as usize)
            .or_insert((line[1], Vec::new()));
        entry.1.push(keypoints);
    }
    Ok(frames)
}

fn main() -> Result<()> {
    let folder = std::env::args().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/walk"),
        PathBuf::from,
    );
    let camera = read_camera(&folder.join("camera.txt"))?;
    let frames = read_detections(&folder.join("detections.txt"))?;
    let mut tracker = Tracker::new(TrackerConfig::default())?;
    let horizons = [0.4, 1.0];
    let mut ahead = [[0.0; 5]; 2];
    for (index, (t, keypoints)) in &frames {
        let (pixels, width, height) = read_depth(&folder.join(format!("depth/{index:04}.pgm")))?;
        let depth = DepthImage::new(&pixels, width, height)?;
        // The outcomes borrow the tracker: copy out what the forecasts below need.
        let outcomes: Vec<_> = tracker.step(*t, keypoints, &depth, &camera)?.to_vec();
        for outcome in outcomes {
            let (Some(track), Some(observation)) = (outcome.track, outcome.observation) else {
                println!("t={t:.3} detection {}: no track", outcome.detection);
                continue;
            };
            let id = track
                .id
                .map_or("tentative".into(), |id| format!("track {id}"));
            let Some(pose) = observation.pose else {
                println!("t={t:.3} {id}: no torso pose this frame");
                continue;
            };
            print!(
                "t={t:.3} {id}: centre ({:.2}, {:.2}, {:.2}) m, azimuth {:.0} deg",
                pose[0],
                pose[1],
                pose[2],
                pose[3].to_degrees()
            );
            if track.id.is_some() && tracker.forecast(track.slot, &horizons, &mut ahead)? {
                for (h, p) in horizons.iter().zip(&ahead) {
                    print!(
                        "; {h} s ahead ({:.2}, {:.2}) m, {:.0} deg",
                        p[0],
                        p[1],
                        p[3].to_degrees()
                    );
                }
            }
            println!();
        }
    }
    Ok(())
}
