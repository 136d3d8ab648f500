//! The parallel pass every integrator runs, stoppable between work items: rayon takes the
//! items, each asks the stop request before it starts, and a pass during which the request
//! said yes is reported as abandoned (`None`), so that the integrator leaves its render state
//! as it was and the iteration can be rendered again whole.

use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A request to stop, asked before each parallel work item (`&|| false` never stops).
pub type Stop<'a> = &'a (dyn Fn() -> bool + Sync);

/// Runs `work` on every item in parallel, unless `stop` says yes before an item starts; then
/// the remaining items are skipped (each returns `T::default()` at once) and `None` returned.
/// Otherwise the items' results joined by `merge` (rayon joins neighbours: with an indexed
/// `items` the order is the items' order).
pub(crate) fn reduce_until<P, T, W, M>(items: P, stop: Stop, work: W, merge: M) -> Option<T>
where
    P: IntoParallelIterator,
    T: Default + Send,
    W: Fn(P::Item) -> T + Sync + Send,
    M: Fn(T, T) -> T + Sync + Send,
{
    let abandoned = AtomicBool::new(false);
    let result = items
        .into_par_iter()
        .map(|item| polled(stop, &abandoned, item, &work))
        .reduce(T::default, merge);
    // The parallel iterator has joined: every store above is visible here.
    (!abandoned.load(Ordering::Relaxed)).then_some(result)
}

/// [`reduce_until`] keeping every item's result, in the items' order.
pub(crate) fn collect_until<P, T, W>(items: P, stop: Stop, work: W) -> Option<Vec<T>>
where
    P: IntoParallelIterator,
    P::Iter: IndexedParallelIterator,
    T: Default + Send,
    W: Fn(P::Item) -> T + Sync + Send,
{
    let abandoned = AtomicBool::new(false);
    let results: Vec<T> = items
        .into_par_iter()
        .map(|item| polled(stop, &abandoned, item, &work))
        .collect();
    (!abandoned.load(Ordering::Relaxed)).then_some(results)
}

/// `work(item)`, or nothing (and `abandoned` set) if `stop` says yes first.
fn polled<I, T: Default>(stop: Stop, abandoned: &AtomicBool, item: I, work: &impl Fn(I) -> T) -> T {
    if stop() {
        abandoned.store(true, Ordering::Relaxed);
        return T::default();
    }
    work(item)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicU32;

    #[test]
    fn a_pass_runs_every_item_in_order_unless_stopped() {
        let sum = reduce_until(0..1000u64, &|| false, |i| i, |a, b| a + b);
        assert_eq!(sum, Some(999 * 1000 / 2));
        let items = collect_until(0..100u32, &|| false, |i| i * 2).unwrap();
        assert_eq!(items, (0..100).map(|i| i * 2).collect::<Vec<_>>());

        // A stop request after the tenth poll abandons the pass, and the work stops soon.
        let polls = AtomicU32::new(0);
        let stop = || polls.fetch_add(1, Ordering::Relaxed) >= 10;
        let ran = AtomicU32::new(0);
        let result = reduce_until(
            0..10_000u32,
            &stop,
            |_| ran.fetch_add(1, Ordering::Relaxed),
            |a, b| a.max(b),
        );
        assert_eq!(result, None);
        assert!(ran.load(Ordering::Relaxed) <= 10);
        assert_eq!(collect_until(0..10u32, &|| true, |i| i), None);
    }
}
