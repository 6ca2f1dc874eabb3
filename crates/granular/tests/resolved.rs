//! The scenario's derived quantities are resolved once ([`granular::scenario::Resolved`])
//! and are the numbers the engines run with: the DSMC cell size and time step, the contact
//! value of the collision rate, the driving's theory and reference temperature, the
//! packing fraction of the summary. Compared bit for bit where the engine applies the same
//! rule to its own state, so that a second copy of a formula cannot drift unnoticed.

use granular::build::AnyEngine;
use granular::driving::Driving;
use granular::dsmc::DsmcEngine;
use granular::dsmc::config::{DsmcConfig, automatic_time_step};
use granular::prelude::*;
use granular::theory::kinetic;

fn scenario(engine: &str, extra: &str) -> Scenario {
    Scenario::from_toml(
        &format!(
            r#"
            engine = "{engine}"
            dimension = 2
            seed = 5
            box = {{ boundary = "periodic" }}
            [[species]]
            name = "disk"
            count = 2000
            packing_fraction = 0.2
            mass = 1.5
            velocity = {{ distribution = "maxwell_boltzmann", temperature = 2.0 }}
            [collisions]
            restitution = 0.8
            [stop]
            time = 0.05
            {extra}
            "#
        ),
        &[],
    )
    .expect("valid scenario")
}

/// The DSMC engine's own defaults (cell size, first automatic step, Enskog factor) are the
/// resolved values; the resolved temperature is the first row's of the time series.
#[test]
fn dsmc_runs_with_the_resolved_cell_size_step_and_contact_value() {
    let sc = scenario("dsmc", "[dsmc]\nenskog = true");
    let mut sim = Simulation::new(sc.clone()).expect("build");
    let g = sim.resolved().grains.clone().expect("grains");
    let d = g.dsmc.clone().expect("dsmc values");
    assert_eq!(g.temperature, sim.observe().temperature);
    let AnyEngine::Dsmc2(engine) = sim.engine() else {
        panic!("a 2D DSMC engine")
    };
    assert_eq!(engine.enskog_factor(), g.chi);
    assert_eq!(g.chi, kinetic::contact_value(2, g.packing_fraction));
    // An engine left to its own default cell size gets the resolved one.
    let own = DsmcEngine::<2>::from_state(
        DsmcConfig {
            enskog: true,
            ..DsmcConfig::default()
        },
        engine.sim_box().clone(),
        engine.radius(),
        engine.mass(),
        engine.positions(),
        engine.velocities(),
        1,
    )
    .expect("engine");
    assert_eq!(own.grid().edges, engine.grid().edges);
    assert_eq!(d.cell_edges, engine.grid().edges.to_vec());
    assert!(
        d.cell_size <= g.mean_free_path,
        "{} {}",
        d.cell_size,
        g.mean_free_path
    );
    // The first step the engine takes is the resolved one.
    assert!(d.follows_mean_free_time);
    sim.advance(1e-12).expect("advance");
    let AnyEngine::Dsmc2(engine) = sim.engine() else {
        panic!("a 2D DSMC engine")
    };
    assert_eq!(engine.time_step(), d.time_step);
    assert_eq!(
        Some(d.time_step),
        automatic_time_step(g.collision_frequency)
    );
    assert_eq!(
        g.collision_frequency,
        kinetic::collision_frequency(2, g.number_density, g.radius, g.temperature, 1.5, g.chi)
    );
}

/// The event-driven engine's driving: its kinetic theory is the resolved one, and the
/// rescaling temperature left out of `[driving]` is the drawn state's.
#[test]
fn edmd_driving_is_the_resolved_state() {
    let sc = scenario("edmd", "[driving]\nkind = \"rescale\"");
    let sim = Simulation::new(sc.clone()).expect("build");
    let g = sim.resolved().grains.clone().expect("grains");
    let state = g.driving.clone().expect("driving");
    let AnyEngine::Edmd2(engine) = sim.engine() else {
        panic!("a 2D event-driven engine")
    };
    assert_eq!(engine.gas_theory(), state.gas);
    let t0 = sim.observe().temperature;
    assert_eq!(state.driving, Driving::Rescale { temperature: t0 });
    assert_eq!(
        engine.driving().map(|d| d.driving.clone()),
        Some(state.driving.clone())
    );
    // The scenario alone resolves at the temperature its velocities give.
    let nominal = sc.resolve().grains.expect("grains");
    assert_eq!(nominal.temperature, 2.0);
    assert_eq!(nominal.packing_fraction, g.packing_fraction);
    assert!(
        (g.packing_fraction - 0.2).abs() < 1e-14,
        "{}",
        g.packing_fraction
    );
    assert!((t0 / 2.0 - 1.0).abs() < 0.1, "drawn temperature {t0}");
}

/// The summary's `resolved` block is the simulation's record.
#[test]
fn the_summary_block_is_the_record() {
    let sc = scenario("dsmc", "[dsmc]\nenskog = true");
    let sim = Simulation::new(sc).expect("build");
    let block = granular::run::ResolvedSummary::of(sim.resolved()).expect("block");
    let g = sim.resolved().grains.as_ref().expect("grains");
    assert_eq!(block.packing_fraction, g.packing_fraction);
    assert_eq!(block.radius["disk"], g.species[0].radius);
    assert_eq!(block.contact_value, Some(g.chi));
}
