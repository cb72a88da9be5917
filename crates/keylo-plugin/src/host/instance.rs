//! A plugin instance behind keylo's stage traits: inputs are lent as ABI views, outputs are
//! copied and checked (keypoints inside the image and finite, descriptor rows matching).

use std::ffi::{c_void, CString};
use std::sync::Arc;

use keylo_core::{
    CoreError, Descriptor, Descriptors, Detector, Downsampler, FrameFeatures, Image, Keypoint,
    LidarFrame, PointCloud, Pose, Registrar, Registration,
};

use super::library::{Kind, Plugin};
use crate::abi::*;
use crate::convert;

/// A created and configured instance of one plugin kind; destroyed on drop.
pub struct Instance {
    plugin: Arc<Plugin>,
    kind: Kind,
    state: *mut c_void,
}

// SAFETY: the ABI requires an instance to be usable from any thread, one thread at a time;
// `&mut self` on every call gives exactly that.
unsafe impl Send for Instance {}

impl Instance {
    /// Creates an instance of `kind` and configures it with `params` (serialised as TOML).
    pub fn new(plugin: Arc<Plugin>, kind: Kind, params: &toml::Table) -> Result<Self, CoreError> {
        let mut err = convert::empty_error();
        // SAFETY: `create` is the plugin's checked, non-NULL create function.
        let state = unsafe { (kind.fns.create)(&mut err) };
        let inst = Self {
            plugin,
            kind,
            state,
        };
        if state.is_null() {
            return Err(inst.failure("create", &err));
        }
        let text = toml::to_string(params).map_err(|e| inst.error(format!("parameters: {e}")))?;
        let text = CString::new(text).map_err(|_| inst.error("parameters hold a NUL byte"))?;
        let mut err = convert::empty_error();
        // SAFETY: a live instance, a NUL-terminated string and a writable error.
        let code = unsafe { (inst.kind.fns.configure)(inst.state, text.as_ptr(), &mut err) };
        if code != KEYLO_OK {
            return Err(inst.failure("configure", &err));
        }
        Ok(inst)
    }

    /// An error naming the plugin, its file and the stage.
    fn error(&self, message: impl std::fmt::Display) -> CoreError {
        CoreError::stage(
            self.kind.stage.section(),
            format!(
                "plugin `{}` ({}): {message}",
                self.plugin.name,
                self.plugin.path.display()
            ),
        )
    }

    fn failure(&self, call: &str, err: &KeyloError) -> CoreError {
        let what = match err.code {
            KEYLO_ERR_CONFIG => "configuration rejected",
            KEYLO_ERR_INPUT => "input rejected",
            KEYLO_ERR_PANIC => "panicked",
            _ => "failed",
        };
        let message = convert::read_error(err);
        let message = if message.is_empty() {
            "(no message)".into()
        } else {
            message
        };
        self.error(format!("{call} {what} (code {}): {message}", err.code))
    }

    /// Runs `f` with the state and a fresh error; a non-zero code becomes an error.
    fn call(
        &mut self,
        name: &str,
        f: impl FnOnce(*mut c_void, *mut KeyloError) -> i32,
    ) -> Result<(), CoreError> {
        let mut err = convert::empty_error();
        let code = f(self.state, &mut err);
        if code != KEYLO_OK {
            if err.code == KEYLO_OK {
                err.code = code;
            }
            return Err(self.failure(name, &err));
        }
        Ok(())
    }

    /// Keypoints inside `image` with finite coordinates, or an error naming the first bad one.
    fn check_keypoints(&self, keypoints: &[Keypoint], image: &Image) -> Result<(), CoreError> {
        let (w, h) = (image.width as f32, image.height as f32);
        for (i, k) in keypoints.iter().enumerate() {
            if !k.x.is_finite() || !k.y.is_finite() {
                return Err(self.error(format!(
                    "keypoint {i} has a non-finite coordinate ({}, {})",
                    k.x, k.y
                )));
            }
            if k.x < 0.0 || k.y < 0.0 || k.x >= w || k.y >= h {
                return Err(self.error(format!(
                    "keypoint {i} at ({}, {}) lies outside the {}x{} image `{}`",
                    k.x,
                    k.y,
                    image.width,
                    image.height,
                    image.name()
                )));
            }
        }
        Ok(())
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if !self.state.is_null() {
            // SAFETY: the instance came from `create` and is not used after this.
            unsafe { (self.kind.fns.destroy)(self.state) };
        }
    }
}

