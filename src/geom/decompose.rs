//! Convex decomposition of simple polygons.

use std::cmp::Ordering;

use glam::DVec2;
use spade::handles::{FaceHandle, InnerTag};
use spade::{CdtEdge, ConstrainedDelaunayTriangulation, HasPosition, Point2, Triangulation};

use super::{ConvexPolygon, GeomError, orientation, sanitize_all};

/// Outline vertex carrying its index into the triangulation.
#[derive(Debug, Clone, Copy)]
struct Indexed {
    pos: Point2<f64>,
    idx: usize,
}

impl HasPosition for Indexed {
    type Scalar = f64;

    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

type Cdt = ConstrainedDelaunayTriangulation<Indexed>;
type InnerFace<'a> = FaceHandle<'a, InnerTag, Indexed, (), CdtEdge<()>, ()>;

/// Splits a simple polygon into convex pieces (metres).
///
/// `outline` lists the vertices of a simple polygon in either orientation, without repeating
/// the first vertex at the end. The outline is triangulated with spade's constrained Delaunay
/// triangulation (outline edges as constraints); triangles inside the outline are found by a
/// flood fill that flips inside/outside whenever it crosses an outline edge (even-odd rule), and
/// adjacent pieces are then merged across their shared diagonal whenever the union stays convex
/// (Hertel–Mehlhorn), which yields at most four times the minimum number of pieces. The pieces
/// tile the outline exactly: their areas sum to its area.
///
/// Vertices lying on a straight stretch of the outline are allowed; they do not appear in the
/// pieces. Errors: fewer than 3 points, non-finite or out-of-range coordinates, repeated points,
/// and edges that cross, touch or overlap (self-intersection).
///
/// Cost: a triangulation, `O(n log n)` for outlines whose edges cross few Delaunay edges. The
/// outline is simple exactly when every one of its edges is an edge of the triangulation, which
/// is planar (its edges meet only at their ends), and no point repeats: spade reports
/// constraints that cross and splits those that pass through a vertex, so that check is linear.
/// Only an outline found not simple is searched pair by pair for the two edges to name.
pub fn decompose(outline: &[DVec2]) -> Result<Vec<ConvexPolygon>, GeomError> {
    let pts = sanitize_all(outline)?;
    let n = pts.len();
    if n < 3 {
        return Err(GeomError::TooFewPoints { found: n });
    }
    check_distinct(&pts)?;

    let vertices: Vec<Indexed> =
        pts.iter().enumerate().map(|(idx, p)| Indexed { pos: Point2::new(p.x, p.y), idx }).collect();
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflict = false;
    let cdt = Cdt::try_bulk_load_cdt(vertices, edges, |_| conflict = true)
        .map_err(|e| GeomError::Triangulation(e.to_string()))?;
    if conflict || cdt.num_vertices() != n || !outline_is_constrained(&cdt, n) {
        check_simple(&pts)?;
        return Err(GeomError::Triangulation("outline edges could not all be inserted as constraints".into()));
    }

    let inside = classify_faces(&cdt);
    let mut tri_of_face = vec![usize::MAX; cdt.num_all_faces()];
    let mut loops = Loops::default();
    for face in cdt.inner_faces() {
        let fi = face.fix().index();
        if !inside[fi] {
            continue;
        }
        let [a, b, c] = face.vertices().map(|v| v.data().idx);
        let tri = if orientation(pts[a], pts[b], pts[c]) == Ordering::Less { [a, c, b] } else { [a, b, c] };
        tri_of_face[fi] = loops.first.len();
        loops.push(tri);
    }
    if loops.first.is_empty() {
        return Err(GeomError::Triangulation("no triangle inside the outline".into()));
    }

    // Hertel–Mehlhorn: drop diagonals whose removal keeps both endpoints convex.
    let mut parent: Vec<usize> = (0..loops.first.len()).collect();
    for edge in cdt.undirected_edges() {
        if edge.is_constraint_edge() {
            continue;
        }
        let directed = edge.as_directed();
        let (Some(f0), Some(f1)) = (directed.face().as_inner(), directed.rev().face().as_inner()) else {
            continue;
        };
        let (t0, t1) = (tri_of_face[f0.fix().index()], tri_of_face[f1.fix().index()]);
        if t0 == usize::MAX || t1 == usize::MAX {
            continue;
        }
        let (r0, r1) = (find(&mut parent, t0), find(&mut parent, t1));
        if r0 == r1 {
            continue;
        }
        let u = directed.from().data().idx;
        let v = directed.to().data().idx;
        if loops.merge(&pts, (t0, r0), t1, u, v) {
            parent[r1] = r0;
        }
    }

    let mut out = Vec::new();
    for (i, &first) in loops.first.iter().enumerate() {
        if parent[i] == i {
            out.push(ConvexPolygon::from_loop(loops.walk(first).map(|k| pts[k]).collect())?);
        }
    }
    Ok(out)
}

/// The pieces of a triangulated outline as loops of half-edges: each triangle's three edges
/// linked in order, so joining two pieces across a diagonal relinks four half-edges, whatever
/// the pieces' sizes, and the whole Hertel–Mehlhorn pass is linear.
#[derive(Debug, Default)]
struct Loops {
    /// The outline point each half-edge starts at.
    origin: Vec<usize>,
    /// The half-edge after each one along its piece, and the one before.
    next: Vec<usize>,
    prev: Vec<usize>,
    /// For each triangle, the half-edge its piece's loop is read from while it is a root.
    first: Vec<usize>,
}

impl Loops {
    /// Adds the triangle `tri` (counter-clockwise): half-edges `3k`, `3k + 1`, `3k + 2`.
    fn push(&mut self, tri: [usize; 3]) {
        let k = self.origin.len();
        self.origin.extend(tri);
        self.next.extend([k + 1, k + 2, k]);
        self.prev.extend([k + 2, k, k + 1]);
        self.first.push(k);
    }

