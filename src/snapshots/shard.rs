//! Shards: deterministic shares of a plan, for job arrays.
//!
//! Shard `k/n` (1-based) owns the cases at plan positions `i` with `i mod n = k − 1`: round
//! robin, so every shard gets a similar mix of `N` and cost. The shards of any `n` partition the
//! plan; each case belongs to exactly one. In a Slurm job array with `--array=0-(n−1)`, task
//! `SLURM_ARRAY_TASK_ID` runs shard `SLURM_ARRAY_TASK_ID + 1` of `n`.

use std::str::FromStr;

use super::SnapshotError;

/// A share `k/n` of a plan (1-based, `1 ≤ k ≤ n`): the cases at positions `i` with
/// `i mod n = k − 1` (round robin, so every shard gets a similar mix of `N`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based index `k`.
    pub index: usize,
    /// Number of shards `n`.
    pub count: usize,
}

impl Shard {
    /// The whole plan.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Whether the case at plan position `position` belongs to this shard.
    pub fn owns(&self, position: usize) -> bool {
        position % self.count == self.index - 1
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = SnapshotError;
    /// Parses `k/n` with integers `1 ≤ k ≤ n`.
    fn from_str(s: &str) -> Result<Self, SnapshotError> {
        let err = |expected: String| SnapshotError::Shard {
            spec: s.to_owned(),
            expected,
        };
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| err("k/n, e.g. 2/8 (shard k of n, 1 ≤ k ≤ n)".into()))?;
        let parse = |t: &str, what: &str| {
            t.trim().parse::<usize>().map_err(|_| {
                err(format!(
                    "k/n with integers: {what} {:?} is not a non-negative integer",
                    t.trim()
                ))
            })
        };
        let (k, n) = (parse(k, "k")?, parse(n, "n")?);
        if n == 0 {
            return Err(err("n ≥ 1 shards".into()));
        }
        if k == 0 || k > n {
            return Err(err(format!("1 ≤ k ≤ {n} (shards are numbered from 1)")));
        }
        Ok(Shard { index: k, count: n })
    }
}
