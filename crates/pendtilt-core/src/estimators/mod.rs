//! The paper's estimators, one per module, all implementing [`crate::Estimator`].
