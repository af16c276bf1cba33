//! The fit of the Gaussian process, in stages: the settings checked, the hyperparameters of
//! each column group (the likelihood of [`super::likelihood`]), the inducing points if the fit
//! is sparse ([`super::sparse`]), then the weights, process variances and factors of each group:
//! exact (`α = R⁻¹Y`) or sparse (the DTC mean on the inducing points).

use std::ops::Range;

use super::super::linalg::{cholesky_in_place, dot, solve_lower, solve_lower_t};
use super::super::regressor::Data;
use super::likelihood::{correlation, optimise};
use super::sparse::{dtc_group, select_inducing, GroupWeights};
use super::{valid_group_bounds, ByFeature, Gp, GpParams, MAX_INPUTS};
use crate::rom::RomError;

impl Gp {
    /// Fits the process: exact, or sparse on [`GpParams::inducing`] points ([`fit`]).
    ///
    /// # Errors
    /// As [`fit`].
    pub(super) fn fit_process(data: &Data<'_>, params: &GpParams) -> Result<Gp, RomError> {
        fit(data, params)
    }
}

/// Fits the process ([`GpParams`]): exact, or sparse on `inducing` points when fewer than the
/// training points.
///
/// # Errors
/// Fewer than 2 points, invalid settings, or a numerical failure naming the stage.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn fit(data: &Data<'_>, params: &GpParams) -> Result<Gp, RomError> {
    let bounds = checked_bounds(data, params)?;
    let ys: Vec<Vec<f64>> = bounds
        .windows(2)
        .map(|w| group_outputs(data, w[0]..w[1]))
        .collect();
    let mut theta = Vec::with_capacity((bounds.len() - 1) * (data.d + 1));
    for (g, w) in bounds.windows(2).enumerate() {
        theta.extend(group_theta(data, params, g, w[0]..w[1], &ys[g])?);
    }
    let inducing = match params.inducing {
        Some(k) if k < data.n => Some(select_inducing(data.x, data.n, data.d, &theta, k)?),
        _ => None,
    };
    assemble(data, bounds, theta, &ys, inducing.as_deref())
}

/// The column-group boundaries of the settings, after checking the sizes, the groups, the
/// fixed hyperparameters and the number of inducing points.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn checked_bounds(data: &Data<'_>, params: &GpParams) -> Result<Vec<usize>, RomError> {
    let (n, d, m) = (data.n, data.d, data.m);
    if n < 2 {
        return Err(RomError::InsufficientData(format!(
            "GP needs ≥ 2 points, got {n}"
        )));
    }
    if d == 0 || d > MAX_INPUTS {
        return Err(RomError::invalid(
            "GP inputs",
            d,
            &format!("1 ..= {MAX_INPUTS} (the prediction paths use fixed-size arrays)"),
        ));
    }
    let bounds: Vec<usize> = if params.groups.is_empty() {
        vec![0, m]
    } else {
        params.groups.clone()
    };
    if !valid_group_bounds(&bounds, m) {
        return Err(RomError::invalid(
            "GP column groups",
            format!("{bounds:?}"),
            &format!("strictly increasing boundaries from 0 to the {m} outputs"),
        ));
    }
    let n_groups = bounds.len() - 1;
    if let Some(t) = &params.theta {
        if t.len() != n_groups * (d + 1) {
            return Err(RomError::invalid(
                "GP theta length",
                t.len(),
                &format!("{} ((inputs + 1) per column group)", n_groups * (d + 1)),
            ));
        }
    }
    if let Some(k) = params.inducing {
        if k < 2 * d {
            return Err(RomError::invalid(
                "GP inducing points",
                k,
                &format!("at least 2 × the {d} inputs = {}", 2 * d),
            ));
        }
    }
    Ok(bounds)
}

/// The outputs of columns `cols`, `n × |cols|`.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn group_outputs(data: &Data<'_>, cols: Range<usize>) -> Vec<f64> {
    let m = data.m;
    (0..data.n)
        .flat_map(|i| data.y[i * m + cols.start..i * m + cols.end].iter().copied())
        .collect()
}

