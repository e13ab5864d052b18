//! Reading a filmed needle-tip track: plain CSV (header names or column positions), Tracker's
//! export (title lines, then `t,x,y`) and Kinovea's (`;`-separated, units in the header, decimal
//! commas), in the file's own units (s, ms or frames; mm, cm, m or px).
//!
//! The delimiter is the first of `;`, tab, `,` found on the first data line (whitespace when
//! none). The data start at the first line whose fields are all numbers or empty; the header is
//! the last line before it with as many fields, its other lines (titles, comments) are skipped.
//! A column's unit is read from its name, `x (px)`, `Time [ms]`. A row with an empty x or y (a
//! frame the tracker lost) is skipped; an `encoder` column (deg) gives each frame's carrier angle; any other empty, non-numeric or non-finite value is an
//! error naming its line and column.

use super::CompareError;
use crate::math::Point;
use serde::{Deserialize, Serialize};

/// Unit of a track's lengths.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum LengthUnit {
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
    /// Image pixels (y down unless told otherwise).
    Px,
}

impl LengthUnit {
    /// The unit of a name (`mm`, `cm`, `m`, `px`, `pixel(s)`), or `None`.
    #[must_use]
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s.trim().to_ascii_lowercase().as_str() {
            "mm" => Self::Mm,
            "cm" => Self::Cm,
            "m" => Self::M,
            "px" | "pixel" | "pixels" => Self::Px,
            _ => return None,
        })
    }

    /// Millimetres per unit, or `None` for pixels.
    #[must_use]
    pub fn mm(self) -> Option<f64> {
        match self {
            Self::Mm => Some(1.0),
            Self::Cm => Some(10.0),
            Self::M => Some(1000.0),
            Self::Px => None,
        }
    }
}

/// How to read a track file.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ReadOptions {
    /// The columns `[time, x, y]` or `[time, x, y, x2, y2]` (x2, y2: a second marker on the
    /// needle's axis), each a header name or a 1-based position; `time` may be `-` (no time
    /// column: frame numbers are the row order, with `fps`). Empty: found by name (`t`, `time`,
    /// `frame`; `x`, `y`; `x2`, `y2`), or positions 1, 2, 3 without a header.
    pub columns: Vec<String>,
    /// Frames per second: turns a frame-number time column (or the row order) into seconds.
    pub fps: Option<f64>,
    /// The lengths' unit, overriding the header's (default: the header's, else mm).
    pub units: Option<LengthUnit>,
    /// Whether y points down (image coordinates); default: yes for pixels, no otherwise.
    pub y_down: Option<bool>,
    /// The encoder column (name or 1-based position): the carrier angle of each frame, deg,
    /// counting in the direction of travel. Default: a column named `encoder` or `carrier_deg`.
    pub encoder: Option<String>,
}

/// A track as read: times in seconds, positions in the file's unit and axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The file's name (for messages).
    pub file: String,
    /// What the file looked like: `plain`, `headerless`, `tracker` or `kinovea`.
    pub format: &'static str,
    /// Time of each frame, s (strictly increasing).
    pub time_s: Vec<f64>,
    /// Needle tip of each frame, file units and axes.
    pub tip: Vec<Point>,
    /// Second marker of each frame (on the needle's axis), when read.
    pub marker: Option<Vec<Point>>,
    /// Line number (1-based) of each frame.
    pub line: Vec<usize>,
    /// The encoder's carrier angle of each frame, deg (travel direction), when read.
    pub encoder_deg: Option<Vec<f64>>,
    /// Length unit.
    pub unit: LengthUnit,
    /// Whether y points down.
    pub y_down: bool,
    /// Rows skipped for an empty x or y.
    pub skipped: usize,
}

/// One header column: lower-case name without its unit, and the unit when given.
fn split_unit(raw: &str) -> (String, Option<String>) {
    let s = raw.trim().trim_matches('"').trim().to_ascii_lowercase();
    for (open, close) in [('(', ')'), ('[', ']')] {
        if let (Some(a), Some(b)) = (s.find(open), s.rfind(close))
            && a < b
        {
            return (s[..a].trim().to_string(), Some(s[a + 1..b].trim().into()));
        }
    }
    (s, None)
}

fn delimiter(line: &str) -> Option<char> {
    [';', '\t', ','].into_iter().find(|d| line.contains(*d))
}

fn fields(line: &str, delim: Option<char>, decimal_comma: bool) -> Vec<String> {
    let conv = |f: &str| {
        let f = f.trim().trim_matches('"').trim();
        if decimal_comma {
            f.replace(',', ".")
        } else {
            f.to_string()
        }
    };
    match delim {
        Some(d) => line.split(d).map(conv).collect(),
        None => line.split_whitespace().map(conv).collect(),
    }
}

