//! ParaView output: the deformed mesh as VTK XML unstructured grids (`.vtu`) and a `.pvd`
//! collection with the pressure as "time".
//!
//! Each 27-node element is written as its 8 trilinear sub-hexahedra (all 27 nodes are kept),
//! with point data `displacement` (mm), `von_mises` (Cauchy, MPa) and `max_log_strain`
//! (largest principal Hencky strain), and cell data `element`. The pressurised faces are
//! written to a second file `*_surfaces.vtu` (quadrilaterals, cell data `surface`:
//! 0 = duct, i + 1 = cavity of bellow i).

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use nalgebra::Matrix3;

use super::element::shape;
use super::mesh::{Face, PressureSurface};
use super::simulate::ActuatorModel;

/// Local nodes (tensor order) of the 8 sub-hexahedra of a 27-node element, VTK hex order.
fn sub_hexes() -> [[usize; 8]; 8] {
    let idx = |i: usize, j: usize, k: usize| i + 3 * j + 9 * k;
    let mut out = [[0; 8]; 8];
    let mut s = 0;
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..2 {
                out[s] = [
                    idx(i, j, k),
                    idx(i + 1, j, k),
                    idx(i + 1, j + 1, k),
                    idx(i, j + 1, k),
                    idx(i, j, k + 1),
                    idx(i + 1, j, k + 1),
                    idx(i + 1, j + 1, k + 1),
                    idx(i, j + 1, k + 1),
                ];
                s += 1;
            }
        }
    }
    out
}

/// Nodal von Mises stress and largest principal log strain, averaged over elements.
fn nodal_fields(model: &ActuatorModel, u: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mesh = &model.fe.mesh;
    let mut vm = vec![0.0; mesh.n_nodes()];
    let mut eps = vec![0.0; mesh.n_nodes()];
    let mut count = vec![0u32; mesh.n_nodes()];
    let mut p = Matrix3::zeros();
    for (conn, &scale) in mesh.elements.iter().zip(&model.fe.stiffness) {
        for (l, &node) in conn.iter().enumerate() {
            let xi = [
                (l % 3) as f64 - 1.0,
                ((l / 3) % 3) as f64 - 1.0,
                (l / 9) as f64 - 1.0,
            ];
            let (_, dn) = shape(xi);
            let mut jac = Matrix3::<f64>::zeros();
            let mut grad_u = Matrix3::<f64>::zeros();
            for (a, &na) in conn.iter().enumerate() {
                let x = mesh.nodes[na];
                for i in 0..3 {
                    for m in 0..3 {
                        jac[(i, m)] += x[i] * dn[a][m];
                        grad_u[(i, m)] += u[3 * na + i] * dn[a][m];
                    }
                }
            }
            let Some(jinv) = jac.try_inverse() else {
                continue;
            };
            let f: Matrix3<f64> = Matrix3::identity() + grad_u * jinv;
            let j = f.determinant();
            if j <= 0.0 {
                continue;
            }
            model.fe.material.stress_into(&f, &mut p);
            p *= scale;
            let sigma = p * f.transpose() / j;
            let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
            vm[node] += (1.5 * dev.component_mul(&dev).sum()).sqrt();
            let c = f.transpose() * f;
            let lmax = c.symmetric_eigenvalues().max();
            eps[node] += 0.5 * lmax.max(1e-300).ln();
            count[node] += 1;
        }
    }
    for n in 0..mesh.n_nodes() {
        let c = f64::from(count[n].max(1));
        vm[n] /= c;
        eps[n] /= c;
    }
    (vm, eps)
}

fn data_array(out: &mut String, name: &str, ncomp: usize, values: impl Iterator<Item = f64>) {
    let _ = write!(
        out,
        "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{ncomp}\" format=\"ascii\">"
    );
    for v in values {
        let _ = write!(out, "{v:.9e} ");
    }
    out.push_str("</DataArray>\n");
}

fn int_array(out: &mut String, name: &str, values: impl Iterator<Item = usize>) {
    let _ = write!(
        out,
        "<DataArray type=\"Int64\" Name=\"{name}\" format=\"ascii\">"
    );
    for v in values {
        let _ = write!(out, "{v} ");
    }
    out.push_str("</DataArray>\n");
}

/// XML header, piece and the deformed points (all mesh nodes), up to the opening `<Cells>`.
fn grid_head(s: &mut String, mesh: &super::mesh::Mesh, u: &[f64], n_cells: usize) {
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{n_cells}\">",
        mesh.n_nodes()
    );
    s.push_str("<Points>\n");
    data_array(
        s,
        "position",
        3,
        mesh.nodes
            .iter()
            .enumerate()
            .flat_map(|(n, x)| (0..3).map(move |i| x[i] + u[3 * n + i])),
    );
    s.push_str("</Points>\n<Cells>\n");
}

