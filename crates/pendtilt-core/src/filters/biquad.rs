//! Second-order low-pass section.
