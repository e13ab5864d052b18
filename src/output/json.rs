//! The JSON text of the reports: indented like `serde_json`'s pretty printer, except that an
//! array of numbers (a point, a table row, a coefficient list) stays on one line.
//!
//! `design.json` holds three pitch tables of thousands of `[θ, r]` rows; one number per line made
//! it four lines per row, twice the bytes and most of the time spent writing the report.
//!
//! ```
//! let rows = vec![vec![0.0, 1.5], vec![2.0, 3.25]];
//! let text = ncgear::output::json::to_string(&rows)?;
//! assert_eq!(text, "[\n  [0.0, 1.5],\n  [2.0, 3.25]\n]");
//! # Ok::<(), serde_json::Error>(())
//! ```

use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter};
use std::io::{self, Write};

/// `value` as indented JSON (two spaces) with arrays of scalars on one line.
pub fn to_string(value: &impl Serialize) -> Result<String, serde_json::Error> {
    let mut out = Vec::with_capacity(4096);
    let mut ser = serde_json::Serializer::with_formatter(&mut out, RowFormatter::default());
    value.serialize(&mut ser)?;
    // The serializer writes UTF-8 only.
    Ok(String::from_utf8(out).expect("serde_json writes UTF-8"))
}

/// How an open array lays out its elements: decided by its first element.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Layout {
    Undecided,
    /// Numbers, booleans or nulls: `[a, b, c]`.
    Inline,
    /// Anything else: one element per line.
    Block,
}

/// The pretty layout of `serde_json` with inline scalar arrays. A value's separator and line
/// break are written once the value's kind is known (at its first token).
#[derive(Debug, Default)]
struct RowFormatter {
    indent: usize,
    /// Open arrays, innermost last.
    arrays: Vec<Layout>,
    /// An array element is about to start (`Some(first)`).
    pending: Option<bool>,
    /// The innermost open object or block array has an element (for the closing line break).
    has_value: Vec<bool>,
}

impl RowFormatter {
    fn newline<W: ?Sized + Write>(&self, w: &mut W) -> io::Result<()> {
        w.write_all(b"\n")?;
        for _ in 0..self.indent {
            w.write_all(b"  ")?;
        }
        Ok(())
    }

    /// Before the first token of any value: the pending array element's separator.
    fn open<W: ?Sized + Write>(&mut self, w: &mut W, scalar: bool) -> io::Result<()> {
        let Some(first) = self.pending.take() else {
            return Ok(());
        };
        let layout = self
            .arrays
            .last_mut()
            .expect("an element is inside an array");
        if *layout == Layout::Undecided {
            *layout = if scalar {
                Layout::Inline
            } else {
                self.indent += 1;
                Layout::Block
            };
        }
        match *layout {
            Layout::Inline => {
                if !first {
                    w.write_all(b", ")?;
                }
                Ok(())
            }
            _ => {
                if !first {
                    w.write_all(b",")?;
                }
                if let Some(h) = self.has_value.last_mut() {
                    *h = true;
                }
                self.newline(w)
            }
        }
    }
}

macro_rules! scalar {
    ($($name:ident: $t:ty),* $(,)?) => {
        $(fn $name<W: ?Sized + Write>(&mut self, w: &mut W, v: $t) -> io::Result<()> {
            self.open(w, true)?;
            CompactFormatter.$name(w, v)
        })*
    };
}

impl Formatter for RowFormatter {
    fn write_null<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, true)?;
        w.write_all(b"null")
    }

    scalar!(
        write_bool: bool, write_i8: i8, write_i16: i16, write_i32: i32, write_i64: i64,
        write_i128: i128, write_u8: u8, write_u16: u16, write_u32: u32, write_u64: u64,
        write_u128: u128, write_f32: f32, write_f64: f64, write_number_str: &str,
    );

    fn begin_string<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, false)?;
        w.write_all(b"\"")
    }

    fn write_raw_fragment<W: ?Sized + Write>(&mut self, w: &mut W, f: &str) -> io::Result<()> {
        self.open(w, false)?;
        w.write_all(f.as_bytes())
    }

    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, false)?;
        self.arrays.push(Layout::Undecided);
        self.has_value.push(false);
        w.write_all(b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        let layout = self.arrays.pop().expect("begin_array came first");
        let had = self.has_value.pop().unwrap_or(false);
        if layout == Layout::Block {
            self.indent -= 1;
            if had {
                self.newline(w)?;
            }
        }
        w.write_all(b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, _w: &mut W, first: bool) -> io::Result<()> {
        self.pending = Some(first);
        Ok(())
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, false)?;
        self.indent += 1;
        self.has_value.push(false);
        w.write_all(b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.indent -= 1;
        if self.has_value.pop().unwrap_or(false) {
            self.newline(w)?;
        }
        w.write_all(b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if !first {
            w.write_all(b",")?;
        }
        if let Some(h) = self.has_value.last_mut() {
            *h = true;
        }
        self.newline(w)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }
}

#[cfg(test)]
mod tests {
    use super::to_string;
    use serde_json::json;

    #[test]
    fn scalar_arrays_stay_on_one_line_and_the_text_reads_back() {
        let v = json!({
            "name": "sun",
            "pitch": [[0.0, 26.5], [0.1, -2e-9]],
            "files": ["a.svg", "b.dxf"],
            "empty": [],
            "nested": {"k": [1, 2, 3], "flag": true, "none": null, "deep": [{"x": 1}]}
        });
        let text = to_string(&v).unwrap();
        assert!(
            text.contains("\n    [0.0, 26.5],\n    [0.1, -2e-9]\n  ]"),
            "{text}"
        );
        assert!(text.contains("\"k\": [1, 2, 3]"), "{text}");
        assert!(
            text.contains("\"files\": [\n    \"a.svg\",\n    \"b.dxf\"\n  ]"),
            "{text}"
        );
        assert!(text.contains("\"empty\": []"), "{text}");
        assert!(
            text.contains("\"deep\": [\n      {\n        \"x\": 1\n      }\n    ]"),
            "{text}"
        );
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, v);
        // Outside arrays the layout is serde_json's pretty one.
        let flat = json!({"a": 1, "b": {"c": "d"}});
        assert_eq!(
            to_string(&flat).unwrap(),
            serde_json::to_string_pretty(&flat).unwrap()
        );
    }
}
