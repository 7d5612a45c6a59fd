//! Kalman filtering.
