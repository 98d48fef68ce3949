//! A bounding-volume hierarchy of axis-aligned boxes for nearest-point queries.
//!
//! # Why our own hierarchy
//!
//! parry3d-f64 has a good BVH, but its types are nalgebra's: every position and every
//! query would be converted from glam, its build is not documented to give the same tree
//! for every thread count, and its point–triangle projection reports a feature id in its
//! own numbering, which we would map back to the mesh's edges and vertices for the
//! pseudo-normal sign. A nearest-point query over a static set of triangles needs little,
//! and what it needs is here:
//!
//! - a linear build (Lauterbach et al. 2009, Karras 2012): the items are sorted along a
//!   Morton curve of their box centres on a grid of cubic cells over the centres' bounding
//!   box, and each range of the sorted items is split where the highest bit of the codes
//!   changes (at the middle when all codes of the range are equal). The tree is a function
//!   of the input alone (ties by item index), whatever the thread count. The only
//!   O(n log n) step is a parallel sort of 64-bit keys; the ranges above a threshold are
//!   split first, and the subtrees below it are built in parallel and concatenated;
//! - nodes that hold the boxes of their *two children* (structure of arrays, 112 bytes),
//!   so one node load gives both box tests, and a leaf is named in its parent and needs
//!   no node of its own (one node per leaf, leaves of one to four items);
//! - an iterative traversal with a caller-provided stack that tests both children,
//!   visits the nearer first and prunes by the best squared distance so far.
//!
//! The exact point–triangle distance and the feature classification stay in our hands,
//! in `f64` throughout.
//!
//! # Layout
//!
//! Items (triangles) are permuted into leaf order by [`Bvh::build`]. Node 0 is the root.
//! Child `c` of a node is a leaf when `count[c] > 0` and then holds items
//! `child[c] .. child[c] + count[c]` (in leaf order); otherwise it is node `child[c]`.
//!
//! # References
//! - C. Lauterbach, M. Garland, S. Sengupta, D. Luebke, D. Manocha: *Fast BVH
//!   construction on GPUs*. Computer Graphics Forum 28(2), 2009.
//! - T. Karras: *Maximizing parallelism in the construction of BVHs, octrees, and k-d
//!   trees*. High Performance Graphics 2012.

use glam::DVec3;
use rayon::prelude::*;

/// At most this many items in a leaf.
const LEAF_SIZE: usize = 4;
/// Ranges with more items than this are split before the parallel part of the build; the
/// subtrees below are built in parallel, one task each.
const PARALLEL_MIN: usize = 1 << 14;

/// A node of the flattened hierarchy: the boxes of its two children and what they are.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Lower corners: `lo[axis][child]`.
    lo: [[f64; 2]; 3],
    /// Upper corners: `hi[axis][child]`.
    hi: [[f64; 2]; 3],
    /// Per child: the first item of a leaf, or the index of an interior node.
    child: [u32; 2],
    /// Per child: the item count of a leaf (≥ 1), or 0 for an interior node.
    count: [u32; 2],
}

impl Node {
    /// The squared distances from `p` to the two child boxes (0 inside).
    #[inline]
    fn child_distances(&self, p: [f64; 3]) -> [f64; 2] {
        let mut d2 = [0.0; 2];
        for ((lo, hi), &x) in self.lo.iter().zip(&self.hi).zip(&p) {
            for (c, acc) in d2.iter_mut().enumerate() {
                let d = (lo[c] - x).max(x - hi[c]).max(0.0);
                *acc += d * d;
            }
        }
        d2
    }

    /// A node over two children given as (reference, box).
    fn new(children: [(Child, Aabb); 2]) -> Self {
        let mut node = Self {
            lo: [[0.0; 2]; 3],
            hi: [[0.0; 2]; 3],
            child: [0; 2],
            count: [0; 2],
        };
        for (c, (child, aabb)) in children.into_iter().enumerate() {
            for (axis, value) in node.lo.iter_mut().zip(aabb.lo.to_array()) {
                axis[c] = value;
            }
            for (axis, value) in node.hi.iter_mut().zip(aabb.hi.to_array()) {
                axis[c] = value;
            }
            (node.child[c], node.count[c]) = match child {
                Child::Leaf { first, count } => (first, count),
                Child::Node(index) => (index, 0),
            };
        }
        node
    }
}

