//! A pose graph for SLAM back ends (`pose_graph.g2o`): one `VERTEX_SE3:QUAT` per keyframe and
//! one `EDGE_SE3:QUAT` odometry edge between consecutive keyframes, whose information is
//! keylo's own estimate of the motion's uncertainty (the registrars' per-frame covariances,
//! calibrated, carried along the frames between the keyframes), not a constant.

use std::fmt::Write as _;
use std::path::Path;

use keylo_core::{FrameResult, Pose};
use nalgebra::Matrix6;

use crate::covariance::{frame_covariance, g2o_information, matrix, relative, NoiseModel};
use crate::keyframes::KeyframePolicy;
use crate::MapError;

/// The covariance (m², rad²) of a frame without an estimate of its own (the registrar makes
/// no degeneracy analysis, or its matrix is singular): the constant KISS-ICP's ROS node
/// publishes for every frame, so such an edge is weak rather than over-confident.
pub const FALLBACK_VARIANCE: f64 = 0.1;

/// Builds the graph frame by frame.
pub struct PoseGraph {
    policy: KeyframePolicy,
    noise: NoiseModel,
    /// The previous frame's pose (the distance each frame moved).
    last_pose: Option<Pose>,
    vertices: Vec<(f64, Pose)>,
    /// `(from, to, measured motion, covariance of its right perturbation)`.
    edges: Vec<(usize, usize, Pose, Matrix6<f64>)>,
    /// World-frame covariances summed over the frames since the last keyframe.
    since_keyframe: Matrix6<f64>,
    /// Frames whose covariance was the fallback.
    pub fallbacks: usize,
}

impl PoseGraph {
    /// A graph with keyframes every `distance` m or `angle_deg` degrees, each frame's motion
    /// covariance from `noise`.
    pub fn new(distance: f64, angle_deg: f64, noise: NoiseModel) -> Self {
        Self {
            policy: KeyframePolicy::new(distance, angle_deg),
            noise,
            last_pose: None,
            vertices: Vec::new(),
            edges: Vec::new(),
            since_keyframe: Matrix6::zeros(),
            fallbacks: 0,
        }
    }

    /// Adds a registered frame; returns whether it became a keyframe (a vertex).
    pub fn add(&mut self, r: &FrameResult) -> bool {
        if let (false, Some(last)) = (self.vertices.is_empty(), self.last_pose) {
            let h_inv = r.degeneracy.as_ref().and_then(|d| d.covariance(1.0));
            self.since_keyframe += match h_inv {
                Some(h) => frame_covariance(&self.noise, &matrix(&h), &r.pose, Some(&last)),
                None => {
                    self.fallbacks += 1;
                    Matrix6::identity() * FALLBACK_VARIANCE
                }
            };
        }
        self.last_pose = Some(r.pose);
        if !self.policy.take(&r.pose) {
            return false;
        }
        if let Some(&(_, last)) = self.vertices.last() {
            let c = relative(&r.pose, &self.since_keyframe);
            let n = self.vertices.len();
            self.edges.push((n - 1, n, last.inverse() * r.pose, c));
        }
        self.vertices.push((r.stamp, r.pose));
        self.since_keyframe = Matrix6::zeros();
        true
    }

    /// The vertices: each keyframe's stamp and pose.
    pub fn vertices(&self) -> &[(f64, Pose)] {
        &self.vertices
    }

    /// The edges: `(from, to, measured motion from⁻¹·to, covariance)`, the covariance of a
    /// right perturbation of the motion in the order `[Δt, Δθ]`.
    pub fn edges(&self) -> impl Iterator<Item = (usize, usize, &Pose, &Matrix6<f64>)> {
        self.edges.iter().map(|(a, b, m, c)| (*a, *b, m, c))
    }

