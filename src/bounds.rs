//! Admissible sizes of the work. Every option whose value sets how much is computed (tooth
//! counts, verification steps, chord tolerances, harmonics, samples) has a range here, derived
//! from what the computation can do in seconds on a two-core machine, not from taste; every
//! accepted input stays within them, and an input outside gets [`OutOfBounds`], naming the
//! option, the value and the range, before any work starts.
//!
//! | quantity | range | why |
//! |---|---|---|
//! | teeth of one gear | [`MIN_TEETH`]..=[`MAX_TEETH`] | a pair of 1000-tooth gears takes ≈ 4 s |
//! | mesh verification steps | 0..=[`MAX_VERIFY_STEPS`] | 3600 positions (0.1° over a turn) ≈ 3.5 s |
//! | export chord tolerance | [`MIN_CHORD_TOL_MODULES`]·m ..= [`MAX_CHORD_TOL_MODULES`]·m | finer than 1e-5·m only multiplies vertices; coarser than 0.05·m loses the involute |
//! | estimated memory | ≤ [`memory_ceiling_bytes`] (default 4 GiB) | refused before allocating, instead of aborting |
//!
//! ```
//! use ncgear::bounds::{MAX_TEETH, check_teeth};
//! assert!(check_teeth("teeth", 24).is_ok());
//! let e = check_teeth("teeth", 1_000_000).unwrap_err();
//! assert!(e.to_string().contains("1000000"));
//! assert!(MAX_TEETH >= 500);
//! ```

use std::sync::atomic::{AtomicU64, Ordering};

/// Fewest teeth on a gear (a rack cuts no useful gear below three).
pub const MIN_TEETH: u32 = 3;

/// Most teeth on one gear: the teeth, the verification and the exports of a pair of 1000-tooth
/// gears take seconds, twice that several times more (docs/performance.md, "The largest
/// tooth count").
pub const MAX_TEETH: u32 = 1000;

/// Most positions of one mesh verification: 3600 (every 0.1° of a turn) take ≈ 3.5 s for a
/// 20-tooth pair; finer steps find nothing a 0.1° step misses (the check is exact between
/// positions only to first order anyway).
pub const MAX_VERIFY_STEPS: usize = 3600;

/// Finest export chord tolerance, in modules: below 1e-5·m the outline's vertices multiply
/// (≈ 1/√tol) while the drawing cannot show the difference.
pub const MIN_CHORD_TOL_MODULES: f64 = 1e-5;

/// Coarsest export chord tolerance, in modules: above 0.05·m a flank is a few chords and no
/// longer an involute.
pub const MAX_CHORD_TOL_MODULES: f64 = 0.05;

/// Default ceiling of [`memory_ceiling_bytes`]: 4 GiB.
pub const DEFAULT_MEMORY_CEILING_BYTES: u64 = 4 << 30;

static MEMORY_CEILING: AtomicU64 = AtomicU64::new(DEFAULT_MEMORY_CEILING_BYTES);

/// The memory a single computation may estimate for itself before it is refused, bytes
/// (default [`DEFAULT_MEMORY_CEILING_BYTES`]; the CLI's `--max-memory-gb` sets it).
#[must_use]
pub fn memory_ceiling_bytes() -> u64 {
    MEMORY_CEILING.load(Ordering::Relaxed)
}

/// Sets [`memory_ceiling_bytes`] for this process.
pub fn set_memory_ceiling_bytes(bytes: u64) {
    MEMORY_CEILING.store(bytes, Ordering::Relaxed);
}

/// An option or a size outside its admissible range.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{quantity} = {value} is outside its admissible range {range}: {why}")]
pub struct OutOfBounds {
    /// The option or quantity (the library's field name, or what the estimate counts).
    pub quantity: String,
    /// The value given or estimated, as written.
    pub value: String,
    /// The admissible range.
    pub range: String,
    /// Why the range is what it is, and what to do.
    pub why: String,
}

/// Checks a tooth count of one gear against [`MIN_TEETH`]..=[`MAX_TEETH`].
///
/// # Errors
/// [`OutOfBounds`] outside the range.
pub fn check_teeth(quantity: &str, z: u32) -> Result<(), OutOfBounds> {
    within(
        quantity,
        z,
        MIN_TEETH..=MAX_TEETH,
        "teeth per gear; more would take minutes to cut and verify",
    )
}

/// Checks the positions of a mesh verification against 0..=[`MAX_VERIFY_STEPS`].
///
/// # Errors
/// [`OutOfBounds`] above the limit.
pub fn check_verify_steps(quantity: &str, steps: usize) -> Result<(), OutOfBounds> {
    within(
        quantity,
        steps,
        0..=MAX_VERIFY_STEPS,
        "positions per mesh check (3600 = every 0.1° of a turn)",
    )
}

