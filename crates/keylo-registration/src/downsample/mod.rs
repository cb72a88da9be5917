//! Raw-cloud downsamplers: `passthrough` and `voxel`.

mod passthrough;
mod voxel_grid;

pub use passthrough::{Passthrough, PassthroughConfig};
pub use voxel_grid::{VoxelDownsampler, VoxelDownsamplerConfig};

/// Registers `passthrough` and `voxel`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.downsamplers.add::<PassthroughConfig>(
        "passthrough",
        "every valid point of the frame (the raw cloud)",
        |c, _| Ok(Box::new(Passthrough::new(c))),
    );
    registry.downsamplers.add::<VoxelDownsamplerConfig>(
        "voxel",
        "one point per voxel of the raw cloud (first point, or the voxel centroid)",
        |c, _| Ok(Box::new(VoxelDownsampler::new(c)?)),
    );
}