/// Writes the deformed mesh of one step to `dir/step_{index:03}.vtu` and its pressurised
/// surfaces to `dir/step_{index:03}_surfaces.vtu`. Returns the volume file's path.
///
/// # Errors
/// I/O errors creating or writing the files.
pub fn write_step(
    dir: &Path,
    index: usize,
    model: &ActuatorModel,
    u: &[f64],
) -> io::Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let mesh = &model.fe.mesh;
    let (vm, eps) = nodal_fields(model, u);
    let subs = sub_hexes();
    let n_cells = 8 * mesh.n_elements();
    let mut s = String::with_capacity(256 * mesh.n_nodes());
    grid_head(&mut s, mesh, u, n_cells);
    int_array(
        &mut s,
        "connectivity",
        mesh.elements.iter().flat_map(|conn| {
            subs.iter()
                .flat_map(move |h| h.iter().map(move |&l| conn[l]))
        }),
    );
    int_array(&mut s, "offsets", (1..=n_cells).map(|c| 8 * c));
    s.push_str("<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in 0..n_cells {
        s.push_str("12 ");
    }
    s.push_str("</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n");
    data_array(&mut s, "displacement", 3, u.iter().copied());
    data_array(&mut s, "von_mises", 1, vm.iter().copied());
    data_array(&mut s, "max_log_strain", 1, eps.iter().copied());
    s.push_str("</PointData>\n<CellData>\n");
    int_array(&mut s, "element", (0..n_cells).map(|c| c / 8));
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    let path = dir.join(format!("step_{index:03}.vtu"));
    crate::io::write_atomic(&path, s.as_bytes())?;
    write_surfaces(&dir.join(format!("step_{index:03}_surfaces.vtu")), model, u)?;
    if !model.fe.pairs.is_empty() {
        write_contact(&dir.join(format!("step_{index:03}_contact.vtu")), model, u)?;
    }
    Ok(path)
}

/// The facing walls of every gap (both sides) with the gap and contact pressure at each face
/// pair's centre.
fn write_contact(path: &Path, model: &ActuatorModel, u: &[f64]) -> io::Result<()> {
    let fe = &model.fe;
    let pos = |n: usize| {
        let x = fe.mesh.nodes[n];
        [x[0] + u[3 * n], x[1] + u[3 * n + 1], x[2] + u[3 * n + 2]]
    };
    let set = fe.pair_settings;
    let values: Vec<(f64, f64)> = fe
        .pairs
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let g =
                super::contact::pair_centre_gap(p.orientation, &p.back.map(pos), &p.front.map(pos));
            let c = fe.pair_centre_shift(i);
            let (_, dpsi, _) = super::contact::barrier(set.stiffness, set.smoothing, g - c);
            (g, -dpsi)
        })
        .collect();
    let quads = |n: [usize; 9]| {
        [
            [n[0], n[1], n[4], n[3]],
            [n[1], n[2], n[5], n[4]],
            [n[3], n[4], n[7], n[6]],
            [n[4], n[5], n[8], n[7]],
        ]
    };
    let n_cells = 8 * fe.pairs.len();
    let mut s = String::new();
    grid_head(&mut s, &fe.mesh, u, n_cells);
    int_array(
        &mut s,
        "connectivity",
        fe.pairs
            .iter()
            .flat_map(|p| quads(p.back).into_iter().chain(quads(p.front)).flatten()),
    );
    int_array(&mut s, "offsets", (1..=n_cells).map(|c| 4 * c));
    s.push_str("<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in 0..n_cells {
        s.push_str("9 ");
    }
    s.push_str("</DataArray>\n</Cells>\n<CellData>\n");
    data_array(
        &mut s,
        "gap_mm",
        1,
        values.iter().flat_map(|v| std::iter::repeat_n(v.0, 8)),
    );
    data_array(
        &mut s,
        "contact_pressure_mpa",
        1,
        values.iter().flat_map(|v| std::iter::repeat_n(v.1, 8)),
    );
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    crate::io::write_atomic(path, s.as_bytes())
}

fn write_surfaces(path: &Path, model: &ActuatorModel, u: &[f64]) -> io::Result<()> {
    let mesh = &model.fe.mesh;
    let faces: Vec<(&Face, usize)> = model
        .mesh
        .pressure_faces
        .iter()
        .flat_map(|(surf, fs)| {
            let id = match surf {
                PressureSurface::Duct => 0,
                PressureSurface::Cavity(i) => i + 1,
            };
            fs.iter().map(move |f| (f, id))
        })
        .collect();
    let quads = |f: &Face| {
        let n = f.nodes;
        [
            [n[0], n[1], n[4], n[3]],
            [n[1], n[2], n[5], n[4]],
            [n[3], n[4], n[7], n[6]],
            [n[4], n[5], n[8], n[7]],
        ]
    };
    let n_cells = 4 * faces.len();
    let mut s = String::new();
    grid_head(&mut s, mesh, u, n_cells);
    int_array(
        &mut s,
        "connectivity",
        faces
            .iter()
            .flat_map(|(f, _)| quads(f).into_iter().flatten()),
    );
    int_array(&mut s, "offsets", (1..=n_cells).map(|c| 4 * c));
    s.push_str("<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in 0..n_cells {
        s.push_str("9 ");
    }
    s.push_str("</DataArray>\n</Cells>\n<CellData>\n");
    int_array(
        &mut s,
        "surface",
        faces.iter().flat_map(|(_, id)| std::iter::repeat_n(*id, 4)),
    );
    s.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    crate::io::write_atomic(path, s.as_bytes())
}

/// Writes `dir/steps.pvd` listing the step files with their pressures (bar) as time values.
///
/// # Errors
/// I/O errors.
pub fn write_collection(dir: &Path, steps: &[(f64, PathBuf)]) -> io::Result<()> {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
    );
    for (p, path) in steps {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "<DataSet timestep=\"{p}\" group=\"\" part=\"0\" file=\"{name}\"/>"
        );
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    std::fs::write(dir.join("steps.pvd"), s)
}
