//! From a ray hit to the four Ouster channels of one pixel.
//!
//! * range: true distance plus Gaussian noise;
//! * signal (photon counts): `K · albedo · cos(incidence) / (r² + 0.25)` plus shot noise,
//!   `K` chosen so a 10 % target drops below the detection threshold at the sensor's rated
//!   range (35 m OS0, 45 m OS1); saturates at 65535;
//! * reflectivity: calibrated, `100 · albedo` (retro-reflectors above 100, max 255), with
//!   noise shrinking as the signal grows; independent of range;
//! * near-IR: ambient light reflected by the surface (`direct · max(0, n·l) + diffuse`), with
//!   shot noise; the sky's value for rays that see nothing.

use nalgebra::{Point3, Vector3};
use parry3d::math::Vector as GVec;

use crate::appearance::BeamResponse;
use crate::mixed_pixels::MixedPixels;
use crate::noise::PixelRng;
use crate::partial_drops::PartialDrops;
use crate::scenes::Ambient;
use crate::world::Hit;

/// Weakest signal (counts) that still yields a return.
pub const MIN_SIGNAL: f64 = 3.0;
/// Largest signal count (16-bit).
const MAX_COUNT: f64 = 65535.0;

/// The channel values of one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelReturn {
    /// Whether the pixel holds a return.
    pub valid: bool,
    /// Range, metres (0 when invalid).
    pub range: f32,
    /// Point in the sensor frame (origin when invalid).
    pub point: Point3<f32>,
    /// Signal, photon counts.
    pub signal: f32,
    /// Calibrated reflectivity, 0..=255.
    pub reflectivity: f32,
    /// Ambient near-IR counts.
    pub near_ir: f32,
}

impl Default for PixelReturn {
    fn default() -> Self {
        Self {
            valid: false,
            range: 0.0,
            point: Point3::origin(),
            signal: 0.0,
            reflectivity: 0.0,
            near_ir: 0.0,
        }
    }
}

/// Sensor and scene constants the shading needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shading {
    /// Range noise standard deviation, metres.
    pub range_noise_m: f64,
    /// Minimum valid range, metres.
    pub min_range_m: f64,
    /// Maximum valid range, metres.
    pub max_range_m: f64,
    /// Signal gain `K`.
    pub signal_gain: f64,
    /// Ambient light.
    pub ambient: Ambient,
    /// Below about this range the signal of a real sensor falls short of `1/r²` (transmitter
    /// and receiver see less of each other up close): the signal is scaled by
    /// `r² / (r² + near_field_m²)` (0: not at all). Returns do not depend on it.
    pub near_field_m: f64,
    /// Variance of the signal over its mean (1: photon shot noise alone). A real sensor's
    /// signal is far noisier: its counts sum many pulses, each with its own gain.
    pub noise_factor: f64,
    /// Weak returns are lost at random, as on dark and glossy surfaces: a pixel whose model
    /// signal is `s` counts drops out with probability `1 / (1 + (s / dropout_counts)²)`
    /// (0: never).
    pub dropout_counts: f64,
    /// Fewest counts a reported return reads (0: a return's noise may read 0).
    pub min_return_counts: f64,
    /// Extra power of the cosine of incidence in the reported signal (0: Lambertian alone):
    /// real floors, ceilings and walls seen at grazing angles are darker than Lambert's law
    /// says. Returns do not depend on it.
    pub grazing_power: f64,
    /// Returns measured far too low at random (see [`PartialDrops`]); `None`: never.
    pub partial_drops: Option<PartialDrops>,
    /// Returns beside a range jump dimmed (see [`MixedPixels`]); `None`: never.
    pub mixed_pixels: Option<MixedPixels>,
}

impl Shading {
    /// The pixel seen along `dir_sensor` (sensor frame) / `dir_world`, given what it hit, by
    /// a beam whose signal is `beam`'s gain at the hit's range times the model's. Whether it
    /// returns depends on the model's signal, not the gain.
    pub fn pixel(
        &self,
        hit: Option<&Hit>,
        dir_sensor: &Vector3<f64>,
        dir_world: GVec,
        beam: &BeamResponse,
        rng: &mut PixelRng,
    ) -> PixelReturn {
        let Some(hit) = hit else {
            return PixelReturn {
                near_ir: self.sky(dir_world, rng),
                ..PixelReturn::default()
            };
        };
        let near_ir = self.near_ir(hit, rng);
        let r_true = f64::from(hit.distance);
        let range = r_true + self.range_noise_m * rng.gaussian();
        let albedo = f64::from(hit.albedo);
        let cos_inc = f64::from(hit.normal.dot(dir_world).abs());
        let model = self.signal_gain * albedo * cos_inc / (r_true * r_true + 0.25);
        // One draw of noise for both: the model's signal decides the return, the sensor's
        // (gain, near field, noise factor; all 1 for the ideal model) is what it reports.
        let shot = rng.gaussian();
        let counts = |mean: f64, factor: f64| {
            let mean = mean.min(MAX_COUNT);
            (mean + (factor * mean).sqrt() * shot).clamp(0.0, MAX_COUNT)
        };
        let model_signal = counts(model, 1.0);
        let near = if self.near_field_m > 0.0 {
            let r2 = r_true * r_true;
            r2 / (r2 + self.near_field_m * self.near_field_m)
        } else {
            1.0
        };
        let grazing = if self.grazing_power > 0.0 {
            cos_inc.powf(self.grazing_power)
        } else {
            1.0
        };
        let mean = beam.at(r_true) * near * grazing * model;
        let mut signal = counts(mean, self.noise_factor);
        if let Some(drops) = &self.partial_drops {
            signal *= drops.factor(mean, rng);
        }
        let refl_noise = 0.5 * rng.gaussian() / (signal + 1.0).sqrt();
        let valid =
            model_signal >= MIN_SIGNAL && range >= self.min_range_m && range <= self.max_range_m;
        let dropped = valid
            && self.dropout_counts > 0.0
            && rng.uniform() < 1.0 / (1.0 + (model / self.dropout_counts).powi(2));
        if !valid || dropped {
            return PixelReturn {
                near_ir,
                ..PixelReturn::default()
            };
        }
        PixelReturn {
            valid,
            range: range as f32,
            point: Point3::from(dir_sensor * range).cast::<f32>(),
            signal: signal.round().max(self.min_return_counts) as f32,
            reflectivity: (100.0 * albedo * (1.0 + refl_noise))
                .round()
                .clamp(0.0, 255.0) as f32,
            near_ir,
        }
    }

