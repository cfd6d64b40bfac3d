//! scatterlab: author subsurface-scattering diffusion profiles.
pub mod model;