/// What a child of a node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Child {
    /// Items `first .. first + count` in leaf order.
    Leaf { first: u32, count: u32 },
    /// An interior node (its index).
    Node(u32),
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Self = Self {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    fn union(self, other: Self) -> Self {
        Self {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }
}

/// A static bounding-volume hierarchy over boxes.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
}

/// A traversal stack, reusable between queries (one per thread or per chunk of queries).
#[derive(Debug, Default)]
pub(crate) struct Stack(Vec<(u32, f64)>);

impl Bvh {
    /// Builds the hierarchy over `n` items with boxes `bounds(i) = [lo, hi]` and returns it
    /// with the leaf order: `order[k]` is the item stored at leaf position `k`.
    /// Deterministic, independent of the thread count.
    ///
    /// # Panics
    /// If there are more than `u32::MAX` items (callers check).
    pub(crate) fn build(n: usize, bounds: impl Fn(usize) -> [DVec3; 2] + Sync) -> (Self, Vec<u32>) {
        let _ = u32::try_from(n).expect("at most u32::MAX items");
        if n == 0 {
            return (Self { nodes: Vec::new() }, Vec::new());
        }
        // Twice the box centres, and their bounding box.
        let centres: Vec<DVec3> = (0..n)
            .into_par_iter()
            .map(|i| {
                let [lo, hi] = bounds(i);
                lo + hi
            })
            .collect();
        let (lo, hi) = centres
            .par_iter()
            .fold(
                || (DVec3::INFINITY, DVec3::NEG_INFINITY),
                |(lo, hi), &c| (lo.min(c), hi.max(c)),
            )
            .reduce(
                || (DVec3::INFINITY, DVec3::NEG_INFINITY),
                |(a, b), (c, d)| (a.min(c), b.max(d)),
            );
        // Cubic cells: one scale for the three axes, so that splits on the code bits cut
        // the longest extent first.
        let extent = (hi - lo).max_element();
        let scale = if extent > 0.0 {
            f64::from(MORTON_CELLS) / extent
        } else {
            0.0
        };
        let mut keys: Vec<(u64, u32)> = centres
            .par_iter()
            .enumerate()
            .map(|(i, &c)| (morton_code((c - lo) * scale), i as u32))
            .collect();
        drop(centres);
        keys.par_sort_unstable();
        let codes: Vec<u64> = keys.iter().map(|&(code, _)| code).collect();
        let order: Vec<u32> = keys.into_iter().map(|(_, i)| i).collect();

        let build = Build {
            codes: &codes,
            order: &order,
            bounds: &bounds,
        };
        // The top of the tree, split sequentially down to ranges of at most `PARALLEL_MIN`
        // items (the tasks), whose subtrees are then built in parallel.
        let mut tasks = Vec::new();
        let plan = build.plan(0, n, &mut tasks);
        let subtrees: Vec<(Vec<Node>, Child, Aabb)> = tasks
            .par_iter()
            .map(|&(start, end)| {
                let mut nodes = Vec::new();
                let (child, aabb) = build.subtree(start, end, &mut nodes);
                (nodes, child, aabb)
            })
            .collect();
        // Layout: the top nodes in depth-first order, then each task's nodes.
        let top = plan.nodes();
        let mut bases = Vec::with_capacity(subtrees.len());
        let mut total = top;
        for (nodes, _, _) in &subtrees {
            bases.push(total);
            total += nodes.len();
        }
        let mut nodes = Vec::with_capacity(total.max(1));
        let root = plan.emit(&subtrees, &bases, &mut nodes);
        for ((task_nodes, _, _), &base) in subtrees.iter().zip(&bases) {
            let shift = base as u32;
            nodes.extend(task_nodes.iter().map(|node| {
                let mut node = *node;
                for (child, &count) in node.child.iter_mut().zip(&node.count) {
                    if count == 0 {
                        *child += shift;
                    }
                }
                node
            }));
        }
        if let (Child::Leaf { .. }, aabb) = root {
            // A single leaf: a root whose two children are that leaf.
            nodes.push(Node::new([root, (root.0, aabb)]));
        }
        debug_assert_eq!(nodes.len(), total.max(1));
        (Self { nodes }, order)
    }

