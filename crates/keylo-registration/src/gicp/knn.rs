//! A k-d tree for the k nearest neighbours of many queries in one cloud (GICP's patches: k = 20
//! for every registered and every admitted point of a frame), its nearest point and the points
//! within a radius. Built once per cloud by median splits along the widest axis into leaves of
//! at most [`LEAF`] points stored contiguously; a query descends to the nearer child first and
//! visits the farther one only when the splitting plane is nearer than its current k-th
//! neighbour. Exact: the same neighbours as a brute-force search (ties aside).

use nalgebra::Point3;

/// Points per leaf at most.
const LEAF: usize = 12;

/// A node: a leaf's range of `points`, or a split with its children.
#[derive(Debug, Clone, Copy)]
enum Node {
    Leaf { start: u32, end: u32 },
    Split(Cut),
}

/// A split: points below `value` along `axis` are in `left`, the others in `right`.
#[derive(Debug, Clone, Copy)]
struct Cut {
    axis: u8,
    value: f64,
    left: u32,
    right: u32,
}

impl Cut {
    /// The child on `q`'s side, the other one, and `q`'s signed distance to the plane.
    #[inline]
    fn sides(&self, q: &[f64; 3]) -> (u32, u32, f64) {
        let diff = q[usize::from(self.axis)] - self.value;
        if diff < 0.0 {
            (self.left, self.right, diff)
        } else {
            (self.right, self.left, diff)
        }
    }
}

/// The tree over a cloud's points.
#[derive(Debug, Clone)]
pub struct KnnTree {
    nodes: Vec<Node>,
    /// The points in leaf order, with their index in the cloud.
    points: Vec<([f64; 3], u32)>,
}

impl KnnTree {
    /// Builds the tree of `cloud` (which may be empty).
    pub fn new(cloud: &[Point3<f64>]) -> Self {
        let mut points: Vec<([f64; 3], u32)> = (0u32..)
            .zip(cloud)
            .map(|(i, p)| ([p.x, p.y, p.z], i))
            .collect();
        let mut nodes = Vec::with_capacity(2 * cloud.len() / LEAF + 1);
        if !points.is_empty() {
            let n = points.len();
            build(&mut nodes, &mut points, 0, n);
        }
        Self { nodes, points }
    }

    /// The (at most) `k` nearest points to `q`: `(index in the cloud, squared distance)`, in no
    /// particular order, appended to `out` (cleared first).
    pub fn nearest_k(&self, q: &Point3<f64>, k: usize, out: &mut Vec<(u32, f64)>) {
        out.clear();
        if self.nodes.is_empty() || k == 0 {
            return;
        }
        let mut best = Best::new(k, out);
        self.search(0, &[q.x, q.y, q.z], &mut best);
    }

    /// The nearest point to `q`: `(index in the cloud, squared distance)`; `None` for an empty
    /// cloud.
    pub fn nearest(&self, q: &Point3<f64>) -> Option<(u32, f64)> {
        let mut out = Vec::with_capacity(1);
        self.nearest_k(q, 1, &mut out);
        out.first().copied()
    }

    /// Appends to `out` the indices of the points closer than `radius` to `q`.
    pub fn within(&self, q: &Point3<f64>, radius: f64, out: &mut Vec<u32>) {
        if self.nodes.is_empty() {
            return;
        }
        let r2 = radius * radius;
        let q = [q.x, q.y, q.z];
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            match self.nodes[i as usize] {
                Node::Leaf { start, end } => {
                    for (p, index) in &self.points[start as usize..end as usize] {
                        if d2(p, &q) < r2 {
                            out.push(*index);
                        }
                    }
                }
                Node::Split(cut) => {
                    let (near, far, diff) = cut.sides(&q);
                    stack.push(near);
                    if diff * diff < r2 {
                        stack.push(far);
                    }
                }
            }
        }
    }

    fn search(&self, i: u32, q: &[f64; 3], best: &mut Best<'_>) {
        match self.nodes[i as usize] {
            Node::Leaf { start, end } => {
                for (p, index) in &self.points[start as usize..end as usize] {
                    best.offer(*index, d2(p, q));
                }
            }
            Node::Split(cut) => {
                let (near, far, diff) = cut.sides(q);
                self.search(near, q, best);
                if diff * diff < best.bound() {
                    self.search(far, q, best);
                }
            }
        }
    }
}

