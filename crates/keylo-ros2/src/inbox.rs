//! The clouds waiting for registration: a bounded queue that drops its oldest cloud when a new
//! one arrives and it is full (a LiDAR's newest scan is worth more than an old one), counting
//! what it dropped. Memory stays bounded however far registration falls behind.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// A bounded, drop-oldest queue shared by the receiving and the registering thread.
pub struct Inbox<T> {
    state: Mutex<State<T>>,
    ready: Condvar,
    capacity: usize,
}

struct State<T> {
    queue: VecDeque<T>,
    dropped: u64,
    received: u64,
}

impl<T> Inbox<T> {
    /// A queue holding at most `capacity` items (at least 1).
    pub fn new(capacity: usize) -> Self {
        Self {
            state: Mutex::new(State {
                queue: VecDeque::with_capacity(capacity.max(1)),
                dropped: 0,
                received: 0,
            }),
            ready: Condvar::new(),
            capacity: capacity.max(1),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State<T>> {
        // A panic elsewhere while holding the lock leaves a queue that is still consistent.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Adds an item; when full, the oldest is dropped first. Returns whether one was dropped.
    pub fn push(&self, item: T) -> bool {
        let mut s = self.lock();
        s.received += 1;
        let dropped = s.queue.len() >= self.capacity;
        if dropped {
            s.queue.pop_front();
            s.dropped += 1;
        }
        s.queue.push_back(item);
        drop(s);
        self.ready.notify_one();
        dropped
    }

    /// The oldest item, waiting up to `timeout` for one.
    pub fn pop(&self, timeout: Duration) -> Option<T> {
        let s = self.lock();
        let (mut s, _) = self
            .ready
            .wait_timeout_while(s, timeout, |s| s.queue.is_empty())
            .unwrap_or_else(|e| e.into_inner());
        s.queue.pop_front()
    }

    /// Items received and items dropped so far.
    pub fn counts(&self) -> (u64, u64) {
        let s = self.lock();
        (s.received, s.dropped)
    }

    /// Items waiting.
    pub fn len(&self) -> usize {
        self.lock().queue.len()
    }

    /// Whether nothing waits.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_the_oldest_when_full_and_counts() {
        let q = Inbox::new(2);
        assert!(!q.push(1));
        assert!(!q.push(2));
        assert!(q.push(3));
        assert!(q.push(4));
        assert_eq!(q.counts(), (4, 2));
        assert_eq!(q.pop(Duration::ZERO), Some(3));
        assert_eq!(q.pop(Duration::ZERO), Some(4));
        assert_eq!(q.pop(Duration::from_millis(5)), None);
    }

    #[test]
    fn stays_bounded_under_a_flood_and_wakes_a_waiting_reader() {
        let q = std::sync::Arc::new(Inbox::new(3));
        let reader = {
            let q = std::sync::Arc::clone(&q);
            std::thread::spawn(move || q.pop(Duration::from_secs(10)))
        };
        for i in 0..10_000u32 {
            q.push(vec![i; 16]);
            assert!(q.len() <= 3);
        }
        let got = reader.join().unwrap();
        assert!(got.is_some());
        let (received, dropped) = q.counts();
        assert_eq!(received, 10_000);
        assert_eq!(dropped + q.len() as u64 + 1, 10_000);
    }
}
