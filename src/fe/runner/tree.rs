//! The order of a tree campaign: cases of the same model (design, mesh, rig and contact: the
//! same unknowns) form a group; within a group the cases are linked by a minimum spanning tree
//! of their parameter points (Prim's algorithm, distances in units of each coordinate's
//! scale), grown from the case nearest the group's centroid. Each case starts from its tree
//! parent, the nearest case already grown when it joined; the tree's edges sum to the least
//! total distance, so the starts are as near as any order allows. The first case of a group
//! has no parent.

use std::collections::BTreeMap;

use super::queue::Link;
use crate::fe::simulate::Case;

/// The order of `cases` (each FE case with its parameter point) as their trees grow, group
/// after group (module docs), each case with its tree parent; `scales` is the unit of each
/// coordinate.
pub fn spanning_order(cases: &[(&Case, &[f64])], scales: &[f64]) -> Vec<Link> {
    let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, (c, _)) in cases.iter().enumerate() {
        groups.entry(model_key(c)).or_default().push(i);
    }
    let points: Vec<&[f64]> = cases.iter().map(|(_, p)| *p).collect();
    let mut out = Vec::with_capacity(cases.len());
    for members in groups.values() {
        out.extend(tree(&points, scales, members));
    }
    out
}

/// Prim's minimum spanning tree of `members`, from the one nearest their centroid, in
/// the order the cases join.
fn tree(points: &[&[f64]], scales: &[f64], members: &[usize]) -> Vec<Link> {
    let dist = |a: usize, b: usize| {
        let (pa, pb) = (points[a], points[b]);
        pa.iter()
            .zip(pb)
            .zip(scales)
            .map(|((x, y), s)| ((x - y) / s).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let dim = scales.len();
    let mut centroid = vec![0.0; dim];
    for &m in members {
        for (c, v) in centroid.iter_mut().zip(points[m]) {
            *c += v / members.len() as f64;
        }
    }
    let to_centroid = |m: usize| {
        points[m]
            .iter()
            .zip(&centroid)
            .zip(scales)
            .map(|((x, y), s)| ((x - y) / s).powi(2))
            .sum::<f64>()
    };
    let Some(root) = members
        .iter()
        .copied()
        .min_by(|&a, &b| to_centroid(a).total_cmp(&to_centroid(b)).then(a.cmp(&b)))
    else {
        return Vec::new();
    };
    let mut links = vec![Link {
        case: root,
        parent: None,
    }];
    // best[k]: (distance to the tree, nearest tree member) of members[k] not yet in it
    let mut best: Vec<Option<(f64, usize)>> = members
        .iter()
        .map(|&m| (m != root).then(|| (dist(m, root), root)))
        .collect();
    while let Some(k) = (0..members.len())
        .filter(|&k| best[k].is_some())
        .min_by(|&a, &b| {
            let (da, db) = (best[a].map_or(0.0, |b| b.0), best[b].map_or(0.0, |b| b.0));
            da.total_cmp(&db).then(members[a].cmp(&members[b]))
        })
    {
        let (_, parent) = best[k].take().expect("filtered on is_some");
        let m = members[k];
        links.push(Link {
            case: m,
            parent: Some(parent),
        });
        for (j, b) in best.iter_mut().enumerate() {
            if let Some((d, p)) = b {
                let dn = dist(members[j], m);
                if dn < *d {
                    *d = dn;
                    *p = m;
                }
            }
        }
    }
    links
}

/// The cases that share a model (the same unknowns and contact points): design, mesh, rig,
/// contact settings and gravity.
fn model_key(c: &Case) -> String {
    serde_json::json!({
        "design": c.design.params(),
        "mesh": c.mesh,
        "mode": c.mode,
        "contact": c.contact,
    })
    .to_string()
}
