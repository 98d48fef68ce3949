//! A bounding-volume hierarchy of axis-aligned boxes for nearest-point queries.
//!
//! # Why our own hierarchy
//!
//! parry3d-f64 has a good BVH, but its types are nalgebra's: every position and every
//! query would be converted from glam, its build is not documented to give the same tree
//! for every thread count, and its point–triangle projection reports a feature id in its
//! own numbering, which we would map back to the mesh's edges and vertices for the
//! pseudo-normal sign. A nearest-point query over a static set of triangles needs little:
//!
//! - a median split on the longest axis of the box centres, so the tree is a function of
//!   the input alone (ties by item index) and its node count a function of the item count,
//!   which lets subtrees be built in parallel into disjoint parts of one preallocated array;
//! - interior nodes flattened in depth-first order, each holding both children's boxes and
//!   references (112 bytes; a leaf of at most eight items is named in its parent, not
//!   stored as a node): 262 143 nodes for the 1 310 720 triangles of a level-8 icosphere
//!   (leaves of five triangles);
//! - an iterative traversal with a reusable stack that tests both children's boxes of a
//!   node at once, visits the nearer first and prunes by the best squared distance so far.
//!
//! The split is computed with `select_nth_unstable` on 16-byte items: the centres rounded
//! to `f32` as integer keys (the order of `f32::total_cmp`) and the item index, one `u64`
//! comparison per axis. The split only has to be *a* deterministic median split: which
//! tree it builds does not change any answer (the search is exact, ties are broken by the
//! caller's face order), only how fast the answers are found.
//!
//! That is this file (and a Morton order that makes batches of queries coherent); the
//! exact point–triangle distance and the feature classification stay in our hands, in
//! `f64` throughout.
//!
//! # Layout
//!
//! Items (triangles) are permuted into leaf order by [`Bvh::build`]. A child reference is a
//! leaf when `count > 0` and then names items `first .. first + count` (in leaf order);
//! otherwise it names interior node `first`. A node's first child, when interior, is the
//! next node.

use glam::DVec3;
use rayon::prelude::*;

/// At most this many items in a leaf.
const LEAF_SIZE: usize = 8;
/// Ranges of at least this many items choose their split axis from a sample of the centres.
const SAMPLE_MIN: usize = 64;
/// Subtrees with at least this many items are built in parallel.
const PARALLEL_MIN: usize = 1 << 15;
/// Traversal stack size: a median split halves the item count at each level, so the depth
/// is at most `ceil(log2(n))` ≤ 32 for `u32` item counts, and at most one entry per level
/// is on the stack.
const STACK: usize = 64;

/// A reference to a subtree: an interior node, or a leaf stored in its parent.
#[derive(Clone, Copy, Debug)]
struct Child {
    /// Leaf: the first item (leaf order). Interior: the node index.
    first: u32,
    /// Leaf: the number of items (≥ 1). Interior: 0.
    count: u32,
}

/// An interior node: both children's boxes and references, so that one visit reads one
/// node (112 bytes) and tests both boxes.
///
/// The boxes are stored axis by axis, both children side by side (`lo[axis][child]`), so
/// that both box distances are computed in one pass over the node.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [[f64; 2]; 3],
    hi: [[f64; 2]; 3],
    child: [Child; 2],
}

impl Node {
    /// The squared distances from `p` to both children's boxes, each computed exactly as
    /// [`box_distance_squared`] computes it.
    #[inline]
    fn distances_squared(&self, p: [f64; 3]) -> [f64; 2] {
        let g: [[f64; 2]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|c| gap(self.lo[a][c], self.hi[a][c], p[a]))
        });
        std::array::from_fn(|c| g[0][c] * g[0][c] + g[1][c] * g[1][c] + g[2][c] * g[2][c])
    }
}

