//! Pairs of candidates the recordings cannot tell apart: nearly collinear signatures past
//! the material, or a leading candidate that does not beat another significantly (the F test
//! of the fit with both against the other alone, and the likelihood ratio of the two
//! non-nested fits), each with the unrecorded measurement that would separate them most.

use nalgebra::DVector;
use statrs::distribution::{ContinuousCDF, FisherSnedecor, Normal};

use super::candidates::Projected;
use super::naming::{Candidate, Indistinguishable};
use crate::diagnose::discrimination::Discrimination;
use crate::diagnose::measurements::Measurement;
use crate::fe::sensitivity::Parameter;

/// `Δχ²` of the fit with two signatures `a`, `b` together, from their Gram entries
/// (`aa = a·a`, `bb`, `ab`) and their products with the residual (`ar`, `br`); the better
/// single fit's where the two are collinear.
fn joint_delta(aa: f64, bb: f64, ab: f64, ar: f64, br: f64) -> f64 {
    let det = aa * bb - ab * ab;
    if det > 1e-12 * aa * bb {
        (bb * ar * ar - 2.0 * ab * ar * br + aa * br * br) / det
    } else {
        (ar * ar / aa).max(br * br / bb)
    }
}

/// What [`pairs`] tests two candidates with.
// public for the tests in tests/diagnose/
#[doc(hidden)]
pub struct PairFit<'a> {
    /// The residual after the material re-fit (whitened, material directions projected out).
    pub residual: &'a DVector<f64>,
    /// Its `χ²`.
    pub chi2_material: f64,
    /// Degrees of freedom of a one-effect fit.
    pub dof: f64,
    /// Level of the separation test.
    pub alpha: f64,
    /// `|cos|` above which two signatures are collinear.
    pub collinear: f64,
}

impl PairFit<'_> {
    /// The p-value of the better of `sa`, `sb` beyond the other: the fit with both against
    /// the fit with the worse one alone (F with 1 and `dof − 1` degrees of freedom).
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn p_separation(&self, sa: &DVector<f64>, sb: &DVector<f64>) -> f64 {
        let r = self.residual;
        let (aa, bb, ab) = (sa.dot(sa), sb.dot(sb), sa.dot(sb));
        let (ar, br) = (sa.dot(r), sb.dot(r));
        let (da, db) = (ar * ar / aa, br * br / bb);
        let joint = joint_delta(aa, bb, ab, ar, br);
        let extra = (joint - da.min(db)).max(0.0);
        let dof = self.dof - 1.0;
        let scale = (self.chi2_material - joint).max(0.0) / dof;
        if scale <= 0.0 || dof < 1.0 {
            return 0.0;
        }
        FisherSnedecor::new(1.0, dof).map_or(f64::NAN, |d| 1.0 - d.cdf(extra / scale))
    }

    /// The likelihood-ratio test of two non-nested one-effect fits (Vuong's idea, with the
    /// Gaussian variance of the cells rather than the empirical one): `D = χ²_b − χ²_a`
    /// (twice the log-likelihood ratio, in units of the variance `s²` of the fit with both),
    /// whose standard deviation is `2 s |ŷ_a − ŷ_b|` (`ŷ` the fitted explanations) to first
    /// order; `z = D / sd`, positive when `sa` fits better. Two identical fits give 0.
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn vuong_z(&self, sa: &DVector<f64>, sb: &DVector<f64>) -> f64 {
        let r = self.residual;
        let (aa, bb, ab) = (sa.dot(sa), sb.dot(sb), sa.dot(sb));
        let (ar, br) = (sa.dot(r), sb.dot(r));
        let (ca, cb) = (ar / aa, br / bb);
        let d = ar * ar / aa - br * br / bb;
        // |ca sa − cb sb|
        let gap = (ca * ca * aa - 2.0 * ca * cb * ab + cb * cb * bb)
            .max(0.0)
            .sqrt();
        let joint = joint_delta(aa, bb, ab, ar, br);
        let s2 = (self.chi2_material - joint).max(0.0) / (self.dof - 1.0).max(1.0);
        if gap <= 1e-12 * r.norm().max(1e-300) || s2 <= 0.0 {
            return 0.0;
        }
        d / (2.0 * s2.sqrt() * gap)
    }

    /// Whether the recordings cannot tell `sa` from `sb`: the better one adds nothing
    /// significant beyond the other, or neither fits significantly better (Vuong).
    // public for the tests in tests/diagnose/
    #[doc(hidden)]
    pub fn tied(&self, p_separation: f64, vuong_z: f64) -> bool {
        p_separation > self.alpha || vuong_z.abs() < two_sided_z(self.alpha)
    }
}

