//! The static world: textured primitives in a BVH, and the ray cast that names what it hit.

use std::f32::consts::FRAC_PI_2;

use parry3d::bounding_volume::Aabb;
use parry3d::math::{Pose as GPose, Rotation, Vector as GVec};
use parry3d::partitioning::{Bvh, BvhBuildStrategy};
use parry3d::query::Ray;
use parry3d::shape::{Ball, Cuboid, Cylinder, Shape};

use crate::texture::Material;

/// The geometric primitive of an [`Object`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    /// A box (half extents along its local axes).
    Cuboid(Cuboid),
    /// A cylinder whose axis is its local y axis (parry's convention).
    Cylinder(Cylinder),
    /// A sphere.
    Ball(Ball),
}

impl Primitive {
    fn shape(&self) -> &dyn Shape {
        match self {
            Self::Cuboid(s) => s,
            Self::Cylinder(s) => s,
            Self::Ball(s) => s,
        }
    }
}

/// One textured, static object.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// Its shape, in its local frame.
    pub primitive: Primitive,
    /// Local frame → world.
    pub pose: GPose,
    /// Its surface.
    pub material: Material,
}

impl Object {
    /// A box centred at `center` with half extents `half`, rotated by `yaw` about z.
    pub fn cuboid(center: [f32; 3], half: [f32; 3], yaw: f32, material: Material) -> Self {
        Self {
            primitive: Primitive::Cuboid(Cuboid::new(GVec::from(half))),
            pose: GPose::from_parts(GVec::from(center), Rotation::from_rotation_z(yaw)),
            material,
        }
    }

    /// An axis-aligned box spanning `min..max`.
    pub fn aabb_box(min: [f32; 3], max: [f32; 3], material: Material) -> Self {
        let c = [0, 1, 2].map(|k| 0.5 * (min[k] + max[k]));
        let h = [0, 1, 2].map(|k| 0.5 * (max[k] - min[k]).abs());
        Self::cuboid(c, h, 0.0, material)
    }

    /// A vertical cylinder standing on `base` (centre of its bottom disc).
    pub fn cylinder(base: [f32; 3], radius: f32, height: f32, material: Material) -> Self {
        let center = GVec::new(base[0], base[1], base[2] + 0.5 * height);
        Self {
            primitive: Primitive::Cylinder(Cylinder::new(0.5 * height, radius)),
            pose: GPose::from_parts(center, Rotation::from_rotation_x(FRAC_PI_2)),
            material,
        }
    }

    /// A sphere.
    pub fn ball(center: [f32; 3], radius: f32, material: Material) -> Self {
        Self {
            primitive: Primitive::Ball(Ball::new(radius)),
            pose: GPose::from_translation(GVec::from(center)),
            material,
        }
    }

    /// World-space bounding box.
    pub fn aabb(&self) -> Aabb {
        self.primitive.shape().compute_aabb(&self.pose)
    }

    /// Distance from `p` to the object (0 inside).
    pub fn distance(&self, p: GVec) -> f32 {
        self.primitive
            .shape()
            .distance_to_point(&self.pose, p, true)
    }

    /// Distance from `p` to the object's surface (also from inside).
    pub fn surface_distance(&self, p: GVec) -> f32 {
        self.primitive
            .shape()
            .distance_to_point(&self.pose, p, false)
            .abs()
    }

    /// Face id and `(u, v)` surface coordinates of a local point with local normal `n`.
    fn surface_coords(&self, p: GVec, n: GVec) -> (u32, f32, f32) {
        match &self.primitive {
            Primitive::Cuboid(_) => {
                let a = n.abs();
                let (k, u, v) = if a.x >= a.y && a.x >= a.z {
                    (0, p.y, p.z)
                } else if a.y >= a.z {
                    (1, p.x, p.z)
                } else {
                    (2, p.x, p.y)
                };
                (2 * k + u32::from(n[k as usize] > 0.0), u, v)
            }
            Primitive::Cylinder(c) => {
                if n.y.abs() > 0.7 {
                    (2 + u32::from(n.y > 0.0), p.x, p.z)
                } else {
                    (0, p.z.atan2(p.x) * c.radius, p.y)
                }
            }
            Primitive::Ball(b) => (0, p.y.atan2(p.x) * b.radius, p.z),
        }
    }
}

/// What a ray hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray, metres.
    pub distance: f32,
    /// Unit surface normal in the world frame, facing the ray.
    pub normal: GVec,
    /// Index of the object hit.
    pub object: u32,
    /// Albedo at the hit point (above 1 for retro-reflectors).
    pub albedo: f32,
    /// Near-infrared reflectance factor of the object.
    pub nir_gain: f32,
}

