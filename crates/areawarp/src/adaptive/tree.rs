//! The subdivision tree's nodes and the helpers that walk it.

use super::*;
// ---------------------------------------------------------------------------
// The subdivision tree.

/// One spherical triangle of the subdivision. Only its vertices and σ⊥
/// (needed to share samples among siblings) are computed when it is
/// created; σ, m, k (needed once samples reach it), its solid-angle sampler
/// (once it is a leaf with samples) and its children (memoized near the
/// root) are computed on first use.
#[derive(Clone, Debug)]
pub(super) struct Node {
    /// Unit vertices.
    pub(super) v: [Vec3<f64>; 3],
    pub(super) sigma_perp: f64,
    pub(super) depth: u32,
    /// `root · 4^depth + Σ digit · 4^…` (see [`Piece::code`]).
    pub(super) code: u64,
    pub(super) measures: OnceLock<TriangleMeasures<f64>>,
    pub(super) sampler: OnceLock<Option<SphericalTriangle<f64>>>,
    pub(super) children: OnceLock<Option<Box<[Node; 4]>>>,
}

impl Node {
    /// The node with unit vertices `v`, if it is not degenerate in `f64`
    /// (see [`robust_solid_angle`]).
    pub(super) fn new(v: [Vec3<f64>; 3], depth: u32, code: u64) -> Option<Self> {
        let (sigma, ok) = robust_solid_angle(&v[0], &v[1], &v[2]);
        if !ok || v.iter().any(|p| !(p.z >= 0.0)) {
            return None;
        }
        let sigma_perp = lambert(&v[0], &v[1], &v[2]);
        let measures = OnceLock::new();
        // Roots compute everything at once; children lazily.
        if depth == 0 {
            let _ = measures.set(TriangleMeasures::with_solid_angle(
                &v[0], &v[1], &v[2], sigma,
            ));
        }
        Some(Node {
            v,
            sigma_perp,
            depth,
            code,
            measures,
            sampler: OnceLock::new(),
            children: OnceLock::new(),
        })
    }

    pub(super) fn measures(&self) -> &TriangleMeasures<f64> {
        self.measures.get_or_init(|| {
            let [a, b, c] = &self.v;
            let (sigma, _) = robust_solid_angle(a, b, c);
            TriangleMeasures::with_solid_angle(a, b, c, sigma)
        })
    }

    /// Arvo's map for this triangle (`None` only if [`SphericalTriangle::new`]
    /// rejected a triangle [`Node::new`] accepted, which its margin rules out).
    pub(super) fn sampler(&self) -> Option<&SphericalTriangle<f64>> {
        self.sampler
            .get_or_init(|| {
                let [a, b, c] = &self.v;
                SphericalTriangle::new(*a, *b, *c).ok()
            })
            .as_ref()
    }

    /// The four children at the normalized edge midpoints (Fig. 2): the
    /// corners at the first, second and third vertex, then the middle
    /// triangle; `None` if a child is degenerate in `f64`.
    pub(super) fn split(&self) -> Option<Box<[Node; 4]>> {
        let [a, b, c] = &self.v;
        let mab = a.add(b).normalized()?;
        let mbc = b.add(c).normalized()?;
        let mca = c.add(a).normalized()?;
        let d = self.depth + 1;
        let code = self.code * 4;
        Some(Box::new([
            Node::new([*a, mab, mca], d, code)?,
            Node::new([mab, *b, mbc], d, code + 1)?,
            Node::new([mca, mbc, *c], d, code + 2)?,
            Node::new([mab, mbc, mca], d, code + 3)?,
        ]))
    }
}

/// The shares `σ⊥(D_i)/Σ_j σ⊥(D_j)` of `nodes` (by solid angle if all
/// σ⊥ vanish).
pub(super) fn shares(nodes: &[Node], out: &mut [f64]) {
    let total: f64 = nodes.iter().map(|d| d.sigma_perp).sum();
    if total > 0.0 && total.is_finite() {
        for (o, d) in out.iter_mut().zip(nodes) {
            *o = d.sigma_perp / total;
        }
    } else {
        let total: f64 = nodes.iter().map(|d| d.measures().solid_angle).sum();
        for (o, d) in out.iter_mut().zip(nodes) {
            *o = d.measures().solid_angle / total;
        }
    }
}

/// The children of a node, memoized or freshly computed.
pub(super) enum Kids<'a> {
    Leaf,
    Memo(&'a [Node; 4]),
    Fresh(Box<[Node; 4]>),
}

impl Kids<'_> {
    pub(super) fn as_ref(&self) -> Option<&[Node; 4]> {
        match self {
            Kids::Leaf => None,
            Kids::Memo(k) => Some(k),
            Kids::Fresh(k) => Some(k),
        }
    }
}

/// `det(e1, e2, p) = p · (e1 × e2)`: the side of the great circle through
/// `e1`, `e2` that `p` is on.
pub(super) fn side(e1: &Vec3<f64>, e2: &Vec3<f64>, p: &Vec3<f64>) -> f64 {
    p.dot(&e1.cross(e2))
}

/// `true` if the unit direction `d` is in the spherical triangle of `node`
/// (boundary included), by the signs of the three edge determinants.
pub(super) fn inside(node: &Node, d: &Vec3<f64>) -> bool {
    let [a, b, c] = &node.v;
    let s = if side(a, b, c) > 0.0 { 1.0 } else { -1.0 };
    s * side(a, b, d) >= 0.0 && s * side(b, c, d) >= 0.0 && s * side(c, a, d) >= 0.0
}

/// The child of `kids` containing the unit direction `d` (a direction of
/// the parent) and its σ⊥ share: corner child `i` if `d` is strictly on its
/// corner's side of its inner edge (the arc between the two midpoints),
/// else the middle child.
pub(super) fn locate(kids: &[Node; 4], d: &Vec3<f64>) -> (usize, f64) {
    let mut p = [0.0; 4];
    shares(kids, &mut p);
    let corner = |i: usize| {
        let [a, b, c] = &kids[i].v;
        let (x, e1, e2) = match i {
            0 => (a, b, c),
            1 => (b, c, a),
            _ => (c, a, b),
        };
        let sd = side(e1, e2, d);
        let sx = side(e1, e2, x);
        (sd > 0.0 && sx > 0.0) || (sd < 0.0 && sx < 0.0)
    };
    let j = (0..3).find(|&i| corner(i)).unwrap_or(3);
    (j, p[j])
}

/// The solid angle in a leaf's density: its sampler's Ω.
pub(super) fn leaf_solid_angle(node: &Node) -> f64 {
    match node.sampler() {
        Some(t) => t.solid_angle(),
        None => node.measures().solid_angle,
    }
}

/// Child `j` of an owned set of children.
pub(super) fn take(kids: [Node; 4], j: usize) -> Node {
    let [a, b, c, d] = kids;
    match j {
        0 => a,
        1 => b,
        2 => c,
        _ => d,
    }
}
