//! Source kinds `ros1-bag` and `mcap`: the clouds of one PointCloud2 topic as frames, with
//! image topics filling channels.

use keylo_core::{BuildContext, Channel, CoreError, ImageSource, LidarFrame, SourceInfo};
use std::path::Path;

use super::beams;
use super::config::BagSourceConfig;
use super::file::{BagFormat, MessageFile, StoredMessage};
use super::framer::CloudFramer;
use super::image::{pixels, restagger};
use super::msgs::{decode_header, decode_string, Image, PointCloud2};
use super::pointcloud2::to_raw_cloud;
use super::sync::{ImageQueue, Sync, SyncError};
use super::topics::{cloud_topic, topics, typed_topic, Topic, IMAGE, STRING};
use super::wire::Encoding;
use crate::cloud::{Projector, RawCloud, Sensor};
use crate::ouster::OusterMetadata;
use crate::select::FrameSelection;
use crate::IoError;

/// Reads the frames of a ROS1 bag, an MCAP file or a ROS2 sqlite3 bag, one cloud message at a
/// time.
pub struct BagSource {
    /// The file read (the `.mcap` or `.db3` inside a ROS2 bag folder).
    path: std::path::PathBuf,
    file: Box<dyn MessageFile>,
    description: String,
    topic: String,
    encoding: Encoding,
    sync: Sync,
    /// The channel each image queue fills.
    channels: Vec<Channel>,
    range_unit_m: f64,
    shift_config: Vec<i64>,
    metadata_topic: String,
    selection: FrameSelection,
    frames: Option<usize>,
    next_index: usize,
    framer: CloudFramer,
    shift: Option<Vec<i64>>,
    done: bool,
}

impl BagSource {
    /// Opens the recording of `config` as `format`; errors name the file and the key to set.
    pub fn open(
        config: &BagSourceConfig,
        ctx: &BuildContext,
        format: BagFormat,
    ) -> Result<Self, IoError> {
        if config.path.is_empty() {
            return Err(IoError::format(
                Path::new("source.path"),
                "no recording given: set `[source] path` or pass --data",
            ));
        }
        let mut file = super::open_file(&ctx.resolve_path(&config.path), Some(format))?;
        let path = file.path().to_path_buf();
        let err = |m: String| IoError::format(&path, m);
        let all = topics(file.channels());
        let cloud = cloud_topic(&all, &config.topic)
            .map_err(|m| err(with_damage(m, file.damage())))?
            .clone();
        let mut queues = Vec::new();
        let mut channels = Vec::new();
        for (channel, name, key) in config.images.selected() {
            let t = typed_topic(&all, name, IMAGE, key).map_err(err)?;
            queues.push(ImageQueue::new(t.name.clone(), t.ids.clone(), encoding(t)));
            channels.push(channel);
        }
        let metadata = read_metadata(file.as_mut(), &all, &config.metadata_topic)?;
        let selection = FrameSelection::new(config.start, config.stride, config.max_frames)
            .map_err(|e| err(e.to_string()))?;
        let frames = match cloud.count {
            Some(n) => Some(
                selection
                    .count(usize::try_from(n).unwrap_or(usize::MAX))
                    .map_err(|e| err(e.to_string()))?,
            ),
            None => None,
        };
        let projector = Projector::from_config(&config.projection, Sensor::Generic)
            .map_err(|e| err(format!("source.{e}")))?;
        let mut ids = cloud.ids.clone();
        ids.extend(queues.iter().flat_map(|q| q.ids.iter().copied()));
        file.select(&ids);
        Ok(Self {
            path: path.clone(),
            description: format!("{} {} topic {}", format.kind(), path.display(), cloud.name),
            file,
            topic: cloud.name.clone(),
            encoding: encoding(&cloud),
            sync: Sync::new(cloud.ids.clone(), queues),
            channels,
            range_unit_m: config.images.range_unit_m,
            shift_config: config.images.pixel_shift_by_row.clone(),
            metadata_topic: config.metadata_topic.clone(),
            selection,
            frames,
            next_index: 0,
            framer: CloudFramer::new(projector, metadata, &cloud.name),
            shift: None,
            done: false,
        })
    }

