//! # rsf-fit

pub mod data;
pub mod diagnose;
pub mod fit;
pub mod lm;
pub mod mcmc;
pub mod segment;
pub mod sens;
pub mod synthetic;
