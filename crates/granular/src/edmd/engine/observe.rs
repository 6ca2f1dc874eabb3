//! Observables of the whole gas: kinetic energy, momentum, `a2`, per-species kinetic
//! energy (at the current time, without perturbing the trajectory).

use super::Edmd;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Total kinetic energy, `Σ m v² / 2`.
    pub fn kinetic_energy_now(&self) -> f64 {
        (0..self.len())
            .map(|s| 0.5 * self.mass(s) * self.velocity_slot(s).norm_squared())
            .sum()
    }

    /// Rotational kinetic energy `Σ I |ω|² / 2` of rough grains (`None` for smooth ones).
    pub fn rotational_energy_now(&self) -> Option<f64> {
        if self.spin.is_empty() {
            return None;
        }
        Some(
            (0..self.len())
                .map(|s| {
                    let w = crate::collision_law::rough::spin_at::<D>(&self.spin, s);
                    let kind = self.grains[s].kind as usize;
                    let body = crate::collision_law::rough::Body {
                        mass: self.kind_mass[kind],
                        radius: self.kind_radius[kind],
                        inertia: self.kind_inertia[kind],
                    };
                    crate::collision_law::rough::rotational_energy(&body, &w)
                })
                .sum(),
        )
    }

    /// Total momentum.
    pub fn momentum(&self) -> Vector<D> {
        let mut p = Vector::zero();
        for s in 0..self.len() {
            p = p.add_scaled(self.mass(s), &self.velocity_slot(s));
        }
        p
    }

    /// The fourth cumulant `a2` of the peculiar velocities, of all grains and per species
    /// (`crate::moments::a2_by_species`).
    pub fn a2_by_species(&self) -> (f64, Vec<f64>) {
        let species = self.species_names.len().max(1);
        crate::moments::a2_by_species::<D>(self.len(), species, |i| {
            let s = self.kind_species[self.grains[i].kind as usize] as usize;
            (s, self.mass(i), self.velocity_slot(i))
        })
    }

    /// Kinetic energy and grain count per species.
    pub(crate) fn species_kinetic_energy(&self) -> Vec<(f64, usize)> {
        let mut out = vec![(0.0, 0usize); self.species_names.len().max(1)];
        for i in 0..self.len() {
            let s = self.kind_species[self.grains[i].kind as usize] as usize;
            if s < out.len() {
                out[s].0 += 0.5 * self.mass(i) * self.velocity_slot(i).norm_squared();
                out[s].1 += 1;
            }
        }
        out
    }
}
