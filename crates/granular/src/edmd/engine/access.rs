//! What the engine tells about its grains and settings: by grain id (the public
//! accessors, through the slot table) and by slot (the engine's own, inlined), and each
//! grain's state at the current time from its local clock (HD-6).

use super::Edmd;
use super::Totals;
use super::collide::CollisionRecord;
use crate::boundary::SimulationBox;
use crate::collision_law::{CollisionLaw, Spin, rough};
use crate::particles::ParticleSet;
use crate::stats::Histogram;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// The box.
    pub fn simulation_box(&self) -> &SimulationBox<D> {
        &self.bx
    }

    /// The collision law.
    pub fn collision_law(&self) -> &CollisionLaw {
        &self.law
    }

    /// Replaces the collision law (takes effect from the next collision). A law that makes
    /// smooth grains rough starts them without spin, each species uniform.
    pub fn set_collision_law(&mut self, law: CollisionLaw) {
        if law.contact_duration > 0.0 && self.last_collision.is_empty() {
            self.last_collision = vec![f64::NEG_INFINITY; self.len()];
        }
        if law.is_rough() && self.spin.is_empty() {
            self.kind_inertia = vec![rough::uniform_inertia(D); self.kind_species.len()];
            self.spin = vec![0.0; rough::rotational_dof(D) * self.len()];
        }
        self.law = law;
    }

    /// Whether the grains are rough (they carry angular velocities).
    pub(crate) fn is_rough(&self) -> bool {
        !self.spin.is_empty()
    }

    /// Angular velocity of grain `id` (radians per time unit; `[0, 0, ω_z]` for a disk);
    /// zero for smooth grains.
    pub fn angular_velocity(&self, id: usize) -> Spin {
        if self.spin.is_empty() {
            return [0.0; 3];
        }
        rough::spin_at::<D>(&self.spin, self.slot_of(id))
    }

    /// Angular velocities of rough grains by id, `d_r` values per grain (`ω_z` in 2D);
    /// empty for smooth grains.
    pub fn angular_velocities(&self) -> Vec<f64> {
        if self.spin.is_empty() {
            return Vec::new();
        }
        let r = rough::rotational_dof(D);
        let mut out = Vec::with_capacity(r * self.len());
        for &s in self.slots() {
            let s = s as usize;
            out.extend_from_slice(&self.spin[r * s..r * s + r]);
        }
        out
    }

    /// The reduced moment of inertia κ of each species of rough grains (empty for smooth
    /// grains).
    pub(crate) fn species_inertia(&self) -> Vec<f64> {
        if self.kind_inertia.is_empty() {
            return Vec::new();
        }
        let mut out = vec![rough::uniform_inertia(D); self.species_names.len().max(1)];
        for (k, &s) in self.kind_species.iter().enumerate() {
            if let Some(x) = out.get_mut(s as usize) {
                *x = self.kind_inertia[k];
            }
        }
        out
    }

    /// Running totals (collision counts, virial, dissipated energy).
    pub fn totals(&self) -> &Totals {
        &self.totals
    }

    /// Histogram of the normalised impact parameter `b / σ` of all pair collisions so far.
    pub(crate) fn impact_histogram(&self) -> &Histogram {
        &self.impact
    }

    /// Starts (or stops, with `false`) recording every collision in a log, in the order
    /// processed ([`Edmd::collision_log`]). For tests and diagnostics: it grows without
    /// bound.
    pub fn record_collisions(&mut self, on: bool) {
        self.log = if on { Some(Vec::new()) } else { None };
    }

    /// The collisions recorded since [`Edmd::record_collisions`] was switched on.
    pub fn collision_log(&self) -> &[CollisionRecord] {
        self.log.as_deref().unwrap_or(&[])
    }

    /// Number of grains.
    pub fn len(&self) -> usize {
        self.grains.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.grains.is_empty()
    }

    /// Masses of the grains, by id.
    pub fn masses(&self) -> Vec<f64> {
        self.by_id(|e, s| e.mass(s))
    }

    /// Species of the grains, by id.
    pub fn species(&self) -> Vec<u32> {
        self.by_id(|e, s| e.kind_species[e.grains[s].kind as usize])
    }

    /// `f(self, slot)` for every grain, in id order.
    pub(super) fn by_id<T>(&self, f: impl Fn(&Self, usize) -> T) -> Vec<T> {
        self.slots().iter().map(|&s| f(self, s as usize)).collect()
    }

    /// The slot of each grain id (see the field `slot`).
    pub(super) fn slots(&self) -> &[u32] {
        self.slot.get_or_init(|| {
            let mut slot = vec![0u32; self.id.len()];
            for (s, &g) in self.id.iter().enumerate() {
                slot[g as usize] = s as u32;
            }
            slot
        })
    }

    /// The slot of grain `id`.
    pub(super) fn slot_of(&self, id: usize) -> usize {
        self.slots()[id] as usize
    }

    #[inline(always)]
    pub(super) fn mass(&self, s: usize) -> f64 {
        self.kind_mass[self.grains[s].kind as usize]
    }

    #[inline(always)]
    pub(super) fn base_radius(&self, s: usize) -> f64 {
        self.kind_radius[self.grains[s].kind as usize]
    }

    /// Current radius of slot `s` (differs from the initial one only during compression).
    #[inline(always)]
    pub(super) fn radius_now(&self, s: usize) -> f64 {
        if self.growth == 0.0 {
            self.base_radius(s)
        } else {
            self.base_radius(s) * (1.0 + self.growth * self.now)
        }
    }

    /// Radii at the current time, by id.
    pub fn radii(&self) -> Vec<f64> {
        self.by_id(|e, s| e.radius_now(s))
    }

    /// Position of grain `id` at the current time (not stored: observing never perturbs
    /// the trajectory).
    pub fn position(&self, id: usize) -> Vector<D> {
        let mut x = self.position_raw(self.slot_of(id));
        self.bx.wrap(&mut x);
        x
    }

    /// Velocity of grain `id` at the current time.
    pub fn velocity(&self, id: usize) -> Vector<D> {
        self.velocity_slot(self.slot_of(id))
    }

    #[inline(always)]
    pub(super) fn velocity_slot(&self, s: usize) -> Vector<D> {
        let g = &self.grains[s];
        if self.has_gravity {
            g.vel.add_scaled(self.now - g.time, &self.gravity)
        } else {
            g.vel
        }
    }

    /// Unwrapped position of slot `s` at the current time (HD-6; may lie outside the box by
    /// round-off).
    #[inline(always)]
    pub(super) fn position_raw(&self, s: usize) -> Vector<D> {
        let g = &self.grains[s];
        let dt = self.now - g.time;
        let x = g.pos.add_scaled(dt, &g.vel);
        if self.has_gravity {
            x.add_scaled(0.5 * dt * dt, &self.gravity)
        } else {
            x
        }
    }

    /// Brings slot `s`'s stored state to the current time.
    #[inline(always)]
    pub(super) fn advance_particle(&mut self, s: usize) {
        let dt = self.now - self.grains[s].time;
        if dt != 0.0 {
            let x = self.position_raw(s);
            let v = self.velocity_slot(s);
            let g = &mut self.grains[s];
            g.pos = x;
            g.vel = v;
        }
        self.grains[s].time = self.now;
    }

    /// Mass of grain `id`.
    pub fn mass_of(&self, id: usize) -> f64 {
        self.mass(self.slot_of(id))
    }

    /// Takes the grains out of the engine (positions and velocities at the current time),
    /// in id order.
    pub(crate) fn particle_set(&self) -> ParticleSet<D> {
        ParticleSet {
            positions: (0..self.len()).map(|i| self.position(i)).collect(),
            velocities: (0..self.len()).map(|i| self.velocity(i)).collect(),
            radii: self.radii(),
            masses: self.masses(),
            species: self.species(),
            species_names: self.species_names.clone(),
            angular_velocities: self.angular_velocities(),
            inertia: self.species_inertia(),
        }
    }
}
