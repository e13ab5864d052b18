//! Why a filmed track cannot be compared with a design: the file, the line or column, what was
//! expected and what to do.

/// Why a track cannot be read, registered or compared. Every variant is bad input (the CLI exits
/// with code 2), except [`CompareError::NoFit`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CompareError {
    /// The track file cannot be read.
    #[error("{file}: cannot read the track: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// A value of a data row is not a finite number, or a row is short.
    #[error("{file}:{line}: column `{column}`: {message}")]
    BadValue {
        /// File.
        file: String,
        /// Line number (1-based).
        line: usize,
        /// Column name.
        column: String,
        /// What is wrong and expected.
        message: String,
    },
    /// The time column does not increase.
    #[error(
        "{file}:{line}: time {time} is not after the previous frame's {previous}: the frames must be in time order, each once"
    )]
    TimeNotIncreasing {
        /// File.
        file: String,
        /// Line number (1-based).
        line: usize,
        /// Time of this frame (the file's unit).
        time: f64,
        /// Time of the previous frame.
        previous: f64,
    },
    /// A column named by the options (or needed) is not in the file.
    #[error("{file}: no column `{column}` (the columns are {available}); {help}")]
    UnknownColumn {
        /// File.
        file: String,
        /// The column asked for.
        column: String,
        /// The file's columns.
        available: String,
        /// What to do.
        help: String,
    },
    /// The track is in pixels and nothing gives the scale.
    #[error(
        "{file}: the track is in pixels and no scale is given: add --px-per-mm S, --calibration x1,y1,x2,y2,dist_mm (two image points and their distance in mm), or --fit-scale to fit the scale to the design (it then absorbs any size error of the built mechanism)"
    )]
    PixelsWithoutScale {
        /// File.
        file: String,
    },
    /// The record is shorter than one carrier turn.
    #[error("{file}: {message}; the comparison needs at least one whole carrier turn of frames")]
    TooShort {
        /// File.
        file: String,
        /// What was found.
        message: String,
    },
    /// A bad option value.
    #[error("option `{option}`: {message}")]
    BadOption {
        /// Option.
        option: &'static str,
        /// What is expected.
        message: String,
    },
    /// The track does not match the design (orientation, size) before any fit.
    #[error("{file}: {message}")]
    Mismatch {
        /// File.
        file: String,
        /// What does not match and what to do.
        message: String,
    },
    /// The registration did not converge (exit code 1).
    #[error("the registration did not converge: {message}")]
    NoFit {
        /// What happened.
        message: String,
    },
}
