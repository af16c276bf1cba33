//! The maps: the surrogate's values over (N, T, P), NaN beyond the buildable wall, as CSV.
use surrogate::case::Query;
use surrogate::design::{map, Output};

use crate::common::{synthetic, OGDEN_002};

#[test]
fn a_map_holds_the_predictions_and_greys_out_unbuildable_walls() {
    let model = synthetic();
    let outputs = [Output::AngleDeg, Output::ForceN];
    let pressures = [1.0, 3.0];
    let n_values = [7, 11, 15];
    let t = [1.5, 2.0, 2.5];
    let m = map(model, OGDEN_002, &outputs, &pressures, &n_values, &t).unwrap();
    assert_eq!(m.values.len(), 2 * 2 * 3 * 3);
    assert_eq!(m.trained_n, n_values);
    for (n_i, &n) in n_values.iter().enumerate() {
        for (t_i, &tt) in t.iter().enumerate() {
            // 15 bellows leave a cavity only up to T = 2.32 mm
            assert_eq!(
                m.buildable(n_i, t_i),
                !(n == 15 && tt > 2.4),
                "N = {n}, T = {tt}"
            );
            for (p_i, &p) in pressures.iter().enumerate() {
                let pred = model.predict(&Query::new(n, tt, p, OGDEN_002)).unwrap();
                let (a, f) = (m.value(0, p_i, n_i, t_i), m.value(1, p_i, n_i, t_i));
                if m.buildable(n_i, t_i) {
                    assert!(
                        (a - pred.angle_deg()).abs() < 1e-9,
                        "{a} {}",
                        pred.angle_deg()
                    );
                    assert!((f - pred.force_n()).abs() < 1e-9, "{f} {}", pred.force_n());
                } else {
                    assert!(a.is_nan() && f.is_nan());
                }
            }
        }
    }
    let mut csv = Vec::new();
    m.write_csv(&mut csv).unwrap();
    let text = String::from_utf8(csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "n_bellows,wall_thickness_mm,pressure_bar,buildable,angle_deg,force_n"
    );
    assert_eq!(lines.len(), 1 + 3 * 3 * 2);
    assert!(lines.contains(&"15,2.5,3,false,,"), "{text}");
}
