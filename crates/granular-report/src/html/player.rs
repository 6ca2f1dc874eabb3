//! The data of the snapshot player: the snapshots of a run, subsampled above a documented
//! size, packed as base64 float32 arrays for the page's script, with the speed histogram of
//! every frame (over all its grains) and the Maxwell-Boltzmann density at the frame's
//! temperature per species (`theory::equilibrium`, HD-12 in 2D).

use crate::table::snapshot_files;
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;
use granular::boundary::AxisKind;
use granular::engine::Snapshot;
use granular::run::RunDir;
use granular::scenario::Scenario;
use granular::theory::equilibrium;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Most grains the player draws per frame; above, every `k`-th grain is drawn (the same
/// grains in every frame) and the page says so.
pub const MAX_GRAINS: usize = 20_000;
/// Most frames the player holds; above, frames are taken evenly (first and last kept).
pub const MAX_FRAMES: usize = 120;
/// Most numbers (coordinates and speeds, float32) embedded over all frames: about 12 MB,
/// 16 MB as base64. Fewer frames are kept when the grains drawn would exceed it.
pub const MAX_VALUES: usize = 3_000_000;
/// How much the player holds: the defaults are [`MAX_GRAINS`], [`MAX_FRAMES`],
/// [`MAX_VALUES`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    pub grains: usize,
    pub frames: usize,
    pub values: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            grains: MAX_GRAINS,
            frames: MAX_FRAMES,
            values: MAX_VALUES,
        }
    }
}

/// Bins of the speed histogram of a frame.
const SPEED_BINS: usize = 40;

fn base64_f32(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(|v| (v as f32).to_le_bytes()).collect();
    STANDARD.encode(bytes)
}

/// Which of `total` items to keep when at most `keep` fit: evenly spaced, first and last
/// included.
fn evenly(total: usize, keep: usize) -> Vec<usize> {
    if total <= keep {
        return (0..total).collect();
    }
    let keep = keep.max(2);
    let mut picked: Vec<usize> = (0..keep)
        .map(|i| ((i as f64) * (total - 1) as f64 / (keep - 1) as f64).round() as usize)
        .collect();
    picked.dedup();
    picked
}

fn speeds(s: &Snapshot) -> Vec<f64> {
    s.velocities
        .chunks(s.dimension)
        .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect()
}

/// Histogram of all speeds of a frame on `[0, v_max)` and the Maxwell-Boltzmann density
/// averaged over each bin (the mixture of the species at their own temperatures,
/// `T_s = <m v²>_s / D`, weighted by their numbers).
fn speed_histogram(s: &Snapshot, v: &[f64], v_max: f64, species: usize) -> Value {
    let width = v_max / SPEED_BINS as f64;
    let mut counts = vec![0u64; SPEED_BINS];
    let mut mv2 = vec![0.0; species];
    let mut number = vec![0usize; species];
    for ((speed, m), sp) in v.iter().zip(&s.masses).zip(&s.species) {
        let bin = (speed / width) as usize;
        if bin < SPEED_BINS {
            counts[bin] += 1;
        }
        let sp = *sp as usize;
        if sp < species {
            mv2[sp] += m * speed * speed;
            number[sp] += 1;
        }
    }
    let n = v.len().max(1) as f64;
    let mut temperatures = Vec::new();
    let mut theory = vec![0.0; SPEED_BINS];
    for sp in 0..species {
        if number[sp] == 0 {
            temperatures.push(f64::NAN);
            continue;
        }
        let t = equilibrium::kinetic_temperature(s.dimension, mv2[sp] / number[sp] as f64);
        temperatures.push(t);
        let mass = s
            .masses
            .iter()
            .zip(&s.species)
            .find(|(_, x)| **x as usize == sp)
            .map_or(1.0, |(m, _)| *m);
        let weight = number[sp] as f64 / n;
        if t > 0.0 {
            for (b, th) in theory.iter_mut().enumerate() {
                let lo = equilibrium::speed_cdf(s.dimension, b as f64 * width, mass, t);
                let hi = equilibrium::speed_cdf(s.dimension, (b + 1) as f64 * width, mass, t);
                *th += weight * (hi - lo) / width;
            }
        }
    }
    json!({
        "width": width,
        "counts": counts,
        "theory": theory,
        "temperatures": temperatures.iter().map(|t| if t.is_finite() { json!(t) } else { Value::Null }).collect::<Vec<_>>(),
    })
}

