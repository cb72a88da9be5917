//! Point-to-point ICP against the voxel map, as upstream's `Registration`: nearest neighbour
//! in the 27 surrounding voxels, kept when closer than `max_distance`, Gauss–Newton with
//! Geman–McClure weights `κ² / (κ + r²)²`, update `exp(dx)` applied on the left, stop when
//! `‖dx‖ < convergence`.

use nalgebra::{Isometry3, Matrix6, Point3, Vector6};
use rayon::prelude::*;

use super::neighbours::{ChunkAround, NeighbourCache};
use super::voxel_map::VoxelHashMap;
use crate::se3;

/// Points per parallel work item; sums are reduced in chunk order, so the result does not
/// depend on the number of threads.
const CHUNK: usize = 512;

/// Solver settings.
#[derive(Debug, Clone, Copy)]
pub struct IcpSettings {
    pub max_iterations: usize,
    pub convergence: f64,
    pub max_distance: f64,
    pub kernel: f64,
}

/// Result of one alignment.
#[derive(Debug, Clone, Copy)]
pub struct IcpResult {
    pub pose: Isometry3<f64>,
    pub iterations: usize,
    pub converged: bool,
    /// Correspondences in the last iteration.
    pub correspondences: usize,
}

/// The normal equations `JᵀWJ`, `JᵀWr` of point-to-point residuals (twist `[ρ, φ]`, left
/// perturbation about the world origin) and their count.
#[derive(Clone, Copy)]
pub(crate) struct System {
    pub(crate) jtj: Matrix6<f64>,
    pub(crate) jtr: Vector6<f64>,
    pub(crate) count: usize,
}

impl System {
    pub(crate) fn zero() -> Self {
        Self {
            jtj: Matrix6::zeros(),
            jtr: Vector6::zeros(),
            count: 0,
        }
    }
    pub(crate) fn add(mut self, other: &System) -> Self {
        self.jtj += other.jtj;
        self.jtr += other.jtr;
        self.count += other.count;
        self
    }
}

/// Aligns `frame` (sensor frame) to `map` starting from `initial_guess`.
/// `scratch` is reused between calls to avoid allocating per frame.
pub fn align(
    frame: &[Point3<f64>],
    map: &VoxelHashMap,
    initial_guess: &Isometry3<f64>,
    settings: &IcpSettings,
    scratch: &mut Vec<Point3<f64>>,
) -> IcpResult {
    let mut result = IcpResult {
        pose: *initial_guess,
        iterations: 0,
        converged: false,
        correspondences: 0,
    };
    if map.is_empty() || frame.is_empty() {
        return result;
    }
    scratch.clear();
    scratch.extend(frame.iter().map(|p| initial_guess * p));
    let mut t_icp = Isometry3::identity();
    let mut around = NeighbourCache::default();
    for iteration in 1..=settings.max_iterations {
        let system = build_system(scratch, map, settings, &mut around);
        result.iterations = iteration;
        result.correspondences = system.count;
        let Some(dx) = solve(&system) else { break };
        let step = se3::exp(&dx);
        scratch
            .par_iter_mut()
            .with_min_len(CHUNK)
            .for_each(|p| *p = step * *p);
        t_icp = step * t_icp;
        t_icp.rotation.renormalize();
        if dx.norm() < settings.convergence {
            result.converged = true;
            break;
        }
    }
    result.pose = t_icp * initial_guess;
    result.pose.rotation.renormalize();
    result
}

/// The system of every point of `source` (world frame) with a map neighbour closer than
/// `s.max_distance`, Geman–McClure weighted with scale `s.kernel`. `around` keeps each
/// point's map blocks between calls of one alignment (in chunks of `CHUNK` source points).
pub(crate) fn build_system<'m>(
    source: &[Point3<f64>],
    map: &'m VoxelHashMap,
    s: &IcpSettings,
    around: &mut NeighbourCache<'m>,
) -> System {
    let partials: Vec<System> = source
        .par_chunks(CHUNK)
        .zip(around.chunks(source.len(), CHUNK).par_iter_mut())
        .map(|(chunk, around)| chunk_system(chunk, around, map, s))
        .collect();
    partials.iter().fold(System::zero(), System::add)
}

