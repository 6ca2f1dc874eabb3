//! What to change in a scenario when its run stops: the engines' typed judgements (an
//! inelastic collapse's [`CollapseRemedy`]) in the words of the scenario, its keys and
//! values.

use crate::engine::{Collapse, CollapseRemedy};

/// The advice after an inelastic collapse, naming the keys of `[collisions]` and the
/// value to give (`docs/edmd.md`, "Inelastic collapse").
pub(crate) fn collapse(collapse: &Collapse) -> String {
    let tau = collapse.mean_free_time;
    match collapse.remedy {
        CollapseRemedy::WallRestitutionAboveZero => {
            "With collisions.wall_restitution = 0 under gravity, a grain that lands on a wall \
             stops there and hits it again at zero intervals, which no TC model can stop: \
             set collisions.wall_restitution above 0 (a landed grain then bounces ever lower \
             until the TC model makes its bounces elastic)."
                .to_string()
        }
        CollapseRemedy::LongerContactDuration {
            contact_duration: t_c,
            advised,
        } => format!(
            "The TC model is on (t_c = {t_c}) but too short to stop it: set \
             collisions.contact_duration = {advised:.1e} (ten times longer; keep it well below \
             the mean free time of the grains in motion, since collisions closer than t_c \
             are elastic), or raise the restitution."
        ),
        CollapseRemedy::EnableContactDuration {
            advised,
            under_gravity: true,
        } => format!(
            "Enable the TC model: grains that come to rest under gravity need \
             collisions.contact_duration = {advised:.1e} (about 0.1 of the mean free time \
             {tau:.3e}; collisions closer than t_c are elastic), or raise the restitution."
        ),
        CollapseRemedy::EnableContactDuration {
            advised,
            under_gravity: false,
        } => format!(
            "Enable the TC model with collisions.contact_duration = {advised:.1e} (about 1e-3 of \
             the mean free time {tau:.3e}), or raise the restitution."
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn worded(remedy: CollapseRemedy) -> String {
        let mut c = Collapse {
            time: 0.38123456,
            events: 65536,
            elapsed: 1.5e-9,
            restitution: 0.5,
            mean_free_time: 0.0682,
            remedy,
            advice: None,
        };
        c.advice = Some(collapse(&c));
        c.to_string()
    }

    /// The messages word for word as the engine wrote them before the advice moved here.
    #[test]
    fn collapse_advice_names_the_keys_and_values() {
        let head = "inelastic collapse at t = 3.812346e-1: the last 65536 events advanced the \
                    time by only 1.500e-9 (grains collide ever faster in a shrinking cluster; \
                    restitution 0.5). ";
        assert_eq!(
            worded(CollapseRemedy::WallRestitutionAboveZero),
            format!(
                "{head}With collisions.wall_restitution = 0 under gravity, a grain that lands \
                 on a wall stops there and hits it again at zero intervals, which no TC model \
                 can stop: set collisions.wall_restitution above 0 (a landed grain then \
                 bounces ever lower until the TC model makes its bounces elastic)."
            )
        );
        assert_eq!(
            worded(CollapseRemedy::LongerContactDuration {
                contact_duration: 1e-4,
                advised: 10.0 * 1e-4
            }),
            format!(
                "{head}The TC model is on (t_c = 0.0001) but too short to stop it: set \
                 collisions.contact_duration = 1.0e-3 (ten times longer; keep it well below \
                 the mean free time of the grains in motion, since collisions closer than t_c \
                 are elastic), or raise the restitution."
            )
        );
        assert_eq!(
            worded(CollapseRemedy::EnableContactDuration {
                advised: 0.1 * 0.0682,
                under_gravity: true
            }),
            format!(
                "{head}Enable the TC model: grains that come to rest under gravity need \
                 collisions.contact_duration = 6.8e-3 (about 0.1 of the mean free time \
                 6.820e-2; collisions closer than t_c are elastic), or raise the restitution."
            )
        );
        assert_eq!(
            worded(CollapseRemedy::EnableContactDuration {
                advised: 1e-3 * 0.0682,
                under_gravity: false
            }),
            format!(
                "{head}Enable the TC model with collisions.contact_duration = 6.8e-5 (about \
                 1e-3 of the mean free time 6.820e-2), or raise the restitution."
            )
        );
    }
}
