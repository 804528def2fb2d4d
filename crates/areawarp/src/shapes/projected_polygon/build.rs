//! Preprocessing: validation and orientation of the polygon, clipping
//! against the receiver's horizon, and the partition into lunes.

use super::coincident::distinct;
use super::geometry::{scaled_unit, unit_direction};
use super::lune::{Lune, LuneCdf, LuneEdge, Pair, Side, SideFit, sin_cos_between};
use super::ranges::ArcEnd;
use crate::error::WarpError;
use crate::real::Real;
use crate::recipe::{Inverter, Newton};
use crate::shapes::polygon_measures::{
    edge_cross, oriented_solid_angle_with_turning, rough_angle, turning_from_normals,
};
use crate::shapes::turns::atan2_by_atan;
use crate::vector::Vec3;

/// [`WarpError::Degenerate`] with the reason `what`.
pub(super) fn degenerate(what: &'static str) -> WarpError {
    WarpError::Degenerate { what }
}

/// `(i + 1) mod n` for `i < n`, without a division.
#[inline]
pub(super) fn next(i: usize, n: usize) -> usize {
    if i + 1 < n { i + 1 } else { 0 }
}

/// `(i − 1) mod n` for `i < n`, without a division.
#[inline]
pub(super) fn prev(i: usize, n: usize) -> usize {
    if i > 0 { i - 1 } else { n - 1 }
}

/// `(b − a) mod n` for `a, b < n`, without a division.
#[inline]
fn steps(a: usize, b: usize, n: usize) -> usize {
    if b >= a { b - a } else { b + n - a }
}

/// A directed minor great arc `a → b` of the clipped boundary, with the
/// unit normal `n` of its great circle oriented as `a × b` (the polygon
/// lies on the side `n · p > 0` next to it).
#[derive(Clone, Debug)]
pub(super) struct Arc<T> {
    /// Start.
    pub a: Vec3<T>,
    /// End.
    pub b: Vec3<T>,
    /// Unit normal of the great circle.
    pub n: Vec3<T>,
}

/// The clipped boundary and its partition into lunes: what `new`
/// precomputes besides Π.
#[derive(Clone, Debug)]
pub(super) struct Parts<T> {
    pub arcs: Vec<Arc<T>>,
    pub lunes: Vec<Lune<T>>,
    pub edges: Vec<LuneEdge<T>>,
    pub pairs: Vec<Pair<T>>,
}

/// Sets each lune's cumulative areas before and after it and its index
/// among the lunes of positive area (those that are sampled); returns the
/// total, Π.
pub(super) fn accumulate<T: Real>(lunes: &mut [Lune<T>]) -> T {
    let zero = T::zero();
    let mut measure = T::zero();
    let mut active = 0;
    for lune in lunes.iter_mut() {
        lune.cum_start = measure.clone();
        if lune.area > zero {
            measure += &lune.area;
            lune.active = Some(active);
            active += 1;
        }
    }
    let mut after = T::zero();
    for lune in lunes.iter_mut().rev() {
        lune.cum_after = after.clone();
        after += &lune.area;
    }
    measure
}

/// The rough (≤ 2·10⁻⁵ per vertex) sum of the turning angles at the unit
/// vertices `v`, which fixes the multiple of 4π of the solid angle
/// (Gauss–Bonnet); an error where the boundary turns by ±π at a vertex
/// (the two sides are then undefined).
fn rough_turning<T: Real>(v: &[Vec3<T>]) -> Result<f64, WarpError> {
    let n = v.len();
    let fold = T::from_i64(64) * &T::unit_roundoff();
    let mut turning = 0.0f64;
    // Each edge's normal once: the edge out of a vertex is the edge into
    // the next (the same operations as `turning_parts`, the same bits).
    let mut n1 = edge_cross(&v[n - 1], &v[0]);
    for i in 0..n {
        let n2 = edge_cross(&v[i], &v[next(i, n)]);
        let (det, cos_part) = turning_from_normals(&n1, &n2, &v[i]);
        n1 = n2;
        if cos_part < T::zero() && det.abs() <= fold.clone() * &cos_part.abs() {
            return Err(degenerate(
                "the polygon folds straight back on itself at a vertex",
            ));
        }
        turning += rough_angle(&det, &cos_part);
    }
    Ok(turning)
}

