//! The order-keeping parallel map of fits, replicates, chains and batch records: on a rayon
//! pool of the caller's size (parallelism is passed explicitly, never read from the
//! environment), each item's result in its own slot, so the output is the same for any number
//! of threads.
//!
//! Items are taken one at a time, in order, by whichever thread is free (a shared counter), not
//! by `par_iter`'s halving splits: the diagnosis's jobs are few and of very unequal cost (the
//! second-state candidate, first, takes as long as the rest together), and halving put its
//! neighbours on its thread. Measured on a 60,762-row record (`long5/rec_026`, 2 cores): 15.6
//! and 17.1 s with `par_iter`, 11.7 and 12.8 s with the counter, the same CPU time (20.5–23 s).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Maps `f` over `items` on `threads` threads (0: all cores), keeping order. One thread, or one
/// item, runs on the caller's thread.
pub fn par_map<T: Sync, R: Send>(items: &[T], threads: usize, f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = if threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { threads };
    let threads = threads.min(items.len()).max(1);
    if threads == 1 {
        return items.iter().map(&f).collect();
    }
    let next = AtomicUsize::new(0);
    let out: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let work = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { break };
            let r = f(item);
            *out[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
        }
    };
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.scope(|s| {
            for _ in 0..threads {
                s.spawn(|_| work());
            }
        }),
        // no threads to be had (a process limit): the same results, one at a time
        Err(_) => work(),
    }
    // every slot is filled: the counter hands out each index exactly once, and a panic in `f`
    // propagates out of the scope before this line
    out.into_iter().map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()).expect("every item mapped")).collect()
}
