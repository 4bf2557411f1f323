//! Cross-crate and cross-process integration tests live in `tests/tests/`.
