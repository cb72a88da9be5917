//! A stage that may differ per image: one backend for every image, with per-image overrides,
//! and one instance per known image name so that images can run in parallel.

use std::collections::BTreeMap;

use crate::config::StageConfig;
use crate::registry::Backends;
use crate::{BuildContext, CoreError};

use super::build::build_optional;

/// The backend of a per-image stage (detector, descriptor) for each image name.
pub struct PerImage<T: ?Sized> {
    /// Used for images without an instance of their own; `None`: no such stage.
    pub default: Option<Box<T>>,
    /// Instances by image name (`signal`, `range`, `signal+range`): the configured
    /// overrides, plus a separate instance of the default for every image name the image
    /// builder announced. `None`: the stage is off for that image.
    pub by_image: BTreeMap<String, Option<Box<T>>>,
    /// The image names that have an override in the config (checked against the images).
    configured: Vec<String>,
}

impl<T: ?Sized> Default for PerImage<T> {
    fn default() -> Self {
        Self {
            default: None,
            by_image: BTreeMap::new(),
            configured: Vec::new(),
        }
    }
}

impl<T: ?Sized + 'static> PerImage<T> {
    /// The same backend for every image.
    pub fn shared(backend: Box<T>) -> Self {
        Self {
            default: Some(backend),
            ..Self::default()
        }
    }

    /// Builds the default backend, every override of a stage config, and an instance of the
    /// default for each of `image_names` without an override.
    pub(super) fn build(
        backends: &Backends<T>,
        section: &str,
        stage: &StageConfig,
        ctx: &BuildContext,
        image_names: &[String],
    ) -> Result<Self, CoreError> {
        let mut by_image = BTreeMap::new();
        for (image, sub) in &stage.by_image {
            let path = format!("{section}.by_image.{image}");
            by_image.insert(image.clone(), build_optional(backends, &path, sub, ctx)?);
        }
        for name in image_names {
            if !by_image.contains_key(name) {
                let own = build_optional(backends, section, stage, ctx)?;
                by_image.insert(name.clone(), own);
            }
        }
        Ok(Self {
            default: build_optional(backends, section, stage, ctx)?,
            by_image,
            configured: stage.by_image.keys().cloned().collect(),
        })
    }

    /// The backend for the image named `image`.
    pub fn for_image(&mut self, image: &str) -> Option<&mut T> {
        match self.by_image.get_mut(image) {
            Some(own) => own.as_deref_mut(),
            None => self.default.as_deref_mut(),
        }
    }

    /// True when some image has a backend.
    pub fn any(&self) -> bool {
        self.default.is_some() || self.by_image.values().any(Option::is_some)
    }

    /// Whether every name in `images` has an instance of its own, names being distinct (the
    /// condition for running those images in parallel).
    pub fn has_own_instances(&self, images: &[String]) -> bool {
        let mut seen = std::collections::BTreeSet::new();
        images
            .iter()
            .all(|n| self.by_image.contains_key(n) && seen.insert(n.as_str()))
    }

    /// Mutable access to the instances of `images` (each its own), in that order.
    /// Call only when [`Self::has_own_instances`] holds.
    pub fn instances_for(&mut self, images: &[String]) -> Vec<Option<&mut T>> {
        let mut by_name: BTreeMap<&str, Option<&mut T>> = self
            .by_image
            .iter_mut()
            .map(|(k, v)| (k.as_str(), v.as_deref_mut()))
            .collect();
        images
            .iter()
            .map(|n| by_name.remove(n.as_str()).flatten())
            .collect()
    }

    /// Override names from the config that are not among `images` (a config naming an
    /// image the image builder does not make).
    pub fn unknown_images<'a>(&'a self, images: &[String]) -> Vec<&'a str> {
        self.configured
            .iter()
            .filter(|k| !images.contains(k))
            .map(String::as_str)
            .collect()
    }
}
