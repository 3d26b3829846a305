//! # rsf-fit

pub mod data;
pub mod segment;