    /// The half-edge of triangle `t` from outline point `from` to `to`.
    fn half_edge(&self, t: usize, from: usize, to: usize) -> Option<usize> {
        (3 * t..3 * t + 3).find(|&h| self.origin[h] == from && self.origin[self.next[h]] == to)
    }

    /// Joins the piece rooted at `r0` (holding triangle `t0`) and the piece holding `t1`
    /// across their diagonal `u`–`v` when the union is convex at both ends; the joined loop
    /// is read from `v`, the end the diagonal points at along `r0`'s loop.
    fn merge(&mut self, pts: &[DVec2], (t0, r0): (usize, usize), t1: usize, u: usize, v: usize) -> bool {
        let pair = |a, b| Some((self.half_edge(t0, a, b)?, self.half_edge(t1, b, a)?));
        let Some((h, t)) = pair(u, v).or_else(|| pair(v, u)) else {
            return false;
        };
        let (ph, nh, pt, nt) = (self.prev[h], self.next[h], self.prev[t], self.next[t]);
        // Around `v`: from the point before it on the second loop to the point after it on
        // the first; around `u`: from the point before it on the first to the one after it on
        // the second.
        let at = |a: usize, b: usize, c: usize| orientation(pts[a], pts[b], pts[c]) != Ordering::Less;
        let o = &self.origin;
        if !(at(o[pt], o[nh], o[self.next[nh]]) && at(o[ph], o[h], o[self.next[nt]])) {
            return false;
        }
        self.next[ph] = nt;
        self.prev[nt] = ph;
        self.next[pt] = nh;
        self.prev[nh] = pt;
        self.first[r0] = nh;
        true
    }

    /// The outline points of the loop through half-edge `first`, from its start.
    fn walk(&self, first: usize) -> impl Iterator<Item = usize> + '_ {
        let mut h = Some(first);
        std::iter::from_fn(move || {
            let at = h?;
            let n = self.next[at];
            h = (n != first).then_some(n);
            Some(self.origin[at])
        })
    }
}

/// Union-find root with path halving.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Whether the constraint edges of `cdt` are exactly the `n` outline edges `i`–`i + 1`.
fn outline_is_constrained(cdt: &Cdt, n: usize) -> bool {
    let consecutive = |a: usize, b: usize| (a + 1) % n == b || (b + 1) % n == a;
    cdt.num_constraints() == n
        && cdt.undirected_edges().filter(|e| e.is_constraint_edge()).all(|e| {
            let [a, b] = e.vertices().map(|v| v.data().idx);
            consecutive(a, b)
        })
}