/// The two-sided standard normal quantile of level `alpha` (1.96 at 0.05): the |z| above
/// which a Vuong test separates two fits.
pub(crate) fn two_sided_z(alpha: f64) -> f64 {
    Normal::new(0.0, 1.0).map_or(1.96, |d| d.inverse_cdf(1.0 - 0.5 * alpha))
}

/// The criterion's problem, its candidates' parameters and the measurements it can add.
pub(crate) type Separating<'a> = (
    &'a Discrimination,
    &'a [Parameter],
    &'a [(Measurement, Vec<f64>)],
);

/// Pairs the recordings cannot tell apart, with the unrecorded output that separates them:
/// nearly collinear pairs among the significant candidates (or the two best when none is),
/// and pairs of the first or the named candidate with another whose fit it does not beat
/// significantly ([`PairFit::tied`]).
pub(crate) fn pairs(
    projected: &[Projected],
    ranked: &[Candidate],
    separating: Option<Separating>,
    fit: &PairFit,
) -> Vec<Indistinguishable> {
    let mut interesting: Vec<&str> = ranked
        .iter()
        .filter(|c| c.significant)
        .map(|c| c.effect.as_str())
        .collect();
    if interesting.is_empty() {
        interesting = ranked.iter().take(2).map(|c| c.effect.as_str()).collect();
    }
    // the candidates a reader acts on: the first of the ranking and the named one, when
    // significant
    let leading: Vec<&str> = ranked
        .first()
        .into_iter()
        .chain(ranked.iter().find(|c| c.significant && c.plausible))
        .filter(|c| c.significant)
        .map(|c| c.effect.as_str())
        .collect();
    let mut out = Vec::new();
    for (a, (na, _, sa, pa)) in projected.iter().enumerate() {
        for (nb, _, sb, pb) in projected.iter().skip(a + 1) {
            if !interesting.contains(&na.as_str()) && !interesting.contains(&nb.as_str()) {
                continue;
            }
            let cos = sa.dot(sb) / (sa.norm() * sb.norm());
            let tests = (leading.contains(&na.as_str()) || leading.contains(&nb.as_str()))
                .then(|| (fit.p_separation(sa, sb), fit.vuong_z(sa, sb)));
            let tied = tests.is_some_and(|(p, z)| fit.tied(p, z));
            if cos.abs() < fit.collinear && !tied {
                continue;
            }
            out.push(Indistinguishable {
                a: na.clone(),
                b: nb.clone(),
                cosine: cos,
                p_separation: tests.map(|t| t.0),
                vuong_z: tests.map(|t| t.1),
                separated_by: match (pa, pb, separating) {
                    (Some(pa), Some(pb), Some((d, effects, items))) => {
                        separation(d, effects, items, *pa, *pb)
                    }
                    _ => None,
                },
            });
        }
    }
    out
}

/// The single unrecorded measurement that separates `a` from `b` most
/// ([`Discrimination::best_single`]: the T-optimality criterion, the material refitted), in
/// words, in the scatter of the better fit ([`Discrimination::scale`]); `effects` the design's candidates in order.
fn separation(
    design: &Discrimination,
    effects: &[Parameter],
    items: &[(Measurement, Vec<f64>)],
    a: Parameter,
    b: Parameter,
) -> Option<String> {
    let ia = effects.iter().position(|p| *p == a)?;
    let ib = effects.iter().position(|p| *p == b)?;
    let scale = design.scale(ia).min(design.scale(ib));
    let before = design.separation(ia, ib, &[]) / scale;
    let (item, after) = design.best_single(ia, ib)?;
    let after = after / scale;
    Some(format!(
        "{}, σ = {:.3}: the two expected {:.2} σ apart (log Bayes factor {:.2}), {:.2} σ on \
         these recordings",
        items[item].0.text(),
        items[item].0.sigma,
        after.sqrt(),
        after / 2.0,
        before.sqrt()
    ))
}
