//! Shader export (see the crate docs).
