//! A batch of cases in two stages: look every case up in the store, then run the rest on the
//! queue ([`super::queue`]), each result kept in the store as soon as it is there.

use std::marker::PhantomData;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use super::queue::{run_linked, Link};

/// What a run gives for a case: its result, and whether the solver stopped early.
pub trait Outcome {
    /// The solver's message if the case stopped early (the result holds what it reached).
    fn failure(&self) -> Option<&str>;
}

/// Where a run keeps its results: one entry per case, under the case's own key, each written
/// whole or not at all (an interrupted run resumes from what is there).
pub trait Store<J>: Sync {
    /// What a run gives for a case and the store keeps.
    type Ramp;
    /// What the store gives back for a case it holds.
    type Held;
    /// A store that cannot be read or written.
    type Error: Send;

    /// What the store holds for `case` (`None`: run it). A held entry is checked here, so that
    /// a bad one stops the batch before anything runs.
    ///
    /// # Errors
    /// An entry that is there but wrong (when the store refuses rather than reruns it).
    fn held(&self, case: &J) -> Result<Option<Self::Held>, Self::Error>;

    /// Keeps `ramp` as the result of `case`.
    ///
    /// # Errors
    /// The store cannot be written.
    fn keep(&self, case: &J, ramp: &Self::Ramp) -> Result<(), Self::Error>;
}

/// No store: nothing is held, nothing kept.
impl<J, S: Store<J>> Store<J> for Option<S> {
    type Ramp = S::Ramp;
    type Held = S::Held;
    type Error = S::Error;

    fn held(&self, case: &J) -> Result<Option<S::Held>, S::Error> {
        self.as_ref().map_or(Ok(None), |s| s.held(case))
    }

    fn keep(&self, case: &J, ramp: &S::Ramp) -> Result<(), S::Error> {
        self.as_ref().map_or(Ok(()), |s| s.keep(case, ramp))
    }
}

/// A store that holds nothing and keeps nothing: every case runs.
pub struct NoStore<R>(PhantomData<fn() -> R>);

impl<R> NoStore<R> {
    /// The store of a run that keeps nothing.
    pub fn new() -> Self {
        Self(PhantomData)
    }
}

impl<R> Default for NoStore<R> {
    fn default() -> Self {
        Self::new()
    }
}

impl<J, R> Store<J> for NoStore<R> {
    type Ramp = R;
    type Held = R;
    type Error = std::convert::Infallible;

    fn held(&self, _: &J) -> Result<Option<R>, Self::Error> {
        Ok(None)
    }

    fn keep(&self, _: &J, _: &R) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// What a solver gave for one case.
pub struct Solved<R, K> {
    /// The result.
    pub ramp: R,
    /// What the case leaves the cases that start from it (`None`: nothing).
    pub kept: Option<K>,
    /// Whether it started from its parent's kept state.
    pub from_parent: bool,
}

/// Computes one case, from its parent when it has one.
pub trait Solver<J>: Sync {
    /// The result of a case.
    type Ramp: Outcome + Send;
    /// What a case leaves the cases that start from it.
    type Kept: Send + Sync;

    /// Runs `case`, from `parent` (the parent's case and what it kept) when given. A failure
    /// is part of the result, not a panic.
    fn solve(&self, case: &J, parent: Option<(&J, &Self::Kept)>) -> Solved<Self::Ramp, Self::Kept>;
}

/// A solver of cases that each run on their own: `f(case)`.
pub struct Independent<F>(pub F);

impl<J, R: Outcome + Send, F: Fn(&J) -> R + Sync> Solver<J> for Independent<F> {
    type Ramp = R;
    type Kept = ();

    fn solve(&self, case: &J, _: Option<(&J, &())>) -> Solved<R, ()> {
        Solved {
            ramp: (self.0)(case),
            kept: None,
            from_parent: false,
        }
    }
}

/// How a case was obtained.
#[derive(Clone, Debug)]
pub enum Obtained<H, R> {
    /// Found in the store.
    Cache(H),
    /// Run now, to the end.
    Run(R),
    /// Run now and stopped early: what it reached, and the solver's message.
    Failed {
        /// What it reached.
        ramp: R,
        /// Why it stopped.
        message: String,
    },
}

/// One case of a run: how it was obtained.
#[derive(Clone, Debug)]
pub struct CaseReport<H, R> {
    /// Its index in the run's list.
    pub case: usize,
    /// The case it started from (`None`: on its own, or found in the store).
    pub parent: Option<usize>,
    /// Wall time of its run (s; 0 when found in the store).
    pub wall_s: f64,
    /// Its result and where it came from.
    pub obtained: Obtained<H, R>,
}

/// The reports of a run, by case.
pub type Reports<H, R> = Vec<CaseReport<H, R>>;

/// Where a run is, after each case it runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tally {
    /// Cases in the run.
    pub cases: usize,
    /// Of which found in the store.
    pub held: usize,
    /// Of which to run.
    pub to_run: usize,
    /// Run so far.
    pub ran: usize,
    /// Of which stopped early.
    pub failed: usize,
}

