//! The parallel pass every integrator runs, stoppable between work items and within them:
//! rayon takes the items, each asks the stop request ([`Poll`]) before it starts, and an item
//! whose paths or pixels can be long (a deep closed scene traces max_depth bounces per path,
//! and VCM connects each camera vertex to every vertex of a light subpath) asks again between
//! its paths, pixels or vertices. A pass during which the request said yes is reported as
//! abandoned (`None`), so that the integrator leaves its render state as it was and the
//! iteration can be rendered again whole: what the items computed after the stop is thrown
//! away with the rest, so stopping never changes an image.

use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A request to stop, asked before each parallel work item (`&|| false` never stops).
pub type Stop<'a> = &'a (dyn Fn() -> bool + Sync);

/// The stop request of one pass, shared by its work items: once it has said yes, the pass is
/// abandoned and every later [`Poll::stopped`] says yes without asking again.
pub(crate) struct Poll<'a> {
    stop: Stop<'a>,
    abandoned: AtomicBool,
}

impl<'a> Poll<'a> {
    /// A pass not yet abandoned, asking `stop`.
    pub(crate) fn new(stop: Stop<'a>) -> Self {
        Poll {
            stop,
            abandoned: AtomicBool::new(false),
        }
    }

    /// True if the pass is abandoned: `stop` said yes now or before. A work item that sees
    /// yes returns at once; what it returns is discarded.
    #[inline]
    pub(crate) fn stopped(&self) -> bool {
        if self.abandoned.load(Ordering::Relaxed) {
            return true;
        }
        if (self.stop)() {
            self.abandoned.store(true, Ordering::Relaxed);
            return true;
        }
        false
    }

    /// True if the pass was abandoned (read after the parallel iterator has joined, when every
    /// store is visible).
    fn was_abandoned(&self) -> bool {
        self.abandoned.load(Ordering::Relaxed)
    }
}

/// Runs `work` on every item in parallel, unless `poll` says stop before an item starts; then
/// the remaining items are skipped (each returns `T::default()` at once) and `None` returned.
/// `work` may ask `poll` itself between its steps and return early; if it saw a stop, the
/// pass is `None` too. Otherwise the items' results joined by `merge` (rayon joins
/// neighbours: with an indexed `items` the order is the items' order).
pub(crate) fn reduce_until<P, T, W, M>(items: P, poll: &Poll, work: W, merge: M) -> Option<T>
where
    P: IntoParallelIterator,
    T: Default + Send,
    W: Fn(P::Item) -> T + Sync + Send,
    M: Fn(T, T) -> T + Sync + Send,
{
    let result = items
        .into_par_iter()
        .map(|item| polled(poll, item, &work))
        .reduce(T::default, merge);
    // The parallel iterator has joined: every store above is visible here.
    (!poll.was_abandoned()).then_some(result)
}

/// [`reduce_until`] keeping every item's result, in the items' order.
pub(crate) fn collect_until<P, T, W>(items: P, poll: &Poll, work: W) -> Option<Vec<T>>
where
    P: IntoParallelIterator,
    P::Iter: IndexedParallelIterator,
    T: Default + Send,
    W: Fn(P::Item) -> T + Sync + Send,
{
    let results: Vec<T> = items
        .into_par_iter()
        .map(|item| polled(poll, item, &work))
        .collect();
    (!poll.was_abandoned()).then_some(results)
}

/// `work(item)`, or nothing if `poll` says stop first.
fn polled<I, T: Default>(poll: &Poll, item: I, work: &impl Fn(I) -> T) -> T {
    if poll.stopped() {
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
        let never = Poll::new(&|| false);
        let sum = reduce_until(0..1000u64, &never, |i| i, |a, b| a + b);
        assert_eq!(sum, Some(999 * 1000 / 2));
        let items = collect_until(0..100u32, &never, |i| i * 2).unwrap();
        assert_eq!(items, (0..100).map(|i| i * 2).collect::<Vec<_>>());

        // A stop request after the tenth poll abandons the pass, and the work stops soon.
        let polls = AtomicU32::new(0);
        let stop = || polls.fetch_add(1, Ordering::Relaxed) >= 10;
        let ran = AtomicU32::new(0);
        let result = reduce_until(
            0..10_000u32,
            &Poll::new(&stop),
            |_| ran.fetch_add(1, Ordering::Relaxed),
            |a, b| a.max(b),
        );
        assert_eq!(result, None);
        assert!(ran.load(Ordering::Relaxed) <= 10);
        assert_eq!(collect_until(0..10u32, &Poll::new(&|| true), |i| i), None);
    }

    #[test]
    fn a_stop_seen_inside_an_item_abandons_the_pass() {
        // One item of many steps, each asking: the stop after the fifth poll ends the item
        // at its sixth step, and the pass is abandoned although the item returned normally.
        let polls = AtomicU32::new(0);
        let stop = || polls.fetch_add(1, Ordering::Relaxed) >= 5;
        let poll = Poll::new(&stop);
        let steps = AtomicU32::new(0);
        let result = reduce_until(
            0..1u32,
            &poll,
            |_| {
                for _ in 0..1_000_000 {
                    if poll.stopped() {
                        break;
                    }
                    steps.fetch_add(1, Ordering::Relaxed);
                }
                1u32
            },
            |a, b| a + b,
        );
        assert_eq!(result, None);
        assert!(steps.load(Ordering::Relaxed) <= 5);
        // Once abandoned, the request is not asked again.
        let asked = polls.load(Ordering::Relaxed);
        assert!(poll.stopped());
        assert_eq!(polls.load(Ordering::Relaxed), asked);
    }
}