impl Detector for Instance {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        let f = self
            .kind
            .fns
            .detect
            .ok_or_else(|| self.error("no detect function"))?;
        let name = convert::image_name(image);
        let view = convert::image_view(image, &name).map_err(|m| self.error(m))?;
        let mut out = KeyloKeypoints {
            data: std::ptr::null(),
            len: 0,
        };
        // SAFETY: valid image view (borrowing `image`, `name`) and output for the call.
        self.call("detect", |s, e| unsafe { f(s, &view, &mut out, e) })?;
        // SAFETY: the plugin's output buffer holds `len` keypoints until its next call.
        let kps = unsafe { convert::keypoints_from_abi(&out) }.map_err(|m| self.error(m))?;
        self.check_keypoints(&kps, image)?;
        Ok(kps)
    }
}

impl Descriptor for Instance {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        let f = self
            .kind
            .fns
            .describe
            .ok_or_else(|| self.error("no describe function"))?;
        let name = convert::image_name(image);
        let view = convert::image_view(image, &name).map_err(|m| self.error(m))?;
        let input = convert::keypoints_view(keypoints);
        let mut out_kp = KeyloKeypoints {
            data: std::ptr::null(),
            len: 0,
        };
        let mut out = convert::descriptors_view(None);
        // SAFETY: valid views of `image` and `keypoints` and outputs for the call.
        self.call("describe", |s, e| unsafe {
            f(s, &view, &input, &mut out_kp, &mut out, e)
        })?;
        // SAFETY: the plugin's buffers hold what their lengths say until its next call.
        let kept = unsafe { convert::keypoints_from_abi(&out_kp) }.map_err(|m| self.error(m))?;
        // SAFETY: as above.
        let d = unsafe { convert::descriptors_from_abi(&out) }.map_err(|m| self.error(m))?;
        if d.rows != kept.len() {
            return Err(self.error(format!(
                "{} descriptor rows for {} keypoints",
                d.rows,
                kept.len()
            )));
        }
        self.check_keypoints(&kept, image)?;
        *keypoints = kept;
        Ok(d)
    }
}

impl Downsampler for Instance {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        let f = self
            .kind
            .fns
            .downsample
            .ok_or_else(|| self.error("no downsample function"))?;
        let view = super::views::FrameView::new(frame).map_err(|m| self.error(m))?;
        let feats = super::views::FeaturesView::new(features).map_err(|m| self.error(m))?;
        let feats_abi = feats.abi();
        let mut out = KeyloCloud {
            timestamp: frame.timestamp,
            len: 0,
            xyz: std::ptr::null(),
            times: std::ptr::null(),
            intensities: std::ptr::null(),
        };
        // SAFETY: valid views of `frame` (with its scan) and `features` and an output for
        // the call.
        self.call("downsample", |s, e| unsafe {
            f(s, view.abi(), &feats_abi, &mut out, e)
        })?;
        // SAFETY: the plugin's buffers hold `len` points until its next call.
        let cloud = unsafe { convert::cloud_from_abi(&out) }.map_err(|m| self.error(m))?;
        if let Some(i) = cloud
            .points
            .iter()
            .position(|p| !p.coords.iter().all(|v| v.is_finite()))
        {
            return Err(self.error(format!("point {i} of the cloud is not finite")));
        }
        Ok(cloud)
    }
}

/// A registrar instance remembers the map size its last registration reported.
pub struct RegistrarInstance {
    pub inner: Instance,
    map_size: usize,
}

impl From<Instance> for RegistrarInstance {
    fn from(inner: Instance) -> Self {
        Self { inner, map_size: 0 }
    }
}

