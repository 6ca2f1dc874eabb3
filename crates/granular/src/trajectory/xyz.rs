//! Extended XYZ (the convention of ASE, QUIP and OVITO): per frame a line with the number
//! of grains, a comment line of `key=value` pairs, and one line per grain.
//!
//! ```text
//! 2
//! Lattice="1 0 0 0 0.5 0 0 0 0.04" Origin="0 0 -0.02" Properties=type:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1 Time=0.25 Step=3 pbc="T F F"
//! bath 0.1 0.2 0 1 -0.5 0 0.01 1 0
//! intruder 0.7 0.4 0 0.125 2 0 0.02 4 1
//! ```
//!
//! * `Lattice` holds the three cell vectors (the box `[0, L_k]`, origin 0); `pbc` says per
//!   axis whether it is periodic (`F`: hard walls).
//! * A 2D run has `z = 0` and `v_z = 0`, `pbc` `F` along z and a thin cell along z (the
//!   largest grain diameter) with `Origin` at `-d/2` so the grains sit mid-slab; the format
//!   has no flag for two dimensions.
//! * The species column is named `type`, not `species`: ASE reads `species` as chemical
//!   symbols and rejects names such as `bath`; both ASE and OVITO read `type` (OVITO as the
//!   particle type). `velo`, `radius`, `mass` and `id` are the names OVITO maps to its
//!   velocity, radius, mass and identifier properties. Ids count from 0, in snapshot order.
//! * Rough grains add the column `omega:R:3`, the angular velocity (radians per time
//!   unit; `(0, 0, ω_z)` for disks, as `velo` has `v_z = 0`): `omega` is the name OVITO's
//!   XYZ reader maps to its Angular Velocity property (`XYZImporter::mapVariableToProperty`,
//!   after the QUIP conventions), and ASE reads it into `atoms.arrays["omega"]` (ASE has no
//!   angular-velocity property of its own). Smooth grains have no such column.
//! * Numbers are written with Rust's shortest round-trip formatting: a reader gets the
//!   `f64` of the snapshot back exactly.

use super::{Frame, Rows};
use std::io::{self, Write};

/// Writes one frame.
pub fn write_frame(out: &mut impl Write, frame: &Frame) -> io::Result<()> {
    write_rows(out, &frame.rows())
}

/// Writes one frame whose grains are read piece by piece.
pub fn write_rows(out: &mut impl Write, frame: &Rows) -> io::Result<()> {
    let n = frame.n;
    let [lx, ly, lz] = frame.lengths3();
    let flag = |p: bool| if p { "T" } else { "F" };
    let [px, py, pz] = frame.periodic3();
    writeln!(out, "{n}")?;
    write!(out, "Lattice=\"{lx} 0 0 0 {ly} 0 0 0 {lz}\" ")?;
    if frame.dimension == 2 {
        write!(out, "Origin=\"0 0 {}\" ", -0.5 * lz)?;
    }
    let spin = if frame.is_rough() { ":omega:R:3" } else { "" };
    writeln!(
        out,
        "Properties=type:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:id:I:1{spin} Time={} Step={} pbc=\"{} {} {}\"",
        frame.time,
        frame.step,
        flag(px),
        flag(py),
        flag(pz)
    )?;
    let names: Vec<String> = frame
        .species_names
        .iter()
        .map(|name| {
            name.chars()
                .map(|c| if c.is_whitespace() { '_' } else { c })
                .collect()
        })
        .collect();
    let rough = frame.is_rough();
    frame.grains.each(&mut |p| {
        for i in 0..p.len() {
            let [x, y, z] = p.position(i);
            let [vx, vy, vz] = p.velocity(i);
            let name = names
                .get(p.species[i] as usize)
                .map_or("grain", String::as_str);
            write!(
                out,
                "{name} {x} {y} {z} {vx} {vy} {vz} {} {} {}",
                p.radii[i],
                p.masses[i],
                p.first + i
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
    use crate::engine::Snapshot;
    use crate::trajectory::Cell;
    use crate::trajectory::test_frame::snapshot_2d;

    #[test]
    fn a_2d_frame_has_the_header_and_one_line_per_grain() {
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
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert_eq!(lines[0], "2");
        assert!(lines[1].starts_with("Lattice=\"1 0 0 0 0.5 0 0 0 0.04\" Origin=\"0 0 -0.02\" "));
        assert!(lines[1].contains(" Time=0.25 Step=3 pbc=\"T F F\""));
        assert_eq!(lines[2], "bath 0.1 0.2 0 1 -0.5 0 0.01 1 0");
        assert_eq!(lines[3], "intruder 0.7 0.4 0 0.125 2 0 0.02 4 1");
    }

    #[test]
    fn rough_grains_add_the_omega_column() {
        use crate::trajectory::test_frame::{rough_2d, rough_3d};
        let lines = |(snap, cell, inertia): (Snapshot, Cell, Vec<f64>)| {
            let frame = Frame {
                step: 3,
                snapshot: &snap,
                cell: &cell,
                inertia: &inertia,
            };
            let mut out = Vec::new();
            write_frame(&mut out, &frame).unwrap();
            String::from_utf8(out)
                .unwrap()
                .lines()
                .map(String::from)
                .collect::<Vec<_>>()
        };
        let two = lines(rough_2d());
        assert!(
            two[1].contains("mass:R:1:id:I:1:omega:R:3 Time="),
            "{}",
            two[1]
        );
        assert_eq!(two[2], "bath 0.1 0.2 0 1 -0.5 0 0.01 1 0 0 0 3.5");
        assert_eq!(two[3], "intruder 0.7 0.4 0 0.125 2 0 0.02 4 1 0 0 -0.25");
        let three = lines(rough_3d());
        assert!(three[1].contains(":omega:R:3 "));
        assert_eq!(
            three[2],
            "bath 0.1 0.2 0.3 1 -0.5 0.25 0.01 1 0 1.5 -2 0.75"
        );
        assert_eq!(three[3], "intruder 0.7 0.4 0.1 0.125 2 -1 0.02 4 1 0 10 -4");
    }
}
