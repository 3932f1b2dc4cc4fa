//! Progress reporting from inside the Allan kernels.
//!
//! A caller passes a hook `Fn(fraction) -> bool` (`fraction` in 0..=1, non-decreasing; return
//! `false` to cancel). The kernels announce their work up front and advance a shared counter
//! as blocks, chunks and stages complete, on whichever thread finishes them; the hook is called
//! under a lock, so calls are serialised and the reported fractions never go backwards.
//!
//! Reporting never changes a result: the kernels run exactly the same arithmetic with or
//! without a hook (the hook only observes a counter), which `tests::hook_does_not_change_results`
//! in the parent module and `tests/test_determinism.py` check bit for bit. A cancelled analysis
//! stops at the next block boundary with [`Error::Cancelled`].

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::{Error, Result};

/// The caller's progress callback: receives the completed fraction, returns `false` to cancel.
pub type Hook<'a> = &'a (dyn Fn(f64) -> bool + Sync);

/// Smallest fraction increment that triggers a call of the hook (besides the final 1.0).
const STEP: f64 = 0.005;

struct State {
    done: f64,
    total: f64,
    reported: f64,
}

/// Shared progress counter of one analysis (possibly many axes or units).
pub struct Progress<'a> {
    hook: Option<Hook<'a>>,
    state: Mutex<State>,
    cancelled: AtomicBool,
}

impl std::fmt::Debug for Progress<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("hook", &self.hook.is_some())
            .field("cancelled", &self.is_cancelled())
            .finish_non_exhaustive()
    }
}

impl<'a> Progress<'a> {
    /// No reporting.
    pub fn none() -> Progress<'static> {
        Progress {
            hook: None,
            state: Mutex::new(State {
                done: 0.0,
                total: 0.0,
                reported: -1.0,
            }),
            cancelled: AtomicBool::new(false),
        }
    }

    /// Reports through `hook` (or not at all when `None`).
    pub fn new(hook: Option<Hook<'a>>) -> Progress<'a> {
        Progress {
            hook,
            ..Progress::none()
        }
    }

    /// True once the hook asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// `Err(Cancelled)` once the hook asked to stop.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }

    /// Announces `work` more units of work (before it starts).
    pub(crate) fn add_total(&self, work: f64) {
        if self.hook.is_some() {
            let mut s = self
                .state
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            s.total += work;
        }
    }

    /// Records `work` completed units and calls the hook when the fraction moved enough.
    pub(crate) fn advance(&self, work: f64) {
        let Some(hook) = self.hook else {
            return;
        };
        let mut s = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        s.done += work;
        let fraction = if s.total > 0.0 {
            (s.done / s.total).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if fraction >= s.reported + STEP || (fraction >= 1.0 && s.reported < 1.0) {
            s.reported = fraction;
            if !hook(fraction) {
                self.cancelled.store(true, Ordering::Relaxed);
            }
        }
    }

    /// Reports the start (0.0).
    pub(crate) fn start(&self) {
        self.advance(0.0);
    }

    /// Reports completion (1.0) unless cancelled.
    pub(crate) fn finish(&self) {
        let Some(hook) = self.hook else {
            return;
        };
        let mut s = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if s.reported < 1.0 && !self.is_cancelled() {
            s.reported = 1.0;
            s.done = s.total;
            if !hook(1.0) {
                self.cancelled.store(true, Ordering::Relaxed);
            }
        }
    }

    /// A stage of `weight` units split into `items` equal parts.
    pub(crate) fn stage(&self, weight: f64, items: usize) -> Stage<'_, 'a> {
        Stage {
            progress: self,
            per_item: if items == 0 {
                0.0
            } else {
                weight / items as f64
            },
        }
    }
}

/// A stage whose items each advance the counter by the same amount.
pub(crate) struct Stage<'p, 'a> {
    progress: &'p Progress<'a>,
    per_item: f64,
}

impl Stage<'_, '_> {
    /// One item done.
    pub(crate) fn item_done(&self) {
        self.progress.advance(self.per_item);
    }

    /// True once cancelled (items may skip their work).
    pub(crate) fn is_cancelled(&self) -> bool {
        self.progress.is_cancelled()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_are_monotone_and_end_at_one() {
        let seen = Mutex::new(Vec::new());
        let hook = |f: f64| {
            seen.lock().unwrap().push(f);
            true
        };
        let p = Progress::new(Some(&hook));
        p.add_total(10.0);
        p.start();
        let stage = p.stage(10.0, 1000);
        for _ in 0..1000 {
            stage.item_done();
        }
        p.finish();
        let seen = seen.into_inner().unwrap();
        assert_eq!(seen.first(), Some(&0.0));
        assert_eq!(seen.last(), Some(&1.0));
        assert!(seen.windows(2).all(|w| w[0] < w[1]));
        // Throttled: about 1/STEP calls, not 1000.
        assert!(seen.len() <= 202, "{}", seen.len());
    }

    #[test]
    fn cancel() {
        let hook = |f: f64| f < 0.5;
        let p = Progress::new(Some(&hook));
        p.add_total(1.0);
        assert!(p.check().is_ok());
        p.advance(0.6);
        assert_eq!(p.check(), Err(Error::Cancelled));
    }
}
