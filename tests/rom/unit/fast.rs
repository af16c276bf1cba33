//! The unit tests of `src/rom/fast.rs`.

use surrogate::rom::fast::*;

/// The one-pass four-node sums equal the per-node sums bit for bit (odd and even counts).
#[test]
fn four_node_pass_is_bit_identical_to_per_node_sums() {
    for n in [1usize, 2, 7, 300, 301] {
        let block = 4 * n;
        let t: Vec<f64> = (0..NS * block)
            .map(|i| ((i as f64) * 0.7311).sin() * 1e3)
            .collect();
        let phi: Vec<f64> = (0..n).map(|i| ((i as f64) * 1.37).cos()).collect();
        let all = accumulate_nodes(&t, block, &phi);
        let body = accumulate_nodes_body(&t, block, &phi);
        for s in 0..NS {
            let one = accumulate::<4>(&t[s * block..(s + 1) * block], &phi);
            for l in 0..4 {
                assert_eq!(
                    all[s][l].to_bits(),
                    one[l].to_bits(),
                    "n {n} node {s} q {l}"
                );
                assert_eq!(
                    body[s][l].to_bits(),
                    one[l].to_bits(),
                    "n {n} node {s} q {l}"
                );
            }
        }
    }
}
