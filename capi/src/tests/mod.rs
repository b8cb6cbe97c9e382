//! Rust-side tests of the C ABI (unit tests: the crate builds no rlib for integration tests).
mod api;
mod header;
mod offsets;
