//! The FE campaign runner: a list of cases run in parallel, each result kept in a store as
//! soon as it is there, so that an interrupted run resumes where it stopped.
//!
//! ```text
//!   cases ──look up in the store──► held (Cache) ─────────────────────────────┐
//!     │                                                                         ▼
//!     └─ the rest ──queue, in order──► solve (from the parent) ──► keep ──► one report per case:
//!                   (rayon threads)                                          Cache | Run | Failed
//! ```
//!
//! A run is two stages ([`Batch`]): every case is looked up in the [`Store`] (a held entry is
//! checked there, so a bad one stops the run before anything is computed), then the cases the
//! store does not hold go through one queue ([`queue`]) on the threads of the current rayon
//! pool, in a given order ([`Link`]: a case and the case it starts from). A [`Solver`]
//! computes each case, from what its parent kept when it has one; its result is kept in the
//! store at once and reported ([`CaseReport`], [`Obtained`]: found in the store, run, or run
//! and stopped with the solver's message) with a [`Tally`] to the progress callback.
//!
//! **Determinism.** A case's result depends only on the case and its parent's result, never
//! on the thread count, on which thread ran it or when; the reports come back by case.
//!
//! **The FE ramp.** [`RampCase`] is a case with its parameter point and the parameters of its
//! sensitivities; [`Start`] is the solver of such cases and how each starts:
//! - [`Start::Cold`]: from the undeformed actuator ([`cold_ramp`]);
//! - [`Start::Tree`]: from its parent in a minimum-spanning-tree order of the points
//!   ([`spanning_order`]), with the parent's converged states as they are
//!   ([`WarmOrder::Zeroth`]) or moved by their displacement sensitivities,
//!   `u(θ + Δθ) ≈ u(θ) + (∂u/∂θ) Δθ` ([`WarmOrder::First`]);
//! - [`Start::Pool`]: from a [`WarmPool`]'s ramp of the same model (an earlier iteration).
//!
//! [`RampDir`] is the keyed ramp cache ([`cache`]); [`run_campaign`] is both stages at once.
//!
//! **Users.** The sweep of [`crate::calibrate::baseline`] (every design's bending and
//! blocked-force ramps, cached by key, cold or from a warm pool), the snapshot shards of
//! [`crate::snapshots::run`] (a plan's cases, one CSV file each, with a runner of their own)
//! and the warm-start campaign of [`super::campaign`] (tree order) are this runner with their
//! own cases, stores and starts.

pub mod batch;
pub mod cache;
pub mod pool;
pub mod queue;
pub mod ramp;
pub mod tree;

pub use batch::{
    Batch, CaseReport, Independent, NoStore, Obtained, Outcome, Reports, Solved, Solver, Store,
    Tally,
};
pub use cache::{RampCacheError, RampDir, RampFile};
pub use pool::WarmPool;
pub use queue::{in_order, Link};
pub use ramp::{cold_ramp, Ramp, RampCase, Start, WarmOrder};
pub use tree::spanning_order;

/// Runs `cases` in `order` from `start`, with `store` ([`Batch::look_up`], then
/// [`Batch::run`]): the cases `store` holds are not run.
///
/// # Errors
/// The store refuses an entry (before anything runs) or cannot keep a result.
pub fn run_campaign<S>(
    cases: &[RampCase],
    order: &[Link],
    start: &Start,
    store: &S,
    progress: impl Fn(&Tally, &CaseReport<S::Held, Ramp>) + Sync,
) -> Result<Reports<S::Held, Ramp>, S::Error>
where
    S: Store<RampCase, Ramp = Ramp>,
    S::Held: Send,
{
    Batch::look_up(cases, store)?.run(order, start, progress)
}