/// Marks each face as inside (true) or outside the outline by flood fill from the outer face,
/// toggling at every constraint edge.
fn classify_faces(cdt: &Cdt) -> Vec<bool> {
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut seen = vec![false; cdt.num_all_faces()];
    let mut stack: Vec<(InnerFace<'_>, bool)> = Vec::new();
    for hull_edge in cdt.convex_hull() {
        if let Some(face) = hull_edge.rev().face().as_inner() {
            let idx = face.fix().index();
            if !seen[idx] {
                seen[idx] = true;
                stack.push((face, hull_edge.is_constraint_edge()));
            }
        }
    }
    while let Some((face, state)) = stack.pop() {
        inside[face.fix().index()] = state;
        for edge in face.adjacent_edges() {
            if let Some(next) = edge.rev().face().as_inner() {
                let idx = next.fix().index();
                if !seen[idx] {
                    seen[idx] = true;
                    stack.push((next, state ^ edge.is_constraint_edge()));
                }
            }
        }
    }
    inside
}

/// Rejects outlines that contain the same point twice.
fn check_distinct(pts: &[DVec2]) -> Result<(), GeomError> {
    let mut order: Vec<usize> = (0..pts.len()).collect();
    order.sort_by(|&i, &j| lex(pts[i], pts[j]).then(i.cmp(&j)));
    for w in order.windows(2) {
        if pts[w[0]] == pts[w[1]] {
            return Err(GeomError::RepeatedPoint { first: w[0].min(w[1]), second: w[0].max(w[1]) });
        }
    }
    Ok(())
}

/// Lexicographic order on points (x, then y).
fn lex(a: DVec2, b: DVec2) -> Ordering {
    a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
}

/// Rejects outlines whose edges cross, touch or overlap (other than neighbouring edges sharing
/// their common endpoint), naming the first such pair: every pair is tested, so this runs only
/// on outlines already found not simple.
fn check_simple(pts: &[DVec2]) -> Result<(), GeomError> {
    let n = pts.len();
    let seg = |i: usize| (pts[i], pts[(i + 1) % n]);
    for i in 0..n {
        // Neighbouring edges i and i + 1 share pts[i + 1]; they overlap when they fold back.
        let (a, b) = seg(i);
        let c = pts[(i + 2) % n];
        if orientation(a, b, c) == Ordering::Equal && (a - b).dot(c - b) > 0.0 {
            return Err(GeomError::SelfIntersecting { first: i, second: (i + 1) % n });
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (p, q) = seg(j);
            if segments_touch(a, b, p, q) {
                return Err(GeomError::SelfIntersecting { first: i, second: j });
            }
        }
    }
    Ok(())
}

/// Whether the closed segments `a`–`b` and `p`–`q` share a point (exact).
fn segments_touch(a: DVec2, b: DVec2, p: DVec2, q: DVec2) -> bool {
    let o1 = orientation(a, b, p);
    let o2 = orientation(a, b, q);
    let o3 = orientation(p, q, a);
    let o4 = orientation(p, q, b);
    if (o1 != Ordering::Equal && o1 == o2) || (o3 != Ordering::Equal && o3 == o4) {
        return false;
    }
    if o1 == Ordering::Equal && o2 == Ordering::Equal {
        // Collinear: compare the spans along the line.
        let (lo1, hi1) = if lex(a, b).is_le() { (a, b) } else { (b, a) };
        let (lo2, hi2) = if lex(p, q).is_le() { (p, q) } else { (q, p) };
        return lex(lo1, hi2).is_le() && lex(lo2, hi1).is_le();
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    fn shoelace(pts: &[DVec2]) -> f64 {
        let n = pts.len();
        (0..n).map(|i| pts[i].perp_dot(pts[(i + 1) % n])).sum::<f64>().abs() * 0.5
    }

    fn check_tiling(outline: &[DVec2], max_pieces: usize) -> Vec<ConvexPolygon> {
        let pieces = decompose(outline).unwrap();
        assert!(!pieces.is_empty() && pieces.len() <= max_pieces, "{} pieces: {pieces:?}", pieces.len());
        let total: f64 = pieces.iter().map(ConvexPolygon::area).sum();
        assert!((total - shoelace(outline)).abs() < 1e-9, "{total} vs {}", shoelace(outline));
        pieces
    }

    #[test]
    fn convex_outline_stays_whole() {
        let sq = [v(0.0, 0.0), v(2.0, 0.0), v(2.0, 2.0), v(1.0, 2.0), v(0.0, 2.0)];
        let pieces = check_tiling(&sq, 1);
        assert_eq!(pieces[0].vertices().len(), 4);
    }

    #[test]
    fn l_shape() {
        // Area 3: a 2 × 2 square minus its upper-right unit square.
        let l = [v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(1.0, 1.0), v(1.0, 2.0), v(0.0, 2.0)];
        check_tiling(&l, 2);
        let mut cw = l;
        cw.reverse();
        check_tiling(&cw, 2);
    }

    #[test]
    fn u_shape() {
        // 3 × 2 block with a 1 × 1 notch cut from the top middle: area 5, two reflex corners.
        let u =
            [v(0.0, 0.0), v(3.0, 0.0), v(3.0, 2.0), v(2.0, 2.0), v(2.0, 1.0), v(1.0, 1.0), v(1.0, 2.0), v(0.0, 2.0)];
        let pieces = check_tiling(&u, 3);
        assert_eq!(pieces.len(), 3);
    }

    #[test]
    fn comb_shape() {
        // A comb with three teeth: area 3·2 + 1·5 = 11.
        let comb = [
            v(0.0, 0.0),
            v(5.0, 0.0),
            v(5.0, 3.0),
            v(4.0, 3.0),
            v(4.0, 1.0),
            v(3.0, 1.0),
            v(3.0, 3.0),
            v(2.0, 3.0),
            v(2.0, 1.0),
            v(1.0, 1.0),
            v(1.0, 3.0),
            v(0.0, 3.0),
        ];
        check_tiling(&comb, 9);
    }

    #[test]
    fn rejects_bad_outlines() {
        assert_eq!(decompose(&[v(0.0, 0.0), v(1.0, 0.0)]), Err(GeomError::TooFewPoints { found: 2 }));
        let bowtie = [v(0.0, 0.0), v(1.0, 1.0), v(1.0, 0.0), v(0.0, 1.0)];
        assert!(matches!(decompose(&bowtie), Err(GeomError::SelfIntersecting { .. })));
        let repeated = [v(0.0, 0.0), v(2.0, 0.0), v(1.0, 1.0), v(2.0, 2.0), v(1.0, 1.0), v(0.0, 2.0)];
        assert_eq!(decompose(&repeated), Err(GeomError::RepeatedPoint { first: 2, second: 4 }));
        let collinear = [v(0.0, 0.0), v(1.0, 0.0), v(2.0, 0.0)];
        assert!(matches!(decompose(&collinear), Err(GeomError::SelfIntersecting { .. })));
        // A vertex touching a non-adjacent edge.
        let touching = [v(0.0, 0.0), v(4.0, 0.0), v(4.0, 4.0), v(2.0, 0.0), v(0.0, 4.0)];
        assert!(matches!(decompose(&touching), Err(GeomError::SelfIntersecting { .. })));
        assert_eq!(decompose(&[v(0.0, 0.0), v(1.0, f64::NAN), v(0.0, 1.0)]), Err(GeomError::NonFinite { index: 1 }));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The triangulation finds an outline simple exactly when no two of its edges meet
        /// pair by pair (small whole coordinates make points on edges, overlaps and folds
        /// common; perturbed ones make crossings near their ends).
        #[test]
        fn the_triangulation_finds_what_the_pairwise_test_finds(
            points in proptest::collection::vec((0i32..5, 0i32..5), 3..12),
            jitter in proptest::collection::vec(-1e-9f64..1e-9, 24),
            jittered in proptest::bool::ANY,
        ) {
            let pts: Vec<DVec2> = points
                .iter()
                .enumerate()
                .map(|(i, &(x, y))| {
                    let j = if jittered { DVec2::new(jitter[2 * i], jitter[2 * i + 1]) } else { DVec2::ZERO };
                    DVec2::new(x.into(), y.into()) + j
                })
                .collect();
            let pairwise = check_distinct(&pts).and_then(|()| check_simple(&pts));
            let found = decompose(&pts);
            match pairwise {
                Err(e) => proptest::prop_assert_eq!(found, Err(e)),
                Ok(()) => proptest::prop_assert!(found.is_ok(), "{pts:?}: {found:?}"),
            }
        }
    }
}
