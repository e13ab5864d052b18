//! Why a trajectory file is refused, and where in it (line, field or point index).

use std::fmt;

/// Where a point came from in its file, for diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// 1-based line of a CSV file.
    Line(usize),
    /// 0-based index in the JSON `points` array.
    Index(usize),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Line(l) => write!(f, "line {l}"),
            Origin::Index(i) => write!(f, "points[{i}]"),
        }
    }
}

/// Why a trajectory file cannot be used. Every variant names the file and, where it applies, the
/// line or field, what was expected and how to fix it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TrajectoryError {
    /// The file cannot be read.
    #[error("{file}: cannot read the trajectory file: {message}")]
    Unreadable {
        /// File name.
        file: String,
        /// OS message.
        message: String,
    },
    /// A CSV line is not two numbers.
    #[error(
        "{file}: {origin}: expected two numbers `x, y` in mm, found `{found}`; fix or comment the line out with #"
    )]
    BadLine {
        /// File name.
        file: String,
        /// Where.
        origin: Origin,
        /// The offending text.
        found: String,
    },
    /// The JSON does not follow the schema.
    #[error("{file}: {message}; expected {{\"units\": \"mm\", \"points\": [[x, y], ...]}}")]
    BadJson {
        /// File name.
        file: String,
        /// Parser message.
        message: String,
    },
    /// A coordinate is NaN or infinite.
    #[error(
        "{file}: {origin}: coordinate is not a finite number; every point needs finite x and y in mm"
    )]
    NotFinite {
        /// File name.
        file: String,
        /// Where.
        origin: Origin,
    },
    /// Too few points.
    #[error(
        "{file}: {count} points, at least {min} are needed (360, one per carrier degree, is typical)"
    )]
    TooFewPoints {
        /// File name.
        file: String,
        /// Points found.
        count: usize,
        /// Minimum.
        min: usize,
    },
    /// Two consecutive points coincide.
    #[error("{file}: {origin} repeats the previous point ({x}, {y}) mm; remove the duplicate")]
    DuplicatePoint {
        /// File name.
        file: String,
        /// Where.
        origin: Origin,
        /// x, mm.
        x: f64,
        /// y, mm.
        y: f64,
    },
    /// One point lies far off the curve its neighbours draw (a typo such as `7.6e19`).
    #[error(
        "{file}: {origin}: the point ({x}, {y}) mm lies {jump_mm:.4e} mm from its neighbours, which are {neighbours_mm:.3} mm apart (typical spacing {spacing_mm:.3} mm): an outlier, probably a typo; correct or remove that line"
    )]
    Outlier {
        /// File name.
        file: String,
        /// Where.
        origin: Origin,
        /// x, mm.
        x: f64,
        /// y, mm.
        y: f64,
        /// Distance to the nearer neighbour, mm.
        jump_mm: f64,
        /// Distance between the two neighbours, mm.
        neighbours_mm: f64,
        /// Median spacing of consecutive points, mm.
        spacing_mm: f64,
    },
    /// The closing gap is far larger than the point spacing.
    #[error(
        "{file}: the curve is open: the gap from the last point back to the first is {gap_mm:.3} mm, while consecutive points are at most {spacing_mm:.3} mm apart; give the whole closed loop in travel order"
    )]
    Open {
        /// File name.
        file: String,
        /// Closing gap, mm.
        gap_mm: f64,
        /// Largest spacing between consecutive points, mm.
        spacing_mm: f64,
    },
    /// A drawing's entity has a coordinate that is not a finite number.
    #[error("{file}: {what} has a coordinate that is not a finite number; fix it in the drawing")]
    NonFiniteCoordinate {
        /// File name.
        file: String,
        /// The entity (its kind, layer and handle or id).
        what: String,
    },
    /// The file is not a readable DXF or SVG drawing.
    #[error(
        "{file}: not a {format} drawing: {message}; save it again as {format} from the CAD program"
    )]
    NotADrawing {
        /// File name.
        file: String,
        /// `DXF` or `SVG`.
        format: String,
        /// Parser message.
        message: String,
    },
    /// The drawing's units cannot be told.
    #[error(
        "{file}: the drawing's units are unknown ({found}); give them with --units mm|cm|m|in|px (DrawingOptions::units)"
    )]
    UnitsUnknown {
        /// File name.
        file: String,
        /// What the file says about its units.
        found: String,
    },
    /// A curve of the drawing does not close.
    #[error(
        "{file}: {what} is open: its ends ({from_x:.4}, {from_y:.4}) mm and ({to_x:.4}, {to_y:.4}) mm are {gap_mm:.4} mm apart; close the loop in the drawing (join the ends, or set the closed flag)"
    )]
    OpenLoop {
        /// File name.
        file: String,
        /// The entity or element.
        what: String,
        /// Gap between the ends, mm.
        gap_mm: f64,
        /// End x, mm.
        from_x: f64,
        /// End y, mm.
        from_y: f64,
        /// Start x, mm.
        to_x: f64,
        /// Start y, mm.
        to_y: f64,
    },
    /// The loop runs back along itself: a zero-area spike or a stretch drawn twice (a crossing
    /// is not this: the drawn order resolves it).
    #[error(
        "{file}: {what} runs back along itself around ({x:.4}, {y:.4}) mm (a spike, or a stretch drawn twice): the order of the points along that stretch cannot be told; redraw it so that every stretch is drawn once (crossing itself is fine)"
    )]
    Retraced {
        /// File name.
        file: String,
        /// The entity or element.
        what: String,
        /// Middle of the retraced stretch, x, mm.
        x: f64,
        /// Middle of the retraced stretch, y, mm.
        y: f64,
    },
    /// More than two ends of a drawing's open pieces meet at one point: where a chain goes on
    /// from there is ambiguous.
    #[error(
        "{file}: {ends} ends meet at ({x:.4}, {y:.4}) mm on layer \"{layer}\" ({pieces}): pieces are joined end to end, two ends at a point, so which way the loop goes on from there cannot be told; draw the loop as one polyline or spline, or delete the extra pieces (or move them to another layer and name the loop's with --layer NAME)"
    )]
    Junction {
        /// File name.
        file: String,
        /// The layer.
        layer: String,
        /// How many ends meet.
        ends: usize,
        /// The entities whose ends they are.
        pieces: String,
        /// Junction x, mm.
        x: f64,
        /// Junction y, mm.
        y: f64,
    },
    /// The named layer (DXF) or id (SVG) holds no closed loop.
    #[error("{file}: no closed loop {wanted}; the drawing has {found}")]
    NoLoopNamed {
        /// File name.
        file: String,
        /// `on layer "X"` or `with id "X"`.
        wanted: String,
        /// The layers or ids with their loops.
        found: String,
    },
    /// Several loops and nothing names one.
    #[error("{file}: the drawing has several closed loops ({found}); pick one with {flag}")]
    SeveralLoops {
        /// File name.
        file: String,
        /// The layers or ids with their loops.
        found: String,
        /// `--layer NAME` (DXF) or `--id ID` (SVG).
        flag: String,
    },
    /// A SPLINE entity is not a valid B-spline.
    #[error("{file}: {what}: {message}")]
    BadSpline {
        /// File name.
        file: String,
        /// The entity.
        what: String,
        /// What is wrong and what to do.
        message: String,
    },
    /// Nothing in the drawing can be read as a loop.
    #[error("{file}: no geometry to read the loop from: {message}")]
    NoGeometry {
        /// File name.
        file: String,
        /// What was looked for.
        message: String,
    },
}
