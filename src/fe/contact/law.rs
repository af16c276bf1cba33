//! The C² penalty barrier (the `contact` module docs) and the augmented-Lagrangian update of
//! its gap shift.

/// ψ(g), ψ'(g), ψ''(g) of the C² penalty barrier with stiffness `e` and smoothing width `d`
/// (module docs).
pub fn barrier(e: f64, d: f64, g: f64) -> (f64, f64, f64) {
    if g >= d {
        (0.0, 0.0, 0.0)
    } else if g >= 0.0 {
        let s = d - g;
        (e * s * s * s / (6.0 * d), -e * s * s / (2.0 * d), e * s / d)
    } else {
        (
            e * (d * d / 6.0 - d * g / 2.0 + g * g / 2.0),
            e * (g - d / 2.0),
            e,
        )
    }
}

/// One Uzawa update of the augmented-Lagrangian gap shift of a contact point at a converged
/// state with gap `g` and shift `c`; returns the new shift and the change of the point's
/// multiplier (its contact pressure at `g = 0`) divided by ε, in mm.
///
/// The barrier acts on `g − c`, so the point carries the pressure `λ = P(g − c)`,
/// `P = −ψ'` (decreasing, zero from δ on). The shift stands for the multiplier `P(−c)`: the
/// pressure the point would carry when just touching. The update sets it to the pressure the
/// point carries now, `c ← −P⁻¹(λ) = c − g` for a point in contact, so that the same pressure
/// is reached at `g = 0`; an open point (`λ = 0`) gets `c = −δ`, the shift whose pressure
/// starts exactly at `g = 0`. At the fixed point every point either touches (`g = 0`,
/// `λ ≥ 0`) or is open without pressure, for any ε and δ: the penalty's offset from the true
/// contact (`δ/2 − λ/ε` for the plain penalty) is gone.
pub fn update_shift(stiffness: f64, smoothing: f64, g: f64, c: f64) -> (f64, f64) {
    let pressure = |x: f64| -barrier(stiffness, smoothing, x).1;
    let before = pressure(-c);
    let now = if g.is_finite() { pressure(g - c) } else { 0.0 };
    let c_new = if now > 0.0 { c - g } else { -smoothing };
    (c_new, (now - before).abs() / stiffness)
}