/// A list of cases looked up in a store: what it holds, what is left to run.
pub struct Batch<'a, J, S: Store<J>> {
    cases: &'a [J],
    store: &'a S,
    held: Vec<Option<S::Held>>,
}

impl<'a, J: Sync, S: Store<J>> Batch<'a, J, S>
where
    S::Held: Send,
{
    /// Looks every case of `cases` up in `store`, in order.
    ///
    /// # Errors
    /// The first entry the store refuses.
    pub fn look_up(cases: &'a [J], store: &'a S) -> Result<Self, S::Error> {
        let held = cases
            .iter()
            .map(|c| store.held(c))
            .collect::<Result<_, _>>()?;
        Ok(Self { cases, store, held })
    }

    /// The indices of the cases the store does not hold, in order.
    pub fn to_run(&self) -> Vec<usize> {
        (0..self.cases.len())
            .filter(|&i| self.held[i].is_none())
            .collect()
    }

    /// The number of cases the store holds.
    pub fn held_count(&self) -> usize {
        self.held.iter().filter(|h| h.is_some()).count()
    }

    /// What the store holds, case by case (without running anything).
    pub fn into_held(self) -> Vec<Option<S::Held>> {
        self.held
    }

    /// Runs every case the store does not hold on the current rayon pool, in `order` (the
    /// cases it leaves out after it, each on its own), each started from its parent when the
    /// parent ran now and kept something, and keeps each result in the store as soon as it is
    /// there; `progress(tally, report)` after each case run, one at a time. The reports come
    /// back by case.
    ///
    /// # Errors
    /// The first result the store could not keep (no case starts after it).
    pub fn run<V>(
        self,
        order: &[Link],
        solver: &V,
        progress: impl Fn(&Tally, &CaseReport<S::Held, V::Ramp>) + Sync,
    ) -> Result<Reports<S::Held, V::Ramp>, S::Error>
    where
        V: Solver<J>,
        S: Store<J, Ramp = V::Ramp>,
    {
        let to_run = self.to_run();
        let mut links: Vec<Link> = order
            .iter()
            .filter(|l| self.held[l.case].is_none())
            .copied()
            .collect();
        let mut listed = vec![false; self.cases.len()];
        for l in &links {
            listed[l.case] = true;
        }
        let left: Vec<usize> = to_run.iter().copied().filter(|&i| !listed[i]).collect();
        links.extend(Link::independent(&left));
        let tally = Tally {
            cases: self.cases.len(),
            held: self.cases.len() - to_run.len(),
            to_run: to_run.len(),
            ran: 0,
            failed: 0,
        };
        let failed = AtomicUsize::new(0);
        let (cases, store) = (self.cases, self.store);
        let ran = run_linked(
            cases.len(),
            &links,
            |link, parent| run_one(cases, store, solver, link, parent),
            |done, report| {
                let f = usize::from(matches!(report.obtained, Obtained::Failed { .. }));
                let t = Tally {
                    ran: done,
                    failed: failed.fetch_add(f, Ordering::SeqCst) + f,
                    ..tally
                };
                progress(&t, report);
            },
        )?;
        Ok(self
            .held
            .into_iter()
            .zip(ran)
            .enumerate()
            .map(|(case, (held, ran))| match (held, ran) {
                (Some(h), _) => CaseReport {
                    case,
                    parent: None,
                    wall_s: 0.0,
                    obtained: Obtained::Cache(h),
                },
                (None, Some(r)) => r,
                (None, None) => unreachable!("every case not held ran"),
            })
            .collect())
    }
}

/// A case run now: its report and what it leaves its children, or the store's error.
type RunNow<J, S, V> = Result<
    (
        CaseReport<<S as Store<J>>::Held, <V as Solver<J>>::Ramp>,
        Option<<V as Solver<J>>::Kept>,
    ),
    <S as Store<J>>::Error,
>;

/// Runs one case of `cases` and keeps its result in `store`.
fn run_one<J, V: Solver<J>, S: Store<J, Ramp = V::Ramp>>(
    cases: &[J],
    store: &S,
    solver: &V,
    link: Link,
    parent: Option<(usize, &V::Kept)>,
) -> RunNow<J, S, V> {
    let start = Instant::now();
    let case = &cases[link.case];
    let solved = solver.solve(case, parent.map(|(p, k)| (&cases[p], k)));
    let wall_s = start.elapsed().as_secs_f64();
    store.keep(case, &solved.ramp)?;
    let obtained = match solved.ramp.failure().map(str::to_owned) {
        Some(message) => Obtained::Failed {
            ramp: solved.ramp,
            message,
        },
        None => Obtained::Run(solved.ramp),
    };
    let report = CaseReport {
        case: link.case,
        parent: parent.filter(|_| solved.from_parent).map(|(p, _)| p),
        wall_s,
        obtained,
    };
    Ok((report, solved.kept))
}
