//! Reading configuration files (scenes, error files, model parameters) in TOML or JSON: one loader
//! for every input of the crate that is a serde document.
//!
//! The format is taken from the extension (`.json`, `.toml`); any other name is JSON when the text
//! starts with `{` and TOML otherwise ([`Format::detect`]). Parser messages keep the key and, for
//! TOML, the line.
//!
//! ```
//! use ncgear::config::{Format, parse};
//! #[derive(Debug, serde::Deserialize)]
//! struct Gear { teeth: u32 }
//! let g: Gear = parse("teeth = 24", "gear.toml", Format::Toml).unwrap();
//! assert_eq!(g.teeth, 24);
//! let e = parse::<Gear>("{\"teeth\": -1}", "gear.json", Format::Json).unwrap_err();
//! assert!(e.to_string().starts_with("gear.json: "));
//! ```

use std::path::Path;

use serde::de::DeserializeOwned;

/// The syntax of a configuration text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// TOML (the default for hand-written files).
    Toml,
    /// JSON (files written by programs).
    Json,
}

impl Format {
    /// The format of a file: by extension (`.json`, `.toml`, case-insensitive); otherwise JSON
    /// when `text` starts with `{` (after white space), TOML else.
    #[must_use]
    pub fn detect(path: &Path, text: &str) -> Self {
        let ext = path.extension().and_then(|e| e.to_str());
        match ext {
            Some(e) if e.eq_ignore_ascii_case("json") => Self::Json,
            Some(e) if e.eq_ignore_ascii_case("toml") => Self::Toml,
            _ if text.trim_start().starts_with('{') => Self::Json,
            _ => Self::Toml,
        }
    }
}

/// A configuration file that could not be read or parsed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read {file}: {message}")]
    Unreadable {
        /// The file.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The text is not valid for the expected document.
    #[error("{file}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message (key, and line for TOML).
        message: String,
    },
}

/// A file's text, its name for messages, and its [`Format`].
#[derive(Debug, Clone)]
pub struct Source {
    /// The whole text.
    pub text: String,
    /// The path as given, for messages.
    pub file: String,
    /// The syntax ([`Format::detect`]).
    pub format: Format,
}

impl Source {
    /// Reads `path`.
    ///
    /// # Errors
    /// [`ConfigError::Unreadable`].
    pub fn from_path(path: &Path) -> Result<Self, ConfigError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::Unreadable {
            file: file.clone(),
            message: e.to_string(),
        })?;
        let format = Format::detect(path, &text);
        Ok(Self { text, file, format })
    }

    /// Deserialises the text.
    ///
    /// # Errors
    /// [`ConfigError::Parse`] with the parser's message.
    pub fn parse<T: DeserializeOwned>(&self) -> Result<T, ConfigError> {
        parse(&self.text, &self.file, self.format)
    }
}

/// Deserialises `text` in `format`; `file` names the source in messages.
///
/// # Errors
/// [`ConfigError::Parse`] with the parser's message (key, and line for TOML).
pub fn parse<T: DeserializeOwned>(
    text: &str,
    file: &str,
    format: Format,
) -> Result<T, ConfigError> {
    let parsed = match format {
        Format::Json => serde_json::from_str(text).map_err(|e| e.to_string()),
        Format::Toml => toml::from_str(text).map_err(|e| e.to_string()),
    };
    parsed.map_err(|message| ConfigError::Parse {
        file: file.into(),
        message,
    })
}

/// Reads and deserialises `path` ([`Source::from_path`], then [`Source::parse`]).
///
/// # Errors
/// [`ConfigError`].
pub fn load<T: DeserializeOwned>(path: &Path) -> Result<T, ConfigError> {
    Source::from_path(path)?.parse()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_follows_the_extension_then_the_text() {
        let f = |p: &str, t: &str| Format::detect(Path::new(p), t);
        assert_eq!(f("a.JSON", "x = 1"), Format::Json);
        assert_eq!(f("a.toml", "{"), Format::Toml);
        assert_eq!(f("a.cfg", "  {\"x\": 1}"), Format::Json);
        assert_eq!(f("a", "x = 1"), Format::Toml);
    }

    #[test]
    fn toml_errors_keep_the_line() {
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct T {
            x: f64,
        }
        let e = parse::<T>("\n\nx = \"a\"", "t.toml", Format::Toml).unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
    }
}
