//! Colours: a categorical palette for series and species, and a perceptually uniform colour
//! map for continuous quantities.

use plotters::style::RGBColor;

/// An sRGB colour.
pub type Colour = RGBColor;

/// Categorical palette (Okabe & Ito 2008), ordered so the first entries differ most on white
/// paper and in grey-scale: blue, vermillion, bluish green, reddish purple, orange, sky blue,
/// black, yellow.
pub const PALETTE: [Colour; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

/// The `i`-th palette colour (cycling).
pub fn palette(i: usize) -> Colour {
    PALETTE[i % PALETTE.len()]
}

/// Control points of matplotlib's *viridis*, every 1/8 of the range.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// The *viridis* colour map at `t` in `[0, 1]` (clamped; NaN maps to the low end):
/// dark purple to yellow, monotonic in lightness so it also reads in grey-scale.
pub fn viridis(t: f64) -> Colour {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A lighter version of `c` (towards white by `amount` in `[0, 1]`), e.g. for bar fills.
pub fn lighten(c: Colour, amount: f64) -> Colour {
    let m = |v: u8| (f64::from(v) + amount * (255.0 - f64::from(v))).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

/// A darker version of `c` (towards black by `amount` in `[0, 1]`), e.g. for outlines.
pub fn darken(c: Colour, amount: f64) -> Colour {
    let m = |v: u8| (f64::from(v) * (1.0 - amount)).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_clamps() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(2.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        // Lightness increases monotonically.
        let lum = |c: Colour| 0.3 * f64::from(c.0) + 0.59 * f64::from(c.1) + 0.11 * f64::from(c.2);
        let mut last = -1.0;
        for i in 0..=100 {
            let l = lum(viridis(f64::from(i) / 100.0));
            assert!(l > last);
            last = l;
        }
    }
}
