//! The order in which an image pass hands its tasks (runs of pixels) to the thread pool.
//!
//! Rayon splits a parallel iterator into contiguous halves: in image order, each thread
//! would start on its own region of the image (with two threads, one the top half and the
//! other the bottom half), and the threads would trace rays into different parts of the scene
//! at the same time. On a scene larger than the shared last-level cache (a mesh of a million
//! triangles is about 100 MB of BVH), each thread then brings its own nodes and triangles in
//! from memory. Dealt out round robin instead, task k to the (k mod T)-th of T runs, the T
//! contiguous runs rayon gives the T threads are the tasks k = j, j + T, j + 2T, ...: at any
//! time the threads work on neighbouring runs of pixels and share what the cache holds.
//! docs/performance.md (2026-12-02 16:30) has the measurement.
//!
//! The order changes no result: every pixel's estimate depends on its index alone, and the
//! counters merged over tasks are integer sums.

/// The tasks `(index, task)` of an image pass in the order to hand to rayon: dealt round
/// robin over the current pool's threads (`rayon::current_num_threads`), each thread's
/// share in image order. On one thread, image order.
pub(crate) fn interleaved<T>(tasks: impl Iterator<Item = T>) -> Vec<(usize, T)> {
    dealt(tasks, rayon::current_num_threads())
}

/// The tasks dealt round robin into `threads` runs, laid end to end.
fn dealt<T>(tasks: impl Iterator<Item = T>, threads: usize) -> Vec<(usize, T)> {
    let threads = threads.max(1);
    let mut order: Vec<(usize, T)> = tasks.enumerate().collect();
    // Keys are distinct, so the unstable sort is deterministic (and allocates nothing).
    order.sort_unstable_by_key(|&(k, _)| (k % threads, k));
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two threads: the even tasks, then the odd ones, each in image order, so that the
    /// halves rayon hands out are neighbours task for task; every task appears once.
    #[test]
    fn two_threads_get_the_even_and_the_odd_tasks() {
        let order: Vec<usize> = dealt(0..7, 2).into_iter().map(|(k, _)| k).collect();
        assert_eq!(order, [0, 2, 4, 6, 1, 3, 5]);
        let order: Vec<usize> = dealt(0..8, 4).into_iter().map(|(k, _)| k).collect();
        assert_eq!(order, [0, 4, 1, 5, 2, 6, 3, 7]);
    }

    /// The index travels with its task, one thread keeps image order, and no thread count
    /// loses or repeats a task.
    #[test]
    fn every_task_keeps_its_index_once() {
        let tasks = ["a", "b", "c", "d", "e"];
        assert_eq!(
            dealt(tasks.iter(), 1),
            tasks.iter().enumerate().collect::<Vec<_>>()
        );
        for threads in 0..9 {
            let order = dealt(tasks.iter(), threads);
            let mut seen: Vec<usize> = order.iter().map(|&(k, _)| k).collect();
            assert!(order.iter().all(|&(k, t)| *t == tasks[k]));
            seen.sort_unstable();
            assert_eq!(seen, [0, 1, 2, 3, 4], "{threads} threads");
        }
    }
}
