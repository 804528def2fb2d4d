//! A sliver straddling the horizon (3·10⁻⁵ rad across, Π ≈ 2·10⁻¹⁵; found
//! by `polygon_fuzz_large` with seed 77) whose last lune, between a vertex
//! 1.7·10⁻⁸ above the horizon and the crossing of its edge with the
//! horizon, is 7.7·10⁻⁹ rad wide: its area rounds to zero in `f64`, so the
//! map does not sample it (a share of Π below 10⁻⁹). It is still part of
//! the polygon, and `outside_by` (with it `inverse` and `pdf`) must say so.

use super::*;

fn sliver() -> Vec<Vec3<f64>> {
    [
        [
            0.8690802105519465,
            0.49467119142616767,
            1.6543232327317128e-8,
        ],
        [
            0.8690977946372044,
            0.4946402966658945,
            1.6462798928605712e-5,
        ],
        [
            0.869105929459952,
            0.49462600317138017,
            -1.9085566245510317e-5,
        ],
        [
            0.8690883453746941,
            0.49465689793165335,
            -3.55318219417887e-5,
        ],
    ]
    .map(Vec3::from)
    .to_vec()
}

#[test]
fn an_unsampled_lune_is_part_of_the_polygon() {
    let v = sliver();
    let (w, exact) = f64_and_exact(&v);
    let parts = w.parts();
    // The case is what it says: a lune with edges that the map skips.
    assert!(
        parts
            .lunes
            .iter()
            .any(|l| l.active.is_none() && l.n_edges > 0),
        "no unsampled lune"
    );
    // Directions in or next to the skipped lune: the samples on the
    // meridian where the map's last lune ends (u = 1, which borders it),
    // and a point inside it: the centroid of the crossing c, the vertex v₀
    // and the sample (1, 0) on the edge v₀v₁ above c.
    let mut dirs: Vec<Vec3<f64>> = (0..=4).map(|k| w.map(&1.0, &(k as f64 / 4.0))).collect();
    let c = parts
        .arcs
        .iter()
        .find(|a| a.a.z == 0.0 && a.b.z > 0.0)
        .expect("the edge coming up through the horizon")
        .a;
    let v0 = v[0].normalized().unwrap();
    dirs.push(c.add(&v0).add(&dirs[0]).normalized().unwrap());
    for d in &dirs {
        // On the polygon at 256 bits, and so in f64 (4u: the radial
        // term and the normalization of d), not refused by the inverse,
        // and not given density 0 as off the shape.
        assert_on_polygon(&w, &exact, d, "sliver");
        assert_eq!(w.pdf(d), w.pdf_unchecked(d), "{d:?}");
    }
}
