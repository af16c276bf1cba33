//! The warm pool of a repeated campaign: the latest converged ramp of each model, to start the
//! next iteration's ramp of the same model from.

use std::collections::BTreeMap;
use std::sync::Mutex;

use crate::fe::sensitivity::WithFields;
use crate::fe::simulate::Case;
use crate::fe::warm_start::WarmStart;

/// A pooled ramp: its parameter point and what it left.
type Pooled = (Vec<f64>, std::sync::Arc<WithFields>);

/// The latest converged ramp of each model in a repeated campaign (a calibration's
/// iterations: the same designs at a new parameter point each time), with its parameter point,
/// to start the next iteration's ramps from. Shared between threads; cloning shares it.
///
/// A ramp is matched by number of bellows, nominal wall thickness, rig, mesh and contact
/// settings: the dimensions being identified may differ (the mesh moves, its unknowns stay
/// the same; a start of another size is not used, [`LevelGuess::fits`](crate::fe::solver::LevelGuess::fits)).
#[derive(Clone, Default)]
pub struct WarmPool {
    inner: std::sync::Arc<Mutex<BTreeMap<String, Pooled>>>,
}

impl std::fmt::Debug for WarmPool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.inner.lock().map_or(0, |m| m.len());
        write!(f, "WarmPool({n} ramps)")
    }
}

/// Two handles are equal when they share the same pool.
impl PartialEq for WarmPool {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.inner, &other.inner)
    }
}

impl WarmPool {
    /// An empty pool.
    pub fn new() -> Self {
        Self::default()
    }

    /// A start for `case` at `point` from the pool's ramp of the same model: its states moved
    /// to `point` by their displacement sensitivities where it has them for every coordinate,
    /// as they are otherwise; `None` if the pool has no such ramp.
    pub fn start_for(&self, case: &Case, point: &[f64]) -> Option<WarmStart> {
        let map = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let (from, ran) = map.get(&pool_key(case))?;
        let delta: Vec<f64> = point.iter().zip(from).map(|(a, b)| a - b).collect();
        if from.len() == point.len() && ran.fields.parameters.len() == point.len() {
            if let Ok(w) = ran.warm_start(&delta) {
                return Some(w);
            }
        }
        Some(WarmStart::new(ran.states.clone()))
    }

    /// Keeps `ran` (of `case` at `point`) as the start of its model's next ramp.
    pub fn keep(&self, case: &Case, point: Vec<f64>, ran: WithFields) {
        let mut map = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        map.insert(pool_key(case), (point, std::sync::Arc::new(ran)));
    }

    /// The number of ramps kept.
    pub fn len(&self) -> usize {
        self.inner.lock().map_or(0, |m| m.len())
    }

    /// Whether it keeps no ramp.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn pool_key(c: &Case) -> String {
    let p = c.design.params();
    serde_json::json!({
        "n": p.n_bellows,
        "t": p.wall_thickness,
        "mesh": c.mesh,
        "mode": c.mode,
        "contact": c.contact,
    })
    .to_string()
}
