//! Staggered beams: an Ouster sensor's beams do not look along their column's azimuth. Each
//! beam has its own azimuth offset (a pattern of four on an OS0-128, about ±10.7° and ±3.5°)
//! and starts from a point on a ring 27 mm around the lidar origin, on the encoder's
//! direction. The sensor fires them column by column; the destaggered image shifts each row by
//! its offset rounded to whole columns. What is left is range-dependent: the beam origin's
//! parallax (up to 1.7 columns of 2048 at 1 m for the outer beams, 3.3 at 0.5 m) and the
//! rounding (up to half a column), which make the vertical edges of near objects ragged in
//! a four-row pattern, as in the real images.
//!
//! With the `ouster` appearance an OS0-128 renders this way; the ground truth stays exact:
//! each pixel's point is its own ray's (from its beam origin, at its beam's azimuth, from
//! the pose at its own firing time), and `column_lag_by_row` gives each pixel's firing time.

/// A real OS0-128's beam azimuth offsets, degrees, Ouster's convention (a beam looks at the
/// encoder angle minus its offset), top beam first: `beam_azimuth_angles` of
/// `../shared/data/ouster/OS-0-128_v3.2.0-rc7_2048x10_dual_from_osf.json` (serial
/// 122305001639; ouster-sdk test data, BSD-3).
pub(crate) const OS0_128_BEAM_AZIMUTH_DEG: [f64; 128] = [
    10.83, 3.58, -3.63, -10.67, 10.45, 3.41, -3.49, -10.27, 10.09, 3.30, -3.37, -9.95, 9.79, 3.22,
    -3.27, -9.69, 9.52, 3.11, -3.19, -9.43, 9.29, 3.06, -3.11, -9.24, 9.11, 2.99, -3.04, -9.05,
    8.92, 2.94, -2.98, -8.89, 8.78, 2.89, -2.94, -8.76, 8.66, 2.85, -2.91, -8.65, 8.56, 2.82,
    -2.86, -8.55, 8.47, 2.80, -2.85, -8.50, 8.43, 2.78, -2.81, -8.43, 8.37, 2.78, -2.80, -8.40,
    8.35, 2.77, -2.80, -8.37, 8.35, 2.77, -2.78, -8.35, 8.34, 2.79, -2.79, -8.37, 8.36, 2.78,
    -2.79, -8.39, 8.39, 2.80, -2.79, -8.41, 8.44, 2.83, -2.80, -8.46, 8.50, 2.85, -2.81, -8.53,
    8.59, 2.88, -2.84, -8.61, 8.69, 2.92, -2.87, -8.71, 8.81, 2.97, -2.90, -8.83, 8.94, 3.02,
    -2.94, -8.96, 9.10, 3.08, -2.99, -9.13, 9.29, 3.16, -3.05, -9.32, 9.50, 3.23, -3.12, -9.55,
    9.75, 3.32, -3.19, -9.81, 10.05, 3.43, -3.29, -10.12, 10.38, 3.56, -3.40, -10.48, 10.76, 3.70,
    -3.53, -10.91,
];

/// That sensor's `lidar_origin_to_beam_origin_mm`, in metres.
pub(crate) const OS0_128_BEAM_ORIGIN_M: f64 = 0.027116;
