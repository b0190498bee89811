//! Light around the sun: environment maps ([`environment`]: loaded from files or rendered from the sky), their
//! sampling against the diffraction BRDF ([`sampling`], model.md §3.10) and the environment's diffraction
//! prefiltered for frames ([`prefilter`], model.md §3.11), the sun a camera-made map holds ([`sun`]), and lamps
//! ([`lamp`]: point and spot lights whose size sets their coherence).

pub mod environment;
pub mod lamp;
pub mod prefilter;
pub mod sampling;
pub mod sun;