    fn next_inner(&mut self) -> Option<Result<LidarFrame, IoError>> {
        loop {
            let i = self.next_index;
            if self.selection.past_end(i) {
                return None;
            }
            let msg = match self.sync.next_cloud(self.file.as_mut())? {
                Ok(m) => m,
                Err(e) => return Some(Err(self.context(e, i))),
            };
            self.next_index += 1;
            if self.selection.wants(i) {
                return Some(self.frame(&msg, i));
            }
            if let Ok(h) = decode_header(&msg.data, self.encoding) {
                self.sync.prune(h.stamp_ns);
            }
        }
    }

    /// Prefixes the topic and message index to an error of the file.
    fn context(&self, e: IoError, i: usize) -> IoError {
        match e {
            IoError::Format { path, message } => IoError::Format {
                path,
                message: format!("reading {} message {i} (from 0): {message}", self.topic),
            },
            other => other,
        }
    }

    fn frame(&mut self, msg: &StoredMessage, i: usize) -> Result<LidarFrame, IoError> {
        let path = self.file.path().to_path_buf();
        let at = format!(
            "{} message {i} (from 0, log time {} ns)",
            self.topic, msg.log_time
        );
        let fail = |m: String| IoError::format(&path, format!("{at}: {m}"));
        let pc = PointCloud2::decode(&msg.data, self.encoding).map_err(|e| fail(e.to_string()))?;
        if self.channels.is_empty() {
            return self.framer.frame_message(&pc, i as u64).map_err(fail);
        }
        let cloud = to_raw_cloud(&pc).map_err(|e| fail(e.to_string()))?;
        if cloud.grid.is_none() && !self.channels.is_empty() {
            return Err(fail(
                "[source.images] fill organised clouds only, and this cloud has height 1 \
                 (it is projected); remove the image topics"
                    .into(),
            ));
        }
        let mut frame = self.framer.frame(&cloud, i as u64).map_err(&fail)?;
        let (rows, cols) = (frame.rows, frame.cols);
        if !self.channels.is_empty() {
            let shift = self.shift_for(&cloud, rows, cols).map_err(fail)?;
            let images = match self.sync.images_at(self.file.as_mut(), pc.header.stamp_ns) {
                Ok(images) => images,
                Err(SyncError::File(e)) => return Err(self.context(e, i)),
                Err(SyncError::Missing(m)) => return Err(fail(m)),
            };
            self.fill(&mut frame, &images, &shift).map_err(fail)?;
        }
        Ok(frame)
    }

    /// The column shift from the cloud to its images (see `ImageTopics::pixel_shift_by_row`).
    fn shift_for(
        &mut self,
        cloud: &RawCloud,
        rows: usize,
        cols: usize,
    ) -> Result<Vec<i64>, String> {
        if let Some(s) = &self.shift {
            return Ok(s.clone());
        }
        let shift = if !self.shift_config.is_empty() {
            let n = self.shift_config.len();
            if n != 1 && n != rows {
                return Err(format!(
                    "source.images.pixel_shift_by_row has {n} entries; expected 1 or rows = {rows}"
                ));
            }
            self.shift_config.clone()
        } else {
            match beams::is_staggered(cloud, rows, cols) {
                Some(false) => vec![0],
                Some(true) => match self.framer.metadata() {
                    Some(m) if m.pixel_shift_by_row.len() == rows => m.pixel_shift_by_row.clone(),
                    _ => {
                        return Err(format!(
                            "the cloud is staggered (each column one firing time) and ouster-ros \
                             images are destaggered, but the file has no `{}` metadata for these \
                             {rows} rows: set source.images.pixel_shift_by_row to the sensor's \
                             pixel_shift_by_row ([0] if the images are staggered too)",
                            self.metadata_topic
                        ))
                    }
                },
                None => {
                    return Err(
                        "the cloud has no point time field, so whether it is staggered \
                                is unknown: set source.images.pixel_shift_by_row ([0] when \
                                images and cloud share their column order)"
                            .into(),
                    )
                }
            }
        };
        self.shift = Some(shift.clone());
        Ok(shift)
    }