#[inline]
fn d2(p: &[f64; 3], q: &[f64; 3]) -> f64 {
    let (a, b, c) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    a * a + b * b + c * c
}

/// Builds the subtree of `points[start..end]`, returns its node's index.
fn build(nodes: &mut Vec<Node>, points: &mut [([f64; 3], u32)], start: usize, end: usize) -> u32 {
    let me = nodes.len() as u32;
    if end - start <= LEAF {
        nodes.push(Node::Leaf {
            start: start as u32,
            end: end as u32,
        });
        return me;
    }
    let slice = &mut points[start..end];
    let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for (p, _) in slice.iter() {
        for k in 0..3 {
            low[k] = low[k].min(p[k]);
            high[k] = high[k].max(p[k]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (high[a] - low[a]).total_cmp(&(high[b] - low[b])))
        .unwrap_or(0);
    let mid = slice.len() / 2;
    slice.select_nth_unstable_by(mid, |a, b| {
        a.0[axis].total_cmp(&b.0[axis]).then(a.1.cmp(&b.1))
    });
    let value = slice[mid].0[axis];
    nodes.push(Node::Leaf { start: 0, end: 0 });
    let left = build(nodes, points, start, start + mid);
    let right = build(nodes, points, start + mid, end);
    nodes[me as usize] = Node::Split(Cut {
        axis: axis as u8,
        value,
        left,
        right,
    });
    me
}

/// The k best candidates so far (unordered) and the worst of them.
struct Best<'a> {
    k: usize,
    items: &'a mut Vec<(u32, f64)>,
    worst: usize,
}

impl<'a> Best<'a> {
    fn new(k: usize, items: &'a mut Vec<(u32, f64)>) -> Self {
        Self { k, items, worst: 0 }
    }

    /// The squared distance a candidate must beat (infinite until k are held).
    #[inline]
    fn bound(&self) -> f64 {
        if self.items.len() < self.k {
            f64::INFINITY
        } else {
            self.items[self.worst].1
        }
    }

    #[inline]
    fn offer(&mut self, index: u32, d2: f64) {
        if self.items.len() < self.k {
            self.items.push((index, d2));
            if self.items.len() == self.k {
                self.find_worst();
            }
        } else if d2 < self.items[self.worst].1 {
            self.items[self.worst] = (index, d2);
            self.find_worst();
        }
    }

    fn find_worst(&mut self) {
        let mut w = 0;
        for (i, item) in self.items.iter().enumerate() {
            if item.1 > self.items[w].1 {
                w = i;
            }
        }
        self.worst = w;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scenes::{rnd, room};

    /// The same k nearest distances, nearest point and radius sets as brute force.
    #[test]
    fn finds_what_brute_force_finds() {
        let mut pts = room();
        let mut s = 3u64;
        pts.extend((0..500).map(|_| {
            Point3::new(
                rnd(&mut s) * 10.0 - 5.0,
                rnd(&mut s) * 8.0 - 4.0,
                rnd(&mut s) * 3.0 - 1.0,
            )
        }));
        let tree = KnnTree::new(&pts);
        let mut out = Vec::new();
        for _ in 0..300 {
            let q = Point3::new(
                rnd(&mut s) * 12.0 - 6.0,
                rnd(&mut s) * 10.0 - 5.0,
                rnd(&mut s) * 4.0 - 2.0,
            );
            let mut all: Vec<f64> = pts.iter().map(|p| (p - q).norm_squared()).collect();
            all.sort_by(f64::total_cmp);
            for k in [1, 5, 20] {
                tree.nearest_k(&q, k, &mut out);
                let mut got: Vec<f64> = out.iter().map(|o| o.1).collect();
                got.sort_by(f64::total_cmp);
                assert_eq!(got, all[..k].to_vec());
                for (i, d) in &out {
                    assert_eq!((pts[*i as usize] - q).norm_squared(), *d);
                }
            }
            assert_eq!(tree.nearest(&q).map(|n| n.1), Some(all[0]));
            let mut near = Vec::new();
            tree.within(&q, 0.7, &mut near);
            let expected = all.iter().filter(|d| **d < 0.49).count();
            assert_eq!(near.len(), expected);
        }
        assert!(KnnTree::new(&[]).nearest(&Point3::origin()).is_none());
    }
}
