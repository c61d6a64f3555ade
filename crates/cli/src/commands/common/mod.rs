//! The leaf modules the commands share (they import no command module): CSV input, numbers,
//! the progress bar, scene options, pictures and charts.

pub mod figures;
pub mod gltf_scene;
pub mod input;
pub mod numbers;
pub mod pictures;
pub mod progress;
pub mod scene;