/// Validates the vertices, normalizes them and orients the polygon so that
/// the smaller of the two regions its boundary bounds lies to the left
/// (`(v_i × v_{i+1}) · p > 0` inside). Returns the vertices and the solid
/// angle of that region if it was computed: the accurate solid angle (a
/// fan of `atan2`s) is needed only where the rough Gauss–Bonnet sum of the
/// turning angles (error ≤ 2·10⁻⁵ per vertex) cannot tell the orientation
/// or the validity, i.e. within a margin of 0, 2π or 4π;
/// [`ProjectedPolygon::solid_angle`](super::ProjectedPolygon::solid_angle)
/// computes it on demand otherwise (`geometry::source_solid_angle`).
/// The vertices come as an iterator (the constructor widens them on the
/// way, without a copy of its own); a vertex coinciding with its
/// predecessor is dropped (`coincident.rs`: `close` and `same` as in
/// [`distinct`]).
pub(super) fn prepare<T: Real>(
    vertices: impl ExactSizeIterator<Item = Vec3<T>>,
    close: &T,
    same: impl Fn(usize, usize) -> bool,
) -> Result<(Vec<Vec3<T>>, Option<T>), WarpError> {
    let n = vertices.len();
    if n < 3 {
        return Err(degenerate("a polygon needs at least 3 vertices"));
    }
    let mut v = Vec::with_capacity(n);
    for p in vertices {
        v.push(unit_direction(&p, "polygon vertex")?);
    }
    // Repeated vertices dropped, antipodal consecutive ones rejected.
    let mut v = distinct(v, close, same)?;
    let n = v.len();
    let u = T::unit_roundoff();
    let turning = rough_turning(&v)?;
    // The rough solid angle 2π − Σ τ is off by at most 2·10⁻⁵ per vertex;
    // 10⁻⁴ per vertex leaves it a margin of 5.
    let rough = 2.0 * core::f64::consts::PI - turning;
    let margin = 1e-4 * n as f64;
    let tau = 2.0 * core::f64::consts::PI;
    if rough > margin && rough < tau - margin {
        return Ok((v, None));
    }
    if rough > tau + margin && rough < 2.0 * tau - margin {
        v.reverse();
        return Ok((v, None));
    }
    let two_pi = T::pi() * &T::from_i64(2);
    let four_pi = two_pi.clone() * &T::from_i64(2);
    let omega = oriented_solid_angle_with_turning(&v, turning);
    let slack = T::from_i64(16 * n as i64) * &u * &two_pi;
    if !(omega > T::zero() && omega < four_pi) {
        return Err(degenerate("the polygon has zero solid angle"));
    }
    if (omega.clone() - &two_pi).abs() <= slack {
        return Err(degenerate(
            "the polygon bounds two regions of solid angle 2π: its interior is ambiguous",
        ));
    }
    if omega > two_pi {
        v.reverse();
        Ok((v, Some(four_pi - &omega)))
    } else {
        Ok((v, Some(omega)))
    }
}

/// The point where the great arc `a → b` crosses the horizon `z = 0`
/// (`a.z` and `b.z` of opposite signs): `|a.z| b + |b.z| a`, normalized;
/// its `z` is exactly 0.
fn horizon_crossing<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    let p = b.scale(&a.z).sub(&a.scale(&b.z));
    let p = if a.z < T::zero() { p.neg() } else { p };
    let p = Vec3::new(p.x, p.y, T::zero());
    scaled_unit(&p).unwrap_or_else(|| a.clone())
}

/// `a × b` for unit vectors, computed as `a × (b ∓ a)`: for nearly
/// coincident (or nearly antipodal) `a` and `b` the difference (sum) is
/// exact, and the product keeps its relative accuracy where the plain
/// cross product of two nearly parallel vectors loses it all (a normal
/// wrong by ~u/|a − b|, enough to flip an edge between inner and outer).
pub(super) fn edge_normal<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    if a.dot(b) >= T::zero() {
        a.cross(&b.sub(a))
    } else {
        a.cross(&b.add(a))
    }
}

