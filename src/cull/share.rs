//! Work shared between the calling thread and rayon's pool, for the culler's short parallel
//! phases (a fraction of a millisecond each). No coordinate space: tasks are only numbered.
//!
//! Handing a phase to the pool (a parallel iterator called from outside it) leaves the caller
//! waiting for a pool thread to wake, and one that has slept while the GPU drew the last frame
//! can take a tenth of a millisecond or more to. Here the calling thread starts on the tasks at
//! once, and pool threads join in when they wake: each participant claims the next unclaimed task
//! until none is left.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Runs `work(&mut state, i)` once for every task `i` in `0..n`, in order of `i` as claimed, on
/// the calling thread and on as many pool threads as join in before the tasks run out, each with
/// its own `state` from `init`; returns the states of those that ran a task (the caller's first).
/// Put the biggest tasks first: a participant claims one at a time.
pub fn share<S: Send>(n: usize, init: impl Fn() -> S + Sync, work: impl Fn(&mut S, usize) + Sync) -> Vec<S> {
    let next = AtomicUsize::new(0);
    let helpers = Mutex::new(Vec::new());
    // Claims and runs tasks until none is left; the state, if it ran any.
    let run = || {
        let mut state = None;
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= n {
                return state;
            }
            work(state.get_or_insert_with(&init), i);
        }
    };
    let mut states = Vec::new();
    rayon::in_place_scope(|scope| {
        for _ in 1..rayon::current_num_threads().min(n) {
            scope.spawn(|_| {
                if let Some(s) = run() {
                    helpers.lock().unwrap_or_else(|e| e.into_inner()).push(s);
                }
            });
        }
        states.extend(run());
    });
    states.extend(helpers.into_inner().unwrap_or_else(|e| e.into_inner()));
    states
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_task_runs_once() {
        for n in [0, 1, 2, 7, 100] {
            let states = share(n, Vec::new, |done: &mut Vec<usize>, i| done.push(i));
            let mut all: Vec<usize> = states.into_iter().flatten().collect();
            all.sort_unstable();
            assert_eq!(all, (0..n).collect::<Vec<_>>());
        }
    }
}
