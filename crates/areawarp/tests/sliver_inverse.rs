//! The spherical triangle's inverse on slivers narrower than rounding
//! (`docs/spherical-triangle.md` §6, "Slivers below rounding"): the
//! triangles the light fuzz found with other seeds, each sampled at the
//! fuzz's values of `u` and `v` and inverted.

use areawarp::shapes::SphericalTriangle;
use areawarp::{Vec3, Warp};

#[path = "support/light_cases.rs"]
mod light_cases;
use light_cases::unit_values;

/// Slivers the fuzz found with other seeds (`AREAWARP_FUZZ_SEED` 13, 14, 17,
/// 30, 33): "nearly collinear" triangles of solid angle 10⁻¹⁸…10⁻¹⁶, whose
/// width is below `f64`'s rounding. Where the great circle through B and a
/// sample lies along the whole arc AC to rounding, the inverse found no
/// chart and refused the map's own samples (A at `(0, 1)`, `C_s` at
/// `(½, 1)`). Every sample is now inverted; those at `u = 0`, `v ≥ ½`
/// (the far half of the arc BA, the vertex A included) to a point of the
/// map within 64 units of roundoff of them. Elsewhere on a sliver a
/// direction rounded to `f64` determines `(u, v)` only to about its
/// distance from B and the short side |BC| (1e-4…1e-3 here), and the
/// inverse's image is that close.
#[test]
fn slivers_invert_their_own_samples() {
    let slivers = [
        [
            [0.5114140524942483, -0.5620470272791651, -0.6500452338399719],
            [
                0.42978424085241546,
                -0.7627657389002218,
                -0.4831914050093517,
            ],
            [0.4298552491135133, -0.762640561150772, -0.48332581070867175],
        ],
        [
            [-0.15319968238887538, 0.914150012836388, 0.37531268476722135],
            [
                -0.40360755230890194,
                -0.6084062120798842,
                -0.6833321482425834,
            ],
            [
                -0.40369528312655784,
                -0.608318256736705,
                -0.6833586297854036,
            ],
        ],
        [
            [0.7115007161676762, -0.5788331727234668, 0.39839539285459746],
            [0.044630992569769753, -0.86216231514903, 0.5046624781367259],
            [0.04335567905226428, -0.8627041503418006, 0.5048657020131901],
        ],
        [
            [
                -0.689865414913739,
                -0.5460394047960413,
                -0.47531744941236853,
            ],
            [0.010897155270553599, 0.7163080527271759, 0.6976990938830367],
            [0.011331540291175193, 0.7170905500375326, 0.6984262172155727],
        ],
        [
            [0.6608528309311836, -0.6011774677480368, -0.4492874226175251],
            [0.25291769674159037, 0.6385197287411614, 0.7268598177662889],
            [0.25245018204962755, 0.6386685623626854, 0.7268915827224101],
        ],
    ];
    let tol = 64.0 * f64::EPSILON / 2.0;
    let mut checked = 0;
    for v in slivers {
        let [a, b, c] = v.map(Vec3::from);
        let t = SphericalTriangle::<f64>::new(a, b, c).unwrap();
        assert!(t.solid_angle() < 1e-15, "{v:?}");
        for u in unit_values::<f64>() {
            for w in unit_values::<f64>() {
                let p = t.map(&u, &w);
                let [iu, iv] = t
                    .inverse(&p)
                    .unwrap_or_else(|e| panic!("{v:?} ({u}, {w}): {e}"));
                let off = t.map(&iu, &iv).sub(&p).norm();
                // Off A: no farther than C is from p, through B.
                let near_b = p.sub(&b).norm() + c.sub(&b).norm();
                let bound = if u == 0.0 && w >= 0.5 {
                    tol
                } else {
                    tol + near_b
                };
                assert!(off <= bound, "{v:?} ({u}, {w}) -> ({iu}, {iv}): {off:e}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 5 * 36);
}
