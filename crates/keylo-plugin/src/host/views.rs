//! Borrowed ABI views of a frame and its features for a downsampler plugin.

use crate::convert::AbiError;
use std::ffi::CString;
use std::marker::PhantomData;

use keylo_core::{FrameFeatures, LidarFrame, ScanPoints};

use crate::abi::*;
use crate::convert::{descriptors_view, image_name, image_view, keypoints_view, to_u32};

/// A view of a frame (ABI version 2: with its scan points), borrowing its buffers.
pub struct FrameView<'a> {
    /// Boxed so that `frame.scan` keeps pointing at it when the view moves.
    _scan: Option<Box<KeyloScanPoints>>,
    /// Per-pixel times the frame derives from its column lags (its heap buffer stays put
    /// when the view moves).
    _pixel_times: Option<Vec<f64>>,
    frame: KeyloFrame,
    _borrow: PhantomData<&'a LidarFrame>,
}

impl<'a> FrameView<'a> {
    /// A view of `frame`, its shape (and its scan's) checked.
    pub fn new(frame: &'a LidarFrame) -> Result<Self, AbiError> {
        frame.check_shape().map_err(|e| e.to_string())?;
        let scan = frame.scan.as_deref().map(|s| Box::new(scan_view(s)));
        let scan_ptr = scan
            .as_deref()
            .map_or(std::ptr::null(), |s| s as *const KeyloScanPoints);
        let lagged = match frame.pixel_times_or_lagged() {
            Some(std::borrow::Cow::Owned(t)) => Some(t),
            _ => None,
        };
        let pixel_times = optional(frame.pixel_times.as_deref().or(lagged.as_deref()));
        let abi = KeyloFrame {
            index: frame.index,
            timestamp: frame.timestamp,
            rows: to_u32(frame.rows, "frame rows")?,
            cols: to_u32(frame.cols, "frame cols")?,
            column_times: frame.column_times.as_ptr(),
            pixel_times,
            range: frame.range.as_ptr(),
            signal: frame.signal.as_ptr(),
            reflectivity: frame.reflectivity.as_ptr(),
            near_ir: frame.near_ir.as_ptr(),
            // `Point3<f32>` is `#[repr(C)]` over `[f32; 3]`: `3 * rows * cols` floats.
            points: frame.points.as_ptr().cast::<f32>(),
            valid: frame.valid.as_ptr(),
            scan: scan_ptr,
        };
        Ok(Self {
            _scan: scan,
            _pixel_times: lagged,
            frame: abi,
            _borrow: PhantomData,
        })
    }

    /// The ABI struct, valid while `self` lives.
    pub fn abi(&self) -> &KeyloFrame {
        &self.frame
    }
}

/// A view of the points of an unorganised scan (checked by the frame's `check_shape`).
fn scan_view(scan: &ScanPoints) -> KeyloScanPoints {
    KeyloScanPoints {
        len: scan.len(),
        // `Point3<f64>` is `#[repr(C)]` over `[f64; 3]`: `3 * len` doubles.
        xyz: scan.points.as_ptr().cast::<f64>(),
        times: optional(scan.times.as_deref()),
        intensity: optional(scan.intensity.as_deref()),
        ring: optional(scan.ring.as_deref()),
        source_index: scan.source_index.as_ptr(),
        pixel: scan.pixel.as_ptr(),
        pixel_to_point: scan.pixel_to_point.as_ptr(),
    }
}

/// The buffer's pointer, NULL for `None`.
fn optional<T>(v: Option<&[T]>) -> *const T {
    v.map_or(std::ptr::null(), <[T]>::as_ptr)
}

/// The per-image entries of a features view with the names they point to.
pub struct FeaturesView {
    _names: Vec<CString>,
    entries: Vec<KeyloImageFeatures>,
}

impl FeaturesView {
    /// A view of `features`, borrowing its images, keypoints and descriptors.
    pub fn new(features: &FrameFeatures) -> Result<Self, AbiError> {
        let names: Vec<CString> = features
            .per_image
            .iter()
            .map(|c| image_name(&c.image))
            .collect();
        let mut entries = Vec::with_capacity(names.len());
        for (c, name) in features.per_image.iter().zip(&names) {
            entries.push(KeyloImageFeatures {
                image: image_view(&c.image, name)?,
                keypoints: keypoints_view(&c.keypoints),
                descriptors: descriptors_view(c.descriptors.as_ref()),
            });
        }
        Ok(Self {
            _names: names,
            entries,
        })
    }

