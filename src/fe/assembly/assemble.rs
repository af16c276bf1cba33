//! The global assembly of residual and tangent: every element term of [`ELEMENT_TERMS`] (and
//! the model's added ones) on every element through the coloured scatter, then the face
//! pairs' contact and the dead loads.

// Index loops over the planes mirror the per-plane outputs.
#![allow(clippy::needless_range_loop)]

use super::load::{LoadFactor, LoadLevel};
use super::model::{AssemblyInfo, FeModel};
use super::projection::project_psd;
use super::scatter::{ColouredScatter, GlobalSystem};
use super::terms::term::{ElementContext, LocalSystem, MAX_PLANES};
use super::terms::{dead_load, pair_contact, ELEMENT_TERMS};
use crate::fe::element::{ElementError, DOFS};

impl FeModel {
    /// Names of the element terms this model assembles, in evaluation order.
    pub fn element_term_names(&self) -> Vec<&'static str> {
        ELEMENT_TERMS
            .iter()
            .copied()
            .chain(self.extra_terms.iter().map(|t| &**t))
            .map(|t| t.name())
            .collect()
    }

    /// The load factors this model's loads are scaled by, in slot order: the dead loads'
    /// (gravity, traction), the constraints' (prescribed) and those its element terms declare
    /// ([`ElementTerm::load_factor`](super::ElementTerm::load_factor)). A level's other factors
    /// have no effect on it.
    pub fn load_factors(&self) -> Vec<LoadFactor> {
        let mut out = vec![
            LoadFactor::GRAVITY,
            LoadFactor::TRACTION,
            LoadFactor::PRESCRIBED,
        ];
        let terms = ELEMENT_TERMS
            .iter()
            .copied()
            .chain(self.extra_terms.iter().map(|t| &**t));
        out.extend(terms.filter_map(|t| t.load_factor()));
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Assembles the residual over all dofs (`r_full`, reactions at constrained dofs) and,
    /// if `k_values` is given, the lower-triangular tangent on the free equations.
    ///
    /// # Errors
    /// [`ElementError::Inverted`] of the lowest-numbered inverted element.
    pub fn assemble(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, false, None, false)
    }

    /// As [`Self::assemble_with_energy`], for the minimisation solver: the tangent's
    /// initial-stress term may take the mixed iteration's pressures (`tangent_pressure`, see
    /// [`Self::assemble_mixed`]), and with `project` each element's local tangent (all of its
    /// terms) is projected onto the positive semi-definite cone ([`super::projection`]) before
    /// it is scattered. The residual and the potential are unchanged by either.
    ///
    /// # Errors
    /// As [`Self::assemble`].
    pub fn assemble_potential(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
        tangent_pressure: Option<&[[f64; 4]]>,
        project: bool,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, true, tangent_pressure, project)
    }

    /// As [`Self::assemble`], with the initial-stress term of each element's tangent evaluated
    /// with the given pressure coefficients (the mixed Newton iteration's pressures, see
    /// [`crate::fe::element::linearised_pressure`]) instead of the consistent ones. The residual is
    /// unchanged.
    ///
    /// # Errors
    /// As [`Self::assemble`].
    pub fn assemble_mixed(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
        tangent_pressure: Option<&[[f64; 4]]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, false, tangent_pressure, false)
    }

    /// As [`Self::assemble`], and also evaluates the total potential
    /// `Π = Σ_e Π_e + p Σ_faces (1/3)∫(x − o)·n da − f_dead · u` (in [`AssemblyInfo::energy`]),
    /// whose gradient is the residual. `o` is [`Self::pressure_origin`]: the potential is exact
    /// when the pressurised surfaces are closed, or closed by planes through `o` on which the
    /// nodes stay (symmetry planes, clamped faces).
    ///
    /// # Errors
    /// As [`Self::assemble`].
    pub fn assemble_with_energy(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        k_values: Option<&mut [f64]>,
    ) -> Result<AssemblyInfo, ElementError> {
        self.assemble_impl(u, level, r_full, k_values, true, None, false)
    }

    #[allow(clippy::too_many_arguments)]
    fn assemble_impl(
        &self,
        u: &[f64],
        level: &LoadLevel,
        r_full: &mut [f64],
        mut k_values: Option<&mut [f64]>,
        with_energy: bool,
        tangent_pressure: Option<&[[f64; 4]]>,
        project: bool,
    ) -> Result<AssemblyInfo, ElementError> {
        r_full.iter_mut().for_each(|v| *v = 0.0);
        if let Some(k) = k_values.as_deref_mut() {
            k.iter_mut().for_each(|v| *v = 0.0);
        }
        let with_k = k_values.is_some();
        let mut p_full = vec![0.0; r_full.len()];
        let mut energy = 0.0;
        let mut plane_forces = [0.0; MAX_PLANES];
        let mut plane_min_gaps = [f64::INFINITY; MAX_PLANES];
        let mut global = GlobalSystem {
            residual: r_full,
            external: &mut p_full,
            tangent: k_values,
        };
        let scatter = ColouredScatter {
            colors: &self.mesh.colors,
            elements: &self.mesh.elements,
            maps: &self.pattern.element_map,
        };
        scatter.run(
            &mut global,
            || LocalSystem::new(with_energy),
            |local, e| {
                let conn = &self.mesh.elements[e];
                let cx = ElementContext {
                    element: e,
                    conn,
                    nodes: &self.mesh.nodes,
                    ue: conn.map(|n| [u[3 * n], u[3 * n + 1], u[3 * n + 2]]),
                    level,
                    with_tangent: with_k,
                    with_energy,
                    mixed: tangent_pressure.map(|t| t[e]),
                };
                local.external = [0.0; DOFS];
                local.plane_forces = [0.0; MAX_PLANES];
                local.plane_gaps = [f64::INFINITY; MAX_PLANES];
                let extra = self.extra_terms.iter().map(|t| &**t);
                for term in ELEMENT_TERMS.iter().copied().chain(extra) {
                    term.add(self, &cx, local)?;
                }
                if project && with_k {
                    project_psd::<DOFS>(&mut local.work.k);
                }
                Ok((local.energy, local.plane_forces, local.plane_gaps))
            },
            |(en, forces, gaps)| {
                energy += en;
                for i in 0..MAX_PLANES {
                    plane_forces[i] += forces[i];
                    plane_min_gaps[i] = plane_min_gaps[i].min(gaps[i]);
                }
                Ok::<(), ElementError>(())
            },
        )?;
        let pairs = pair_contact::add(self, u, with_energy.then_some(&mut energy), &mut global);
        let ext2 = dead_load::add(
            self,
            u,
            level,
            &p_full,
            with_energy.then_some(&mut energy),
            r_full,
        );
        Ok(AssemblyInfo {
            energy,
            external_norm: ext2.sqrt(),
            plane_forces,
            plane_min_gaps,
            pair_force: pairs.force,
            pair_min_gap: pairs.min_gap,
        })
    }
}