/// Clips the oriented polygon against the horizon `z ≥ 0`: the parts of
/// its edges above the horizon, plus arcs of the horizon from each point
/// where the boundary goes below to the next point (counter-clockwise, the
/// direction that keeps the region on the left) where it comes back.
/// Horizon arcs are split into pieces of at most a quarter turn.
/// The vertices `v` come in any type `W`, converted by `conv` on the way
/// (the wide vertices of [`prepare`], without a converted copy).
pub(super) fn clip<W, T: Real>(
    v: &[Vec3<W>],
    conv: impl Fn(&Vec3<W>) -> Vec3<T>,
) -> Result<Vec<Arc<T>>, WarpError> {
    let n = v.len();
    let zero = T::zero();
    let mut arcs = Vec::with_capacity(n + 4);
    let mut exits: Vec<Vec3<T>> = Vec::new();
    let mut entries: Vec<Vec3<T>> = Vec::new();
    let mut b = conv(&v[0]);
    for i in 0..n {
        let a = b;
        b = conv(&v[next(i, n)]);
        let (a, b) = (&a, &b);
        let normal = match scaled_unit(&edge_normal(a, b)) {
            Some(m) => m,
            None => return Err(degenerate("coincident consecutive vertices")),
        };
        let arc = |p: &Vec3<T>, q: &Vec3<T>| Arc {
            a: p.clone(),
            b: q.clone(),
            n: normal.clone(),
        };
        let (a_below, b_below) = (a.z < zero, b.z < zero);
        match (a_below, b_below) {
            (true, true) => {}
            (false, false) => arcs.push(arc(a, b)),
            (false, true) => {
                if a.z > zero {
                    let c = horizon_crossing(a, b);
                    arcs.push(arc(a, &c));
                    exits.push(c);
                } else {
                    exits.push(a.clone());
                }
            }
            (true, false) => {
                if b.z > zero {
                    let c = horizon_crossing(a, b);
                    arcs.push(arc(&c, b));
                    entries.push(c);
                } else {
                    entries.push(b.clone());
                }
            }
        }
    }
    if exits.len() != entries.len() {
        return Err(degenerate("inconsistent horizon crossings"));
    }
    // Pair each exit with the next entry counter-clockwise.
    let two_pi = T::pi() * &T::from_i64(2);
    let quarter = T::pi() / &T::from_i64(2);
    let mut used = vec![false; entries.len()];
    for e in &exits {
        let mut best: Option<(usize, T)> = None;
        for (j, x) in entries.iter().enumerate() {
            let cross = e.x.clone() * &x.y - &(e.y.clone() * &x.x);
            let dot = e.x.clone() * &x.x + &(e.y.clone() * &x.y);
            let mut ang = cross.atan2(&dot);
            if ang < zero {
                ang += &two_pi;
            }
            if best.as_ref().is_none_or(|(_, b)| ang < *b) {
                best = Some((j, ang));
            }
        }
        let Some((j, ang)) = best else {
            return Err(degenerate("inconsistent horizon crossings"));
        };
        if used[j] {
            return Err(degenerate(
                "self-intersecting polygon (its horizon crossings do not pair up)",
            ));
        }
        used[j] = true;
        if ang == zero {
            continue;
        }
        // ⌈ang / (π/2)⌉ pieces, each at most a quarter turn.
        let mut pieces = 1;
        while pieces < 4 && ang > quarter.clone() * &T::from_i64(pieces) {
            pieces += 1;
        }
        let up = Vec3::new(zero.clone(), zero.clone(), T::one());
        let mut prev = e.clone();
        for k in 1..=pieces {
            let next = if k == pieces {
                entries[j].clone()
            } else {
                let t = ang.clone() * &T::from_ratio(k, pieces);
                let (s, c) = t.sin_cos();
                Vec3::new(
                    e.x.clone() * &c - &(e.y.clone() * &s),
                    e.x.clone() * &s + &(e.y.clone() * &c),
                    zero.clone(),
                )
            };
            arcs.push(Arc {
                a: prev,
                b: next.clone(),
                n: up.clone(),
            });
            prev = next;
        }
    }
    if arcs.is_empty() {
        return Err(degenerate(
            "the polygon lies below the receiver's horizon (zero projected solid angle)",
        ));
    }
    Ok(arcs)
}

/// An arc of the clipped boundary that sweeps azimuth, as the partition
/// uses it.
struct UsableArc<'a, T> {
    arc: &'a Arc<T>,
    /// Azimuths of its start and end.
    az: (T, T),
    /// (cos, sin) of the azimuths of its start and end.
    cs: [(T, T); 2],
    /// Indices of the (merged) meridians of its start and end.
    ends: (usize, usize),
    /// r = √(x² + y²) of its start and end ([`meridian`]; 0 next to the
    /// pole).
    r: [T; 2],
    /// Whether the map takes the edge's g at its start and end from the
    /// point ([`vertex_g`]): where g summed from the normal is
    /// ill-conditioned there ([`g_is_ill_conditioned`]) and the end's
    /// meridian is at the point's own azimuth (a point merged into a
    /// neighbour's meridian lies beside it).
    g_from_end: [bool; 2],
    /// Its index among the clipped arcs.
    index: usize,
    /// The lunes it crosses: `count` lunes from number `first` on,
    /// cyclically (`(first, count)`; count 0 for none).
    span: (usize, usize),
}

