//! The JSON Schemas of the reports, derived from the report types: what `docs/schemas/` holds.
//!
//! Each schema describes what ncgear *writes* (the serialisation contract of `schemars`): a key
//! left out when empty is optional, every other key required, and no object takes a key its
//! type does not name (`additionalProperties: false`, or `unevaluatedProperties: false` where an
//! object is composed of subschemas). Descriptions are the types' doc comments.
//!
//! ```
//! let all = ncgear::output::schemas::schemas();
//! let (file, design) = &all[0];
//! assert_eq!(*file, "design.schema.json");
//! assert_eq!(design["title"], "DesignReport");
//! assert_eq!(design["additionalProperties"], false);
//! ```

use schemars::generate::SchemaSettings;
use schemars::transform::{Transform, transform_subschemas};
use schemars::{JsonSchema, Schema};
use serde_json::Value;

use crate::analysis::dynamics::DynamicsReport;
use crate::analysis::dynamics::rotor::RotorReport;
use crate::analysis::orbit::report::{IdentifyReport, MeasureReport, ModelReport};
use crate::analysis::tolerance::ToleranceReport;
use crate::analysis::transplanter::TransplanterReport;
use crate::compare::CompareReport;
use crate::design::DesignReport;
use crate::design::tradeoff::TradeOff;
use crate::loads::LoadsReport;
use crate::pair::PairReport;
use crate::synthesis::SynthesisReport;

use super::SimulationReport;

/// Closes every object schema: a key its type does not name is a violation.
///
/// An object with properties of its own and no subschema gets `additionalProperties: false`;
/// one composed of subschemas (a flattened enum: `allOf`/`oneOf`) gets
/// `unevaluatedProperties: false`, which sees the keys its subschemas name. A map (an object
/// schema whose `additionalProperties` is a schema) is left as `schemars` wrote it; the variants
/// of a flattened enum are opened, the object that holds them is closed.
#[derive(Debug, Clone, Default)]
struct Closed;

const COMPOSED: [&str; 5] = ["allOf", "anyOf", "oneOf", "if", "$ref"];

impl Transform for Closed {
    fn transform(&mut self, schema: &mut Schema) {
        transform_subschemas(self, schema);
        let Some(obj) = schema.as_object_mut() else {
            return;
        };
        let is_object =
            obj.get("type").is_some_and(|t| t == "object") || obj.contains_key("properties");
        if !is_object || obj.contains_key("additionalProperties") {
            return;
        }
        let composed = COMPOSED.iter().any(|k| obj.contains_key(*k));
        if composed && obj.contains_key("properties") {
            // A flattened enum: its variants name only their own keys, the object closes them
            // all (`unevaluatedProperties` sees the keys of the variant that matched).
            for key in ["allOf", "anyOf", "oneOf"] {
                if let Some(Value::Array(alternatives)) = obj.get_mut(key) {
                    for a in alternatives.iter_mut().filter_map(Value::as_object_mut) {
                        if a.get("additionalProperties") == Some(&Value::Bool(false)) {
                            a.remove("additionalProperties");
                        }
                    }
                }
            }
        }
        let key = if composed {
            "unevaluatedProperties"
        } else {
            "additionalProperties"
        };
        obj.insert(key.into(), Value::Bool(false));
    }
}

/// The schema of `T` as written: draft 2020-12, serialisation contract, every object closed.
pub fn schema_for<T: JsonSchema>() -> Value {
    let generator = SchemaSettings::draft2020_12()
        .for_serialize()
        .with_transform(Closed)
        .into_generator();
    generator.into_root_schema_for::<T>().to_value()
}

/// `(file name, schema)` of every report the CLI writes, in the order of `docs/schemas.md`:
/// the file in `docs/schemas/` is `<report>.schema.json` for the report `<report>.json`
/// (`orbit_*`: what `ncgear orbit … --json` prints).
pub fn schemas() -> Vec<(&'static str, Value)> {
    vec![
        ("design.schema.json", schema_for::<DesignReport>()),
        ("pair.schema.json", schema_for::<PairReport>()),
        ("simulate.schema.json", schema_for::<SimulationReport>()),
        ("dynamics.schema.json", schema_for::<DynamicsReport>()),
        ("dynamics_rotor.schema.json", schema_for::<RotorReport>()),
        ("tolerance.schema.json", schema_for::<ToleranceReport>()),
        (
            "transplanter.schema.json",
            schema_for::<TransplanterReport>(),
        ),
        ("loads.schema.json", schema_for::<LoadsReport>()),
        ("tradeoff.schema.json", schema_for::<TradeOff>()),
        ("synthesis.schema.json", schema_for::<SynthesisReport>()),
        ("orbit_model.schema.json", schema_for::<ModelReport>()),
        ("orbit_measure.schema.json", schema_for::<MeasureReport>()),
        ("orbit_identify.schema.json", schema_for::<IdentifyReport>()),
        ("compare.schema.json", schema_for::<CompareReport>()),
    ]
}

/// The text of a schema file: pretty JSON (two spaces, keys sorted) and a final line break.
pub fn schema_text(schema: &Value) -> String {
    let mut s = serde_json::to_string_pretty(schema).expect("a JSON value serialises");
    s.push('\n');
    s
}
