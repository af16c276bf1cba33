//! `docs/MODEL.md` states the code's own numbers: every table row names a constant or default
//! of the code and its value, and each is compared here. A row whose item is unknown fails.
use surrogate::fe::geometry::{Design, DesignParams, MIN_CAVITY_LENGTH, N_RANGE, T_RANGE};
use surrogate::fe::simulate::{BAR, DENSITY, GRAVITY, MAX_PRESSURE_BAR, PLATE_OFFSET, PLATE_REACH};

fn code_value(item: &str) -> Option<f64> {
    let d = DesignParams::default();
    Some(match item {
        "DesignParams::default().n_bellows" => d.n_bellows as f64,
        "DesignParams::default().wall_thickness" => d.wall_thickness,
        "DesignParams::default().free_length" => d.free_length,
        "DesignParams::default().height" => d.height,
        "DesignParams::default().width" => d.width,
        "DesignParams::default().base_thickness" => d.base_thickness,
        "DesignParams::default().gap" => d.gap,
        "DesignParams::default().duct_half_width" => d.duct_half_width,
        "DesignParams::default().duct_bottom" => d.duct_bottom,
        "DesignParams::default().duct_top" => d.duct_top,
        "N_RANGE.0" => N_RANGE.0 as f64,
        "N_RANGE.1" => N_RANGE.1 as f64,
        "T_RANGE.0" => T_RANGE.0,
        "T_RANGE.1" => T_RANGE.1,
        "MIN_CAVITY_LENGTH" => MIN_CAVITY_LENGTH,
        "PLATE_OFFSET" => PLATE_OFFSET,
        "PLATE_REACH.0" => PLATE_REACH.0,
        "PLATE_REACH.1" => PLATE_REACH.1,
        "DENSITY" => DENSITY,
        "GRAVITY" => GRAVITY,
        "BAR" => BAR,
        "MAX_PRESSURE_BAR" => MAX_PRESSURE_BAR,
        _ => return None,
    })
}

#[test]
fn model_doc_numbers_are_the_codes() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/MODEL.md")).unwrap();
    let mut checked = 0;
    for line in text
        .lines()
        .filter(|l| l.starts_with('|') && l.contains('`'))
    {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let item = cells.last().unwrap().trim_matches('`');
        let value: f64 = cells[cells.len() - 3]
            .parse()
            .unwrap_or_else(|_| panic!("no value in {line}"));
        let code = code_value(item).unwrap_or_else(|| panic!("unknown code item in {line}"));
        assert_eq!(value, code, "{line}");
        checked += 1;
    }
    assert_eq!(checked, 22);
    // the geometry rules stated in prose, on the default design
    let d: Design = DesignParams::default().validate().unwrap();
    let p = d.params();
    let m = d.markers();
    assert_eq!(m[8], [p.width / 2.0, 0.0, p.free_length]);
    assert_eq!(d.support_point(), [p.width / 2.0, 0.0, 0.0]);
    assert_eq!(d.pitch(), p.free_length / p.n_bellows as f64);
    assert!(text.contains("Uz = −Δz") && text.contains("Uy = Δy"));
    assert!(text.contains("α = atan2(−y_tip, z_tip)"));
}