/// The larger of `a` and `b` by a plain comparison (no NaN handling: the inputs are
/// finite), so that it is one `max` instruction.
#[inline]
fn larger(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// The distance from `p` to the interval `[lo, hi]` along one axis (0 inside; possibly
/// `-0.0`, which squares like `0.0`).
#[inline]
fn gap(lo: f64, hi: f64, p: f64) -> f64 {
    larger(larger(lo - p, p - hi), 0.0)
}

/// The squared distance from `p` to the box `[lo, hi]` (0 inside).
#[inline]
pub(crate) fn box_distance_squared(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    let [x, y, z] = [
        gap(lo.x, hi.x, p.x),
        gap(lo.y, hi.y, p.y),
        gap(lo.z, hi.z, p.z),
    ];
    x * x + y * y + z * z
}

/// A subtree's box and reference, as its build returns them.
#[derive(Clone, Copy, Debug)]
struct Built {
    lo: DVec3,
    hi: DVec3,
    child: Child,
}

/// The traversal stack of [`Bvh::nearest`]: deferred subtrees and their box distances.
/// Kept by the caller across queries, so that no query allocates or clears one.
#[derive(Debug, Default)]
pub(crate) struct Stack(Vec<(Child, f64)>);

/// A static bounding-volume hierarchy over boxes.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    /// The root's box and reference (`None` without items).
    root: Option<Built>,
    /// Interior nodes in depth-first order: a node's first child subtree follows it.
    nodes: Vec<Node>,
}

impl Bvh {
    /// Builds the hierarchy over `boxes` (`[lo, hi]` per item) and returns it with the leaf
    /// order: `order[k]` is the item stored at leaf position `k`. Object-median split on the
    /// longest axis of the box centres (rounded to `f32`, ties by item index); deterministic,
    /// independent of the thread count.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` items (callers check).
    pub(crate) fn build(n: usize, bounds: impl Fn(usize) -> [DVec3; 2] + Sync) -> (Self, Vec<u32>) {
        let _ = u32::try_from(n).expect("at most u32::MAX items");
        let mut items: Vec<Item> = (0..n)
            .into_par_iter()
            .map(|i| {
                let [lo, hi] = bounds(i);
                let centre = lo + hi;
                Item {
                    key: [centre.x, centre.y, centre.z].map(|c| order_key(c as f32)),
                    index: i as u32,
                }
            })
            .collect();
        if n == 0 {
            return (
                Self {
                    root: None,
                    nodes: Vec::new(),
                },
                Vec::new(),
            );
        }
        let sizes = SubtreeSizes::new(n);
        let empty = Child { first: 0, count: 0 };
        // Initialised in parallel (tens of megabytes of fresh pages), then overwritten.
        let mut nodes: Vec<Node> = (0..sizes.nodes(n))
            .into_par_iter()
            .map(|_| Node {
                lo: [[0.0; 2]; 3],
                hi: [[0.0; 2]; 3],
                child: [empty; 2],
            })
            .collect();
        let build = Build {
            sizes: &sizes,
            bounds: &bounds,
        };
        let root = build.subtree(&mut nodes, 0, &mut items, 0);
        (
            Self {
                root: Some(root),
                nodes,
            },
            items.par_iter().map(|item| item.index).collect(),
        )
    }

    /// Finds the nearest item to `p`. `bound` is an upper bound of the answer's squared
    /// distance (`f64::INFINITY` when none is known); `visit(k)` is called for every item
    /// (leaf position `k`) of every leaf whose box is within the current bound and returns
    /// the new bound (the caller keeps the best item). Returns the final bound. `stack` is
    /// scratch space, reused across calls.
    ///
    /// Boxes at exactly the bound are visited, so a caller can break ties by its own rule.
    /// Subtrees are visited depth first, the nearer child first (the first child when both
    /// are at the same distance).
    #[inline]
    pub(crate) fn nearest(
        &self,
        p: DVec3,
        mut bound: f64,
        stack: &mut Stack,
        mut visit: impl FnMut(usize) -> f64,
    ) -> f64 {
        let Some(root) = self.root else {
            return bound;
        };
        if box_distance_squared(root.lo, root.hi, p) > bound {
            return bound;
        }
        let stack = &mut stack.0;
        stack.clear();
        let q = p.to_array();
        let mut next = root.child;
        loop {
            if next.count > 0 {
                let first = next.first as usize;
                for k in first..first + next.count as usize {
                    bound = visit(k);
                }
            } else {
                let node = &self.nodes[next.first as usize];
                let [d0, d1] = node.distances_squared(q);
                let ((near, dn), (far, df)) = if d0 <= d1 {
                    ((node.child[0], d0), (node.child[1], d1))
                } else {
                    ((node.child[1], d1), (node.child[0], d0))
                };
                if df <= bound {
                    stack.push((far, df));
                }
                if dn <= bound {
                    next = near;
                    continue;
                }
            }
            next = loop {
                let Some((child, d)) = stack.pop() else {
                    return bound;
                };
                if d <= bound {
                    break child;
                }
            };
        }
    }