/// The azimuth of the point `p` (off the pole), its (cos, sin), the
/// latter from `p` itself: a square root, not a `sin_cos` of the rounded
/// angle (the fallback for a point within 10⁻⁶⁴-ish of the pole, where
/// x² + y² could underflow), and there r = √(x² + y²) (0 in the fallback),
/// from which an edge ending at `p` may take its g ([`vertex_g`]).
fn meridian<T: Real>(p: &Vec3<T>) -> (T, (T, T), T) {
    let az = atan2_by_atan(&p.y, &p.x);
    let r2 = p.x.square() + &p.y.square();
    if r2 > T::unit_roundoff().powi(8) {
        let r = r2.sqrt();
        (az, (p.x.clone() / &r, p.y.clone() / &r), r)
    } else {
        let (s, c) = az.sin_cos();
        (az, (c, s), T::zero())
    }
}

/// Whether the edge with normal z-component `nz` places its point at its
/// end point `(z, r)` (unit, `r = √(x² + y²)`) with a relative error above
/// 16u in r² or in z² when g is summed from the normal: that sum
/// `g₀ = n_x cos φ + n_y sin φ` has an absolute error of about u, and with
/// `|g| = |n_z z|/r` there it moves `r² = n_z²/(n_z² + g²)` by about
/// `2u|z| r/|n_z|` and `z² = g²/(n_z² + g²)` by about `2u r³/(|n_z z|)`,
/// relative. So `8|n_z| < |z| r` (an edge nearly along a meridian) or
/// `8|n_z z| < r³` (also a point next to the horizon, where z² carries the
/// position). `false` at `r = 0` (the pole: no g from the point).
fn g_is_ill_conditioned<T: Real>(nz: &T, z: &T, r: &T) -> bool {
    let eight_nz = nz.abs() * &T::from_i64(8);
    let abs_z = z.abs();
    *r > T::zero() && (eight_nz < abs_z.clone() * r || eight_nz * &abs_z < r.square() * r)
}

/// g at the end point V of the arc `ua` that lies on the meridian number
/// `meridian`, taken from V: `−n_z z/r` (`n ⊥ V`, `r = √(x² + y²)`), with
/// which the edge's point there is V whatever the error of n_z
/// (`r² = n_z²/(n_z² + n_z² z²/r²) = r²_V`, and z² alike). `None` where no
/// end of the arc lies on the meridian and where the map keeps the edge's
/// own sum g₀ there ([`UsableArc::g_from_end`]). Derivation:
/// `docs/projected-polygon.md` (Numerics).
fn vertex_g<T: Real>(ua: &UsableArc<'_, T>, meridian: usize) -> Option<T> {
    let (end, v) = if ua.ends.0 == meridian {
        (0, &ua.arc.a)
    } else if ua.ends.1 == meridian {
        (1, &ua.arc.b)
    } else {
        return None;
    };
    ua.g_from_end[end].then(|| -(ua.arc.n.z.clone() * &v.z) / &ua.r[end])
}

/// `true` if `p` is the pole (no azimuth).
fn at_pole<T: Real>(p: &Vec3<T>) -> bool {
    p.x == T::zero() && p.y == T::zero()
}

