//! The order-keeping parallel map of fits, replicates, chains and batch records: rayon on a
//! pool of the caller's size (parallelism is passed explicitly, never read from the
//! environment), each item's result in its own slot, so the output is the same for any number
//! of threads.

/// Maps `f` over `items` on `threads` threads (0: all cores), keeping order. One thread, or one
/// item, runs on the caller's thread.
pub fn par_map<T: Sync, R: Send>(items: &[T], threads: usize, f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use rayon::prelude::*;
    let threads = if threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { threads };
    let threads = threads.min(items.len()).max(1);
    if threads == 1 {
        return items.iter().map(&f).collect();
    }
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.install(|| items.par_iter().map(&f).collect()),
        // no threads to be had (a process limit): the same results, one at a time
        Err(_) => items.iter().map(&f).collect(),
    }
}
