//! Why a design file cannot be simulated, or a simulation option is refused.

/// Why a design file cannot be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// The file cannot be read.
    #[error("{file}: cannot read the design file: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// JSON syntax or schema error.
    #[error(
        "{file}: {message}; a design file is what `ncgear design` writes (design.json, see docs/design.md)"
    )]
    BadJson {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// A field has an impossible value.
    #[error("{file}: field `{field}`: {message}")]
    BadField {
        /// File.
        file: String,
        /// Field path.
        field: String,
        /// What is wrong and expected.
        message: String,
    },
    /// A bad simulation option.
    #[error("option `{option}`: {message}")]
    BadOption {
        /// Option.
        option: &'static str,
        /// What is expected.
        message: String,
    },
}