    /// Replaces the channels of `frame` by the images, restaggered by `shift`.
    fn fill(
        &self,
        frame: &mut LidarFrame,
        images: &[StoredMessage],
        shift: &[i64],
    ) -> Result<(), String> {
        let (rows, cols) = (frame.rows, frame.cols);
        for ((msg, q), channel) in images.iter().zip(&self.sync.images).zip(&self.channels) {
            let img = Image::decode(&msg.data, q.encoding)
                .map_err(|e| e.to_string())
                .and_then(|img| {
                    if (img.height as usize, img.width as usize) != (rows, cols) {
                        return Err(format!(
                            "{}×{} pixels, the cloud {cols}×{rows}",
                            img.width, img.height
                        ));
                    }
                    pixels(&img)
                })
                .map_err(|e| format!("{} image: {e}", q.topic))?;
            let mut values = restagger(&img, rows, cols, shift);
            let target = match channel {
                Channel::Range => {
                    values
                        .iter_mut()
                        .for_each(|v| *v *= self.range_unit_m as f32);
                    &mut frame.range
                }
                Channel::Signal => &mut frame.signal,
                Channel::Reflectivity => &mut frame.reflectivity,
                Channel::NearIr => &mut frame.near_ir,
            };
            *target = values;
        }
        Ok(())
    }
}

/// A topic error on a damaged file also says where the listing stopped (a file without index is
/// listed by reading it, so topics after the damage are unknown).
fn with_damage(message: String, damage: Option<&str>) -> String {
    match damage {
        Some(d) => format!("{message} (the file was listed up to its damage: {d})"),
        None => message,
    }
}

fn encoding(t: &Topic) -> Encoding {
    t.encoding.unwrap_or(Encoding::Ros1)
}

/// The Ouster metadata of the file's `topic`, when it has one.
fn read_metadata(
    file: &mut dyn MessageFile,
    all: &[Topic],
    topic: &str,
) -> Result<Option<OusterMetadata>, IoError> {
    if topic.is_empty() || !all.iter().any(|t| t.name == topic) {
        return Ok(None);
    }
    let path = file.path().to_path_buf();
    let hint = "(set source.metadata_topic = \"\" to ignore it)";
    let t = typed_topic(all, topic, STRING, "source.metadata_topic")
        .map_err(|e| IoError::format(&path, format!("{e} {hint}")))?;
    file.select(&t.ids);
    let Some(msg) = file.next_message().transpose()? else {
        return Ok(None);
    };
    let text = decode_string(&msg.data, encoding(t))
        .map_err(|e| IoError::format(&path, format!("{topic}: {e}")))?;
    let name = format!("{}:{topic}", path.display());
    OusterMetadata::parse(Path::new(&name), text)
        .map(Some)
        .map_err(|e| IoError::format(&path, format!("{e} {hint}")))
}

impl ImageSource for BagSource {
    fn info(&self) -> SourceInfo {
        SourceInfo {
            description: self.description.clone(),
            frames: self.frames,
        }
    }

    fn set_grid_needed(&mut self, needed: bool) {
        self.framer.set_grid_needed(needed);
    }

    /// What `keylo info` shows: the recording's time span and every topic with its type,
    /// encoding, count and (PointCloud2) layout, as [`super::bag_info`] reads them.
    fn details(&self) -> Vec<(String, String)> {
        let info = match super::bag_info(&self.path) {
            Ok(i) => i,
            Err(e) => return vec![("recording".into(), format!("unreadable: {e}"))],
        };
        let mut d = vec![("cloud topic".into(), self.topic.clone())];
        if let Some(s) = info.duration_s {
            d.push(("recording span (s)".into(), format!("{s:.3}")));
        }
        for note in [&info.note, &info.damage].into_iter().flatten() {
            d.push(("note".into(), note.clone()));
        }
        for t in &info.topics {
            let count = t.count.map_or("?".to_string(), |n| n.to_string());
            let mut v = format!("{} [{}], {count} messages", t.msg_type, t.encoding);
            if let Some(c) = &t.cloud {
                let fields: Vec<&str> = c.fields.iter().map(|f| f.name.as_str()).collect();
                v += &format!("; {}x{}, fields {}", c.height, c.width, fields.join(" "));
            }
            d.push((format!("topic {}", t.name), v));
        }
        d
    }

    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>> {
        if self.done {
            return None;
        }
        let next = self.next_inner();
        if !matches!(next, Some(Ok(_))) {
            self.done = true;
        }
        next.map(|r| r.map_err(CoreError::from))
    }
}

#[cfg(test)]
#[path = "source_tests.rs"]
mod tests;
