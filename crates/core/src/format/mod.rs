//! Formats (in progress).
