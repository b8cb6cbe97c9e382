//! The n-sided Generalized Bézier patch (seed 000 §2.4–2.7, §3.4–3.6; seed 002).

pub mod cgb;
pub mod connected;
pub mod decompose;
pub mod derivs;
pub mod domain;
pub mod elevate;
pub mod error;
pub mod gbp;
pub mod layout;
pub mod eval;
pub mod patch;
pub mod weights;

pub mod table;

pub use cgb::CgbBasisEvaluator;
pub use derivs::{angle_deg, Curvature, Jet2, SurfaceDerivs};
pub use domain::{Domain, DomainScratch, LocalParam};
pub use error::GbError;
pub use eval::Evaluate;
pub use layout::{bilinear, bilinear_inverse, Layout, LayoutError, SampleLayout, Sampling, SectorPoint};
pub use patch::{CgbPatch, GbPatch, Ribbon, WeightForm};
pub use weights::{gb_basis, layers_for_degree, GbBasis, GbBasisEvaluator};