    /// The number of interior nodes.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.nodes.len()
    }
}

impl Stack {
    /// An empty stack with room for the deepest hierarchy.
    pub(crate) fn new() -> Self {
        Self(Vec::with_capacity(STACK))
    }
}

/// The key of `x` in the total order of [`f32::total_cmp`], as an integer: comparing keys
/// is comparing the values as `total_cmp` does.
#[inline]
fn order_key(x: f32) -> i32 {
    // Negative values: every bit but the sign flipped (larger magnitudes lower).
    order_key_bits(x.to_bits() as i32)
}

/// The value of an [`order_key`] (the map is its own inverse on the bits).
#[inline]
fn key_value(key: i32) -> f32 {
    f32::from_bits(order_key_bits(key) as u32)
}

/// [`order_key`] on bits: an involution.
#[inline]
fn order_key_bits(bits: i32) -> i32 {
    bits ^ ((((bits >> 31) as u32) >> 1) as i32)
}

/// An item, moved around by the build: the [`order_key`]s of (twice) its box centre
/// rounded to `f32` (the split needs an order of the centres, not their exact values),
/// and its index. 16 bytes, so a selection moves half the bytes of `f64` centres.
/// Centres beyond the `f32` range (above about `3e38`) become infinite keys: the tree
/// stays valid and the answers exact, only its split positions are then by index.
#[derive(Clone, Copy, Debug)]
struct Item {
    key: [i32; 3],
    index: u32,
}

impl Item {
    /// The sort key along `axis`: the centre's key, then the index.
    #[inline]
    fn along(&self, axis: usize) -> u64 {
        (u64::from(self.key[axis] as u32 ^ (1 << 31)) << 32) | u64::from(self.index)
    }
}

/// The number of interior nodes of the subtree over `n` items. Median splits make it a
/// function of `n` alone, so the node array is allocated once and subtrees are built in
/// place, in parallel, into disjoint slices of it.
struct SubtreeSizes(Vec<(usize, usize)>);

impl SubtreeSizes {
    /// The sizes of every subtree of a tree over `n` items (at most two item counts per
    /// level).
    fn new(n: usize) -> Self {
        let mut sizes = Self(Vec::new());
        sizes.fill(n);
        sizes
    }

    fn fill(&mut self, n: usize) -> usize {
        if let Some(&(_, count)) = self.0.iter().find(|&&(m, _)| m == n) {
            return count;
        }
        let count = if n <= LEAF_SIZE {
            0
        } else {
            1 + self.fill(n / 2) + self.fill(n - n / 2)
        };
        self.0.push((n, count));
        count
    }

    /// The interior node count of a subtree over `n` items (`n` a subtree size of the
    /// tree).
    fn nodes(&self, n: usize) -> usize {
        self.0
            .iter()
            .find(|&&(m, _)| m == n)
            .map_or(0, |&(_, count)| count)
    }
}

/// What a build needs besides the items: the subtree sizes and the item boxes.
struct Build<'a, F> {
    sizes: &'a SubtreeSizes,
    bounds: &'a F,
}

