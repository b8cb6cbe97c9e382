//! Surface construction from a control mesh (seed 000 §2–4): curve network, ribbons, twists, patches.

pub mod surface;

pub use surface::{Patch, PatchSource, SideRef, Surface};