    /// Finds the nearest item to `p`. `bound` is an upper bound of the answer's squared
    /// distance (`f64::INFINITY` when none is known); `visit(k)` is called for every item
    /// (leaf position `k`) whose leaf box is within the current bound and returns the new
    /// bound (the caller keeps the best item). Returns the final bound. `stack` is scratch
    /// space (its content on entry is ignored).
    ///
    /// Boxes at exactly the bound are visited, so a caller can break ties by its own rule.
    #[inline]
    pub(crate) fn nearest(
        &self,
        p: DVec3,
        mut bound: f64,
        stack: &mut Stack,
        mut visit: impl FnMut(usize) -> f64,
    ) -> f64 {
        if self.nodes.is_empty() {
            return bound;
        }
        let stack = &mut stack.0;
        stack.clear();
        let q = p.to_array();
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            let d = node.child_distances(q);
            let order = if d[1] < d[0] { [1, 0] } else { [0, 1] };
            let mut descend = None;
            for c in order {
                if d[c] > bound {
                    continue;
                }
                let count = node.count[c] as usize;
                if count > 0 {
                    let first = node.child[c] as usize;
                    for k in first..first + count {
                        bound = visit(k);
                    }
                } else if descend.is_none() {
                    descend = Some(node.child[c] as usize);
                } else {
                    stack.push((node.child[c], d[c]));
                }
            }
            index = match descend {
                Some(next) => next,
                None => loop {
                    let Some((next, d)) = stack.pop() else {
                        return bound;
                    };
                    if d <= bound {
                        break next as usize;
                    }
                },
            };
        }
    }

    /// The number of nodes.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.nodes.len()
    }
}

/// The top of the tree: split nodes above the parallel tasks.
enum Plan {
    Split(Box<Plan>, Box<Plan>),
    Task(usize),
}

impl Plan {
    /// The number of split nodes.
    fn nodes(&self) -> usize {
        match self {
            Self::Split(left, right) => 1 + left.nodes() + right.nodes(),
            Self::Task(_) => 0,
        }
    }

    /// Writes the split nodes in depth-first order (task subtrees at `bases`) and returns
    /// this part's reference and box.
    fn emit(
        &self,
        subtrees: &[(Vec<Node>, Child, Aabb)],
        bases: &[usize],
        nodes: &mut Vec<Node>,
    ) -> (Child, Aabb) {
        match self {
            Self::Task(t) => {
                let (_, child, aabb) = &subtrees[*t];
                let child = match *child {
                    Child::Node(local) => Child::Node(local + bases[*t] as u32),
                    leaf => leaf,
                };
                (child, *aabb)
            }
            Self::Split(left, right) => {
                let index = nodes.len();
                nodes.push(Node::new([(Child::Node(0), Aabb::EMPTY); 2]));
                let l = left.emit(subtrees, bases, nodes);
                let r = right.emit(subtrees, bases, nodes);
                nodes[index] = Node::new([l, r]);
                (Child::Node(index as u32), l.1.union(r.1))
            }
        }
    }
}

/// What a build reads: the sorted Morton codes, the items in that order, their boxes.
struct Build<'a, F> {
    codes: &'a [u64],
    order: &'a [u32],
    bounds: &'a F,
}

impl<F: Fn(usize) -> [DVec3; 2] + Sync> Build<'_, F> {
    /// Where the sorted range `start .. end` (more than one item) splits: at the first code
    /// with the highest differing bit set, or in the middle when all codes are equal.
    fn split(&self, start: usize, end: usize) -> usize {
        let (first, last) = (self.codes[start], self.codes[end - 1]);
        if first == last {
            return start + (end - start) / 2;
        }
        let bit = 63 - (first ^ last).leading_zeros();
        start + self.codes[start..end].partition_point(|&code| code >> bit & 1 == 0)
    }

    /// Splits `start .. end` sequentially down to ranges of at most [`PARALLEL_MIN`] items,
    /// appended to `tasks` in depth-first order.
    fn plan(&self, start: usize, end: usize, tasks: &mut Vec<(usize, usize)>) -> Plan {
        if end - start <= PARALLEL_MIN {
            tasks.push((start, end));
            return Plan::Task(tasks.len() - 1);
        }
        let mid = self.split(start, end);
        let left = self.plan(start, mid, tasks);
        let right = self.plan(mid, end, tasks);
        Plan::Split(Box::new(left), Box::new(right))
    }

    /// Builds the subtree over the sorted range `start .. end` (at least one item),
    /// appending its interior nodes to `nodes` in depth-first order with indices local to
    /// `nodes`, and returns its reference and box.
    fn subtree(&self, start: usize, end: usize, nodes: &mut Vec<Node>) -> (Child, Aabb) {
        if end - start <= LEAF_SIZE {
            let aabb = self.order[start..end]
                .iter()
                .fold(Aabb::EMPTY, |aabb, &item| {
                    let [lo, hi] = (self.bounds)(item as usize);
                    aabb.union(Aabb { lo, hi })
                });
            let leaf = Child::Leaf {
                first: start as u32,
                count: (end - start) as u32,
            };
            return (leaf, aabb);
        }
        let mid = self.split(start, end);
        let index = nodes.len();
        nodes.push(Node::new([(Child::Node(0), Aabb::EMPTY); 2]));
        let left = self.subtree(start, mid, nodes);
        let right = self.subtree(mid, end, nodes);
        nodes[index] = Node::new([left, right]);
        (Child::Node(index as u32), left.1.union(right.1))
    }
}