impl Registrar for RegistrarInstance {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        let inst = &mut self.inner;
        let f = inst
            .kind
            .fns
            .register_cloud
            .ok_or_else(|| inst.error("no register_cloud function"))?;
        let view = convert::cloud_view(cloud);
        let mut out = KeyloRegistration {
            stamp: cloud.timestamp,
            translation: [0.0; 3],
            rotation: [0.0, 0.0, 0.0, 1.0],
            source_points: 0,
            iterations: 0,
            converged: false,
            map_size: 0,
        };
        // SAFETY: a valid view of `cloud` and an output for the call.
        inst.call("register_cloud", |s, e| unsafe { f(s, &view, &mut out, e) })?;
        let mut reg = convert::registration_from_abi(&out).map_err(|m| inst.error(m))?;
        self.map_size = out.map_size;
        // A plugin that leaves `source_points` at 0 did not say how many it used: count the
        // cloud it was given (the degenerate-frame verdict reads this number).
        if reg.source_points == 0 {
            reg.source_points = cloud.len();
        }
        Ok(reg)
    }

    fn map_size(&self) -> usize {
        self.map_size
    }

    fn set_motion_prior(&mut self, delta: &Pose) -> Result<(), CoreError> {
        keylo_core::rigid::check_rigid(delta, "motion prior")?;
        let f = self.hook(self.inner.kind.fns.set_motion_prior, "set_motion_prior")?;
        let m = keylo_core::rigid::pose_to_matrix(delta);
        // SAFETY: a live instance and 16 doubles for the call.
        self.inner
            .call("set_motion_prior", |s, e| unsafe { f(s, m.as_ptr(), e) })
    }

    fn set_pose(&mut self, pose: &Pose) -> Result<(), CoreError> {
        keylo_core::rigid::check_rigid(pose, "pose")?;
        let f = self.hook(self.inner.kind.fns.set_pose, "set_pose")?;
        let m = keylo_core::rigid::pose_to_matrix(pose);
        // SAFETY: a live instance and 16 doubles for the call.
        self.inner
            .call("set_pose", |s, e| unsafe { f(s, m.as_ptr(), e) })
    }

    fn reset(&mut self) -> Result<(), CoreError> {
        let f = self.hook(self.inner.kind.fns.reset, "reset")?;
        // SAFETY: a live instance for the call.
        self.inner.call("reset", |s, e| unsafe { f(s, e) })?;
        self.map_size = 0;
        Ok(())
    }

    /// The plugin's local map; empty when it offers none, or its call fails (the trait has no
    /// error to report it with) or lends a map that is not finite.
    fn local_map(&self) -> Vec<nalgebra::Point3<f64>> {
        let Some(f) = self.inner.kind.fns.local_map else {
            return Vec::new();
        };
        let (mut xyz, mut n) = (std::ptr::null(), 0usize);
        let mut err = convert::empty_error();
        // SAFETY: a live instance (used by this thread only: `Instance` is not `Sync`) and
        // writable outputs for the call.
        let code = unsafe { f(self.inner.state, &mut xyz, &mut n, &mut err) };
        let len = n.checked_mul(3);
        if code != KEYLO_OK || xyz.is_null() || len.is_none() {
            return Vec::new();
        }
        // SAFETY: the plugin lends `3 * n` doubles until its next call.
        let flat = unsafe { std::slice::from_raw_parts(xyz, len.unwrap_or(0)) };
        let points: Vec<_> = flat
            .chunks_exact(3)
            .map(|c| nalgebra::Point3::new(c[0], c[1], c[2]))
            .collect();
        if points
            .iter()
            .all(|p| p.coords.iter().all(|v| v.is_finite()))
        {
            points
        } else {
            Vec::new()
        }
    }
}

impl RegistrarInstance {
    /// The hook `f` of the plugin, or an error saying that it does not offer `name`.
    fn hook<F>(&self, f: Option<F>, name: &str) -> Result<F, CoreError> {
        f.ok_or_else(|| {
            self.inner.error(format!(
                "does not offer `{name}` (a SLAM hook: ABI 3 registrars may; this plugin is ABI {})",
                self.inner.plugin.abi_version
            ))
        })
    }
}
