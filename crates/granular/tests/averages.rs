//! The summary's `averages` block: its errors are honest (z-scores against an exact result
//! over independent seeds are standard normal), it survives a checkpoint bit for bit, and
//! it says where no error is valid.

use granular::Summary;
use granular::run::Run;
use granular::scenario::Scenario;
use granular::theory::equilibrium;

/// Elastic hard disks at packing fraction `phi` in a periodic unit box, at rest as a whole
/// (the temperature and the pressure's kinetic part are those of the raw velocities: a
/// drift of the centre of mass would lower `Z` by its share of the kinetic energy).
fn disks(seed: u64, phi: f64, stop: f64) -> Scenario {
    let text = format!(
        r#"
engine = "edmd"
dimension = 2
seed = {seed}
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = 400
packing_fraction = {phi}
mass = 1.0
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[initial]
zero_momentum = true
[collisions]
restitution = 1.0
[stop]
collisions_per_particle = {stop}
[output]
interval = 0.05
checkpoint_seconds = inf
"#
    );
    Scenario::from_toml(&text, &[]).expect("scenario")
}

fn average(s: &Summary, name: &str) -> granular::run::AverageValue {
    s.averages.as_ref().expect("averages block").observables[name].clone()
}

/// `Z = P / (n T)` of elastic hard disks at φ = 0.1 against Henderson's equation of state
/// (whose error there, from the third and fourth virial coefficients, is 3e-5, well below
/// the statistical error): each seed's z-score within 4, and the sum of their squares
/// below the 99.9 % point of chi-square with 6 degrees of freedom (22.46).
#[test]
fn compressibility_factor_z_scores_are_standard_normal() {
    let exact = equilibrium::hard_disk_compressibility(0.1);
    let mut chi2 = 0.0;
    let mut lines = Vec::new();
    for seed in 1..=6 {
        let (summary, dir) = crate::common::run("averages-z", disks(seed, 0.1, 1000.0));
        let _ = std::fs::remove_dir_all(dir);
        let z = average(&summary, "compressibility_factor");
        let error = z.error.expect("an error for an equilibrium gas");
        assert!(z.blocks >= 8 && z.samples > 500, "{z:?}");
        let score = (z.mean - exact) / error;
        lines.push(format!(
            "seed {seed}: Z = {} ± {error}, z = {score:.2}",
            z.mean
        ));
        assert!(score.abs() < 4.0, "{}", lines.join("\n"));
        chi2 += score * score;
    }
    assert!(chi2 < 22.46, "chi2 = {chi2}\n{}", lines.join("\n"));
    eprintln!(
        "Henderson Z = {exact}, chi2 = {chi2:.2}\n{}",
        lines.join("\n")
    );
}

/// A run stopped after 200 outputs (checkpointed at each) and resumed gives the same
/// `averages`, bit for bit, as the run without a stop.
#[test]
fn averages_survive_checkpoint_and_resume() {
    let scenario = Scenario::from_toml(
        &disks(9, 0.2, 1000.0).to_toml(),
        &["output.checkpoint_seconds=1e-9".into()],
    )
    .expect("scenario");
    let (whole, dir) = crate::common::run("averages-whole", scenario.clone());
    let _ = std::fs::remove_dir_all(dir);
    let dir = crate::common::tmp("averages-resumed");
    let stopped = Run::create(&dir, scenario)
        .expect("run")
        .run_to_end(&mut |_| {}, Some(200));
    assert!(stopped.is_err(), "the run should stop after 200 outputs");
    let resumed = Run::resume(&dir)
        .expect("resume")
        .run_to_end(&mut |_| {}, None)
        .expect("resumed run");
    let _ = std::fs::remove_dir_all(&dir);
    let (a, b) = (
        whole.averages.expect("averages"),
        resumed.averages.expect("averages"),
    );
    assert!(a.observables["pressure"].samples > 300);
    let bits = |s: &granular::run::AveragesSummary| {
        s.observables
            .iter()
            .map(|(k, v)| (k.clone(), v.mean.to_bits(), v.error.map(f64::to_bits)))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a, b);
}
