//! Clouds and the images taken with them. Messages come in log-time order, so an image may be
//! stored before or after its cloud: images wait in per-topic queues, and finding the images
//! of a cloud reads ahead (queueing later clouds) until every image topic has shown a stamp at
//! or past the cloud's. Images older than the current cloud are dropped, so memory holds a
//! few messages, not the file.

use std::collections::VecDeque;

use super::file::{MessageFile, StoredMessage};
use super::msgs::decode_header;
use super::wire::Encoding;
use crate::IoError;

/// Clouds read ahead at most while looking for a cloud's images.
const MAX_AHEAD: usize = 16;

/// One image topic and its waiting messages.
pub(crate) struct ImageQueue {
    pub topic: String,
    pub ids: Vec<u32>,
    pub encoding: Encoding,
    queue: VecDeque<(i64, StoredMessage)>,
}

impl ImageQueue {
    /// An empty queue for a topic.
    pub fn new(topic: String, ids: Vec<u32>, encoding: Encoding) -> Self {
        Self {
            topic,
            ids,
            encoding,
            queue: VecDeque::new(),
        }
    }
}

/// Routes the messages of one read to the cloud queue and the image queues.
pub(crate) struct Sync {
    cloud_ids: Vec<u32>,
    pub images: Vec<ImageQueue>,
    clouds: VecDeque<StoredMessage>,
    ended: bool,
}

/// Why the images of a cloud were not found.
pub(crate) enum SyncError {
    /// Reading the file failed.
    File(IoError),
    /// The file holds no image with the stamp (message for the frame's error).
    Missing(String),
}

impl Sync {
    /// Routes messages of `cloud_ids` and of `images`.
    pub fn new(cloud_ids: Vec<u32>, images: Vec<ImageQueue>) -> Self {
        Self {
            cloud_ids,
            images,
            clouds: VecDeque::new(),
            ended: false,
        }
    }

    /// Reads one message: `Ok(false)` at the end of the file.
    fn pull(&mut self, file: &mut dyn MessageFile) -> Result<bool, SyncError> {
        if self.ended {
            return Ok(false);
        }
        let Some(next) = file.next_message() else {
            self.ended = true;
            return Ok(false);
        };
        let msg = next.map_err(|e| {
            self.ended = true;
            SyncError::File(e)
        })?;
        if self.cloud_ids.contains(&msg.channel) {
            self.clouds.push_back(msg);
        } else if let Some(q) = self
            .images
            .iter_mut()
            .find(|q| q.ids.contains(&msg.channel))
        {
            let stamp = decode_header(&msg.data, q.encoding)
                .map_err(|e| SyncError::Missing(format!("{} image: {e}", q.topic)))?
                .stamp_ns;
            q.queue.push_back((stamp, msg));
        }
        Ok(true)
    }

    /// The next cloud message, `None` at the end of the file.
    pub fn next_cloud(
        &mut self,
        file: &mut dyn MessageFile,
    ) -> Option<Result<StoredMessage, IoError>> {
        loop {
            if let Some(c) = self.clouds.pop_front() {
                return Some(Ok(c));
            }
            match self.pull(file) {
                Ok(true) => {}
                Ok(false) => return None,
                Err(SyncError::File(e)) => return Some(Err(e)),
                Err(SyncError::Missing(m)) => return Some(Err(IoError::format(file.path(), m))),
            }
        }
    }

    /// Drops the images stamped before `stamp_ns`.
    pub fn prune(&mut self, stamp_ns: i64) {
        for q in &mut self.images {
            while q.queue.front().is_some_and(|(s, _)| *s < stamp_ns) {
                q.queue.pop_front();
            }
        }
    }

    /// The image of every queue stamped `stamp_ns`, in queue order.
    pub fn images_at(
        &mut self,
        file: &mut dyn MessageFile,
        stamp_ns: i64,
    ) -> Result<Vec<StoredMessage>, SyncError> {
        self.prune(stamp_ns);
        let mut out = Vec::with_capacity(self.images.len());
        for k in 0..self.images.len() {
            while self.images[k].queue.is_empty() {
                if self.clouds.len() > MAX_AHEAD {
                    return Err(self.missing(k, stamp_ns, "within the next clouds"));
                }
                if !self.pull(file)? {
                    return Err(self.missing(k, stamp_ns, "before the end of the file"));
                }
                self.prune(stamp_ns);
            }
            match self.images[k].queue.front() {
                Some((s, _)) if *s == stamp_ns => {
                    if let Some((_, m)) = self.images[k].queue.pop_front() {
                        out.push(m);
                    }
                }
                _ => return Err(self.missing(k, stamp_ns, "")),
            }
        }
        Ok(out)
    }

    fn missing(&self, k: usize, stamp_ns: i64, where_: &str) -> SyncError {
        let q = &self.images[k];
        let next = q.queue.front().map_or(String::new(), |(s, _)| {
            format!(" (the next one is stamped {s} ns)")
        });
        let where_ = if where_.is_empty() {
            String::new()
        } else {
            format!(" {where_}")
        };
        SyncError::Missing(format!(
            "no {} image stamped {stamp_ns} ns (the cloud's header stamp){where_}{next}; images \
             are matched to clouds by equal header stamps",
            q.topic
        ))
    }
}
