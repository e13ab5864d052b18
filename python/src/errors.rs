//! `ncgear.NcgearError` and the library's errors in the words of the Python API: an option the
//! library names by its field (`tol_mm`) is named by the argument that sets it (`tol_mm`),
//! and no message quotes a CLI flag (a design file, which only `ncgear design` writes, is told by
//! its command).
use ncgear::analysis::dynamics::rotor::RotorError;
use ncgear::bounds::OutOfBounds;
use ncgear::design::DesignError;
use ncgear::loads::LoadsError;
use ncgear::pair::PairError;
use ncgear::teeth::TeethError;
use pyo3::PyErr;
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use std::fmt::Display;

create_exception!(
    _ncgear,
    NcgearError,
    PyValueError,
    "An ncgear input or design error."
);

/// The Python argument that sets the library option `field`, if one does.
fn arg_of(field: &str) -> Option<&'static str> {
    Some(match field {
        "order" => "order",
        "smooth" => "smooth",
        "tol_mm" => "tol_mm",
        "inverse.grid" => "grid",
        "inverse.sense" => "sense",
        "inverse.dense_samples" => "dense",
        "samples" => "samples",
        "refine_options.ratio_bounds" => "ratio_bounds",
        "center_mm" => "center",
        "segmented.w1" => "w1",
        "segmented.k_max" => "k_max",
        "refine_order" => "refine_order",
        "max_pressure_angle_rad" => "max_pressure_angle",
        "min_concave_radius_mm" => "min_concave_radius",
        "min_convex_radius_mm" => "min_convex_radius",
        "module_mm" => "module",
        "pressure_angle_deg" => "pressure_angle",
        "addendum" => "addendum",
        "clearance" => "clearance",
        "fillet" => "fillet",
        "chord_tol_mm" => "chord_tol",
        "backlash_mm" => "backlash",
        "cutter_teeth" => "cutter_teeth",
        "verify_steps" | "verify_steps × driver turns per cycle" => "verify_steps",
        "teeth" | "teeth of the driven gear (z·q/p)" => "teeth",
        "centrode_advance_rad" => "cycle_advance",
        "open_sector_rad" => "drive",
        "bore" => "bore",
        "face_width" => "face_width",
        _ => return None,
    })
}

/// The library's message with its CLI flags said the Python way.
fn unflagged(message: &str) -> String {
    message
        .replace("`--sense auto`", "`sense=\"auto\"`")
        .replace("--max-memory-gb", "ncgear.set_max_memory_gb()")
        .replace("(--max-pressure-angle)", "(`max_pressure_angle`)")
        .replace(
            "--units mm|cm|m|in|px",
            "units=\"mm\"|\"cm\"|\"m\"|\"in\"|\"px\"",
        )
        .replace("--layer NAME", "layer=\"NAME\"")
        .replace("--id ID", "id=\"ID\"")
}

/// An `NcgearError` carrying `e`'s message.
pub fn err(e: impl Display) -> PyErr {
    NcgearError::new_err(unflagged(&e.to_string()))
}

/// An `NcgearError` on Python argument `arg` given `value`: `arg=value: what`.
pub fn arg_err(arg: &str, value: impl Display, what: impl Display) -> PyErr {
    NcgearError::new_err(unflagged(&format!("{arg}={value}: {what}")))
}

/// The error of library option `field` (value `value`, `what` is wrong), on its argument when
/// one sets it.
fn field_err(field: &str, value: impl Display, what: impl Display) -> PyErr {
    match arg_of(field) {
        Some(arg) => arg_err(arg, value, what),
        None => err(format!("`{field}` = {value}: {what}")),
    }
}

/// A size outside its admissible range, on the argument that sets it.
pub fn bounds_err(b: &OutOfBounds) -> PyErr {
    let what = format!("outside its admissible range {}: {}", b.range, b.why);
    field_err(&b.quantity, &b.value, what)
}

/// A design error, a bad option on its argument.
pub fn design_err(e: &DesignError) -> PyErr {
    match e {
        DesignError::BadOption {
            option,
            value,
            expected,
        } => field_err(option, value, expected),
        DesignError::Bounds(b) => bounds_err(b),
        _ => err(e),
    }
}

/// A tooth error, a bad parameter on its argument.
pub fn teeth_err(e: &TeethError) -> PyErr {
    match e {
        TeethError::Bounds(b) => bounds_err(b),
        TeethError::InvalidParameter {
            name,
            value,
            expected,
        } => field_err(name, value, expected),
        _ => err(e),
    }
}

/// A pair error, a bad parameter on its argument.
pub fn pair_err(e: &PairError) -> PyErr {
    match e {
        PairError::Teeth(t) => teeth_err(t),
        PairError::Bounds(b) => bounds_err(b),
        PairError::InvalidParameter {
            name,
            value,
            expected,
        } => field_err(name, value, expected),
        _ => err(e),
    }
}

/// `message` without the line and column a dict scene's JSON adds (`from_dict`).
fn dict_message(mut message: String, from_dict: bool) -> String {
    if from_dict && let Some(i) = message.rfind(" at line 1 column ") {
        message.truncate(i);
    }
    message
}

/// A loads error. `from_dict`: the scene is a dict (its JSON's line and column are dropped);
/// `in_memory`: the train is a Python object, so a design without teeth is told to pass
/// `ncgear.teeth(...)`; a design file's teeth come from `ncgear design --module`.
pub fn loads_err(e: &LoadsError, from_dict: bool, in_memory: bool) -> PyErr {
    let m = dict_message(
        e.to_string(),
        from_dict && matches!(e, LoadsError::Scene(_)),
    );
    // The library says what is wrong; how to mend it from Python is said here.
    let hint = match e {
        LoadsError::NoTeeth if in_memory => {
            Some("pass the toothed train, ncgear.teeth(design, module)")
        }
        LoadsError::NoTeeth => Some("write the design file with `ncgear design --module M`"),
        LoadsError::SelfLocking { .. } => Some("`max_pressure_angle` sets the gear limit"),
        _ => None,
    };
    err(match hint {
        Some(h) => format!("{m} ({h})"),
        None => m,
    })
}

/// A rotor dynamics error, `from_dict` and `in_memory` as for [`loads_err`] (the loads tables'
/// errors are the loads').
pub fn rotor_err(e: &RotorError, from_dict: bool, in_memory: bool) -> PyErr {
    match e {
        RotorError::Loads(l) => loads_err(l, from_dict, in_memory),
        RotorError::Scene(m) => err(dict_message(m.clone(), from_dict)),
        _ => err(e),
    }
}
