//! Where a long computation reports how far it has come: [`Progress`], one way — an argument of
//! the long call: the mesh checks of the toothed train and pair (their staged `run`), the
//! trade-off's designs, the analyses (Monte Carlo samples, dynamics periods and sweep points, the
//! orbit's frequency refinement). Never part of the options: it does not change the result.

use std::fmt;
use std::sync::Arc;

/// A progress sink: nothing (the default) or a function told how many steps were just done
/// (`1` per verified mesh position, for example). It may be called from several threads at
/// once. A sink does not change what is computed, and it is neither serialised nor read from a
/// file.
///
/// ```
/// use ncgear::progress::Progress;
/// use std::sync::Arc;
/// use std::sync::atomic::{AtomicU64, Ordering};
///
/// let done = Arc::new(AtomicU64::new(0));
/// let seen = Arc::clone(&done);
/// let sink = Progress::new(move |n| {
///     seen.fetch_add(n, Ordering::Relaxed);
/// });
/// sink.advance(3);
/// Progress::none().advance(5); // goes nowhere
/// assert_eq!(done.load(Ordering::Relaxed), 3);
/// ```
#[derive(Clone, Default)]
pub struct Progress(Option<Arc<dyn Fn(u64) + Send + Sync>>);

impl Progress {
    /// A sink that calls `f(n)` after each `n` steps done.
    pub fn new(f: impl Fn(u64) + Send + Sync + 'static) -> Self {
        Self(Some(Arc::new(f)))
    }

    /// No sink: progress goes nowhere (the default).
    #[must_use]
    pub fn none() -> Self {
        Self(None)
    }

    /// Reports `steps` more steps done (nothing without a sink).
    pub fn advance(&self, steps: u64) {
        if let Some(f) = &self.0 {
            f(steps);
        }
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "Progress(sink)"
        } else {
            "Progress(none)"
        })
    }
}