/// What the player shows, for the page's notice.
pub(crate) struct PlayerData {
    pub json: String,
    pub grains_total: usize,
    pub grains_shown: usize,
    pub stride: usize,
    pub frames_total: usize,
    pub frames_shown: usize,
}

/// Reads the snapshots of `dir` (subsampled as the constants above say) into the JSON
/// object the player's script reads; `None` when the run has no snapshots.
pub(crate) fn player_data(
    dir: &Path,
    scenario: &Scenario,
    limits: Limits,
) -> Result<Option<PlayerData>, String> {
    let files = snapshot_files(dir);
    let Some(first_file) = files.first() else {
        return Ok(None);
    };
    let read = |f: &PathBuf| granular::run::read_snapshot(f).map_err(|e| e.to_string());
    let first = read(first_file)?;
    let n = first.radii.len();
    let d = first.dimension;
    let stride = n.div_ceil(limits.grains.max(1)).max(1);
    let shown: Vec<usize> = (0..n).step_by(stride).collect();
    let per_frame = (shown.len() * (d + 1)).max(1);
    let keep = limits.frames.min(limits.values / per_frame).max(2);
    let picked = evenly(files.len(), keep);
    let mut snaps = Vec::with_capacity(picked.len());
    for &i in &picked {
        snaps.push(if i == 0 {
            first.clone()
        } else {
            read(&files[i])?
        });
    }
    let all_speeds: Vec<Vec<f64>> = snaps.iter().map(speeds).collect();
    let v_max = all_speeds
        .iter()
        .flatten()
        .fold(0.0f64, |a, b| a.max(*b))
        .max(f64::MIN_POSITIVE)
        * 1.0001;
    let species = first.species_names.len().max(1);
    let mut frames = Vec::new();
    for (s, v) in snaps.iter().zip(&all_speeds) {
        if s.radii.len() != n {
            return Err(format!(
                "{}: snapshots hold different numbers of grains ({} and {n})",
                RunDir::new(dir).snapshot_dir().display(),
                s.radii.len()
            ));
        }
        frames.push(json!({
            "time": s.time,
            "positions": base64_f32(shown.iter().flat_map(|&i| s.positions[i * d..(i + 1) * d].iter().copied())),
            "speeds": base64_f32(shown.iter().map(|&i| v[i])),
            "histogram": speed_histogram(s, v, v_max, species),
        }));
    }
    let periodic: Vec<bool> = scenario
        .axes()
        .iter()
        .map(|a| *a == AxisKind::Periodic)
        .collect();
    let species_of: Vec<u8> = shown
        .iter()
        .map(|&i| first.species[i].min(255) as u8)
        .collect();
    let data = json!({
        "dimension": d,
        "lengths": scenario.lengths(),
        "periodic": periodic,
        "species_names": first.species_names,
        "grains_total": n,
        "grains_shown": shown.len(),
        "stride": stride,
        "frames_total": files.len(),
        "speed_max": v_max,
        "radii": base64_f32(shown.iter().map(|&i| first.radii[i])),
        "species": STANDARD.encode(&species_of),
        "frames": frames,
    });
    Ok(Some(PlayerData {
        json: data.to_string(),
        grains_total: n,
        grains_shown: shown.len(),
        stride,
        frames_total: files.len(),
        frames_shown: picked.len(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evenly_keeps_first_and_last() {
        assert_eq!(evenly(3, 10), vec![0, 1, 2]);
        let p = evenly(1000, 5);
        assert_eq!(p, vec![0, 250, 500, 749, 999]);
    }

    /// A run directory with `frames` synthetic snapshots of `n` disks on a lattice, each
    /// with speed 1 (grain `i` of frame `f` at `x = (i + f/10) / n`).
    fn synthetic_run(name: &str, n: usize, frames: usize) -> (PathBuf, Scenario) {
        let dir = std::env::temp_dir().join(format!("granular-html-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("snapshots")).unwrap();
        for f in 0..frames {
            let snap = Snapshot {
                time: f as f64,
                dimension: 2,
                positions: (0..n)
                    .flat_map(|i| [(i as f64 + f as f64 / 10.0) / n as f64, 0.5])
                    .collect(),
                velocities: (0..n).flat_map(|_| [0.6, 0.8]).collect(),
                radii: vec![1e-6; n],
                masses: vec![1.0; n],
                species: vec![0; n],
                species_names: vec!["disk".into()],
                ..Default::default()
            };
            granular::run::write_snapshot(
                dir.join(format!("snapshots/snapshot_{f:06}.npz")),
                &snap,
            )
            .unwrap();
        }
        let text = format!(
            "engine = \"edmd\"\n[[species]]\nname = \"disk\"\ncount = {n}\nradius = 1e-6\n\
             velocity = {{ distribution = \"fixed_speed\", speed = 1.0 }}\n[stop]\ntime = 1.0\n"
        );
        (dir, Scenario::from_toml(&text, &[]).unwrap())
    }

    #[test]
    fn large_runs_are_subsampled_and_histograms_count_every_grain() {
        let n = 1001;
        let (dir, scenario) = synthetic_run("large", n, 30);
        let limits = Limits {
            grains: 500,
            frames: 100,
            values: 10_020,
        };
        let p = player_data(&dir, &scenario, limits).unwrap().unwrap();
        assert_eq!((p.grains_total, p.stride, p.grains_shown), (n, 3, 334));
        // 3 numbers per grain drawn and frame: the number budget binds (10 frames).
        assert_eq!((p.frames_total, p.frames_shown), (30, 10));
        let data: Value = serde_json::from_str(&p.json).unwrap();
        let frames = data["frames"].as_array().unwrap();
        assert_eq!(frames.len(), p.frames_shown);
        assert_eq!(frames.last().unwrap()["time"], 29.0);
        for f in frames {
            let counts: u64 = f["histogram"]["counts"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_u64().unwrap())
                .sum();
            assert_eq!(counts, n as u64);
            let bytes = STANDARD.decode(f["positions"].as_str().unwrap()).unwrap();
            assert_eq!(bytes.len(), 4 * 2 * p.grains_shown);
            // Grain 3 (the second drawn) of this frame, as float32.
            let x = f32::from_le_bytes(bytes[8..12].try_into().unwrap());
            let t = f["time"].as_f64().unwrap();
            assert_eq!(x, ((3.0 + t / 10.0) / n as f64) as f32);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn small_runs_are_shown_whole() {
        let (dir, scenario) = synthetic_run("small", 50, 4);
        let p = player_data(&dir, &scenario, Limits::default())
            .unwrap()
            .unwrap();
        assert_eq!((p.stride, p.grains_shown, p.frames_shown), (1, 50, 4));
        // The frame limit alone: 3 of 4 frames, first and last kept.
        let limits = Limits {
            frames: 3,
            ..Limits::default()
        };
        let p = player_data(&dir, &scenario, limits).unwrap().unwrap();
        let data: Value = serde_json::from_str(&p.json).unwrap();
        let times: Vec<f64> = data["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["time"].as_f64().unwrap())
            .collect();
        assert_eq!(times, vec![0.0, 2.0, 3.0]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn base64_round_trips_float32() {
        let s = base64_f32([1.5, -2.0].into_iter());
        let bytes = STANDARD.decode(s).unwrap();
        assert_eq!(f32::from_le_bytes(bytes[0..4].try_into().unwrap()), 1.5);
        assert_eq!(f32::from_le_bytes(bytes[4..8].try_into().unwrap()), -2.0);
    }
}
