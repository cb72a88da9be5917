//! Ouster sensors without the Ouster SDK. This first part reads the sensor metadata JSON in
//! both layouts ouster-sdk reads: the legacy flat layout (firmware ≤ 2.x, with or without
//! `data_format`) and the nested layout of firmware 3.x (`beam_intrinsics`,
//! `lidar_data_format`, `config_params`, …). Packet decoding and frame assembly follow.

mod json;
mod metadata;

pub use metadata::{OusterMetadata, UdpProfile};
