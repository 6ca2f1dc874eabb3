//! `granular scaling`: the speed-up model read from a benchmark CSV.

use super::{granular, tmp};

const HEADER: &str = "scaling,dimension,n,packing_fraction,ranks,threads,cell_planes,steps,segments,seconds,particle_steps_per_second,rank,particles,seconds_per_step,compute_seconds_per_step,migration_seconds_per_step,reduction_seconds_per_step,compute_particle_steps_per_second,migration_bytes_per_step,reduction_bytes_per_step,bytes_received_per_step,migrants_per_step,migration_calls_per_step,reduction_calls_per_step,resident_bytes,peak_resident_bytes";

/// One rank's row: (ranks, rank, particles, particle-steps/s, compute s/step, migrants).
fn row(k: usize, rank: usize, particles: usize, pss: f64, compute: f64, migrants: f64) -> String {
    format!(
        "strong,2,500000,0.1,{k},1,224,20,3,1.0,{pss},{rank},{particles},{compute},{compute},0,0,1,{},100,100,{migrants},1,6,1e8,2e8",
        40.0 * migrants
    )
}

#[test]
fn scaling_reads_the_benchmark_and_reduces_to_compute_alone_on_a_free_network() {
    let dir = tmp("scaling");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("bench.csv");
    let text = [
        HEADER.to_string(),
        row(1, 0, 500_000, 2e7, 0.025, 0.0),
        row(2, 0, 250_000, 3.8e7, 0.0125, 44.0),
        row(2, 1, 250_000, 3.8e7, 0.0125, 46.0),
    ]
    .join("\n");
    std::fs::write(&csv, text).unwrap();
    let out = dir.join("out");
    // A network without latency and with 10^21 bytes/s: only the compute of the thickest
    // slab is left, 224 planes over 2 ranks exactly halved.
    let o = granular()
        .arg("scaling")
        .arg(&csv)
        .arg("--out")
        .arg(&out)
        .args(["--latency-us", "0", "--bandwidth-gbs", "1e12"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("scaling_model.json")).unwrap())
            .unwrap();
    let inputs = &model["inputs"];
    assert_eq!(
        inputs["compute_seconds_per_particle_step"],
        0.025 / 500_000.0
    );
    // The mean over the two ranks, over the two faces of a rank.
    assert_eq!(inputs["migrants_per_face_per_step"], 22.5);
    assert_eq!(inputs["cell_planes"], 224.0);
    let speedups: Vec<f64> = model["measured_strong"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["particle_steps_per_second"].as_f64().unwrap())
        .collect();
    assert_eq!(speedups, vec![2e7, 3.8e7]);
    let table = std::fs::read_to_string(out.join("scaling_model.csv")).unwrap();
    let speedup = |variant: &str, ranks: &str| -> f64 {
        table
            .lines()
            .find(|l| {
                let c: Vec<&str> = l.split(',').collect();
                c[0] == variant && c[1] == "500000" && c[2] == ranks
            })
            .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
            .unwrap()
    };
    assert_eq!(speedup("slabs", "1"), 1.0);
    assert!((speedup("slabs", "2") - 2.0).abs() < 1e-6);
    // 224 planes over 128 ranks: the thickest slab has 2 planes, so 112 at best.
    assert!((speedup("slabs", "128") - 112.0).abs() < 1e-3);
    assert!(out.join("dsmc_speedup.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scaling_without_two_rank_rows_says_what_to_run() {
    let dir = tmp("scaling-missing");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("bench.csv");
    std::fs::write(
        &csv,
        [HEADER.to_string(), row(1, 0, 500_000, 2e7, 0.025, 0.0)].join("\n"),
    )
    .unwrap();
    let o = granular()
        .arg("scaling")
        .arg(&csv)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("1 and 2 ranks") && err.contains("bench dsmc-ranks --csv"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
