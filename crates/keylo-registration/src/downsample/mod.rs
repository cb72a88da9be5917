//! Raw-cloud downsamplers: `passthrough` and `voxel`.

mod passthrough;
mod voxel_grid;

pub use passthrough::{Passthrough, PassthroughConfig};
pub use voxel_grid::{VoxelDownsampler, VoxelDownsamplerConfig};

use keylo_core::config::StageParams;

keylo_core::stage_params!(PassthroughConfig => "passthrough" as DownsamplerParams);
keylo_core::stage_params!(VoxelDownsamplerConfig => "voxel" as DownsamplerParams);

/// Registers `passthrough` and `voxel`.
pub fn register(registry: &mut keylo_core::Registry) {
    registry.downsamplers.add::<PassthroughConfig>(
        PassthroughConfig::KIND,
        "every valid point of the frame (the raw cloud)",
        |c, _| Ok(Box::new(Passthrough::new(c))),
    );
    registry.downsamplers.add::<VoxelDownsamplerConfig>(
        VoxelDownsamplerConfig::KIND,
        "one point per voxel of the raw cloud (first point, or the voxel centroid)",
        |c, _| Ok(Box::new(VoxelDownsampler::new(c)?)),
    );
}