impl<F: Fn(usize) -> [DVec3; 2] + Sync> Build<'_, F> {
    /// Builds the subtree over `items` (at leaf positions `offset ..`) into `nodes`, whose
    /// first node has the global index `base`, and returns its box and reference. Node
    /// boxes are unions of their children's, computed on the way back up; large subtrees
    /// build their halves in parallel.
    fn subtree(&self, nodes: &mut [Node], base: usize, items: &mut [Item], offset: u32) -> Built {
        if items.len() <= LEAF_SIZE {
            let (lo, hi) =
                items
                    .iter()
                    .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), item| {
                        let [a, b] = (self.bounds)(item.index as usize);
                        (lo.min(a), hi.max(b))
                    });
            return Built {
                lo,
                hi,
                child: Child {
                    first: offset,
                    count: items.len() as u32,
                },
            };
        }
        split(items);
        let mid = items.len() / 2;
        let left_nodes = self.sizes.nodes(mid);
        let (root, rest) = nodes.split_at_mut(1);
        let (left, right) = rest.split_at_mut(left_nodes);
        let right_base = base + 1 + left_nodes;
        let parallel = items.len() >= PARALLEL_MIN;
        let (left_items, right_items) = items.split_at_mut(mid);
        let right_offset = offset + mid as u32;
        let (l, r) = if parallel {
            rayon::join(
                || self.subtree(left, base + 1, left_items, offset),
                || self.subtree(right, right_base, right_items, right_offset),
            )
        } else {
            (
                self.subtree(left, base + 1, left_items, offset),
                self.subtree(right, right_base, right_items, right_offset),
            )
        };
        root[0] = Node {
            lo: std::array::from_fn(|a| [l.lo[a], r.lo[a]]),
            hi: std::array::from_fn(|a| [l.hi[a], r.hi[a]]),
            child: [l.child, r.child],
        };
        Built {
            lo: l.lo.min(r.lo),
            hi: l.hi.max(r.hi),
            child: Child {
                first: base as u32,
                count: 0,
            },
        }
    }
}

/// Reorders `items` so that the first half has the smaller centres along the longest axis
/// of the centres' extent (ties by item index, so the split is a deterministic function of
/// the input).
///
/// The extent is folded over the integer keys (their order is that of the values; every
/// fourth item of a range of at least [`SAMPLE_MIN`]) and measured on the values of the
/// extreme keys.
fn split(items: &mut [Item]) {
    // Four lanes (the index lane unused), so that the fold is one vector min and max.
    // Large ranges: every fourth item (the selection leaves them in no particular order,
    // so a stride is a fair sample); the extent only decides the split axis.
    let stride = if items.len() >= SAMPLE_MIN { 4 } else { 1 };
    let (lo, hi) =
        items
            .iter()
            .step_by(stride)
            .fold(([i32::MAX; 4], [i32::MIN; 4]), |(lo, hi), item| {
                let k = [item.key[0], item.key[1], item.key[2], item.index as i32];
                (
                    std::array::from_fn(|a| lo[a].min(k[a])),
                    std::array::from_fn(|a| hi[a].max(k[a])),
                )
            });
    let extent: [f64; 3] =
        std::array::from_fn(|a| f64::from(key_value(hi[a])) - f64::from(key_value(lo[a])));
    let mid = items.len() / 2;
    // One comparator per axis, so that the axis is not looked up in every comparison.
    if extent[0] >= extent[1] && extent[0] >= extent[2] {
        items.select_nth_unstable_by_key(mid, |item| item.along(0));
    } else if extent[1] >= extent[2] {
        items.select_nth_unstable_by_key(mid, |item| item.along(1));
    } else {
        items.select_nth_unstable_by_key(mid, |item| item.along(2));
    }
}

/// Cells per axis of the Morton grid (10 bits): a 30-bit code, so that the code and a
/// 32-bit point index make one `u64` sort key. 1024 cells per axis are finer than the
/// vertex spacing of any mesh this is used on up to about 10⁷ vertices, and points that
/// share a cell stay in index order.
const MORTON_CELLS: u32 = (1 << 10) - 1;

