//! The scenario's derived quantities are resolved once ([`granular::scenario::Resolved`])
//! and are the numbers the engines run with: the DSMC cell size and time step, the contact
//! value of the collision rate, the driving's theory and reference temperature, the
//! packing fraction of the summary. Compared bit for bit where the engine applies the same
//! rule to its own state, so that a second copy of a formula cannot drift unnoticed.

use granular::driving::Driving;
use granular::dsmc::DsmcEngine;
use granular::dsmc::config::{DsmcConfig, automatic_time_step};
use granular::prelude::*;
use granular::run::AnyEngine;
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

/// Rough grains' driven state is resolved with the rough gas's theory (RS-6, RS-8, RS-9),
/// not the smooth gas's KT-11..KT-13: the record that `granular check`, `summary.json`'s
/// `resolved` and `steady_state` blocks and Python's `resolved` read.
#[test]
fn rough_grains_driven_state_is_the_rough_theory() {
    for (kind, extra) in [
        (
            "white_noise",
            "[driving]\nkind = \"white_noise\"\nstrength = 2.0",
        ),
        ("rescale", "[driving]\nkind = \"rescale\""),
    ] {
        let sc = scenario("dsmc", extra);
        let sc = Scenario::from_toml(
            &sc.to_toml(),
            &["collisions.tangential_restitution=0.5".to_string()],
        )
        .expect("rough");
        let g = sc.resolve().grains.expect("grains");
        let state = g.driving.clone().expect("driving");
        let gas = g.rough.as_ref().expect("rough").gas(2, 0.8);
        match state.driving {
            Driving::WhiteNoise { strength } => {
                assert_eq!(kind, "white_noise");
                let nu = kinetic::collision_frequency(
                    2,
                    state.gas.number_density,
                    state.gas.radius,
                    1.0,
                    state.gas.mass,
                    state.gas.chi,
                );
                let t = gas.white_noise_temperature(strength, 1.5, 2000, nu);
                assert_eq!(state.temperature, t);
                assert_ne!(
                    state.temperature,
                    state.gas.white_noise_temperature(strength, state.a2)
                );
                let a20 = gas.sonine_white_noise_state().expect("RS-9").a20;
                assert_eq!(state.a2, a20);
            }
            Driving::Rescale { temperature } => {
                assert_eq!(state.temperature, temperature);
                assert_eq!(state.a2, gas.sonine_cooling_state().expect("RS-8").a20);
                assert_eq!(state.a2_first, None);
            }
        }
        assert_ne!(
            state.a2,
            state.gas.a2(&state.driving),
            "{kind}: not the smooth a2"
        );
    }
}
