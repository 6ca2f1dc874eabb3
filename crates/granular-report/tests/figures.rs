//! `granular plot` on small run and sweep directories made here: the figures a referee
//! checks first. PNGs are decoded to count the curves (distinct palette colours); SVG text
//! is read for the axis labels, legends and goodness of fit.

use std::path::{Path, PathBuf};

use granular::run::Run;
use granular::scenario::Scenario;
use granular_report::plot::PALETTE;

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("granular-report-figures-{}", std::process::id()))
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.parent().expect("parent")).expect("temp dir");
    dir
}

fn run(dir: &Path, toml: &str) {
    let scenario = Scenario::from_toml(toml, &[]).expect("scenario");
    Run::create(dir, scenario)
        .expect("create run")
        .run_to_end(&mut |_| {}, None)
        .expect("run");
}

/// Decoded RGB pixels of a PNG.
fn pixels(path: &Path) -> Vec<[u8; 3]> {
    let file = std::fs::File::open(path).expect("open png");
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png frame");
    let channels = info.color_type.samples();
    buf[..info.buffer_size()]
        .chunks(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect()
}

/// The palette colours drawn on at least `min_pixels` pixels: the curves of a line plot
/// (black, palette entry 6, is left out: it is also the colour of the frame and the text).
fn palette_colours(path: &Path, min_pixels: usize) -> Vec<usize> {
    let px = pixels(path);
    (0..PALETTE.len())
        .filter(|&i| i != 6)
        .filter(|&i| {
            let c = PALETTE[i];
            px.iter().filter(|p| **p == [c.0, c.1, c.2]).count() >= min_pixels
        })
        .collect()
}

fn svg(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join("figures").join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn assert_contains(text: &str, needles: &[&str], what: &str) {
    for n in needles {
        assert!(text.contains(n), "{what} lacks `{n}`");
    }
}

const COOLING: &str = r#"
engine = "dsmc"
dimension = 2
seed = 3
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "grain"
count = 2000
packing_fraction = 0.05
mass = 1.0
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[initial]
zero_momentum = true
[collisions]
restitution = 0.8
[stop]
collisions_per_particle = 10.0
[output]
interval = 0.01
"#;

/// A single cooling run: the energy is drawn log-log against Haff's law at the
/// kinetic-theory `t0`, axes with units; two curves (data and theory) in two colours.
#[test]
fn cooling_run_energy_has_haff_law_and_units() {
    let dir = temp_dir("cooling");
    run(&dir, COOLING);
    granular_report::plot_dir(&dir, false).expect("plot");
    let text = svg(&dir, "energy.svg");
    assert_contains(
        &text,
        &[
            "time t [τ]",
            "kinetic energy per grain E/N [m L²/τ²]",
            "law, t₀ =",
            "all grains",
        ],
        "energy.svg",
    );
    assert_eq!(
        palette_colours(&dir.join("figures/energy.png"), 200),
        vec![0, 1],
        "one data curve and the Haff curve"
    );
}

const ELASTIC_MIXTURE: &str = r#"
engine = "edmd"
dimension = 2
seed = 5
[box]
lengths = [1.0, 1.0]
boundary = "wall"
[[species]]
name = "light"
count = 300
radius = 0.01
mass = 1.0
velocity = { distribution = "fixed_speed", speed = 1.0 }
[[species]]
name = "heavy"
count = 300
radius = 0.01
mass = 4.0
velocity = { distribution = "fixed_speed", speed = 1.0 }
[collisions]
restitution = 1.0
[stop]
collisions_per_particle = 60.0
[output]
interval = 0.02
equilibration_collisions_per_particle = 10.0
histogram_sample_spacing = 2.0
"#;

/// Histograms against a theory print chi-square, dof and p; speed axes carry units.
#[test]
fn histograms_print_their_goodness_of_fit() {
    let dir = temp_dir("mixture");
    run(&dir, ELASTIC_MIXTURE);
    granular_report::plot_dir(&dir, false).expect("plot");
    for species in ["light", "heavy"] {
        let text = svg(&dir, &format!("speed_equilibrium_{species}.svg"));
        assert_contains(
            &text,
            &[
                "speed v [L/τ]",
                "probability density p(v) [τ/L]",
                "χ² = ",
                ", dof = ",
                ", p = ",
            ],
            species,
        );
    }
    let text = svg(&dir, "impact_parameter.svg");
    assert_contains(
        &text,
        &["reduced impact parameter b/σ", "χ² = ", "molecular chaos"],
        "impact_parameter.svg",
    );
    // Two species: all grains and one curve per species.
    assert_eq!(
        palette_colours(&dir.join("figures/energy.png"), 200),
        vec![0, 1, 2]
    );
}

/// 3D runs get snapshot figures: the projection and a central slice.
#[test]
fn three_dimensional_runs_get_snapshot_figures() {
    let dir = temp_dir("three_d");
    run(
        &dir,
        r#"
engine = "edmd"
dimension = 3
seed = 9
[box]
lengths = [1.0, 1.0, 1.0]
boundary = "periodic"
[[species]]
name = "ball"
count = 400
packing_fraction = 0.1
mass = 1.0
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[collisions]
restitution = 1.0
[stop]
collisions_per_particle = 2.0
[output]
interval = 0.05
"#,
    );
    let made = granular_report::plot_dir(&dir, false).expect("plot");
    for f in [
        "snapshot_first.png",
        "snapshot_last.png",
        "snapshot_first_slice.png",
        "snapshot_last_slice.png",
    ] {
        let p = dir.join("figures").join(f);
        assert!(made.contains(&p), "{f} not made");
    }
    assert_contains(
        &svg(&dir, "snapshot_last_slice.svg"),
        &["slice", "z &lt;"],
        "slice",
    );
}

/// A sweep over the restitution of a two-species gas: figures only of physical
/// observables, the swept axis labelled by its meaning, one colour per swept value.
#[test]
fn sweep_figures_mean_something() {
    let dir = temp_dir("sweep");
    let text = format!(
        "{}\n[sweep]\nkey = \"collisions.restitution\"\nvalues = [1.0, 0.7]\nseeds = 2\n",
        ELASTIC_MIXTURE
            .replace(
                "collisions_per_particle = 60.0",
                "collisions_per_particle = 5.0"
            )
            .replace("equilibration_collisions_per_particle = 10.0", "")
    );
    granular::run::sweep::run_sweep(&dir, &text, &[], 1, &|_, _| {}).expect("sweep");
    let made = granular_report::plot_dir(&dir, false).expect("plot");
    let names: Vec<String> = made
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().to_string()))
        .collect();
    for left_out in ["sweep_time.png", "sweep_wall_collisions.png"] {
        assert!(!names.iter().any(|n| n == left_out), "{left_out} drawn");
    }
    assert!(
        names.iter().any(|n| n == "sweep_temperature.png"),
        "{names:?}"
    );
    assert_contains(
        &svg(&dir, "sweep_temperature.svg"),
        &["restitution ξ", "final temperature T [m L²/τ²]"],
        "sweep_temperature.svg",
    );
    let energy = svg(&dir, "sweep_energy_time.svg");
    assert_contains(&energy, &["ξ = 1.0: light", "ξ = 0.7: heavy"], "energy");
    // Two swept values, two colours (the species differ by line style).
    assert_eq!(
        palette_colours(&dir.join("figures/sweep_energy_time.png"), 200),
        vec![0, 1]
    );
}