fn is_data(f: &[String]) -> bool {
    f.len() >= 2
        && f.iter().filter(|s| !s.is_empty()).count() >= 2
        && f.iter().all(|s| s.is_empty() || s.parse::<f64>().is_ok())
}

/// The text of a track file, parsed (see the module doc); `file` names it in messages.
///
/// # Errors
/// [`CompareError`] naming the line and column of a bad value, an unknown column, a time that
/// does not increase, or a frame-number time without `fps`.
pub fn parse_track(text: &str, file: &str, opts: &ReadOptions) -> Result<Track, CompareError> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}').trim_end()))
        .filter(|(_, l)| !l.trim().is_empty())
        .collect();
    let probe = |l: &str| {
        let d = delimiter(l);
        let dc = matches!(d, Some(';' | '\t')) && l.contains(',') && !l.contains('.');
        (d, dc)
    };
    let first = lines
        .iter()
        .position(|(_, l)| {
            let (d, dc) = probe(l);
            is_data(&fields(l, d, dc))
        })
        .ok_or_else(|| CompareError::TooShort {
            file: file.into(),
            message: "no data rows (rows of numbers) found".into(),
        })?;
    let (delim, decimal_comma) = probe(lines[first].1);
    let width = fields(lines[first].1, delim, decimal_comma).len();
    let header: Option<Vec<(String, Option<String>)>> = lines[..first]
        .iter()
        .rev()
        .map(|(_, l)| fields(l, delim, false))
        .find(|f| f.len() == width)
        .map(|f| f.iter().map(|s| split_unit(s)).collect());
    let kinovea = lines[..first]
        .iter()
        .any(|(_, l)| l.to_ascii_lowercase().contains("kinovea"));
    let format = match (&header, first) {
        (None, _) => "headerless",
        _ if kinovea => "kinovea",
        (Some(_), f) if f >= 2 => "tracker",
        _ => "plain",
    };
    let cols = Columns::find(header.as_deref(), width, file, opts)?;
    let unit = match opts.units {
        Some(u) => u,
        None => cols
            .x_unit
            .as_deref()
            .and_then(LengthUnit::parse)
            .unwrap_or(LengthUnit::Mm),
    };
    let mut track = Track {
        file: file.into(),
        format,
        time_s: Vec::new(),
        tip: Vec::new(),
        marker: cols.marker.map(|_| Vec::new()),
        line: Vec::new(),
        encoder_deg: cols.encoder.map(|_| Vec::new()),
        unit,
        y_down: opts.y_down.unwrap_or(unit == LengthUnit::Px),
        skipped: 0,
    };
    let to_s = cols.time_scale(file, opts.fps)?;
    for (row, (line, text)) in lines[first..].iter().enumerate() {
        let f = fields(text, delim, decimal_comma);
        let value = |k: usize, name: &str| -> Result<Option<f64>, CompareError> {
            let bad = |message: String| CompareError::BadValue {
                file: file.into(),
                line: *line,
                column: name.into(),
                message,
            };
            let s = f
                .get(k)
                .ok_or_else(|| bad(format!("the row has {} fields", f.len())))?;
            if s.is_empty() {
                return Ok(None);
            }
            let v: f64 = s
                .parse()
                .map_err(|_| bad(format!("`{s}`: expected a number")))?;
            if !v.is_finite() {
                return Err(bad(format!("`{s}`: expected a finite number")));
            }
            Ok(Some(v))
        };
        let (x, y) = (value(cols.x, "x")?, value(cols.y, "y")?);
        let (Some(x), Some(y)) = (x, y) else {
            track.skipped += 1;
            continue;
        };
        let t = match cols.time {
            Some(k) => value(k, "time")?.ok_or_else(|| CompareError::BadValue {
                file: file.into(),
                line: *line,
                column: "time".into(),
                message: "empty: every frame needs its time".into(),
            })?,
            None => row as f64,
        } * to_s;
        if let Some(&prev) = track.time_s.last()
            && !(t > prev)
        {
            return Err(CompareError::TimeNotIncreasing {
                file: file.into(),
                line: *line,
                time: t / to_s,
                previous: prev / to_s,
            });
        }
        if let (Some((kx, ky)), Some(m)) = (cols.marker, track.marker.as_mut()) {
            let (Some(mx), Some(my)) = (value(kx, "x2")?, value(ky, "y2")?) else {
                track.skipped += 1;
                continue;
            };
            m.push(Point::new(mx, my));
        }
        if let (Some(k), Some(e)) = (cols.encoder, track.encoder_deg.as_mut()) {
            e.push(value(k, "encoder")?.ok_or_else(|| CompareError::BadValue {
                file: file.into(),
                line: *line,
                column: "encoder".into(),
                message: "empty: every frame needs its carrier angle".into(),
            })?);
        }
        track.time_s.push(t);
        track.tip.push(Point::new(x, y));
        track.line.push(*line);
    }
    Ok(track)
}

