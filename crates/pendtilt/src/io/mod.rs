//! CSV input and output: the sensor-log reader and the estimates writer (MODEL.md section 5).
