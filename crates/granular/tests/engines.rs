//! The event-driven and DSMC engines on the same scenario: at low density both solve the
//! (Enskog-)Boltzmann equation, so their cooling curves must agree, and both must follow
//! Haff's law with the kinetic-theory cooling time.

use granular::scenario::Scenario;
use granular::stats::RunningStats;
use granular::theory::haff;
use std::path::PathBuf;

fn cooling_curve(engine: &str, seed: u64) -> Vec<(f64, f64)> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let mut o: Vec<String> = [
        format!("engine=\"{engine}\""),
        "species[0].count=3000".into(),
        "species[0].packing_fraction=0.02".into(),
        format!("seed={seed}"),
        "stop.time=1.0".into(),
        "output.interval=0.25".into(),
    ]
    .to_vec();
    // `[dsmc]` is an error in an event-driven scenario (the event-driven engine has the
    // Enskog factor built in).
    if engine == "dsmc" {
        o.push("dsmc.enskog=true".into());
    }
    let s = Scenario::from_toml(&text, &o).unwrap();
    let rows: Vec<(f64, f64)> = crate::common::observations(s)
        .iter()
        .map(|o| (o.time, o.kinetic_energy))
        .collect();
    let k0 = rows[0].1;
    rows.into_iter().map(|(t, k)| (t, k / k0)).collect()
}

fn ensemble(engine: &str) -> Vec<(f64, RunningStats)> {
    let mut out: Vec<(f64, RunningStats)> = Vec::new();
    for seed in 1..=6 {
        for (i, (t, k)) in cooling_curve(engine, seed).into_iter().enumerate() {
            if out.len() <= i {
                out.push((t, RunningStats::new()));
            }
            out[i].1.push(k);
        }
    }
    out
}

#[test]
fn edmd_and_dsmc_agree_on_homogeneous_cooling_and_follow_haff() {
    let ed = ensemble("edmd");
    let ds = ensemble("dsmc");
    // Kinetic theory: n = 3000 in the unit box, radius from φ = 0.02, T(0) ≈ 1.
    let (n, phi, e) = (3000.0, 0.02, 0.9);
    let r = (phi / (n * std::f64::consts::PI)).sqrt();
    let chi = haff::contact_value(2, phi);
    for ((t, a), (_, b)) in ed.iter().zip(&ds).skip(1) {
        let err = (a.standard_error().powi(2) + b.standard_error().powi(2)).sqrt();
        assert!(
            (a.mean() - b.mean()).abs() < 4.0 * err,
            "t = {t}: EDMD {} vs DSMC {} (± {err})",
            a.mean(),
            b.mean()
        );
        // Haff with the Sonine-corrected Enskog cooling rate; T(0) is the sample's
        // temperature (≈ 1, the energy ratio removes it).
        let t0 = haff::haff_time(2, n, r, 1.0, 1.0, e, chi, true);
        let haff = 1.0 / (1.0 + t / t0).powi(2);
        let stat = a.standard_error().max(b.standard_error());
        // 4 σ plus 1 %: the initial temperature of each sample differs from 1 by O(1/sqrt(N)).
        assert!(
            (a.mean() - haff).abs() < 4.0 * stat + 0.01 * haff,
            "t = {t}: EDMD {} vs Haff {haff}",
            a.mean()
        );
    }
}
