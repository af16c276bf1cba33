//! The query's inputs and the 22 predicted quantities: their numbers, names and indices.

/// Number of raw regression features: `N, T, ln μ0, α₁, s, α₂`.
pub const N_FEATURES: usize = 6;
/// Number of query inputs: `N, T, P, μ₁, α₁, μ₂, α₂`.
pub const N_INPUTS: usize = 7;
/// Number of predicted quantities: 18 marker components (`m1_uz, m1_uy, …, m9_uy`), then
/// `tip_uz, tip_uy, angle, force`; each has a named index ([`TIP_UZ`], [`ANGLE`], [`M1_UZ`],
/// [`marker_uz`] …) and a name ([`OUTPUT_NAMES`]).
pub const N_QUANTITIES: usize = 22;
/// Names of the 22 outputs in storage order (the columns of `surrogate predict`, with their
/// units as suffix: mm, degrees, N); `OUTPUT_NAMES[TIP_UZ] == "tip_uz_mm"`.
pub const OUTPUT_NAMES: [&str; N_QUANTITIES] = [
    "m1_uz_mm",
    "m1_uy_mm",
    "m2_uz_mm",
    "m2_uy_mm",
    "m3_uz_mm",
    "m3_uy_mm",
    "m4_uz_mm",
    "m4_uy_mm",
    "m5_uz_mm",
    "m5_uy_mm",
    "m6_uz_mm",
    "m6_uy_mm",
    "m7_uz_mm",
    "m7_uy_mm",
    "m8_uz_mm",
    "m8_uy_mm",
    "m9_uz_mm",
    "m9_uy_mm",
    "tip_uz_mm",
    "tip_uy_mm",
    "angle_deg",
    "force_n",
];

/// Index of marker `k`'s Uz (mm) among the outputs, `k = 1 … 9` as in the columns `m1` … `m9`
/// (marker 9 is the tip): `2 (k − 1)`.
///
/// # Panics
/// `k` outside `1 … 9` (at compile time in a `const`).
pub const fn marker_uz(k: usize) -> usize {
    assert!(k >= 1 && k <= 9, "markers are numbered 1 … 9");
    2 * (k - 1)
}

/// Index of marker `k`'s Uy (mm) among the outputs, `k = 1 … 9`: `2 (k − 1) + 1`.
///
/// # Panics
/// `k` outside `1 … 9`.
pub const fn marker_uy(k: usize) -> usize {
    marker_uz(k) + 1
}

macro_rules! output_indices {
    ($($name:ident = $index:expr, $column:literal;)*) => {
        $(
            #[doc = concat!("Index of `", $column, "` among the 22 outputs.")]
            pub const $name: usize = $index;
        )*
    };
}

output_indices! {
    M1_UZ = 0, "m1_uz_mm";
    M1_UY = 1, "m1_uy_mm";
    M2_UZ = 2, "m2_uz_mm";
    M2_UY = 3, "m2_uy_mm";
    M3_UZ = 4, "m3_uz_mm";
    M3_UY = 5, "m3_uy_mm";
    M4_UZ = 6, "m4_uz_mm";
    M4_UY = 7, "m4_uy_mm";
    M5_UZ = 8, "m5_uz_mm";
    M5_UY = 9, "m5_uy_mm";
    M6_UZ = 10, "m6_uz_mm";
    M6_UY = 11, "m6_uy_mm";
    M7_UZ = 12, "m7_uz_mm";
    M7_UY = 13, "m7_uy_mm";
    M8_UZ = 14, "m8_uz_mm";
    M8_UY = 15, "m8_uy_mm";
    M9_UZ = 16, "m9_uz_mm";
    M9_UY = 17, "m9_uy_mm";
    TIP_UZ = 18, "tip_uz_mm";
    TIP_UY = 19, "tip_uy_mm";
    ANGLE = 20, "angle_deg";
    FORCE = 21, "force_n";
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;

    #[test]
    fn named_outputs_index_their_columns() {
        let named = [
            (TIP_UZ, "tip_uz_mm"),
            (TIP_UY, "tip_uy_mm"),
            (ANGLE, "angle_deg"),
            (FORCE, "force_n"),
            (M1_UZ, "m1_uz_mm"),
            (M1_UY, "m1_uy_mm"),
            (M5_UY, "m5_uy_mm"),
            (M9_UZ, "m9_uz_mm"),
            (M9_UY, "m9_uy_mm"),
        ];
        for (i, name) in named {
            assert_eq!(OUTPUT_NAMES[i], name);
        }
        for k in 1..=9 {
            assert_eq!(OUTPUT_NAMES[marker_uz(k)], std::format!("m{k}_uz_mm"));
            assert_eq!(OUTPUT_NAMES[marker_uy(k)], std::format!("m{k}_uy_mm"));
        }
        // every index once, in order
        let all = [
            M1_UZ, M1_UY, M2_UZ, M2_UY, M3_UZ, M3_UY, M4_UZ, M4_UY, M5_UZ, M5_UY, M6_UZ, M6_UY,
            M7_UZ, M7_UY, M8_UZ, M8_UY, M9_UZ, M9_UY, TIP_UZ, TIP_UY, ANGLE, FORCE,
        ];
        assert!(all.iter().enumerate().all(|(i, &q)| i == q));
        assert!(std::panic::catch_unwind(|| marker_uz(0)).is_err());
        assert!(std::panic::catch_unwind(|| marker_uy(10)).is_err());
    }
}