    /// Ambient near-IR reflected by the hit surface, with shot noise.
    fn near_ir(&self, hit: &Hit, rng: &mut PixelRng) -> f32 {
        let a = &self.ambient;
        let reflectance = hit.albedo.min(1.0) * hit.nir_gain;
        let lit = a.direct * hit.normal.dot(a.light_dir).max(0.0);
        let diffuse = a.diffuse * (0.6 + 0.4 * hit.normal.z);
        let mean = f64::from(reflectance * (lit + diffuse));
        noisy_count(mean, rng)
    }

    /// Near-IR of the open sky along `dir` (brighter towards the zenith and the sun).
    fn sky(&self, dir: GVec, rng: &mut PixelRng) -> f32 {
        let a = &self.ambient;
        if a.sky <= 0.0 {
            return 0.0;
        }
        let sun = dir.dot(a.light_dir).max(0.0).powi(8);
        let mean = f64::from(a.sky * (0.7 + 0.3 * dir.z.max(0.0)) + 0.5 * a.direct * sun);
        noisy_count(mean, rng)
    }
}

/// `mean` plus shot and read noise, rounded, non-negative.
fn noisy_count(mean: f64, rng: &mut PixelRng) -> f32 {
    (mean + ((mean + 1.0).sqrt()) * rng.gaussian())
        .round()
        .clamp(0.0, MAX_COUNT) as f32
}

/// Signal gain `K` so that a 10 % target at `rated_range_m`, facing the sensor, gives
/// [`MIN_SIGNAL`] counts.
pub fn signal_gain(rated_range_m: f64) -> f64 {
    MIN_SIGNAL * (rated_range_m * rated_range_m + 0.25) / 0.1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shading() -> Shading {
        Shading {
            range_noise_m: 0.0,
            min_range_m: 0.3,
            max_range_m: 75.0,
            signal_gain: signal_gain(35.0),
            ambient: crate::scenes::Ambient {
                light_dir: GVec::Z,
                direct: 1000.0,
                diffuse: 100.0,
                sky: 300.0,
            },
            near_field_m: 0.0,
            noise_factor: 1.0,
            dropout_counts: 0.0,
            min_return_counts: 0.0,
            grazing_power: 0.0,
            partial_drops: None,
            mixed_pixels: None,
        }
    }

    fn hit(distance: f32, albedo: f32) -> Hit {
        Hit {
            distance,
            normal: -GVec::X,
            object: 0,
            albedo,
            nir_gain: 1.0,
        }
    }

    #[test]
    fn signal_falls_with_range_reflectivity_does_not() {
        let s = shading();
        let d = Vector3::x();
        let mut rng = PixelRng::for_pixel(0, 0, 0, 0);
        let near = s.pixel(
            Some(&hit(5.0, 0.5)),
            &d,
            GVec::X,
            &BeamResponse::UNIT,
            &mut rng,
        );
        let far = s.pixel(
            Some(&hit(20.0, 0.5)),
            &d,
            GVec::X,
            &BeamResponse::UNIT,
            &mut rng,
        );
        assert!(near.valid && far.valid);
        assert!(near.signal > 10.0 * far.signal);
        assert!(
            (near.reflectivity - 50.0).abs() <= 2.0,
            "{}",
            near.reflectivity
        );
        assert!(
            (far.reflectivity - 50.0).abs() <= 6.0,
            "{}",
            far.reflectivity
        );
        assert!((near.point.x - 5.0).abs() < 1e-6);
    }

    #[test]
    fn weak_close_and_far_returns_are_invalid() {
        let s = shading();
        let d = Vector3::x();
        let mut rng = PixelRng::for_pixel(0, 0, 0, 1);
        assert!(
            !s.pixel(
                Some(&hit(60.0, 0.05)),
                &d,
                GVec::X,
                &BeamResponse::UNIT,
                &mut rng
            )
            .valid
        );
        assert!(
            !s.pixel(
                Some(&hit(0.2, 0.5)),
                &d,
                GVec::X,
                &BeamResponse::UNIT,
                &mut rng
            )
            .valid
        );
        assert!(
            !s.pixel(
                Some(&hit(80.0, 1.0)),
                &d,
                GVec::X,
                &BeamResponse::UNIT,
                &mut rng
            )
            .valid
        );
        let sky = s.pixel(None, &d, GVec::X, &BeamResponse::UNIT, &mut rng);
        assert!(!sky.valid && sky.range == 0.0 && sky.near_ir > 100.0);
    }
}