/// `value` within `range`, or the [`OutOfBounds`] that names `quantity` and says `why`.
fn within<T: PartialOrd + std::fmt::Display>(
    quantity: &str,
    value: T,
    range: std::ops::RangeInclusive<T>,
    why: &str,
) -> Result<(), OutOfBounds> {
    if range.contains(&value) {
        return Ok(());
    }
    Err(OutOfBounds {
        quantity: quantity.into(),
        value: value.to_string(),
        range: format!("{}..={}", range.start(), range.end()),
        why: why.into(),
    })
}

/// Checks an export chord tolerance `tol_mm` against the module `module_mm`:
/// [`MIN_CHORD_TOL_MODULES`]·m ..= [`MAX_CHORD_TOL_MODULES`]·m.
///
/// # Errors
/// [`OutOfBounds`] outside the range or not finite.
pub fn check_chord_tol(quantity: &str, tol_mm: f64, module_mm: f64) -> Result<(), OutOfBounds> {
    let (lo, hi) = (
        MIN_CHORD_TOL_MODULES * module_mm,
        MAX_CHORD_TOL_MODULES * module_mm,
    );
    if tol_mm >= lo && tol_mm <= hi {
        return Ok(());
    }
    Err(OutOfBounds {
        quantity: quantity.into(),
        value: format!("{tol_mm} mm"),
        range: format!("[{lo:e}, {hi:e}] mm (1e-5·m to 0.05·m at m = {module_mm} mm)"),
        why: "chord sag of the exported outlines, relative to the module".into(),
    })
}

/// Checks an estimate of the memory a computation needs against [`memory_ceiling_bytes`];
/// `what` says what is counted (e.g. "3 outlines of 2 000 000 vertices").
///
/// # Errors
/// [`OutOfBounds`] above the ceiling.
pub fn check_memory(what: &str, bytes: f64) -> Result<(), OutOfBounds> {
    let ceiling = memory_ceiling_bytes();
    if bytes.is_finite() && bytes <= ceiling as f64 {
        return Ok(());
    }
    Err(OutOfBounds {
        quantity: format!("estimated memory of {what}"),
        value: format!("{:.3} GB", bytes / 1e9),
        range: format!("≤ {:.3} GB", ceiling as f64 / 1e9),
        why: "refused before allocating; lower the size named, or raise the ceiling with \
              --max-memory-gb if the machine has the memory"
            .into(),
    })
}

/// The admissible range of one number of an input file (an error file, a scene, a spec, a
/// design file): finite, and within `[lo, hi]`, or `(lo, hi]` when the lower end is excluded.
/// The file readers check every number with [`Span::check`] before any work and name the file
/// and the key; the ranges are listed in docs/bounds.md, "Ranges inside input files".
///
/// ```
/// use ncgear::bounds::Span;
/// let amplitude = Span::closed(-1e6, 1e6);
/// assert_eq!(amplitude.check(-13.0, "an amplitude in µm"), Ok(-13.0));
/// let e = amplitude.check(1e308, "an amplitude in µm").unwrap_err();
/// assert!(e.contains("1e308") && e.contains("[-1e6, 1e6]"), "{e}");
/// assert!(Span::positive(1.0).check(f64::NAN, "a σ").is_err());
/// assert!(Span::positive(1.0).check(0.0, "a σ").is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Lower end.
    pub lo: f64,
    /// Upper end (included).
    pub hi: f64,
    /// Whether `lo` itself is excluded.
    pub lo_excluded: bool,
}

impl Span {
    /// `[lo, hi]`.
    #[must_use]
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            hi,
            lo_excluded: false,
        }
    }

    /// `(0, hi]`: a positive number.
    #[must_use]
    pub const fn positive(hi: f64) -> Self {
        Self {
            lo: 0.0,
            hi,
            lo_excluded: true,
        }
    }

    /// `[-limit, limit]`.
    #[must_use]
    pub const fn symmetric(limit: f64) -> Self {
        Self::closed(-limit, limit)
    }

    /// Whether `v` is finite and within the span.
    #[must_use]
    pub fn contains(&self, v: f64) -> bool {
        let above = if self.lo_excluded {
            v > self.lo
        } else {
            v >= self.lo
        };
        v.is_finite() && above && v <= self.hi
    }

    /// `v` when it is within the span; else what is wrong, for the caller to prefix with the
    /// file and the key: `"{v} is outside {span}: {what}"` (`what` says what the number is, its
    /// unit and why the range).
    ///
    /// # Errors
    /// The message, when `v` is not finite or outside the span.
    pub fn check(&self, v: f64, what: &str) -> Result<f64, String> {
        if self.contains(v) {
            return Ok(v);
        }
        Err(format!("{} is outside {self}: {what}", number(v)))
    }
}

impl std::fmt::Display for Span {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let open = if self.lo_excluded { '(' } else { '[' };
        write!(f, "{open}{}, {}]", number(self.lo), number(self.hi))
    }
}

/// A number as a message shows it: plainly between 1e-4 and 1e6, else in exponent form (a
/// 1e308 is not printed as 309 digits).
#[must_use]
pub fn number(v: f64) -> String {
    if v == 0.0 || (v.is_finite() && (1e-4..1e6).contains(&v.abs())) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}
