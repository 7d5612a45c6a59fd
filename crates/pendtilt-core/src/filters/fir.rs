//! Windowed-sinc FIR low-pass.
