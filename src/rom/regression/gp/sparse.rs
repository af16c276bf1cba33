//! The sparse fit of the Gaussian process ([`GpParams::inducing`](super::GpParams::inducing)):
//! `m < n` inducing points `Z`, a subset of the training inputs, carry the weights, so that a
//! prediction costs `m` kernel values instead of `n` in the same form `μ_c(x) = k(x, Z)ᵀα_c`
//! (the fast path, the Jacobian, the model file and the embedded export are those of the exact
//! process with `n = m`).
//!
//! **Inducing points.** Greedy pivoted Cholesky of the correlation matrices `R_g = K_g + η_g I`
//! of the column groups at their fitted hyperparameters. With `L_g` the first `k` columns of
//! the pivoted factor, step `k` takes the point `p` of largest residual variance summed over
//! the groups, `Σ_g [(R_g)_ii − ‖L_g[i, :k]‖²]` (ties: the lowest index), and appends the
//! column `L_g[:, k] = (R_g[:, p] − L_g L_g[p, :]ᵀ) / √res_g(p)`. The nugget keeps every
//! residual of an unchosen point at least `η_g`, so the selection does not break down on close
//! points. `Z` is shared by the groups (the process stores one set of inputs) and kept in
//! training order.
//!
//! **Weights.** The subset-of-regressors (DTC) mean of each group: with the degenerate prior
//! `f(x) = k(x, Z)ᵀw`, `w ~ N(0, σ² K_ZZ⁻¹)`, and noise variance `σ²η`, the posterior mean of
//! `w` is
//!
//! `α = (K_Zn K_nZ + η K_ZZ)⁻¹ K_Zn Y`,
//!
//! `K` the kernel without the nugget, in the exact fit's normalisation (correlations; `σ²`
//! cancels). At `Z = X` it is the exact `R⁻¹Y`, since `(K² + ηK)⁻¹K = (K + ηI)⁻¹`. It is
//! solved without forming the normal matrix: with `K_ZZ = L Lᵀ`, `α` is the least-squares
//! solution of `[K_nZ; √η Lᵀ] α ≈ [Y; 0]` (Householder QR, whose error grows with the
//! condition number of that matrix, the square root of the normal matrix's). `K_ZZ` alone may
//! be numerically singular (small `η`, close points): its factor is then taken of
//! `K_ZZ + τI` with the smallest `τ` of `10⁻¹², 10⁻¹⁰, …` below `η` that succeeds, else
//! `τ = η` (that is `R_ZZ`); the regulariser becomes `η(K_ZZ + τI)`.
//!
//! **Variances.** The stored factor is that of `R_ZZ` (nugget included) and the process
//! variance of each column is the subset-of-data one, `σ̂_c² = y_Zcᵀ R_ZZ⁻¹ y_Zc / m`, so that
//! the process's variance formula gives the subset-of-data variance
//! `σ̂_c²(1 − k(x, Z)ᵀR_ZZ⁻¹k(x, Z))`, which at `Z = X` is the exact one. It ignores what the
//! other `n − m` points add to the mean, so it overstates the error away from `Z`; the
//! surrogate rescales every predictive standard deviation by the z-scores of its held-out
//! predictions (`std_scale`, from the cross-validation of the same sparse fit), which
//! recalibrates it. (The profiled DTC variance `y_cᵀ(K_nZ K_ZZ⁻¹ K_Zn + ηI)⁻¹y_c / n` was
//! not taken: with the small nuggets the exact likelihood fits, it is the misfit of the `n`
//! points over `η`, and overstated the held-out errors 20–50 times on the synthetic set,
//! against 1.5 times for this one.)

use super::super::linalg::{cholesky_in_place, dot, householder_least_squares, solve_lower};
use super::kernel::kernel;
use super::likelihood::{correlation, scaled_dist};
use crate::rom::RomError;

