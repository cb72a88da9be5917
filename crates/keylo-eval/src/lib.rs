//! Trajectory evaluation for keylo, computing the metrics the way
//! [evo](https://github.com/MichaelGrupp/evo) does. Pure math on [`keylo_core::Trajectory`]
//! values: trajectory files are read and written by `keylo_io::trajectory`.
//!
//! * [`associate`]: stamp matching (`evo --t_max_diff / --t_offset`).
//! * [`align`]: Umeyama SE(3)/Sim(3) alignment.
//! * [`ape`]: absolute pose error (`evo_ape -a`), [`rpe`]: relative pose error (`evo_rpe`).
//! * [`drift`]: KITTI-style drift over path segments.
//! * [`divergence`]: whether a run diverged (`keylo compare`'s verdict).
//! * [`coverage`]: how many estimated poses associated, and why so few when few did.
//! * [`stamp_map`]: a reference's clock (scale, offset) mapped onto the estimate's.
//! * [`evaluate`]: all of the above in one call, serialisable for `summary.json`.
//!
//! Parity with evo 1.38.1 is checked against committed fixtures in `tests/fixtures/evo/`.

#![warn(missing_docs)]

pub mod align;
pub mod align_roll;
pub mod ape;
pub mod associate;
pub mod coverage;
pub mod divergence;
pub mod drift;
mod error;
mod evaluate;
pub mod pose_error;
pub mod rpe;
pub mod stamp_map;
pub mod stats;

pub use error::EvalError;
pub use evaluate::{evaluate, Accuracy, EvalOptions};
