//! Ouster sensors without the Ouster SDK: the metadata JSON in both layouts ouster-sdk reads
//! (legacy flat, firmware ≤ 2.x; nested, firmware 3.x), lidar packets from pcap captures
//! (IP fragments joined; profiles LEGACY, RNG19_RFL8_SIG16_NIR16 and its dual-return variant,
//! RNG15_RFL8_NIR8), frames batched by frame id, destaggered, with XYZ and per-pixel times as
//! ouster-sdk computes them. [`OusterSource`] is source kind `ouster`.

mod batcher;
mod checks;
mod datagrams;
mod destagger;
mod ipv4;
mod json;
mod live;
mod metadata;
mod packet;
mod pcap;
mod source;
mod udp_source;
mod xyz;

pub use batcher::{BatchedFrame, Batcher, Skipped};
pub use datagrams::Datagrams;
pub use destagger::{Destaggerer, Return};
pub use live::{stop_live_sources, LiveUdp};
pub use metadata::{OusterMetadata, UdpProfile};
pub use packet::{PacketFormat, RawFrame, UnsupportedProfile};
pub use pcap::{Datagram, UdpReader};
pub use source::{is_pcap, metadata_path, OusterSource, OusterSourceConfig, PartialFrames};
pub use udp_source::OusterUdpConfig;
pub use xyz::XyzLut;