/// The fit of one column group on the process's points (all training points, or the
/// inducing points).
pub(super) struct GroupWeights {
    /// Weights, `n_points × mg` (row `j`: point `j`'s weight of every column of the group).
    pub alpha: Vec<f64>,
    /// Process variance `σ_c²` of each column of the group.
    pub sigma2: Vec<f64>,
    /// Lower Cholesky factor of the points' correlation matrix `R` (nugget included),
    /// row-major `n_points × n_points`.
    pub chol: Vec<f64>,
}

/// The inducing points: indices (ascending) of `m < n` training inputs chosen by greedy
/// pivoted Cholesky of the groups' correlation matrices (see the [module](self)); `theta`
/// holds `(ln ℓ, ln η)`, `d + 1` per group.
///
/// # Errors
/// A residual variance that is not positive (a correlation matrix not positive definite),
/// naming the group.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn select_inducing(
    x: &[f64],
    n: usize,
    d: usize,
    theta: &[f64],
    m: usize,
) -> Result<Vec<usize>, RomError> {
    let n_groups = theta.len() / (d + 1);
    let kernels: Vec<(Vec<f64>, f64)> = theta
        .chunks_exact(d + 1)
        .map(|t| (t[..d].iter().map(|v| (-v).exp()).collect(), t[d].exp()))
        .collect();
    // group g's factor row i at `l[(g n + i) m ..][..m]`; residual variances `res[g n + i]`
    let mut l = vec![0.0; n_groups * n * m];
    let mut res: Vec<f64> = kernels
        .iter()
        .flat_map(|(_, eta)| std::iter::repeat_n(1.0 + eta, n))
        .collect();
    let mut chosen = vec![false; n];
    let mut z = Vec::with_capacity(m);
    let mut lp = vec![0.0; m];
    for k in 0..m {
        let p = next_pivot(&res, &chosen, n);
        chosen[p] = true;
        z.push(p);
        for (g, (inv_len, _)) in kernels.iter().enumerate() {
            let piv = res[g * n + p];
            if !(piv > 0.0 && piv.is_finite()) {
                return Err(RomError::Numerical {
                    stage: "GP inducing points".into(),
                    message: format!(
                        "column group {g}: residual variance {piv:e} at training point {p} \
                         after {k} inducing points (correlation matrix not positive definite)"
                    ),
                });
            }
            let s = piv.sqrt();
            let rows = &mut l[g * n * m..(g + 1) * n * m];
            lp[..k].copy_from_slice(&rows[p * m..p * m + k]);
            let xp = &x[p * d..(p + 1) * d];
            for j in 0..n {
                if chosen[j] {
                    continue;
                }
                let row = &mut rows[j * m..j * m + k + 1];
                let r_jp = kernel(scaled_dist(&x[j * d..(j + 1) * d], xp, inv_len));
                let v = (r_jp - dot(&row[..k], &lp[..k])) / s;
                row[k] = v;
                res[g * n + j] -= v * v;
            }
            rows[p * m + k] = s;
        }
    }
    z.sort_unstable();
    Ok(z)
}

/// The unchosen point of largest residual variance summed over the groups (the first of
/// equal ones).
fn next_pivot(res: &[f64], chosen: &[bool], n: usize) -> usize {
    let mut best: Option<(usize, f64)> = None;
    for i in (0..n).filter(|&i| !chosen[i]) {
        let s: f64 = res.iter().skip(i).step_by(n).sum();
        if best.is_none_or(|(_, b)| s > b) {
            best = Some((i, s));
        }
    }
    best.map_or(0, |(i, _)| i)
}

