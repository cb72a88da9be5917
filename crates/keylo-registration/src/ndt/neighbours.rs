//! Which target voxels a transformed source point is scored against: PCL's neighbour
//! search methods `DIRECT1`, `DIRECT7` and `RADIUS` (a k-d tree of voxel means, `kiddo`).

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

use super::voxel_grid::{require_cells, Cell, Distributions, GridSettings};
use crate::voxel::voxel_of;
use crate::RegistrationError;

/// Neighbour search of a transformed source point among the target voxels.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum NeighbourSearch {
    /// Every voxel whose mean lies within one resolution of the point (k-d tree radius search,
    /// PCL's default `RADIUS`).
    #[default]
    Radius,
    /// The voxel holding the point and its six face neighbours (PCL `DIRECT7`).
    Direct7,
    /// Only the voxel holding the point (PCL `DIRECT1`; fastest, narrowest basin).
    Direct1,
}

const FACES: [[i32; 3]; 7] = [
    [0, 0, 0],
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
];

/// The NDT target: voxel distributions plus the structure its neighbour search needs.
pub struct NdtTarget {
    distributions: Distributions,
    tree: Option<ImmutableKdTree<f64, 3>>,
    search: NeighbourSearch,
    resolution: f64,
}

impl NdtTarget {
    /// Builds the target from finite `points`; an error when no voxel is usable.
    pub fn new(
        points: &[Point3<f64>],
        settings: &GridSettings,
        search: NeighbourSearch,
    ) -> Result<Self, RegistrationError> {
        let distributions = Distributions::build(points, settings);
        require_cells(&distributions, points.len(), settings)?;
        let tree = match search {
            NeighbourSearch::Radius => {
                let means: Vec<[f64; 3]> = distributions
                    .cells
                    .iter()
                    .map(|c| [c.mean.x, c.mean.y, c.mean.z])
                    .collect();
                Some(ImmutableKdTree::new_from_slice(&means).map_err(|e| {
                    RegistrationError::BadCloud(format!("NDT target k-d tree: {e:?}"))
                })?)
            }
            NeighbourSearch::Direct7 | NeighbourSearch::Direct1 => None,
        };
        Ok(Self {
            distributions,
            tree,
            search,
            resolution: settings.resolution,
        })
    }

    /// The usable target voxels.
    pub fn cells(&self) -> &[Cell] {
        self.distributions.cells()
    }

    /// Voxel edge (m).
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// Calls `f` with every cell `p` is scored against.
    #[inline]
    pub fn for_each_neighbour(&self, p: &Point3<f64>, mut f: impl FnMut(&Cell)) {
        let cells = &self.distributions.cells;
        match (self.search, &self.tree) {
            (NeighbourSearch::Radius, Some(tree)) => {
                let r2 = self.resolution * self.resolution;
                tree.query(&[p.x, p.y, p.z])
                    .within::<SquaredEuclidean<f64>>(r2)
                    .unsorted()
                    .visit(|hit| {
                        if let Some(c) = cells.get(hit.item as usize) {
                            f(c);
                        }
                    });
            }
            (NeighbourSearch::Direct7, _) => {
                let v = voxel_of(p, self.resolution);
                for d in FACES {
                    let key = [
                        v[0].saturating_add(d[0]),
                        v[1].saturating_add(d[1]),
                        v[2].saturating_add(d[2]),
                    ];
                    if let Some(&i) = self.distributions.index.get(&key) {
                        f(&cells[i as usize]);
                    }
                }
            }
            _ => {
                let key = voxel_of(p, self.resolution);
                if let Some(&i) = self.distributions.index.get(&key) {
                    f(&cells[i as usize]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×3×1 slab of voxels, each with a small cloud around its centre.
    fn slab() -> Vec<Point3<f64>> {
        let mut pts = Vec::new();
        for (i, j) in (0..3).flat_map(|i| (0..3).map(move |j| (i, j))) {
            for k in 0..12 {
                let t = f64::from(k);
                pts.push(Point3::new(
                    f64::from(i) + 0.3 + 0.03 * t,
                    f64::from(j) + 0.4 + 0.02 * (t * 1.7).sin(),
                    0.5 + 0.02 * (t * 2.3).cos(),
                ));
            }
        }
        pts
    }

    fn count(search: NeighbourSearch, p: Point3<f64>) -> usize {
        let target = NdtTarget::new(&slab(), &GridSettings::default(), search).unwrap();
        let mut n = 0;
        target.for_each_neighbour(&p, |_| n += 1);
        n
    }

    #[test]
    fn direct_modes_visit_the_voxel_and_its_faces() {
        let centre = Point3::new(1.5, 1.5, 0.5);
        assert_eq!(count(NeighbourSearch::Direct1, centre), 1);
        assert_eq!(count(NeighbourSearch::Direct7, centre), 5); // ±z voxels are empty
        assert_eq!(
            count(NeighbourSearch::Direct7, Point3::new(0.5, 0.5, 0.5)),
            3
        );
        assert_eq!(
            count(NeighbourSearch::Direct1, Point3::new(7.0, 0.0, 0.0)),
            0
        );
    }

    #[test]
    fn radius_search_matches_a_brute_force_scan() {
        let target =
            NdtTarget::new(&slab(), &GridSettings::default(), NeighbourSearch::Radius).unwrap();
        for p in [
            Point3::new(1.5, 1.5, 0.5),
            Point3::new(0.2, 2.9, 0.1),
            Point3::new(9.0, 9.0, 9.0),
        ] {
            let mut got = Vec::new();
            target.for_each_neighbour(&p, |c| got.push(c.mean));
            let want = target
                .cells()
                .iter()
                .filter(|c| (c.mean - p.coords).norm_squared() <= 1.0)
                .count();
            assert_eq!(got.len(), want, "{p}");
        }
    }
}
