//! The queue a run's cases go through: one shared list in a given order, taken by the threads
//! of the current rayon pool, each case once its parent has finished.
//!
//! A thread takes the first case of the order not yet taken whose parent (if any) has
//! finished, runs it outside the lock, and records its result and what it leaves its children.
//! The results come back by case, not by the order they finished in: a case's result depends
//! only on itself and its parent's, never on the thread count or on timing.

use std::sync::{Arc, Condvar, Mutex};

/// One link of a run's order: a case and the case it starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Link {
    /// The case (its index in the run's list).
    pub case: usize,
    /// The case it starts from (`None`: on its own).
    pub parent: Option<usize>,
}

impl Link {
    /// The cases of `order` (indices), each on its own.
    pub fn independent(order: &[usize]) -> Vec<Link> {
        order
            .iter()
            .map(|&case| Link { case, parent: None })
            .collect()
    }
}

/// What the threads share: which positions of the order are taken, which cases have
/// finished, what each left its children, the results, the first error.
struct Board<R, K, E> {
    taken: Vec<bool>,
    finished: Vec<bool>,
    kept: Vec<Option<Arc<K>>>,
    results: Vec<Option<R>>,
    done: usize,
    error: Option<E>,
}

/// Runs `f(link, parent)` for every link of `order` on the threads of the current rayon pool
/// (module docs), `parent` being the parent's index and what it kept when it kept something;
/// `on_done(done, &result)` after each, one at a time. `cases` is the number of case indices;
/// a case that is in no link counts as finished from the start (with nothing kept), a parent
/// listed after its case is ignored. After an error no case is started; the first error is
/// returned once the running ones are done.
///
/// # Errors
/// The first error of `f`.
pub(super) fn run_linked<R: Send, K: Send + Sync, E: Send>(
    cases: usize,
    order: &[Link],
    f: impl Fn(Link, Option<(usize, &K)>) -> Result<(R, Option<K>), E> + Sync,
    on_done: impl Fn(usize, &R) + Sync,
) -> Result<Vec<Option<R>>, E> {
    let n = order.len();
    let mut position = vec![None; cases];
    for (k, l) in order.iter().enumerate() {
        position[l.case] = Some(k);
    }
    // a parent in the order must come before its case; one outside it is finished already
    let parents: Vec<Option<usize>> = order
        .iter()
        .enumerate()
        .map(|(k, l)| l.parent.filter(|&p| position[p].is_none_or(|q| q < k)))
        .collect();
    let board = Mutex::new(Board::<R, K, E> {
        taken: vec![false; n],
        finished: (0..cases).map(|c| position[c].is_none()).collect(),
        kept: (0..cases).map(|_| None).collect(),
        results: (0..cases).map(|_| None).collect(),
        done: 0,
        error: None,
    });
    let ready = Condvar::new();
    let lock = || board.lock().unwrap_or_else(|e| e.into_inner());
    let workers = rayon::current_num_threads().clamp(1, n.max(1));
    rayon::scope(|s| {
        for _ in 0..workers {
            s.spawn(|_| loop {
                // the next case, in order, whose parent has finished
                let (k, parent) = {
                    let mut b = lock();
                    loop {
                        if b.error.is_some() {
                            return;
                        }
                        let next = (0..n)
                            .find(|&k| !b.taken[k] && parents[k].is_none_or(|p| b.finished[p]));
                        if let Some(k) = next {
                            b.taken[k] = true;
                            let parent = parents[k].and_then(|p| b.kept[p].clone().map(|a| (p, a)));
                            break (k, parent);
                        }
                        if b.taken.iter().all(|&t| t) {
                            return;
                        }
                        b = ready.wait(b).unwrap_or_else(|e| e.into_inner());
                    }
                };
                let link = order[k];
                let ran = f(link, parent.as_ref().map(|(p, a)| (*p, a.as_ref())));
                let mut b = lock();
                b.finished[link.case] = true;
                match ran {
                    Ok((r, kept)) => {
                        b.kept[link.case] = kept.map(Arc::new);
                        b.done += 1;
                        on_done(b.done, &r);
                        b.results[link.case] = Some(r);
                    }
                    Err(e) => {
                        if b.error.is_none() {
                            b.error = Some(e);
                        }
                    }
                }
                ready.notify_all();
            });
        }
    });
    let b = board.into_inner().unwrap_or_else(|e| e.into_inner());
    match b.error {
        Some(e) => Err(e),
        None => Ok(b.results),
    }
}

/// `f` of every item on the threads of the current rayon pool, started in the order `order`
/// (indices into `items`; a shared queue: each thread takes the next item when it is free),
/// the results in item order. Each item's result does not depend on which thread ran it or
/// when.
///
/// # Panics
/// If `order` leaves out an item (it has no result to return).
pub fn in_order<T: Sync, R: Send>(
    items: &[T],
    order: &[usize],
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let ran = run_linked(
        items.len(),
        &Link::independent(order),
        |l, _: Option<(usize, &())>| Ok::<_, std::convert::Infallible>((f(&items[l.case]), None)),
        |_, _| {},
    );
    let results = match ran {
        Ok(r) => r,
        Err(e) => match e {},
    };
    results
        .into_iter()
        .map(|r| r.expect("the order lists every item"))
        .collect()
}
