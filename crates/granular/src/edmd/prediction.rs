//! Event-time prediction: when do two grains touch, when does a grain reach a wall or a
//! cell boundary. Every formula is written in a cancellation-free form, so that round-off
//! never produces a negative time or a missed contact.

/// Time until two grains touch, for relative position `dx = x_j - x_i` and relative
/// velocity `dv = v_j - v_i` (both at the current time), contact distance `sigma` and
/// contact-distance growth rate `sigma_rate` (zero except during Lubachevsky-Stillinger
/// compression).
///
/// Without growth this is HD-7 to HD-10, with the smaller root
/// written as `c / (-b + sqrt(d))` instead of `-(b + sqrt(d)) / a`, which cancels
/// catastrophically for grazing or slow approaches. Round-off cases:
/// * overlapping (`|dx| < sigma`) and approaching: collide now (returns `Some(0.0)`);
/// * overlapping and receding, or never touching: `None`.
#[inline(always)]
pub(crate) fn pair_contact_time(
    dx_dv: f64,
    dx2: f64,
    dv2: f64,
    sigma: f64,
    sigma_rate: f64,
) -> Option<f64> {
    if sigma_rate == 0.0 {
        let b = dx_dv;
        if b >= 0.0 {
            return None;
        }
        let c = dx2 - sigma * sigma;
        if c <= 0.0 {
            return Some(0.0);
        }
        let d = b * b - dv2 * c;
        if d <= 0.0 {
            return None;
        }
        Some(c / (-b + d.sqrt()))
    } else {
        // |dx + dv t|^2 = (sigma + sigma_rate t)^2:
        // (dv2 - s'^2) t^2 + 2 (dx.dv - sigma s') t + (dx2 - sigma^2) = 0.
        let b = dx_dv - sigma * sigma_rate;
        let c = dx2 - sigma * sigma;
        if c <= 0.0 {
            return if b < 0.0 { Some(0.0) } else { None };
        }
        let a = dv2 - sigma_rate * sigma_rate;
        let d = b * b - a * c;
        if d < 0.0 {
            return None;
        }
        // Root with the surfaces approaching: t = c / (-b + sqrt(d)) when b < 0; when
        // b >= 0 a root in the future exists only if a < 0 (growth outruns separation).
        if b < 0.0 {
            Some(c / (-b + d.sqrt()))
        } else if a < 0.0 {
            Some((b + d.sqrt()) / -a)
        } else {
            None
        }
    }
}

/// Smallest `t >= 0` at which `f(t) = c + b t + a t^2` crosses zero *upwards*
/// (`f' > 0` there), i.e. when a coordinate `x(t) = target + f(t)` moving with velocity `b`
/// and acceleration `2a` arrives at `target` from below. `None` if it never does.
///
/// The root with positive slope is `t = (-b + s) / (2a)`, `s = sqrt(b^2 - 4ac)`; for
/// `b > 0` it is evaluated as `-2c / (b + s)`, which has no cancellation and also covers
/// `a = 0` (uniform motion).
#[inline(always)]
pub(crate) fn upward_crossing(c: f64, b: f64, a: f64) -> Option<f64> {
    if a == 0.0 {
        if b <= 0.0 {
            return None;
        }
        return Some((-c / b).max(0.0));
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let t = if b > 0.0 {
        -2.0 * c / (b + s)
    } else {
        (s - b) / (2.0 * a)
    };
    if t >= 0.0 {
        Some(t)
    } else if c >= 0.0 && b > 0.0 {
        // Already past the target by round-off and moving on: cross now.
        Some(0.0)
    } else {
        None
    }
}

/// Smallest `t >= 0` at which `c + b t + a t^2` crosses zero *downwards* (mirror image of
/// [`upward_crossing`]).
#[inline(always)]
pub(crate) fn downward_crossing(c: f64, b: f64, a: f64) -> Option<f64> {
    upward_crossing(-c, -b, -a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_pair() {
        // Two unit-diameter disks 3 apart approaching at relative speed 2: touch after 1.
        let t = pair_contact_time(-6.0, 9.0, 4.0, 1.0, 0.0).unwrap();
        assert!((t - 1.0).abs() < 1e-15);
    }

    #[test]
    fn overlapping_pairs() {
        assert_eq!(pair_contact_time(-1e-3, 0.81, 1.0, 1.0, 0.0), Some(0.0));
        assert_eq!(pair_contact_time(1e-3, 0.81, 1.0, 1.0, 0.0), None);
    }

    #[test]
    fn nearly_touching_pair_has_no_cancellation() {
        // Head-on at unit speed with a gap of 1e-10: the hard-disk assignment's form (-b - sqrt(d)) / a
        // subtracts two numbers equal to 1 - 1e-20 and returns garbage; ours is exact to
        // the representation error of the gap itself.
        let x: f64 = 1.0 + 1e-10;
        let t = pair_contact_time(-x, x * x, 1.0, 1.0, 0.0).unwrap();
        let gap = x - 1.0;
        assert!((t - gap).abs() < 1e-6 * gap, "{t} vs {gap}");
    }

    #[test]
    fn growing_pair_collides_even_when_receding_slowly() {
        // Separation 2, receding at 0.1, contact distance 1 growing at 1: 2 + 0.1t = 1 + t.
        let t = pair_contact_time(0.2, 4.0, 0.01, 1.0, 1.0).unwrap();
        assert!((t - 1.0 / 0.9).abs() < 1e-12);
    }

    #[test]
    fn ballistic_crossings() {
        // x = 0.2 + t - t^2/2 reaches 0.6 going up at t = 1 - sqrt(0.2).
        let t = upward_crossing(-0.4, 1.0, -0.5).unwrap();
        assert!((t - (1.0 - 0.2f64.sqrt())).abs() < 1e-14);
        // and comes back down through 0.6 at t = 1 + sqrt(0.2).
        let t = downward_crossing(-0.4, 1.0, -0.5).unwrap();
        assert!((t - (1.0 + 0.2f64.sqrt())).abs() < 1e-14);
        // Uniform motion away never arrives.
        assert_eq!(upward_crossing(-0.4, -1.0, 0.0), None);
        // A ball on the wall thrown up under gravity returns after 2 v / g.
        let t = downward_crossing(0.0, 2.0, -0.5).unwrap();
        assert!((t - 4.0).abs() < 1e-14);
    }
}