    /// The ABI struct, valid while `self` and the features live.
    pub fn abi(&self) -> KeyloFeatures {
        KeyloFeatures {
            images: self.entries.as_ptr(),
            len: self.entries.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use keylo_core::BeamGeometry;
    use nalgebra::Point3;

    use super::*;
    use crate::sdk::{frame_from_abi, scan_from_abi};

    /// A 2 x 3 frame with four scan points: two share pixel 0 (the first is nearer), one lies
    /// outside the grid, one is in pixel 5.
    fn scan_frame() -> LidarFrame {
        // The beams a frame has after crossing the ABI, so that the copy compares equal.
        let beams = Arc::new(BeamGeometry::unknown("unknown (plugin ABI)", 3));
        let mut f = LidarFrame::empty(7, 2.5, 2, 3, beams);
        let points = vec![
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.5, 0.1, 0.0),
            Point3::new(0.0, 0.0, 9.0),
            Point3::new(-2.0, 0.5, 0.25),
        ];
        for (pixel, point) in [(0, points[0]), (5, points[3])] {
            f.valid[pixel] = true;
            f.range[pixel] = point.coords.norm() as f32;
            f.points[pixel] = point.cast::<f32>();
        }
        f.pixel_times = Some(vec![2.5; 6]);
        f.scan = Some(Arc::new(ScanPoints {
            points,
            times: Some(vec![0.0, 0.01, 0.02, 0.03]),
            intensity: None,
            ring: Some(vec![0, 0, 1, 1]),
            source_index: vec![0, 1, 3, 4],
            pixel: vec![0, 0, ScanPoints::NONE, 5],
            pixel_to_point: vec![
                0,
                ScanPoints::NONE,
                ScanPoints::NONE,
                ScanPoints::NONE,
                ScanPoints::NONE,
                3,
            ],
        }));
        f
    }

    #[test]
    fn a_frame_and_its_scan_cross_the_abi_unchanged() {
        let frame = scan_frame();
        let view = FrameView::new(&frame).unwrap();
        assert!(!view.abi().scan.is_null());
        // SAFETY: the view lends a version-2 frame whose buffers live as long as `frame`.
        let back = unsafe { frame_from_abi(view.abi()) }.unwrap();
        assert_eq!(back, frame);

        let mut organised = frame.clone();
        organised.scan = None;
        let view = FrameView::new(&organised).unwrap();
        assert!(view.abi().scan.is_null());
        // SAFETY: as above.
        let back = unsafe { frame_from_abi(view.abi()) }.unwrap();
        assert_eq!(back, organised);
    }

    /// A frame whose pixel times come from its beams' column lags lends them to the plugin
    /// as the per-pixel array.
    #[test]
    fn lagged_pixel_times_cross_the_abi() {
        let mut frame = scan_frame();
        frame.scan = None;
        frame.pixel_times = None;
        frame.column_times = vec![2.5, 2.6, 2.7];
        let mut beams = (*frame.beams).clone();
        beams.column_lag_by_row = vec![1, 0];
        frame.beams = Arc::new(beams);
        let view = FrameView::new(&frame).unwrap();
        // SAFETY: as in the test above.
        let back = unsafe { frame_from_abi(view.abi()) }.unwrap();
        let expected: Vec<f64> = (0..6).map(|i| frame.pixel_time(i)).collect();
        assert_eq!(back.pixel_times.as_deref(), Some(&expected[..]));
        assert_eq!(expected[..3], [2.7, 2.5, 2.6]);
    }

    #[test]
    fn a_bad_scan_is_refused_on_both_sides() {
        let mut frame = scan_frame();
        let mut scan = (**frame.scan.as_ref().unwrap()).clone();
        scan.pixel_to_point.pop();
        frame.scan = Some(Arc::new(scan.clone()));
        let e = FrameView::new(&frame).err().unwrap();
        assert!(e.message().contains("pixel_to_point"), "{e}");

        // A plugin-side copy checks what it reads: here a pixel beyond the grid.
        scan.pixel_to_point.push(3);
        scan.pixel[1] = 6;
        let mut abi = scan_view(&scan);
        // SAFETY: `abi` borrows `scan`, which outlives the call.
        let e = unsafe { scan_from_abi(&abi, 6) }.unwrap_err();
        assert!(e.message().contains("scan.pixel"), "{e}");
        abi.source_index = std::ptr::null();
        // SAFETY: as above; the NULL array is what is tested.
        let e = unsafe { scan_from_abi(&abi, 6) }.unwrap_err();
        assert!(e.message().contains("source_index: NULL"), "{e}");
    }

    #[test]
    fn version_2_only_appends_to_the_version_1_frame() {
        use std::mem::{offset_of, size_of};
        // ABI version 1's frame: u64, f64, two u32 and eight pointers, without padding.
        let ptr = size_of::<*const f64>();
        let v1_size = 8 + 8 + 4 + 4 + 8 * ptr;
        assert_eq!(offset_of!(KeyloFrame, valid), v1_size - ptr);
        assert_eq!(offset_of!(KeyloFrame, scan), v1_size);
        assert_eq!(size_of::<KeyloFrame>(), v1_size + ptr);
    }
}