/// The hyperparameters of group `g` (columns `cols`, outputs `y`): fixed, or maximising the
/// likelihood of the group's columns as a data set of their own.
fn group_theta(
    data: &Data<'_>,
    params: &GpParams,
    g: usize,
    cols: Range<usize>,
    y: &[f64],
) -> Result<Vec<f64>, RomError> {
    let d = data.d;
    if let Some(t) = &params.theta {
        return Ok(t[g * (d + 1)..(g + 1) * (d + 1)].to_vec());
    }
    let sub = Data {
        y,
        m: cols.len(),
        weights: data.weights.get(cols).unwrap_or(&[]),
        ..*data
    };
    optimise(
        &sub,
        params.seed,
        params.n_start,
        params.max_iter,
        params.max_points,
    )
}

/// The process from the hyperparameters: on every training point (`inducing` `None`, weights
/// `R⁻¹Y`) or on the inducing points (their indices, weights of [`dtc_group`]).
///
/// # Errors
/// A correlation matrix that is not positive definite, or a failed sparse solve.
// public for the tests in tests/rom/
#[doc(hidden)]
pub fn assemble(
    data: &Data<'_>,
    bounds: Vec<usize>,
    theta: Vec<f64>,
    ys: &[Vec<f64>],
    inducing: Option<&[usize]>,
) -> Result<Gp, RomError> {
    let (n, d, m) = (data.n, data.d, data.m);
    let n_groups = bounds.len() - 1;
    let np = inducing.map_or(n, <[usize]>::len);
    let x: Vec<f64> = match inducing {
        None => data.x.to_vec(),
        Some(z) => z
            .iter()
            .flat_map(|&i| data.x[i * d..(i + 1) * d].iter().copied())
            .collect(),
    };
    let mut xs = Vec::with_capacity(n_groups * np * d);
    let mut inv_len = Vec::with_capacity(n_groups * d);
    let mut chol = Vec::with_capacity(n_groups * np * (np + 1) / 2);
    let mut alpha = vec![0.0; np * m];
    let mut sigma2 = vec![0.0; m];
    for (g, w) in bounds.windows(2).enumerate() {
        let (cols, mg) = (w[0]..w[1], w[1] - w[0]);
        let t = &theta[g * (d + 1)..(g + 1) * (d + 1)];
        let fit = match inducing {
            None => exact_group(data, t, &ys[g], mg)?,
            Some(z) => dtc_group((data.x, n, d), z, t, (&ys[g], mg), g)?,
        };
        for j in 0..np {
            alpha[j * m + cols.start..j * m + cols.end]
                .copy_from_slice(&fit.alpha[j * mg..(j + 1) * mg]);
        }
        sigma2[cols].copy_from_slice(&fit.sigma2);
        // packed lower triangle: row i holds L[i][0..=i] at offset i(i+1)/2
        chol.extend((0..np).flat_map(|i| fit.chol[i * np..i * np + i + 1].to_vec()));
        let il: Vec<f64> = t[..d].iter().map(|t| (-t).exp()).collect();
        xs.extend((0..np * d).map(|e| x[e] * il[e % d]));
        inv_len.extend(il);
    }
    Ok(Gp {
        d,
        n: np,
        m,
        x,
        groups: if n_groups > 1 { bounds } else { Vec::new() },
        xs,
        theta,
        inv_len,
        alpha,
        sigma2,
        chol,
        by_feature: ByFeature::default(),
    })
}

/// The exact fit of one group: `R = LLᵀ`, `α_c = R⁻¹y_c`, `σ_c² = y_cᵀR⁻¹y_c/n`.
fn exact_group(
    data: &Data<'_>,
    theta: &[f64],
    y: &[f64],
    mg: usize,
) -> Result<GroupWeights, RomError> {
    let (n, d) = (data.n, data.d);
    let mut l = correlation(data.x, n, d, theta);
    cholesky_in_place(&mut l, n).map_err(|i| RomError::Numerical {
        stage: "GP fit".into(),
        message: format!("correlation matrix not positive definite (pivot {i})"),
    })?;
    let mut alpha = vec![0.0; n * mg];
    let mut sigma2 = vec![0.0; mg];
    let mut col = vec![0.0; n];
    for c in 0..mg {
        for i in 0..n {
            col[i] = y[i * mg + c];
        }
        solve_lower(&l, n, &mut col);
        sigma2[c] = dot(&col, &col) / n as f64;
        solve_lower_t(&l, n, &mut col);
        for i in 0..n {
            alpha[i * mg + c] = col[i];
        }
    }
    Ok(GroupWeights {
        alpha,
        sigma2,
        chol: l,
    })
}
