//! The LAMMPS text dump (`dump custom`), as LAMMPS writes it with `dump_modify time yes`:
//!
//! ```text
//! ITEM: TIME
//! 0.25
//! ITEM: TIMESTEP
//! 3
//! ITEM: NUMBER OF ATOMS
//! 2
//! ITEM: BOX BOUNDS pp ff ff
//! 0 1
//! 0 0.5
//! -0.02 0.02
//! ITEM: ATOMS id type x y z vx vy vz radius mass
//! 1 1 0.1 0.2 0 1 -0.5 0 0.01 1
//! 2 2 0.7 0.4 0 0.125 2 0 0.02 4
//! ```
//!
//! * `TIMESTEP` is the output index of the snapshot, `TIME` the simulation time.
//! * `BOX BOUNDS` has one flag pair per axis: `pp` periodic, `ff` fixed (hard walls). A 2D
//!   run has `z = 0` in a thin fixed z range `[-d/2, d/2]` (`d` the largest grain
//!   diameter); the dump has no flag for two dimensions.
//! * `id` counts from 1 (LAMMPS' convention; it is the snapshot order plus one) and `type`
//!   is the species index plus 1, in the order of the scenario's `[[species]]` (the dump
//!   has no type names).
//! * Rough grains add the columns `omegax omegay omegaz`, the angular velocity (radians
//!   per time unit): the names LAMMPS' `dump custom` gives it for spherical particles, which
//!   OVITO's LAMMPS dump reader maps to its Angular Velocity property. Disks write all
//!   three, `0 0 ω_z`, as LAMMPS does for a 2D `atom_style sphere` run (its `omega` is
//!   always a 3-vector) and as `vz` is written: a reader gets a whole vector property, not
//!   one component of it. Smooth grains have no such columns.
//! * Numbers are written with Rust's shortest round-trip formatting.

use super::{Frame, Rows};
use std::io::{self, Write};

/// Writes one frame.
pub fn write_frame(out: &mut impl Write, frame: &Frame) -> io::Result<()> {
    write_rows(out, &frame.rows())
}

/// Writes one frame whose grains are read piece by piece.
pub fn write_rows(out: &mut impl Write, frame: &Rows) -> io::Result<()> {
    let flag = |p: bool| if p { "pp" } else { "ff" };
    let [px, py, pz] = frame.periodic3();
    let [lx, ly, lz] = frame.lengths3();
    writeln!(out, "ITEM: TIME\n{}", frame.time)?;
    writeln!(out, "ITEM: TIMESTEP\n{}", frame.step)?;
    writeln!(out, "ITEM: NUMBER OF ATOMS\n{}", frame.n)?;
    writeln!(
        out,
        "ITEM: BOX BOUNDS {} {} {}",
        flag(px),
        flag(py),
        flag(pz)
    )?;
    writeln!(out, "0 {lx}\n0 {ly}")?;
    if frame.dimension == 2 {
        writeln!(out, "{} {}", -0.5 * lz, 0.5 * lz)?;
    } else {
        writeln!(out, "0 {lz}")?;
    }
    let rough = frame.is_rough();
    let spin = if rough { " omegax omegay omegaz" } else { "" };
    writeln!(out, "ITEM: ATOMS id type x y z vx vy vz radius mass{spin}")?;
    frame.grains.each(&mut |p| {
        for i in 0..p.len() {
            let [x, y, z] = p.position(i);
            let [vx, vy, vz] = p.velocity(i);
            write!(
                out,
                "{} {} {x} {y} {z} {vx} {vy} {vz} {} {}",
                p.first + i + 1,
                p.species[i] + 1,
                p.radii[i],
                p.masses[i]
            )?;
            if rough {
                let [wx, wy, wz] = p.angular_velocity(i);
                write!(out, " {wx} {wy} {wz}")?;
            }
            writeln!(out)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trajectory::test_frame::snapshot_2d;

    #[test]
    fn a_2d_frame_has_every_item_and_one_line_per_grain() {
        let (snap, cell) = snapshot_2d();
        let frame = Frame {
            step: 3,
            snapshot: &snap,
            cell: &cell,
            inertia: &[],
        };
        let mut out = Vec::new();
        write_frame(&mut out, &frame).unwrap();
        let text = String::from_utf8(out).unwrap();
        let expected = "ITEM: TIME\n0.25\nITEM: TIMESTEP\n3\nITEM: NUMBER OF ATOMS\n2\n\
            ITEM: BOX BOUNDS pp ff ff\n0 1\n0 0.5\n-0.02 0.02\n\
            ITEM: ATOMS id type x y z vx vy vz radius mass\n\
            1 1 0.1 0.2 0 1 -0.5 0 0.01 1\n2 2 0.7 0.4 0 0.125 2 0 0.02 4\n";
        assert_eq!(text, expected);
    }

    #[test]
    fn rough_grains_add_the_omega_columns() {
        use crate::trajectory::test_frame::{rough_2d, rough_3d};
        for ((snap, cell, inertia), rows) in [
            (
                rough_2d(),
                [
                    "1 1 0.1 0.2 0 1 -0.5 0 0.01 1 0 0 3.5",
                    "2 2 0.7 0.4 0 0.125 2 0 0.02 4 0 0 -0.25",
                ],
            ),
            (
                rough_3d(),
                [
                    "1 1 0.1 0.2 0.3 1 -0.5 0.25 0.01 1 1.5 -2 0.75",
                    "2 2 0.7 0.4 0.1 0.125 2 -1 0.02 4 0 10 -4",
                ],
            ),
        ] {
            let frame = Frame {
                step: 3,
                snapshot: &snap,
                cell: &cell,
                inertia: &inertia,
            };
            let mut out = Vec::new();
            write_frame(&mut out, &frame).unwrap();
            let text = String::from_utf8(out).unwrap();
            let atoms = "ITEM: ATOMS id type x y z vx vy vz radius mass omegax omegay omegaz\n";
            let tail = format!("{atoms}{}\n{}\n", rows[0], rows[1]);
            assert!(text.ends_with(&tail), "{text}");
        }
    }
}
