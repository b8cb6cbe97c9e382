//! The C ABI: the only module with `unsafe`.
