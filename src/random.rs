//! Seeded random draws shared by the studies: a standard normal from any generator, and the
//! SplitMix64 finaliser that derives independent seeds from structured ones.
//!
//! Every study in the crate draws from a `rand_xoshiro` generator seeded with a documented
//! seed, so that its results do not depend on the thread count or the platform. These two
//! functions are the only hand-written draws; both are deterministic bit for bit.

use rand::RngCore;

/// A standard normal draw: Box–Muller on two uniforms in (0, 1], the cosine branch.
///
/// The uniforms are the top 53 bits of two `next_u64` calls, shifted by one unit so that the
/// logarithm never sees 0.
// public for the tests in tests/case/ and tests/calibrate/
#[doc(hidden)]
pub fn standard_normal<R: RngCore>(rng: &mut R) -> f64 {
    let mut uniform = || ((rng.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64;
    let (a, b) = (uniform(), uniform());
    (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
}

/// The SplitMix64 finaliser (Steele, Lea and Flood 2014): a bijection of `u64` whose outputs
/// for neighbouring inputs look independent. Used to turn a (seed, index) pair into the seed
/// of one draw, so that draws do not depend on the order in which they are made.
// public for the tests in tests/case/
#[doc(hidden)]
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
