//! Ouster sensors without the Ouster SDK. This first part reads the sensor metadata JSON in
//! both layouts ouster-sdk reads: the legacy flat layout (firmware ≤ 2.x, with or without
//! `data_format`) and the nested layout of firmware 3.x (`beam_intrinsics`,
//! `lidar_data_format`, `config_params`, …). Packet decoding and frame assembly follow.

mod batcher;
mod destagger;
mod ipv4;
mod json;
mod metadata;
mod packet;
mod pcap;
mod xyz;

pub use batcher::{BatchedFrame, Batcher, Skipped};
pub use destagger::{Destaggerer, Return};
pub use metadata::{OusterMetadata, UdpProfile};
pub use packet::{PacketFormat, RawFrame};
pub use pcap::{Datagram, UdpReader};
pub use xyz::XyzLut;