/// The columns of a track (0-based) and the time column's unit.
struct Columns {
    time: Option<usize>,
    time_unit: Option<String>,
    time_is_frames: bool,
    x: usize,
    y: usize,
    x_unit: Option<String>,
    marker: Option<(usize, usize)>,
    encoder: Option<usize>,
}

impl Columns {
    fn find(
        header: Option<&[(String, Option<String>)]>,
        width: usize,
        file: &str,
        opts: &ReadOptions,
    ) -> Result<Self, CompareError> {
        let names: Vec<String> = header.map_or_else(
            || (1..=width).map(|k| k.to_string()).collect(),
            |h| h.iter().map(|(n, _)| n.clone()).collect(),
        );
        let available = names.join(", ");
        let unknown = |column: &str, help: &str| CompareError::UnknownColumn {
            file: file.into(),
            column: column.into(),
            available: available.clone(),
            help: help.into(),
        };
        let lookup = |c: &str| -> Result<usize, CompareError> {
            let c = c.trim().to_ascii_lowercase();
            if let Ok(k) = c.parse::<usize>()
                && (1..=width).contains(&k)
            {
                return Ok(k - 1);
            }
            names.iter().position(|n| *n == c).ok_or_else(|| {
                unknown(
                    &c,
                    "name a column of the header or give its position (1-based) in --columns",
                )
            })
        };
        let auto = |want: &[&str]| names.iter().position(|n| want.contains(&n.as_str()));
        let (time, x, y, marker) = if !opts.columns.is_empty() {
            let c = &opts.columns;
            if !(c.len() == 3 || c.len() == 5) {
                return Err(CompareError::BadOption {
                    option: "columns",
                    message: format!(
                        "{} columns given: expected time,x,y or time,x,y,x2,y2 (names or 1-based positions; time `-` for none)",
                        c.len()
                    ),
                });
            }
            let time = if c[0].trim() == "-" {
                None
            } else {
                Some(lookup(&c[0])?)
            };
            let marker = if c.len() == 5 {
                Some((lookup(&c[3])?, lookup(&c[4])?))
            } else {
                None
            };
            (time, lookup(&c[1])?, lookup(&c[2])?, marker)
        } else if header.is_some() {
            let help = "name the columns with --columns time,x,y";
            let x = auto(&["x", "x1", "tip x", "x_tip"]).ok_or_else(|| unknown("x", help))?;
            let y = auto(&["y", "y1", "tip y", "y_tip"]).ok_or_else(|| unknown("y", help))?;
            let time = auto(&["t", "time", "frame", "frames", "frame number"]);
            let marker = auto(&["x2"]).zip(auto(&["y2"]));
            (time, x, y, marker)
        } else if width >= 3 {
            (Some(0), 1, 2, None)
        } else {
            (None, 0, 1, None)
        };
        let encoder = match &opts.encoder {
            Some(c) => Some(lookup(c)?),
            None if header.is_some() => auto(&["encoder", "carrier_deg", "encoder_deg"]),
            None => None,
        };
        let unit_of = |k: usize| header.and_then(|h| h[k].1.clone());
        let time_is_frames = time.is_some_and(|k| {
            names[k].starts_with("frame") || unit_of(k).is_some_and(|u| u.starts_with("frame"))
        }) || time.is_none();
        Ok(Self {
            time,
            time_unit: time.and_then(unit_of),
            time_is_frames,
            x,
            y,
            x_unit: unit_of(x),
            marker,
            encoder,
        })
    }

    /// Seconds per unit of the time column: s, ms, or frames at `fps`.
    fn time_scale(&self, file: &str, fps: Option<f64>) -> Result<f64, CompareError> {
        if let Some(f) = fps
            && !(f.is_finite() && f > 0.0)
        {
            return Err(CompareError::BadOption {
                option: "fps",
                message: format!("{f}: expected a positive frame rate"),
            });
        }
        if self.time_is_frames {
            return fps.map(|f| 1.0 / f).ok_or_else(|| CompareError::BadOption {
                option: "fps",
                message: format!(
                    "{file}: the frames are numbered, not timed: give the frame rate with --fps"
                ),
            });
        }
        match self.time_unit.as_deref() {
            None | Some("s" | "sec" | "seconds") => Ok(1.0),
            Some("ms") => Ok(1e-3),
            Some(u) => Err(CompareError::BadOption {
                option: "columns",
                message: format!("{file}: time unit `{u}`: expected s, ms or frames"),
            }),
        }
    }
}
