//! A stage that may differ per image: one backend for every image, with per-image overrides.

use std::collections::BTreeMap;

use crate::config::StageConfig;
use crate::registry::Backends;
use crate::{BuildContext, CoreError};

use super::build_optional;

/// The backend of a per-image stage (detector, descriptor) for each image name.
pub struct PerImage<T: ?Sized> {
    /// Used for images without an override; `None`: no such stage.
    pub default: Option<Box<T>>,
    /// Overrides by image name (`signal`, `range`, `signal+range`); `None`: the stage is off
    /// for that image.
    pub by_image: BTreeMap<String, Option<Box<T>>>,
}

impl<T: ?Sized> Default for PerImage<T> {
    fn default() -> Self {
        Self {
            default: None,
            by_image: BTreeMap::new(),
        }
    }
}

impl<T: ?Sized + 'static> PerImage<T> {
    /// The same backend for every image.
    pub fn shared(backend: Box<T>) -> Self {
        Self {
            default: Some(backend),
            by_image: BTreeMap::new(),
        }
    }

    /// Builds the default backend and every override of a stage config.
    pub(super) fn build(
        backends: &Backends<T>,
        section: &str,
        stage: &StageConfig,
        ctx: &BuildContext,
    ) -> Result<Self, CoreError> {
        let mut by_image = BTreeMap::new();
        for (image, sub) in &stage.by_image {
            let path = format!("{section}.by_image.{image}");
            by_image.insert(image.clone(), build_optional(backends, &path, sub, ctx)?);
        }
        Ok(Self {
            default: build_optional(backends, section, stage, ctx)?,
            by_image,
        })
    }

    /// The backend for the image named `image`.
    pub fn for_image(&mut self, image: &str) -> Option<&mut T> {
        match self.by_image.get_mut(image) {
            Some(over) => over.as_deref_mut(),
            None => self.default.as_deref_mut(),
        }
    }

    /// True when some image has a backend.
    pub fn any(&self) -> bool {
        self.default.is_some() || self.by_image.values().any(Option::is_some)
    }

    /// Override names that are not among `images` (a config naming an image the image
    /// builder does not make).
    pub fn unknown_images<'a>(&'a self, images: &[String]) -> Vec<&'a str> {
        self.by_image
            .keys()
            .filter(|k| !images.contains(k))
            .map(String::as_str)
            .collect()
    }
}