fn chunk_system<'m>(
    chunk: &[Point3<f64>],
    around: &mut ChunkAround<'m>,
    map: &'m VoxelHashMap,
    s: &IcpSettings,
) -> System {
    let mut sys = System::zero();
    let kappa2 = s.kernel * s.kernel;
    for (i, p) in chunk.iter().enumerate() {
        // Voxels that cannot hold a point closer than the threshold are not searched; the
        // correspondences are the ones upstream's full search followed by the threshold gives.
        let Some((q, _)) = around.closest(i, map, p, s.max_distance) else {
            continue;
        };
        let r = p - q;
        let w = kappa2 / (s.kernel + r.norm_squared()).powi(2);
        accumulate(&mut sys, p, &r, w);
    }
    sys
}

/// Adds `w·JᵀJ` and `w·Jᵀr` for `J = [I | −hat(p)]`.
#[inline]
fn accumulate(sys: &mut System, p: &Point3<f64>, r: &nalgebra::Vector3<f64>, w: f64) {
    let mut j = nalgebra::Matrix3x6::<f64>::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
    j.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-se3::hat(&p.coords)));
    let jt = j.transpose();
    sys.jtj += jt * j * w;
    sys.jtr += jt * r * w;
    sys.count += 1;
}

/// Solves `JᵀJ dx = −Jᵀr`; `None` without correspondences or with a non-finite system.
fn solve(sys: &System) -> Option<Vector6<f64>> {
    if sys.count == 0 || !sys.jtj.iter().chain(sys.jtr.iter()).all(|v| v.is_finite()) {
        return None;
    }
    let rhs = -sys.jtr;
    if let Some(chol) = sys.jtj.cholesky() {
        return Some(chol.solve(&rhs));
    }
    // Rank-deficient (degenerate geometry): least-squares solution, as LDLT would give.
    let svd = sys.jtj.try_svd(true, true, 1e-12, 200)?;
    svd.solve(&rhs, 1e-12)
        .ok()
        .filter(|dx| dx.iter().all(|v| v.is_finite()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Points scattered (not on a lattice, which would alias) over three walls and a floor.
    fn box_cloud() -> Vec<Point3<f64>> {
        let mut state = 12345u64;
        let mut rnd = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..6000)
            .map(|i| {
                let (a, b) = (rnd() * 10.0 - 5.0, rnd() * 4.0);
                match i % 4 {
                    0 => Point3::new(a, 5.0, b),
                    1 => Point3::new(a, -5.0, b),
                    2 => Point3::new(5.0, a, b),
                    _ => Point3::new(a, b - 2.0, -1.0),
                }
            })
            .collect()
    }

    #[test]
    fn recovers_a_small_rigid_motion() {
        let target = box_cloud();
        let mut map = VoxelHashMap::new(1.0, 100.0, 1000);
        map.update(&target, &Isometry3::identity());
        let truth = Isometry3::from_parts(
            Translation3::new(0.2, -0.1, 0.05),
            UnitQuaternion::from_euler_angles(0.01, -0.01, 0.05),
        );
        let source: Vec<_> = target.iter().map(|p| truth.inverse() * p).collect();
        let settings = IcpSettings {
            max_iterations: 500,
            convergence: 1e-4,
            max_distance: 3.0,
            kernel: 1.0,
        };
        let r = align(
            &source,
            &map,
            &Isometry3::identity(),
            &settings,
            &mut Vec::new(),
        );
        let err = r.pose.inverse() * truth;
        assert!(r.converged);
        assert!(err.translation.vector.norm() < 0.01, "{err}");
        assert!(err.rotation.angle() < 0.002);
    }
}
