//! Twin recordings: what the rigs would record if the actuators had 0.1 mm thicker walls than
//! the model assumes (an effect of the library, concealed from whoever reads the files), in
//! the experiments' format, with their noise; read back like any recordings.
//!
//! ```sh
//! cargo run --release --example twin                    # N = 11, T = 2 only: 2 coarse ramps, ~3 min
//! cargo run --release --example twin -- all             # the 9 experimental designs, ~20 min
//! ```
use std::path::Path;

use surrogate::calibrate::twin::{write_twin, TwinSettings};
use surrogate::calibrate::Recordings;
use surrogate::fe::effects::Effects;
use surrogate::fe::material::{Material, DEFAULT_BULK_RATIO};
use surrogate::fe::mesh::{MeshLevel, MeshOptions};

fn main() -> surrogate::Result<()> {
    let mut noise = Recordings::read_dir(Path::new("training_data"))?;
    if std::env::args().nth(1).as_deref() != Some("all") {
        noise
            .bending
            .retain(|r| r.n_bellows == 11 && r.wall_thickness_mm == 2.0);
        noise
            .force
            .retain(|r| r.n_bellows == 11 && r.wall_thickness_mm == 2.0);
    }
    let mut settings = TwinSettings::new(
        Material::from_spec("ogden_002", DEFAULT_BULK_RATIO)?,
        "ogden_002",
        MeshOptions::level(MeshLevel::Coarse),
        Effects::parse(["wall_bias=0.1"])?,
        1,
        Path::new("twin_example/fe_ramps"),
    );
    settings.key = Some("twin_example/key.json".into());
    let out = Path::new("twin_example/recordings");
    let outcome = write_twin(&settings, &noise, out, |k, n| eprintln!("FE ramp {k}/{n}"))?;
    eprintln!(
        "{} ramps run, {} cached",
        outcome.ramps_run, outcome.ramps_cached
    );
    // the twin reads like the shipped experiments
    let twin = Recordings::read_dir(out)?;
    println!("| N | T (mm) | P (bar) | angle, twin (deg) | angle, measured (deg) |");
    for (t, m) in twin.bending.iter().zip(&noise.bending) {
        println!(
            "| {} | {} | {} | {:.2} | {:.2} |",
            t.n_bellows, t.wall_thickness_mm, t.pressure_bar, t.angle_deg, m.angle_deg
        );
    }
    println!("wrote {} (the key: twin_example/key.json)", out.display());
    Ok(())
}