/// DTC weights, subset-of-data process variances and the factor of `R_ZZ` of one column
/// group (see the [module](self)): inputs `x` (`n × d`), inducing points `z` (indices), the
/// group's hyperparameters `theta = (ln ℓ, ln η)` and outputs `y` (`n × mg`); `group` names
/// the group in errors.
///
/// # Errors
/// `R_ZZ` not positive definite, or a rank-deficient least-squares matrix, naming the group.
pub(super) fn dtc_group(
    (x, n, d): (&[f64], usize, usize),
    z: &[usize],
    theta: &[f64],
    (y, mg): (&[f64], usize),
    group: usize,
) -> Result<GroupWeights, RomError> {
    let m = z.len();
    let failed = |message: String| RomError::Numerical {
        stage: "sparse GP fit".into(),
        message: format!("column group {group}: {message}"),
    };
    let xz: Vec<f64> = z
        .iter()
        .flat_map(|&i| x[i * d..(i + 1) * d].iter().copied())
        .collect();
    let eta = theta[d].exp();
    let mut chol_rzz = correlation(&xz, m, d, theta);
    let kzz = chol_rzz.clone();
    cholesky_in_place(&mut chol_rzz, m).map_err(|i| {
        failed(format!(
            "correlation matrix of the inducing points not positive definite (pivot {i})"
        ))
    })?;
    let l = kzz_factor(kzz, m, eta).unwrap_or_else(|| chol_rzz.clone());
    let (mut a, mut b) = least_squares_system((x, n, d), &xz, theta, &l, (y, mg));
    let rows = n + m;
    householder_least_squares(&mut a, rows, m, &mut b, mg).map_err(|k| {
        failed(format!(
            "least-squares matrix of the weights rank-deficient (column {k})"
        ))
    })?;
    let mut alpha = vec![0.0; m * mg];
    let mut sigma2 = vec![0.0; mg];
    for (c, col) in b.chunks_exact(rows).enumerate() {
        for j in 0..m {
            alpha[j * mg + c] = col[j];
        }
        let mut yz: Vec<f64> = z.iter().map(|&i| y[i * mg + c]).collect();
        solve_lower(&chol_rzz, m, &mut yz);
        sigma2[c] = dot(&yz, &yz) / m as f64;
    }
    Ok(GroupWeights {
        alpha,
        sigma2,
        chol: chol_rzz,
    })
}

/// The least-squares system of the weights, `[K_nZ; √η Lᵀ]` and `[Y; 0]`, column-major with
/// `n + m` rows: inputs `x` (`n × d`), inducing inputs `xz` (`m × d`), hyperparameters
/// `theta`, the factor `L` of `K_ZZ` (row-major) and outputs `y` (`n × mg`).
fn least_squares_system(
    (x, n, d): (&[f64], usize, usize),
    xz: &[f64],
    theta: &[f64],
    l: &[f64],
    (y, mg): (&[f64], usize),
) -> (Vec<f64>, Vec<f64>) {
    let m = xz.len() / d;
    let rows = n + m;
    let inv_len: Vec<f64> = theta[..d].iter().map(|t| (-t).exp()).collect();
    let sqrt_eta = theta[d].exp().sqrt();
    let mut a = vec![0.0; rows * m];
    for (j, col) in a.chunks_exact_mut(rows).enumerate() {
        let xj = &xz[j * d..(j + 1) * d];
        for (i, v) in col[..n].iter_mut().enumerate() {
            *v = kernel(scaled_dist(&x[i * d..(i + 1) * d], xj, &inv_len));
        }
        for r in 0..=j {
            col[n + r] = sqrt_eta * l[j * m + r];
        }
    }
    let mut b = vec![0.0; rows * mg];
    for (c, col) in b.chunks_exact_mut(rows).enumerate() {
        for (i, v) in col[..n].iter_mut().enumerate() {
            *v = y[i * mg + c];
        }
    }
    (a, b)
}

/// Lower Cholesky factor of `K_ZZ + τI` (row-major) for the smallest jitter `τ` of
/// `0, 10⁻¹², 10⁻¹⁰, …` below `η` that succeeds; `None` if none does (then `τ = η`: the factor
/// of `R_ZZ`). `r_zz` is `R_ZZ = K_ZZ + ηI`, row-major.
fn kzz_factor(r_zz: Vec<f64>, m: usize, eta: f64) -> Option<Vec<f64>> {
    const JITTER: [f64; 6] = [0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4];
    JITTER
        .iter()
        .take_while(|&&tau| tau < eta)
        .find_map(|&tau| {
            let mut k = r_zz.clone();
            for i in 0..m {
                k[i * m + i] = 1.0 + tau;
            }
            cholesky_in_place(&mut k, m).ok().map(|_| k)
        })
}
