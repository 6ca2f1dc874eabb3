//! Reproducible random streams.
//!
//! Every random number in the library comes from a named generator
//! ([`Xoshiro256PlusPlus`], fixed algorithm, serialisable state) seeded from the user's
//! `seed` and a *path* of integers that names the consumer: an ensemble member, a sweep
//! point, a DSMC cell and time step, an intruder walker. Streams with different paths are
//! statistically independent (the path is hashed through SplitMix64, whose output is a
//! bijection of a 64-bit state), and a stream depends only on `(seed, path)`, never on
//! the number of threads or the order in which work is scheduled.

pub use rand::RngExt;
pub(crate) use rand::SeedableRng;
pub(crate) use rand_xoshiro::Xoshiro256PlusPlus;

/// The generator used everywhere in granular.
pub(crate) type Stream = Xoshiro256PlusPlus;

/// One step of SplitMix64 (Steele, Lea and Flood 2014): a bijective 64-bit mixer.
#[inline]
pub(crate) fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Hashes `(seed, path)` into one 64-bit key.
pub fn derive_key(seed: u64, path: &[u64]) -> u64 {
    path.iter().fold(splitmix64(seed), |h, &p| extend_key(h, p))
}

/// The key of `path` followed by `p`, from the key `h` of `path`:
/// `derive_key(seed, &[a, b, p]) == extend_key(derive_key(seed, &[a, b]), p)`. Lets a
/// loop over many streams that share a prefix (the cells of one DSMC step) hash the
/// prefix once.
#[inline]
pub(crate) fn extend_key(h: u64, p: u64) -> u64 {
    splitmix64(h ^ splitmix64(p.wrapping_add(0x632B_E59B_D9B4_E019)))
}

/// The random stream named by `path` under the run's `seed`.
///
/// Conventional path prefixes (so that engines never share a stream by accident):
/// `[0, ..]` initial state, `[1, ..]` engine dynamics, `[2, member]` ensemble member seeds.
pub fn stream(seed: u64, path: &[u64]) -> Stream {
    Stream::seed_from_u64(derive_key(seed, path))
}

/// `Stream::seed_from_u64(key)` without its byte-wise fill: rand_xoshiro expands `key`
/// into the four state words with SplitMix64 (outputs `splitmix64(key + k phi)`,
/// `k = 0 .. 3`, little-endian), then `from_seed`. The same generator bit for bit (unit
/// test), in about a third of the instructions: for loops that seed a stream per cell.
#[inline]
pub(crate) fn stream_from_key(key: u64) -> Stream {
    const PHI: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut seed = [0u8; 32];
    for (k, w) in (0u64..).zip(seed.chunks_exact_mut(8)) {
        w.copy_from_slice(&splitmix64(key.wrapping_add(k.wrapping_mul(PHI))).to_le_bytes());
    }
    Stream::from_seed(seed)
}

/// `rng.random_range(0..n)` for `n >= 1`, the same value and the same use of the stream:
/// rand's single-sample Canon method on 32 bits (the high half of one `u64`, widened
/// product with `n`, a second draw only when the low half of the product falls in the
/// top `n` values), written out so that it inlines into a loop that keeps the generator
/// in registers (unit test against `random_range`). Ranges beyond `u32::MAX` go through
/// `random_range` itself.
#[inline(always)]
#[cfg(test)]
pub(crate) fn uniform_index(rng: &mut Stream, n: usize) -> usize {
    use rand::Rng;
    if n > u32::MAX as usize || n == 0 {
        return rng.random_range(0..n);
    }
    let range = n as u64;
    let m = (rng.next_u64() >> 32) * range;
    let (mut hi, lo) = ((m >> 32) as u32, m as u32);
    if lo > (n as u32).wrapping_neg() {
        let extra = (((rng.next_u64() >> 32) * range) >> 32) as u32;
        hi += lo.checked_add(extra).is_none() as u32;
    }
    hi as usize
}

/// Path prefix for the initial-state construction.
pub(crate) const INITIAL_STATE: u64 = 0;
/// Path prefix for the dynamics of an engine.
pub(crate) const DYNAMICS: u64 = 1;
/// Path prefix for ensemble members and sweep points.
pub(crate) const MEMBER: u64 = 2;
/// Path prefix of an engine's dynamics after its grains were set from outside at time
/// `t` (`Simulation::set_state`): the streams restart under
/// `derive_key(seed, [RESTART, t.to_bits()])`, so that what follows depends only on the
/// state set and its time, not on the history before it. (3 is the driving's `KICKS`.)
pub(crate) const RESTART: u64 = 4;

