//! Verification of the hyperelastic laws (`surrogate::fe::material`).
//!
//! * [`derivatives`]: one finite-difference checker applied to every law, isochoric and total;
//!   objectivity and isotropy.
//! * [`closed_forms`]: material-point checks against the incompressible closed forms.
//! * [`admissibility`]: parameter validation, specification parsing, literature sets.
//! * Here: the quadrature-point functions do not allocate (with and without a fibre term).

mod admissibility;
mod closed_forms;
mod derivatives;

use nalgebra::Matrix3;
use surrogate::fe::material::{Fibre, Material, Tangent9};

/// Counts heap allocations of the current thread (other test threads are not counted).
struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

// SAFETY: forwards to the system allocator; the counter is a const-initialised thread-local
// `Cell`, which does not allocate.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn quadrature_point_functions_do_not_allocate() {
    let f = Matrix3::new(1.1, 0.05, -0.02, 0.03, 0.95, 0.04, -0.01, 0.02, 1.02);
    let (mut p, mut a) = (Matrix3::zeros(), Tangent9::zeros());
    let before = ALLOCATIONS.with(|n| n.get());
    let boxed = std::hint::black_box(Box::new(1.0_f64));
    assert!(
        ALLOCATIONS.with(|n| n.get()) > before && *boxed == 1.0,
        "the counter counts"
    );
    let printed = Material::from_spec("ogden_002", 1000.0)
        .unwrap()
        .with_fibre(Fibre::new([0.3, -0.5, 0.8], -1.0).unwrap())
        .unwrap();
    let materials = ["ogden_002", "mooney_rivlin_5", "neo_hookean:2.5"]
        .map(|spec| (spec, Material::from_spec(spec, 1000.0).unwrap()));
    for (spec, m) in materials
        .into_iter()
        .chain([("ogden_002 + fibre", printed)])
    {
        let before = ALLOCATIONS.with(|n| n.get());
        let mut energy = m.energy(&f) + m.iso_energy(&f);
        m.iso_stress_into(&f, &mut p);
        m.iso_stress_tangent_into(&f, &mut p, &mut a);
        m.stress_into(&f, &mut p);
        m.stress_tangent_into(&f, &mut p, &mut a);
        energy += p[(0, 0)] + a[(0, 0)];
        let after = ALLOCATIONS.with(|n| n.get());
        assert!(energy.is_finite());
        assert_eq!(after, before, "{spec}: {} heap allocations", after - before);
    }
}
