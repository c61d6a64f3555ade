//! The GPU renderer (see the crate docs).