/// The Morton code of a point given in grid cells (`[0, MORTON_CELLS]` per axis).
fn morton_code(q: DVec3) -> u64 {
    let q = q.clamp(DVec3::ZERO, DVec3::splat(f64::from(MORTON_CELLS)));
    spread(q.x as u64) | (spread(q.y as u64) << 1) | (spread(q.z as u64) << 2)
}

/// Spreads the low 21 bits of `x` to every third bit.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1F_FFFF;
    x = (x | (x << 32)) & 0x001F_0000_0000_FFFF;
    x = (x | (x << 16)) & 0x001F_0000_FF00_00FF;
    x = (x | (x << 8)) & 0x100F_00F0_0F00_F00F;
    x = (x | (x << 4)) & 0x10C3_0C30_C30C_30C3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// The indices of `points` sorted along a Morton curve over their bounding box (ties by
/// index): an order in which consecutive points are mostly close.
pub(crate) fn morton_order(points: &[DVec3]) -> Vec<u32> {
    let (lo, hi) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let extent = hi - lo;
    let scale = DVec3::select(
        extent.cmpgt(DVec3::ZERO),
        DVec3::splat(f64::from(MORTON_CELLS)) / extent,
        DVec3::ZERO,
    );
    let mut keyed: Vec<u64> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (morton_code((p - lo) * scale) << 32) | i as u64)
        .collect();
    sort_by_code(&mut keyed);
    keyed.into_iter().map(|key| key as u32).collect()
}

/// Bits of a Morton code sorted per pass of [`sort_by_code`].
const DIGIT_BITS: u32 = 10;