mod ziggurat_tables;
use rand::Rng;
use ziggurat_tables::{ZIG_EXP_F, ZIG_EXP_R, ZIG_EXP_X, ZIG_NORM_F, ZIG_NORM_R, ZIG_NORM_X};

/// `2^-53`.
const TWO_POW_M53: f64 = 1.0 / 9_007_199_254_740_992.0;

/// The uniform deviate in `[0, 1)` made of the 53 high bits of `bits`, exactly as
/// `rng.random::<f64>()` makes it from one `u64`; the 11 low bits are left free for other
/// uses (they are independent of the deviate).
#[inline(always)]
pub(crate) fn unit_f64(bits: u64) -> f64 {
    (bits >> 11) as f64 * TWO_POW_M53
}

/// A standard exponential deviate (density `e^{-x}`, `x > 0`): the ziggurat (ZIGNOR,
/// Doornik 2005) of `rand_distr::Exp1`, with the same tables and the same use of random
/// bits, so it returns exactly the values `rng.sample(Exp1)` would (a unit test checks this
/// bit for bit). The fast path (about 98.9 % of the draws) is inlined and the rest is out of
/// line, taking and returning the generator by value, so a loop that owns its generator can
/// keep the state in registers.
#[inline(always)]
pub(crate) fn exp1(rng: &mut Stream) -> f64 {
    let bits = rng.next_u64();
    let i = (bits & 0xff) as usize;
    let u = f64::from_bits((bits >> 12) | 0x3FF0_0000_0000_0000) - (1.0 - f64::EPSILON / 2.0);
    let x = u * ZIG_EXP_X[i];
    if x < ZIG_EXP_X[i + 1] {
        return x;
    }
    let (x, r) = exp1_slow(rng.clone(), i, x);
    *rng = r;
    x
}

#[cold]
#[inline(never)]
fn exp1_slow(mut rng: Stream, mut i: usize, mut x: f64) -> (f64, Stream) {
    loop {
        if i == 0 {
            let x = ZIG_EXP_R - rng.random::<f64>().ln();
            return (x, rng);
        }
        if ZIG_EXP_F[i + 1] + (ZIG_EXP_F[i] - ZIG_EXP_F[i + 1]) * rng.random::<f64>() < (-x).exp() {
            return (x, rng);
        }
        let bits = rng.next_u64();
        i = (bits & 0xff) as usize;
        let u = f64::from_bits((bits >> 12) | 0x3FF0_0000_0000_0000) - (1.0 - f64::EPSILON / 2.0);
        x = u * ZIG_EXP_X[i];
        if x < ZIG_EXP_X[i + 1] {
            return (x, rng);
        }
    }
}

/// A standard normal deviate: the ziggurat of `rand_distr::StandardNormal`, same tables and
/// same use of random bits, so exactly the values `rng.sample(StandardNormal)` would return
/// (checked bit for bit by a unit test); fast path inlined as in `exp1`.
#[inline(always)]
pub fn std_normal(rng: &mut Stream) -> f64 {
    let bits = rng.next_u64();
    let i = (bits & 0xff) as usize;
    let u = f64::from_bits((bits >> 12) | 0x4000_0000_0000_0000) - 3.0;
    let x = u * ZIG_NORM_X[i];
    if x.abs() < ZIG_NORM_X[i + 1] {
        return x;
    }
    let (x, r) = std_normal_slow(rng.clone(), i, u, x);
    *rng = r;
    x
}

/// `rand`'s `Open01` for `f64`: 52 random bits, values `(k + 1/2) 2^-52`.
#[inline]
fn open01_52(rng: &mut Stream) -> f64 {
    f64::from_bits((rng.next_u64() >> 12) | 0x3FF0_0000_0000_0000) - (1.0 - f64::EPSILON / 2.0)
}

#[cold]
#[inline(never)]
fn std_normal_slow(mut rng: Stream, mut i: usize, mut u: f64, mut x: f64) -> (f64, Stream) {
    loop {
        if i == 0 {
            // The tail beyond R (Marsaglia's method), as in rand_distr.
            let mut tx = 1.0f64;
            let mut ty = 0.0f64;
            while -2.0 * ty < tx * tx {
                let x_ = open01_52(&mut rng);
                let y_ = open01_52(&mut rng);
                tx = x_.ln() / ZIG_NORM_R;
                ty = y_.ln();
            }
            let x = if u < 0.0 {
                tx - ZIG_NORM_R
            } else {
                ZIG_NORM_R - tx
            };
            return (x, rng);
        }
        if ZIG_NORM_F[i + 1] + (ZIG_NORM_F[i] - ZIG_NORM_F[i + 1]) * rng.random::<f64>()
            < (-x * x / 2.0).exp()
        {
            return (x, rng);
        }
        let bits = rng.next_u64();
        i = (bits & 0xff) as usize;
        u = f64::from_bits((bits >> 12) | 0x4000_0000_0000_0000) - 3.0;
        x = u * ZIG_NORM_X[i];
        if x.abs() < ZIG_NORM_X[i + 1] {
            return (x, rng);
        }
    }
}