/// Partitions the clipped polygon into lunes, computes the per-edge
/// constants, sorts each lune's edges outwards from the pole, checks the
/// structure, and sums Π (returned with the parts).
pub(super) fn partition<T: Real>(arcs: Vec<Arc<T>>) -> Result<(Parts<T>, T), WarpError> {
    let zero = T::zero();
    let u = T::unit_roundoff();
    let two_pi = T::pi() * &T::from_i64(2);
    // Arcs along meridians (n_z = 0, including those through the pole)
    // sweep no azimuth and bound no projected area. The others, with the
    // azimuths of their ends (once per point: an arc that starts where the
    // previous one ends, cyclically, reuses its azimuth), in one vector
    // (a single allocation; the meridian indices of the ends are filled in
    // below).
    let mut usable: Vec<UsableArc<'_, T>> = Vec::with_capacity(arcs.len());
    for (index, a) in arcs
        .iter()
        .enumerate()
        .filter(|(_, a)| a.n.z != zero && !at_pole(&a.a) && !at_pole(&a.b))
    {
        let (az_b, cs_b, r_b) = meridian(&a.b);
        usable.push(UsableArc {
            arc: a,
            az: (T::zero(), az_b),
            cs: [(T::zero(), T::zero()), cs_b],
            ends: (0, 0),
            r: [T::zero(), r_b],
            g_from_end: [false, false],
            index,
            span: (0, 0),
        });
    }
    let nu = usable.len();
    for i in 0..nu {
        let prev = prev(i, nu);
        let (az_a, cs_a, r_a) = if usable[prev].arc.b == usable[i].arc.a {
            (
                usable[prev].az.1.clone(),
                usable[prev].cs[1].clone(),
                usable[prev].r[1].clone(),
            )
        } else {
            meridian(&usable[i].arc.a)
        };
        let a = &mut usable[i];
        a.az.0 = az_a;
        a.cs[0] = cs_a;
        a.r[0] = r_a;
        a.g_from_end = [
            g_is_ill_conditioned(&a.arc.n.z, &a.arc.a.z, &a.r[0]),
            g_is_ill_conditioned(&a.arc.n.z, &a.arc.b.z, &a.r[1]),
        ];
    }
    // Vertex meridians. Azimuths within rounding of each other (an edge
    // lying along a meridian, computed with n_z a few units of roundoff off
    // zero) are one meridian: no lune thinner than `merge` is formed, so the
    // partition does not depend on the rounding of such edges. Each merged
    // meridian is the least azimuth of its cluster.
    // (azimuth, cos, sin) of each meridian.
    // An end that the next arc starts from shares its azimuth (the same
    // bits, pushed next): only the start is pushed, which leaves the
    // merged meridians as they are.
    let mut bounds: Vec<(T, T, T)> = Vec::with_capacity(2 * nu);
    for (i, a) in usable.iter().enumerate() {
        bounds.push((a.az.0.clone(), a.cs[0].0.clone(), a.cs[0].1.clone()));
        if usable[next(i, nu)].arc.a != a.arc.b {
            bounds.push((a.az.1.clone(), a.cs[1].0.clone(), a.cs[1].1.clone()));
        }
    }
    bounds.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap_or(core::cmp::Ordering::Equal));
    let merge = T::from_i64(16) * &u * &T::pi();
    let mut last: Option<T> = None;
    bounds.retain(|(x, _, _)| {
        let keep = last.as_ref().is_none_or(|b| x.clone() - b > merge);
        if keep {
            last = Some(x.clone());
        }
        keep
    });
    let mut m = bounds.len();
    // Across the branch cut of atan2 the last meridian may be the first:
    // azimuths from `wrap` on then belong to meridian 0.
    let mut wrap: Option<T> = None;
    if m >= 2 && bounds[0].0.clone() + &two_pi - &bounds[m - 1].0 <= merge {
        wrap = bounds.pop().map(|b| b.0);
        m -= 1;
    }
    if m < 2 {
        return Err(degenerate("zero projected solid angle"));
    }
    // The meridian of an end's azimuth `x` (one of the sorted azimuths):
    // the last merged meridian at or before it.
    let index = |x: &T| -> usize {
        if wrap.as_ref().is_some_and(|w| x >= w) {
            return 0;
        }
        // `partition_point(b ≤ x).max(1) − 1`; for a few meridians by a
        // linear scan (the convex quad's eight ends: 56 instructions fewer
        // than the binary search, `docs/projected-polygon-cost.md`).
        if m <= 8 {
            let mut i = 0;
            while i + 1 < m && bounds[i + 1].0 <= *x {
                i += 1;
            }
            i
        } else {
            bounds.partition_point(|b| b.0 <= *x).max(1) - 1
        }
    };
    for a in usable.iter_mut() {
        a.ends = (index(&a.az.0), index(&a.az.1));
        // g from the end point only at its own meridian (tested only for
        // the rare ill-conditioned end).
        if a.g_from_end[0] {
            a.g_from_end[0] = a.az.0 == bounds[a.ends.0].0;
        }
        if a.g_from_end[1] {
            a.g_from_end[1] = a.az.1 == bounds[a.ends.1].0;
        }
    }
    let width = |k: usize| -> T {
        if k + 1 < m {
            bounds[k + 1].0.clone() - &bounds[k].0
        } else {
            bounds[0].0.clone() + &two_pi - &bounds[m - 1].0
        }
    };
    let slack = T::exp2i(-((T::precision() / 2) as i32));
    // The lunes each arc crosses (no list of (lune, arc) pairs to sort:
    // each lune takes its arcs in boundary order from the spans).
    let mut crossings = 0;
    for ua in usable.iter_mut() {
        let (ia, ib) = ua.ends;
        if ia == ib {
            continue;
        }
        let a = ua.arc;
        let (first, last) = if a.n.z > zero { (ia, ib) } else { (ib, ia) };
        let mut sweep = T::zero();
        let mut k = first;
        while k != last {
            sweep += &width(k);
            k = next(k, m);
        }
        if sweep > T::pi() + &slack {
            if a.n.z.abs() <= slack {
                // An edge through the pole within rounding: no area.
                continue;
            }
            return Err(degenerate(
                "an edge sweeps more than half a turn of azimuth",
            ));
        }
        let count = steps(first, last, m);
        ua.span = (first, count);
        crossings += count;
    }

    let half = T::from_ratio(1, 2);
    let end_of = |k: usize| -> T {
        if k + 1 < m {
            bounds[k + 1].0.clone()
        } else {
            bounds[0].0.clone() + &two_pi
        }
    };
    // Do arcs `i` and `j` share an endpoint on meridian number `k`?
    let share_at = |i: usize, j: usize, k: usize| -> bool {
        let (p, q, ends) = (usable[i].arc, usable[j].arc, usable[i].ends);
        (ends.0 == k && (p.a == q.a || p.a == q.b)) || (ends.1 == k && (p.b == q.a || p.b == q.b))
    };
    let mut lunes = Vec::with_capacity(m);
    let mut edges: Vec<LuneEdge<T>> = Vec::with_capacity(crossings);
    let mut pairs: Vec<Pair<T>> = Vec::with_capacity(crossings);
    let mut magnitude = T::zero();
    // The arc of each of the current lune's edges (on the stack for up to
    // 16 arcs).
    let mut arc_stack = [0usize; 16];
    let mut arc_heap = Vec::new();
    let arc_of: &mut [usize] = if nu <= arc_stack.len() {
        &mut arc_stack
    } else {
        arc_heap.resize(nu, 0);
        &mut arc_heap
    };
    for (k, (start, cos_a, sin_a)) in bounds.iter().enumerate() {
        let (start, cos_a, sin_a) = (start.clone(), cos_a.clone(), sin_a.clone());
        let end_az = end_of(k);
        let w = width(k);
        // The last lune ends one turn after the first meridian.
        let (_, cos_b, sin_b) = bounds[next(k, m)].clone();
        // The lune's edges, in boundary order, written in place.
        let first_edge = edges.len();
        let mut ne = 0;
        for (ai, ua) in usable.iter().enumerate() {
            let (f, count) = ua.span;
            if steps(f, k, m) < count {
                let n = &ua.arc.n;
                arc_of[ne] = ai;
                ne += 1;
                // The arc's own end points on the lune's meridians (its
                // range in the lune, computed on first use: `ranges.rs`).
                let end_on = |meridian: usize| {
                    if ua.ends.0 == meridian {
                        ArcEnd::Start
                    } else if ua.ends.1 == meridian {
                        ArcEnd::End
                    } else {
                        ArcEnd::Neither
                    }
                };
                edges.push(LuneEdge::new(
                    [&n.x, &n.y, &n.z],
                    (&cos_a, &sin_a),
                    (&cos_b, &sin_b),
                    ua.index,
                    [end_on(k), end_on(next(k, m))],
                ));
                // Where the arc ends on a side's own meridian, the map's
                // g there from the end point (`vertex_g`).
                if ua.g_from_end[0] || ua.g_from_end[1] {
                    let last = edges.len() - 1;
                    for (si, meridian) in [(0, k), (1, next(k, m))] {
                        if let Some(g) = vertex_g(ua, meridian) {
                            edges[last].side[si].gv = g;
                        }
                    }
                }
            }
        }
        let arc_of = &mut arc_of[..ne];
        let lune_edges = &mut edges[first_edge..];
        // (sin Δ, cos Δ) from the two meridians (no library call): the
        // area below, and the middle meridian by the half-angle formulas
        // (each from the side without cancellation).
        let (s1, c1) = sin_cos_between((&cos_a, &sin_a), (&cos_b, &sin_b));
        // Sort outwards at the middle meridian; check the order at the ends.
        let (sm, cm) = if lune_edges.len() < 2 {
            (zero.clone(), T::one())
        } else if c1 >= zero {
            let cm = ((T::one() + &c1) * &half).sqrt();
            (s1.clone() / &(cm.clone() * &T::from_i64(2)), cm)
        } else {
            let sm = ((T::one() - &c1) * &half).sqrt();
            (sm.clone(), s1.clone() / &(sm * &T::from_i64(2)))
        };
        // Edge p lies nearer the pole than q at the middle meridian when
        // cot θ_p > cot θ_q, cot θ = −g/n_z: the sign of
        // D = n_z,p g_q − n_z,q g_p = A cos x + B sin x times that of
        // n_z,p n_z,q. Where p and q meet on a bounding meridian, A is 0
        // there (exactly: the sign is B's, however thin the lune), and
        // cot θ keeps its relative accuracy near the horizon, where r²
        // rounds to 1 (a comparison of r² would tie).
        // D at the middle meridian, and (if `bound`) a bound on its
        // rounding error (else 0).
        // (Edges come as (arc index, edge).)
        let separation =
            |p: (usize, &LuneEdge<T>), q: (usize, &LuneEdge<T>), bound: bool| -> (T, T) {
                let (si, a_zero) = if share_at(p.0, q.0, k) {
                    (0, true)
                } else if share_at(p.0, q.0, next(k, m)) {
                    (1, true)
                } else {
                    (0, false)
                };
                let (ps, qs) = (&p.1.side[si], &q.1.side[si]);
                let (b1, b2) = (p.1.nz.clone() * &qs.k0, q.1.nz.clone() * &ps.k0);
                let mut err = T::zero();
                if bound {
                    err = (b1.abs() + &b2.abs()) * &sm;
                }
                let mut d = (b1 - &b2) * &sm;
                if !a_zero {
                    let (a1, a2) = (p.1.nz.clone() * &qs.g0, q.1.nz.clone() * &ps.g0);
                    if bound {
                        err += &((a1.abs() + &a2.abs()) * &cm.abs());
                    }
                    d += &((a1 - &a2) * &cm);
                }
                (d, err * &T::from_i64(8) * &u)
            };
        let nearer_pole = |p: (usize, &LuneEdge<T>), q: (usize, &LuneEdge<T>)| -> bool {
            let d = separation(p, q, false).0;
            let flip = (p.1.nz < zero) != (q.1.nz < zero);
            if flip { d < zero } else { d > zero }
        };
        // Insertion sort (stable, a handful of edges per lune, no
        // allocation, and no total order demanded of a rounded comparison).
        for i in 1..lune_edges.len() {
            let mut j = i;
            while j > 0
                && nearer_pole(
                    (arc_of[j], &lune_edges[j]),
                    (arc_of[j - 1], &lune_edges[j - 1]),
                )
            {
                lune_edges.swap(j, j - 1);
                arc_of.swap(j, j - 1);
                j -= 1;
            }
        }
        for side in [Side::Start, Side::End] {
            for pair in lune_edges.windows(2) {
                let (r0, r1) = (
                    pair[0].r2(side, &T::one(), &zero),
                    pair[1].r2(side, &T::one(), &zero),
                );
                if r1 < r0 - &slack {
                    return Err(degenerate("self-intersecting polygon (edges cross)"));
                }
            }
        }
        // Boundaries alternate inner/outer and the outermost is outer.
        let is_outer = |e: &LuneEdge<T>| e.nz > zero;
        if let Some(last) = lune_edges.last()
            && (!is_outer(last)
                || lune_edges
                    .windows(2)
                    .any(|p| is_outer(&p[0]) == is_outer(&p[1])))
        {
            // Two edges whose order on the meridian is within rounding
            // (a polygon narrower than the rounding of its vertices, whose
            // interior is not resolved): no projected area, not a crossing.
            if (1..lune_edges.len()).any(|j| {
                let (d, err) = separation(
                    (arc_of[j - 1], &lune_edges[j - 1]),
                    (arc_of[j], &lune_edges[j]),
                    true,
                );
                d.abs() <= err
            }) {
                return Err(degenerate(
                    "zero projected solid angle (two edges coincide within rounding)",
                ));
            }
            return Err(degenerate(
                "self-intersecting polygon (inconsistent edge orientation)",
            ));
        }
        let pole_inside = lune_edges.first().is_some_and(is_outer);
        let first_pair = pairs.len();
        let mut j = 0;
        while j < lune_edges.len() {
            let (inner, outer_j) = if j == 0 && pole_inside {
                (None, 0)
            } else {
                (Some(j), j + 1)
            };
            let o = &lune_edges[outer_j];
            let mut d = [(zero.clone(), zero.clone()), (zero.clone(), zero.clone())];
            let mut shared = [false, false];
            let mut r0 = [zero.clone(), zero.clone()];
            if let Some(i) = inner {
                let e = &lune_edges[i];
                for (si, meridian) in [(0usize, k), (1, next(k, m))] {
                    let (os, es) = (&o.side[si], &e.side[si]);
                    let a = o.nz.clone() * &es.g0 - &(e.nz.clone() * &os.g0);
                    let b = o.nz.clone() * &es.k0 - &(e.nz.clone() * &os.k0);
                    shared[si] = share_at(arc_of[i], arc_of[outer_j], meridian);
                    d[si] = (if shared[si] { zero.clone() } else { a }, b);
                    if shared[si] {
                        // r at the shared vertex (on the side's meridian).
                        r0[si] = o.abs_nz.clone() / &(o.nz2.clone() + &os.g0.square()).sqrt();
                    }
                }
            }
            pairs.push(Pair {
                inner: inner.map(|i| first_edge + i),
                outer: first_edge + outer_j,
                d,
                shared,
                r0,
                range: std::sync::OnceLock::new(),
            });
            j = outer_j + 1;
        }
        let n_edges = lune_edges.len();
        // Written in place: the lune is large, a copy into the vector costs
        // more than its sums.
        lunes.push(Lune {
            start,
            end_az,
            width: w.clone(),
            cs_a: (cos_a, sin_a),
            cs_b: (cos_b, sin_b),
            width_sc: (s1.clone(), c1.clone()),
            two_area_start: zero.clone(),
            two_area_end: std::sync::OnceLock::new(),
            area: zero.clone(),
            cum_start: zero.clone(),
            cum_after: zero.clone(),
            first: first_pair,
            end: pairs.len(),
            n_edges,
            active: None,
        });
        if n_edges > 0 {
            let lune = lunes.last_mut().expect("pushed above");
            // From the start only: the end's sum (the same area) is
            // computed when a sample first needs it (`Lune::two_area`).
            lune.two_area_start = lune.swept(&edges, &pairs, Side::Start, &c1, &s1).max(&zero);
            for e in &edges[first_edge..] {
                // The size of the Lambert terms, for the rounding-level test.
                magnitude += &(e.abs_nz.clone() * &w);
            }
            if lune.two_area_start > zero {
                lune.area = lune.two_area_start.clone() * &half;
            }
        }
    }
    // Projected area by lune; lunes of zero area are never sampled.
    let measure = accumulate(&mut lunes);
    if !(measure > T::from_i64(64) * &u * &magnitude) || !measure.is_finite() {
        return Err(degenerate(
            "projected solid angle not resolved at this precision: below 64 units of \
             roundoff of its Lambert sum (a polygon on or below the horizon, or a needle or \
             sliver too thin for the type's unit vectors)",
        ));
    }
    Ok((
        Parts {
            arcs,
            lunes,
            edges,
            pairs,
        },
        measure,
    ))
}

/// The fitted inverse marginal of one lune, from its start and its end:
/// split where F = 1/2 (each side inverts its own half), then a cubic per
/// side. Some twenty evaluations of F per lune: the polygon computes it
/// lazily, the first time a sample falls in the lune.
pub(super) fn fit_lune<T: Real>(
    lune: &Lune<T>,
    edges: &[LuneEdge<T>],
    pairs: &[Pair<T>],
) -> [SideFit<T>; 2] {
    let cdf = |side| LuneCdf {
        lune,
        edges,
        pairs,
        side,
    };
    let xh = Newton::default()
        .invert(&cdf(Side::Start), &T::from_ratio(1, 2))
        .x;
    let xh_end = lune.width.clone() - &xh;
    [
        SideFit::new(cdf(Side::Start), xh),
        SideFit::new(cdf(Side::End), xh_end),
    ]
}