    /// Vertices (keyframes) so far.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether the graph has no vertex.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// The graph in g2o's text format: vertices, `FIX 0`, edges (information as upper
    /// triangles, row by row).
    pub fn to_g2o(&self) -> String {
        let mut out = String::new();
        for (i, (_, p)) in self.vertices.iter().enumerate() {
            let _ = writeln!(out, "VERTEX_SE3:QUAT {i} {}", pose_text(p));
        }
        if !self.vertices.is_empty() {
            out.push_str("FIX 0\n");
        }
        for (a, b, m, c) in &self.edges {
            // A singular covariance (no frame between): as constrained as the fallback.
            let info =
                g2o_information(c).unwrap_or_else(|| Matrix6::identity() / FALLBACK_VARIANCE);
            let _ = write!(out, "EDGE_SE3:QUAT {a} {b} {}", pose_text(m));
            for i in 0..6 {
                for j in i..6 {
                    let _ = write!(out, " {:?}", info[(i, j)]);
                }
            }
            out.push('\n');
        }
        out
    }

    /// Writes [`Self::to_g2o`] to `path`.
    pub fn write(&self, path: &Path) -> Result<(), MapError> {
        std::fs::write(path, self.to_g2o()).map_err(|e| MapError::io(path, e))
    }
}

/// `x y z qx qy qz qw` (the quaternion with `qw ≥ 0`), shortest exact numbers.
fn pose_text(p: &Pose) -> String {
    let t = p.translation.vector;
    let mut q = p.rotation.coords;
    if q.w < 0.0 {
        q = -q;
    }
    format!(
        "{:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        t.x, t.y, t.z, q.x, q.y, q.z, q.w
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use keylo_core::Degeneracy;
    use nalgebra::Vector3;

    fn result(k: u64, pose: Pose, degeneracy: Option<Degeneracy>) -> FrameResult {
        FrameResult {
            degeneracy,
            ..FrameResult::with_pose(k, 0.1 * k as f64, pose)
        }
    }

    fn isotropic(information: f64) -> Degeneracy {
        let mut eigenvectors = [[0.0; 6]; 6];
        for (i, v) in eigenvectors.iter_mut().enumerate() {
            v[i] = 1.0;
        }
        Degeneracy {
            eigenvalues: [information; 6],
            eigenvectors,
            condition: 1.0,
            weak: 0,
            length_scale: 1.0,
            residuals: 1,
        }
    }

    /// Parses the numbers after the tag of every line starting with `tag`.
    fn lines(text: &str, tag: &str) -> Vec<Vec<f64>> {
        text.lines()
            .filter(|l| l.starts_with(tag))
            .map(|l| {
                l.split_whitespace()
                    .skip(1)
                    .map(|v| v.parse().unwrap())
                    .collect()
            })
            .collect()
    }

    #[test]
    fn keyframes_become_vertices_and_edges_carry_the_summed_covariance() {
        let noise = NoiseModel::plain(0.1);
        let mut g = PoseGraph::new(1.0, 90.0, noise);
        // 0.25 m a frame along x, turning slowly: keyframes at frames 0, 4, 8.
        for k in 0..9u64 {
            let pose = Pose::new(
                Vector3::new(0.25 * k as f64, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 0.01 * k as f64),
            );
            let d = (k != 5).then(|| isotropic(100.0));
            g.add(&result(k, pose, d));
        }
        assert_eq!((g.len(), g.fallbacks), (3, 1));
        let text = g.to_g2o();
        let vertices = lines(&text, "VERTEX_SE3:QUAT");
        let edges = lines(&text, "EDGE_SE3:QUAT");
        assert_eq!((vertices.len(), edges.len()), (3, 2));
        assert!(text.contains("\nFIX 0\n"));
        assert_eq!(vertices[1][1], 1.0);
        // Edge 0 → 1: the relative pose of its vertices; 4 frames of σ² H⁻¹ = 0.01 / 100 each.
        let e = &edges[0];
        assert_eq!((e[0], e[1]), (0.0, 1.0));
        assert!((e[2] - 1.0).abs() < 1e-12 && e[3].abs() < 1e-12);
        let info: Vec<f64> = e[9..].to_vec();
        assert_eq!(info.len(), 21);
        // The world sum is isotropic here, so the edge's is too: 4 × 1e-4 → information 2500.
        assert!((info[0] - 2500.0).abs() < 1e-6, "{}", info[0]);
        // Edge 1 → 2 includes frame 5's fallback: far weaker.
        assert!(edges[1][9] < 10.0, "{}", edges[1][9]);
    }
}