/// Sorts keys `code << 32 | index` whose indices are in increasing order: a stable
/// least-significant-digit radix sort by the 30-bit code (three passes of ten bits), so
/// that equal codes keep their index order and the result is the keys' sorted order.
fn sort_by_code(keys: &mut Vec<u64>) {
    const BUCKETS: usize = 1 << DIGIT_BITS;
    let mut other = vec![0u64; keys.len()];
    for pass in 0..3 {
        let shift = 32 + pass * DIGIT_BITS;
        let digit = |key: u64| ((key >> shift) as usize) & (BUCKETS - 1);
        let mut start = [0usize; BUCKETS];
        for &key in keys.iter() {
            start[digit(key)] += 1;
        }
        if start.contains(&keys.len()) {
            // One digit for every key: this pass would keep the order.
            continue;
        }
        let mut sum = 0;
        for slot in &mut start {
            let count = *slot;
            *slot = sum;
            sum += count;
        }
        for &key in keys.iter() {
            let slot = &mut start[digit(key)];
            other[*slot] = key;
            *slot += 1;
        }
        std::mem::swap(keys, &mut other);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Asserts that `order` is a permutation of the items.
    fn assert_permutation(order: &[u32]) {
        let mut sorted = order.to_vec();
        sorted.sort_unstable();
        assert!(sorted.iter().enumerate().all(|(k, &i)| k == i as usize));
    }

    /// The smallest squared distance from `q` to `points` and its point (the lowest index
    /// on ties), found through the tree.
    fn nearest_through(bvh: &Bvh, order: &[u32], points: &[DVec3], q: DVec3) -> (f64, usize) {
        let mut best = (f64::INFINITY, usize::MAX);
        bvh.nearest(q, f64::INFINITY, &mut Stack::new(), |k| {
            let i = order[k] as usize;
            let d = (points[i] - q).length_squared();
            if d < best.0 || (d == best.0 && i < best.1) {
                best = (d, i);
            }
            best.0
        });
        best
    }

    /// The radix sort by code gives the sorted order of the keys, with ties in the
    /// code (few distinct codes, all codes equal, empty input) kept in index order.
    #[test]
    fn codes_are_sorted_as_the_keys_are() {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (n, mask) in [
            (0, 0),
            (1, 0),
            (5000, 0),
            (5000, 0x3),
            (70_000, (1 << 30) - 1),
        ] {
            let mut keys: Vec<u64> = (0..n).map(|i| ((next() & mask) << 32) | i).collect();
            let mut sorted = keys.clone();
            sorted.sort_unstable();
            sort_by_code(&mut keys);
            assert_eq!(keys, sorted, "{n} keys, codes masked by {mask:#x}");
        }
    }

    #[test]
    fn nearest_point_matches_a_scan() {
        // A deterministic scatter of points on a helix.
        let points: Vec<DVec3> = (0..1000)
            .map(|i| {
                let t = f64::from(i) * 0.37;
                DVec3::new(t.cos(), t.sin(), 0.01 * t)
            })
            .collect();
        let (bvh, order) = Bvh::build(points.len(), |i| [points[i], points[i]]);
        assert!(bvh.len() < points.len());
        assert_permutation(&order);
        for q in [
            DVec3::ZERO,
            DVec3::new(0.3, -2.0, 1.0),
            DVec3::new(5.0, 5.0, 5.0),
        ] {
            let best = nearest_through(&bvh, &order, &points, q);
            let scan = points
                .iter()
                .map(|p| (p - q).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(best.0, scan);
        }
    }

    #[test]
    fn coincident_and_collinear_items_are_all_found() {
        // A third of the items at one point (equal keys on every axis: ties by index), the
        // rest on a segment along x (zero extent in y and z), in ranges far above the
        // sampling and parallel-build thresholds.
        let n = 3 * PARALLEL_MIN;
        let points: Vec<DVec3> = (0..n)
            .map(|i| {
                if i % 3 == 0 {
                    DVec3::new(0.5, 0.0, 0.0)
                } else {
                    DVec3::new(i as f64 / n as f64, 0.0, 0.0)
                }
            })
            .collect();
        let (bvh, order) = Bvh::build(points.len(), |i| [points[i], points[i]]);
        assert_permutation(&order);
        for q in [
            DVec3::new(0.5, 0.1, 0.0),
            DVec3::new(0.123_456, 0.0, -0.2),
            DVec3::new(2.0, 1.0, 1.0),
        ] {
            let best = nearest_through(&bvh, &order, &points, q);
            let scan = points
                .iter()
                .enumerate()
                .map(|(i, p)| ((p - q).length_squared(), i))
                .fold(
                    (f64::INFINITY, usize::MAX),
                    |a, b| if b.0 < a.0 { b } else { a },
                );
            assert_eq!(best, scan, "query {q}");
        }
    }

    #[test]
    fn order_keys_sort_as_total_cmp_and_give_the_values_back() {
        let values = [
            f32::NEG_INFINITY,
            -3.0e38,
            -2.0,
            -1.0,
            -f32::MIN_POSITIVE,
            -1e-45,
            -0.0,
            0.0,
            1e-45,
            f32::MIN_POSITIVE,
            0.5,
            1.0,
            1.0000001,
            3.0e38,
            f32::INFINITY,
        ];
        for pair in values.windows(2) {
            assert!(order_key(pair[0]) < order_key(pair[1]), "{pair:?}");
        }
        for &x in &values {
            assert_eq!(key_value(order_key(x)).to_bits(), x.to_bits());
        }
        // The split's sort key: the centre's key first, then the index.
        let item = |x: f32, index| Item {
            key: [order_key(x); 3],
            index,
        };
        assert!(item(-1.0, 9).along(0) < item(-0.5, 0).along(0));
        assert!(item(-0.5, 0).along(1) < item(-0.5, 1).along(1));
        assert!(item(-0.5, 7).along(2) < item(0.25, 0).along(2));
    }

    #[test]
    fn an_empty_hierarchy_finds_nothing() {
        let (bvh, order) = Bvh::build(0, |_| [DVec3::ZERO; 2]);
        assert!(order.is_empty());
        assert_eq!(
            bvh.nearest(DVec3::ZERO, 1.0, &mut Stack::new(), |_| 0.0),
            1.0
        );
    }
}
