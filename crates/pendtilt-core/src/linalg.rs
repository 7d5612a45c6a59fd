//! Small fixed-size linear algebra helpers.
