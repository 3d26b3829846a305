//! The one progress observer of fits, MCMC, diagnoses and batches: the library reports, the
//! caller (the CLI's bars, Python's printout) draws.

/// Called as work completes: `(done, total, what)` — units of work done so far, the total
/// expected, and what is being done. Called from worker threads; cheap calls only.
pub type Progress = std::sync::Arc<dyn Fn(usize, usize, &str) + Send + Sync>;
