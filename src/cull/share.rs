//! Work shared between the calling thread and rayon's pool, for the culler's short parallel
//! phases (a fraction of a millisecond each).
//!
//! - No coordinate space: tasks are only numbered.
//! - Handing a phase to the pool (a parallel iterator called from outside it) leaves the caller
//!   waiting for a pool thread to wake, and one that has slept while the GPU drew the last frame
//!   can take a tenth of a millisecond or more to.
//! - So the pool's threads are woken once, when the work begins ([`with_crew`]), and wait there
//!   for its phases in turn.
//! - The calling thread starts on each phase's tasks at once ([`Phase::run`]), and the others join
//!   in as they come: each participant claims the next unclaimed task until none is left.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::SeqCst};
use std::sync::{Mutex, OnceLock};

/// A phase's work: numbered tasks, each participant running those it claims with a state of its own.
pub trait Tasks: Sync {
    type State: Send;
    /// How many tasks. A participant claims one at a time, in order: the biggest first balance
    /// the load best; tasks in an order of their own hand back states in that order.
    fn count(&self) -> usize;
    /// A participant's state, made before its first task.
    fn state(&self) -> Self::State;
    fn run(&self, state: &mut Self::State, task: usize);
}

/// One phase, run once: by [`Phase::run`] on the calling thread, helped by [`Phase::help`].
pub struct Phase<J: Tasks> {
    job: OnceLock<J>,
    next: AtomicUsize,
    /// Helpers that have claimed and not yet handed in their state.
    busy: AtomicUsize,
    states: Mutex<Vec<J::State>>,
}

impl<J: Tasks> Default for Phase<J> {
    fn default() -> Self {
        Phase { job: OnceLock::new(), next: AtomicUsize::new(0), busy: AtomicUsize::new(0), states: Mutex::default() }
    }
}

impl<J: Tasks> Phase<J> {
    /// Runs every task of `job` once, on the calling thread and on the helpers that join before
    /// the tasks run out; returns the states of those that ran a task (the caller's first) once
    /// every helper has handed its state in. A phase runs one job: a second is ignored.
    pub fn run(&self, job: J) -> Vec<J::State> {
        let job = self.job.get_or_init(move || job);
        let mut states: Vec<J::State> = self.claim(job).into_iter().collect();
        // Every task is claimed: a helper still busy is finishing its last one.
        while self.busy.load(SeqCst) != 0 {
            std::thread::yield_now();
        }
        states.extend(std::mem::take(&mut *self.states.lock().unwrap_or_else(|e| e.into_inner())));
        states
    }

    /// A helper's part: waits until the phase's job is given to [`Phase::run`] (or `quit` is set:
    /// it never will be), then claims tasks until none is left.
    pub fn help(&self, quit: &AtomicBool) {
        let job = loop {
            if let Some(job) = self.job.get() {
                break job;
            }
            if quit.load(SeqCst) {
                return;
            }
            std::thread::yield_now();
        };
        // Counted busy before claiming, so that `run` cannot miss a state still to come.
        self.busy.fetch_add(1, SeqCst);
        let leave = Leave(&self.busy);
        if let Some(state) = self.claim(job) {
            self.states.lock().unwrap_or_else(|e| e.into_inner()).push(state);
        }
        drop(leave);
    }

    /// Claims and runs tasks until none is left; the state, if any was claimed.
    fn claim(&self, job: &J) -> Option<J::State> {
        let mut state = None;
        loop {
            let i = self.next.fetch_add(1, SeqCst);
            if i >= job.count() {
                return state;
            }
            job.run(state.get_or_insert_with(|| job.state()), i);
        }
    }
}

/// Counts a helper out of `busy` when dropped, also when its task panics (the panic then reaches
/// the caller from the end of [`with_crew`]).
struct Leave<'a>(&'a AtomicUsize);

impl Drop for Leave<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, SeqCst);
    }
}

/// Runs `body` on the calling thread while the other threads of rayon's pool (as many as keep
/// every core busy) run `helper`, woken now so as to be awake when `body`'s phases begin. `helper`
/// gets a flag set once `body` has returned: one waiting for a phase that never ran gives up then.
pub fn with_crew<R>(helper: impl Fn(&AtomicBool) + Sync, body: impl FnOnce() -> R) -> R {
    let quit = AtomicBool::new(false);
    rayon::in_place_scope(|scope| {
        for _ in 1..rayon::current_num_threads() {
            scope.spawn(|_| helper(&quit));
        }
        let quit_on_drop = Quit(&quit);
        let r = body();
        drop(quit_on_drop);
        r
    })
}

/// Sets the crew's flag when dropped, also when `body` panics.
struct Quit<'a>(&'a AtomicBool);

impl Drop for Quit<'_> {
    fn drop(&mut self) {
        self.0.store(true, SeqCst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tasks that record their own number.
    struct Numbers(usize);

    impl Tasks for Numbers {
        type State = Vec<usize>;
        fn count(&self) -> usize {
            self.0
        }
        fn state(&self) -> Vec<usize> {
            Vec::new()
        }
        fn run(&self, done: &mut Vec<usize>, i: usize) {
            done.push(i);
        }
    }

    #[test]
    fn every_task_of_every_phase_runs_once() {
        for n in [0, 1, 2, 7, 100] {
            let phases: [Phase<Numbers>; 2] = Default::default();
            let states = with_crew(
                |quit| phases.iter().for_each(|p| p.help(quit)),
                || phases.iter().map(|p| p.run(Numbers(n))).collect::<Vec<_>>(),
            );
            for s in states {
                let mut all: Vec<usize> = s.into_iter().flatten().collect();
                all.sort_unstable();
                assert_eq!(all, (0..n).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn helpers_waiting_for_a_phase_never_run_give_up() {
        let phases: [Phase<Numbers>; 2] = Default::default();
        let first = with_crew(|quit| phases.iter().for_each(|p| p.help(quit)), || phases[0].run(Numbers(5)));
        assert_eq!(first.into_iter().flatten().count(), 5);
    }

    #[test]
    fn a_phase_runs_alone_without_a_crew() {
        let phase = Phase::default();
        assert_eq!(phase.run(Numbers(3)), vec![vec![0, 1, 2]]);
    }
}