/// Cells per axis of the Morton grid (21 bits).
const MORTON_CELLS: u32 = (1 << 21) - 1;

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
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (morton_code((p - lo) * scale), i as u32))
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert!(sorted.iter().enumerate().all(|(k, &i)| k == i as usize));
        for q in [
            DVec3::ZERO,
            DVec3::new(0.3, -2.0, 1.0),
            DVec3::new(5.0, 5.0, 5.0),
        ] {
            let mut best = (f64::INFINITY, usize::MAX);
            bvh.nearest(q, f64::INFINITY, &mut Stack::default(), |k| {
                let i = order[k] as usize;
                let d = (points[i] - q).length_squared();
                if d < best.0 || (d == best.0 && i < best.1) {
                    best = (d, i);
                }
                best.0
            });
            let scan = points
                .iter()
                .map(|p| (p - q).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(best.0, scan);
        }
    }

    #[test]
    fn many_items_and_equal_codes_match_a_scan() {
        // More items than one build task, a third of them at one point (equal Morton
        // codes, split in the middle), the rest in a thin slab.
        let mut state = 0x1234_5678_u64;
        let points: Vec<DVec3> = (0..60_000u32)
            .map(|i| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let r = |shift: u32| ((state >> shift) & 0xFFFF) as f64 / 65535.0;
                if i % 3 == 0 {
                    DVec3::splat(0.25)
                } else {
                    DVec3::new(r(16), r(32), r(48) * 1e-3)
                }
            })
            .collect();
        let (bvh, order) = Bvh::build(points.len(), |i| [points[i], points[i]]);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert!(sorted.iter().enumerate().all(|(k, &i)| k == i as usize));
        let mut stack = Stack::default();
        for q in [
            DVec3::new(0.25, 0.25, 0.25),
            DVec3::new(0.5, 0.5, 0.0),
            DVec3::new(0.1, 0.9, 0.01),
            DVec3::new(-3.0, 2.0, 7.0),
        ] {
            let mut best = f64::INFINITY;
            bvh.nearest(q, f64::INFINITY, &mut stack, |k| {
                best = best.min((points[order[k] as usize] - q).length_squared());
                best
            });
            let scan = points
                .iter()
                .map(|p| (p - q).length_squared())
                .fold(f64::INFINITY, f64::min);
            assert_eq!(best, scan);
        }
    }

    #[test]
    fn a_single_leaf_is_found() {
        let points = [DVec3::X, DVec3::Y];
        let (bvh, order) = Bvh::build(points.len(), |i| [points[i], points[i]]);
        let mut best = f64::INFINITY;
        bvh.nearest(DVec3::ZERO, f64::INFINITY, &mut Stack::default(), |k| {
            best = best.min(points[order[k] as usize].length_squared());
            best
        });
        assert_eq!(best, 1.0);
    }

    #[test]
    fn an_empty_hierarchy_finds_nothing() {
        let (bvh, order) = Bvh::build(0, |_| [DVec3::ZERO; 2]);
        assert!(order.is_empty());
        assert_eq!(
            bvh.nearest(DVec3::ZERO, 1.0, &mut Stack::default(), |_| 0.0),
            1.0
        );
    }
}
