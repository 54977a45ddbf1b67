//! The cluster tree: recursive bisection of the points (docs/math.md §13.1).

use crate::points::Points;

/// One cluster: the points `perm[start..end]` of the cluster order and their bounding box.
#[derive(Debug, Clone)]
pub(crate) struct Cluster {
    /// First position in cluster order.
    pub start: usize,
    /// One past the last position in cluster order.
    pub end: usize,
    /// Lower corner of the bounding box (unused coordinates 0).
    pub lo: [f64; 3],
    /// Upper corner of the bounding box.
    pub hi: [f64; 3],
    /// Indices of the two sons in the tree's node list, if any.
    pub sons: Option<(usize, usize)>,
}

impl Cluster {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.end - self.start
    }

    /// Diameter of the bounding box (Euclidean).
    pub fn diam(&self) -> f64 {
        (0..3)
            .map(|c| (self.hi[c] - self.lo[c]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Euclidean distance between two bounding boxes (0 if they overlap).
    pub fn dist(&self, other: &Cluster) -> f64 {
        (0..3)
            .map(|c| {
                let gap = (self.lo[c] - other.hi[c]).max(other.lo[c] - self.hi[c]);
                gap.max(0.0).powi(2)
            })
            .sum::<f64>()
            .sqrt()
    }
}

/// Binary cluster tree by bisection along the longest side of the bounding box, splitting
/// at the median (the two halves differ by at most one point, or by a run of coincident
/// points, which are never separated), down to `leaf_size` points.
#[derive(Debug, Clone)]
pub(crate) struct ClusterTree {
    /// The nodes; the root is node 0 (absent for no points).
    pub nodes: Vec<Cluster>,
    /// Cluster order → original index.
    pub perm: Vec<usize>,
}

impl ClusterTree {
    /// Builds the tree. Deterministic: ties in the coordinate are broken by the index.
    pub fn new(points: &Points, leaf_size: usize) -> Self {
        let n = points.len();
        let mut tree = Self {
            nodes: Vec::new(),
            perm: (0..n).collect(),
        };
        if n > 0 {
            tree.build(points, 0, n, leaf_size.max(1));
        }
        tree
    }

    fn build(&mut self, points: &Points, start: usize, end: usize, leaf_size: usize) -> usize {
        let dim = points.dim();
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for c in 0..dim {
            lo[c] = f64::INFINITY;
            hi[c] = f64::NEG_INFINITY;
        }
        for &i in &self.perm[start..end] {
            for (c, &x) in points.point(i).iter().enumerate() {
                lo[c] = lo[c].min(x);
                hi[c] = hi[c].max(x);
            }
        }
        let id = self.nodes.len();
        self.nodes.push(Cluster {
            start,
            end,
            lo,
            hi,
            sons: None,
        });
        if end - start <= leaf_size {
            return id;
        }
        let axis = (0..dim)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(b.cmp(&a)))
            .unwrap_or(0);
        self.perm[start..end].sort_by(|&a, &b| {
            points.point(a)[axis]
                .total_cmp(&points.point(b)[axis])
                .then(a.cmp(&b))
        });
        // The median, moved past a run of coincident points so that it never separates
        // them: a node's slip components (coincident points, consecutive indices, so
        // adjacent in this order) stay in one leaf, and so in one part of a row split
        // (`HMatrix::split_rows`; a process that shares the product computes whole nodes).
        // A cluster of coincident points only stays a leaf.
        let same = |a: usize, b: usize| points.point(self.perm[a]) == points.point(self.perm[b]);
        let mut mid = start + (end - start) / 2;
        while mid < end && same(mid - 1, mid) {
            mid += 1;
        }
        if mid == end {
            mid = start + (end - start) / 2;
            while mid > start && same(mid - 1, mid) {
                mid -= 1;
            }
            if mid == start {
                return id;
            }
        }
        let left = self.build(points, start, mid, leaf_size);
        let right = self.build(points, mid, end, leaf_size);
        self.nodes[id].sons = Some((left, right));
        id
    }

    /// The leaves in cluster order (their ranges are consecutive and cover `0..n`).
    pub fn leaves(&self) -> Vec<usize> {
        let mut out = Vec::new();
        if !self.nodes.is_empty() {
            self.collect_leaves(0, &mut out);
        }
        out
    }

    fn collect_leaves(&self, id: usize, out: &mut Vec<usize>) {
        match self.nodes[id].sons {
            None => out.push(id),
            Some((a, b)) => {
                self.collect_leaves(a, out);
                self.collect_leaves(b, out);
            }
        }
    }
}