/// A uniform deviate in the open interval (0, 1): never 0, so that `-ln(u)` is finite.
#[inline]
pub(crate) fn open01(rng: &mut Stream) -> f64 {
    // 53 random bits, shifted by half an ulp: values are (k + 0.5) / 2^53, k = 0 .. 2^53 - 1.
    let bits = rng.random::<u64>() >> 11;
    (bits as f64 + 0.5) * (1.0 / 9_007_199_254_740_992.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first(seed: u64, path: &[u64], n: usize) -> Vec<u64> {
        let mut r = stream(seed, path);
        (0..n).map(|_| r.random::<u64>()).collect()
    }

    #[test]
    fn stream_from_key_is_seed_from_u64() {
        use rand::Rng;
        for key in [
            0,
            1,
            42,
            0x9E37_79B9_7F4A_7C15,
            u64::MAX,
            derive_key(3, &[1, 2, 3]),
        ] {
            let mut a = stream_from_key(key);
            let mut b = Stream::seed_from_u64(key);
            for _ in 0..8 {
                assert_eq!(a.next_u64(), b.next_u64());
            }
        }
    }

    #[test]
    fn extend_key_continues_a_path() {
        for seed in [0, 7, u64::MAX] {
            let prefix = derive_key(seed, &[DYNAMICS, 12]);
            for cell in [0, 1, 97_335] {
                assert_eq!(
                    extend_key(prefix, cell),
                    derive_key(seed, &[DYNAMICS, 12, cell])
                );
            }
        }
    }

    #[test]
    fn streams_are_reproducible_and_distinct() {
        assert_eq!(first(7, &[1, 2], 4), first(7, &[1, 2], 4));
        assert_ne!(first(7, &[1, 2], 4), first(7, &[1, 3], 4));
        assert_ne!(first(7, &[1, 2], 4), first(8, &[1, 2], 4));
    }

    /// Golden values: the first outputs of a stream must never change between versions or
    /// platforms, or old seeds would stop reproducing old results.
    #[test]
    fn golden_first_values() {
        assert_eq!(first(42, &[DYNAMICS], 2), GOLDEN.to_vec());
        let mut r = stream(42, &[DYNAMICS]);
        let u = open01(&mut r);
        assert!(u > 0.0 && u < 1.0);
    }

    /// The inlined ziggurats are the samplers of rand_distr, value for value (so they
    /// sample exactly the same laws), including the rare slow paths and tails.
    #[test]
    fn ziggurats_reproduce_rand_distr_bit_for_bit() {
        let mut a = stream(11, &[3]);
        let mut b = a.clone();
        for k in 0..2_000_000 {
            let (x, y) = if k % 2 == 0 {
                (exp1(&mut a), b.sample::<f64, _>(rand_distr::Exp1))
            } else {
                (
                    std_normal(&mut a),
                    b.sample::<f64, _>(rand_distr::StandardNormal),
                )
            };
            assert_eq!(x.to_bits(), y.to_bits(), "draw {k}");
        }
        assert_eq!(a.random::<u64>(), b.random::<u64>());
        let u = unit_f64(a.random::<u64>());
        assert_eq!(u.to_bits(), b.random::<f64>().to_bits());
    }

    /// `uniform_index` is `random_range(0..n)`, value for value and stream position,
    /// including ranges where the second draw happens often (close to `2^32`).
    #[test]
    fn uniform_index_is_random_range() {
        let mut a = stream(5, &[9]);
        let mut b = a.clone();
        let ns = [
            1usize,
            2,
            3,
            7,
            10,
            11,
            1000,
            (1 << 31) + 1,
            u32::MAX as usize - 1,
            u32::MAX as usize,
            u32::MAX as usize + 1,
            1 << 40,
        ];
        for k in 0..400_000 {
            let n = ns[k % ns.len()];
            assert_eq!(
                uniform_index(&mut a, n),
                b.random_range(0..n),
                "draw {k}, n = {n}"
            );
        }
        assert_eq!(a.random::<u64>(), b.random::<u64>());
    }

    const GOLDEN: [u64; 2] = [16842389006524088220, 2581731596818908892];
}