/// A set of objects with a bounding-volume hierarchy over them.
pub struct World {
    objects: Vec<Object>,
    bvh: Bvh,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World")
            .field("objects", &self.objects.len())
            .finish()
    }
}

impl World {
    /// Builds the BVH over `objects`.
    pub fn new(objects: Vec<Object>) -> Self {
        let aabbs: Vec<Aabb> = objects.iter().map(Object::aabb).collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &aabbs);
        Self { objects, bvh }
    }

    /// The objects, in leaf-index order.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// The closest hit of the ray `origin + t·dir` (`dir` unit) with `t ≤ max_dist`.
    pub fn cast(&self, origin: GVec, dir: GVec, max_dist: f32) -> Option<Hit> {
        let ray = Ray::new(origin, dir);
        let (id, _) = self.bvh.cast_ray(&ray, max_dist, |i, best| {
            let o = self.objects.get(i as usize)?;
            o.primitive.shape().cast_ray(&o.pose, &ray, best, true)
        })?;
        let o = self.objects.get(id as usize)?;
        let hit = o
            .primitive
            .shape()
            .cast_ray_and_get_normal(&o.pose, &ray, max_dist, true)?;
        let mut normal = hit.normal.normalize_or_zero();
        if normal.dot(dir) > 0.0 {
            normal = -normal;
        }
        let world_p = ray.point_at(hit.time_of_impact);
        let local_p = o.pose.inverse_transform_point(world_p);
        let local_n = o.pose.rotation.inverse() * normal;
        let (face, u, v) = o.surface_coords(local_p, local_n);
        Some(Hit {
            distance: hit.time_of_impact,
            normal,
            object: id,
            albedo: o.material.albedo(face, u, v),
            nir_gain: o.material.nir_gain,
        })
    }

    /// Distance from `p` to the nearest object (0 inside one).
    pub fn clearance(&self, p: GVec) -> f32 {
        self.objects
            .iter()
            .map(|o| o.distance(p))
            .fold(f32::INFINITY, f32::min)
    }

    /// Distance from `p` to the nearest surface (brute force; for checks and tests).
    pub fn surface_distance(&self, p: GVec) -> f32 {
        self.objects
            .iter()
            .map(|o| o.surface_distance(p))
            .fold(f32::INFINITY, f32::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Pattern;

    fn mat() -> Material {
        Material::new(Pattern::Tiles { cell: 0.5 }, 0.5, 3)
    }

    #[test]
    fn ray_names_the_closest_object() {
        let world = World::new(vec![
            Object::aabb_box([5.0, -1.0, -1.0], [6.0, 1.0, 1.0], mat()),
            Object::aabb_box([2.0, -1.0, -1.0], [3.0, 1.0, 1.0], mat()),
            Object::cylinder([0.0, 4.0, -1.0], 0.5, 2.0, mat()),
            Object::ball([0.0, -4.0, 0.0], 1.0, mat()),
        ]);
        let h = world.cast(GVec::ZERO, GVec::X, 100.0).unwrap();
        assert_eq!(h.object, 1);
        assert!((h.distance - 2.0).abs() < 1e-5);
        assert!((h.normal - (-GVec::X)).length() < 1e-5);
        let h = world.cast(GVec::ZERO, GVec::Y, 100.0).unwrap();
        assert_eq!(h.object, 2);
        assert!((h.distance - 3.5).abs() < 1e-3, "{}", h.distance);
        let h = world.cast(GVec::ZERO, -GVec::Y, 100.0).unwrap();
        assert_eq!(h.object, 3);
        assert!((h.distance - 3.0).abs() < 1e-4);
        assert!(world.cast(GVec::ZERO, GVec::Z, 100.0).is_none());
        assert!(world.cast(GVec::ZERO, GVec::X, 1.5).is_none());
    }

    #[test]
    fn clearance_and_surface_distance() {
        let world = World::new(vec![Object::aabb_box(
            [1.0, -1.0, -1.0],
            [2.0, 1.0, 1.0],
            mat(),
        )]);
        assert!((world.clearance(GVec::ZERO) - 1.0).abs() < 1e-6);
        assert_eq!(world.clearance(GVec::new(1.5, 0.0, 0.0)), 0.0);
        let d = world.surface_distance(GVec::new(1.5, 0.0, 0.0));
        assert!((d - 0.5).abs() < 1e-6);
    }
}
