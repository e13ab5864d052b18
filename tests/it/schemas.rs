//! The JSON Schemas of docs/schemas/ are what `ncgear::output::schemas` generates from the report
//! types (`scripts/write_schemas.sh` writes them; `NCGEAR_BLESS=1 cargo test --release schemas`
//! rewrites them too), and they are strict: every object closed, the keys a report writes named.
//! scripts/check_schemas.sh validates the bundled examples' outputs against them.

use ncgear::output::schemas::{schema_text, schemas};
use serde_json::Value;
use std::fs;
use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/schemas")
}

#[test]
fn committed_schemas_equal_the_generated_ones() {
    let bless = std::env::var_os("NCGEAR_BLESS").is_some();
    let mut stale = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for (file, schema) in schemas() {
        let path = dir().join(file);
        let want = schema_text(&schema);
        names.push(file.to_string());
        if fs::read_to_string(&path).ok().as_deref() != Some(want.as_str()) {
            if bless {
                fs::create_dir_all(dir()).expect("docs/schemas writable");
                fs::write(&path, &want).expect("schema file writable");
            } else {
                stale.push(file);
            }
        }
    }
    assert!(
        stale.is_empty(),
        "docs/schemas is out of date for {stale:?}; run scripts/write_schemas.sh (or NCGEAR_BLESS=1 cargo test --release schemas)"
    );
    let mut on_disk: Vec<String> = fs::read_dir(dir())
        .expect("docs/schemas")
        .map(|e| {
            e.expect("dir entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|n| n.ends_with(".schema.json"))
        .collect();
    on_disk.sort();
    names.sort();
    assert_eq!(on_disk, names, "docs/schemas holds a schema of no report");
}

/// Where an object schema with properties of its own is not closed. `covered`: `v` is an
/// alternative of an object closed by `unevaluatedProperties: false` (a flattened enum's
/// variant), which closes it.
fn open_objects(v: &Value, at: &str, covered: bool, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            let closes = m.get("unevaluatedProperties") == Some(&Value::Bool(false));
            if m.contains_key("properties")
                && !covered
                && m.get("additionalProperties") != Some(&Value::Bool(false))
                && !closes
            {
                out.push(at.to_string());
            }
            for (k, x) in m {
                let alternatives = closes && ["allOf", "anyOf", "oneOf"].contains(&k.as_str());
                match x {
                    Value::Array(a) if alternatives => {
                        for (i, y) in a.iter().enumerate() {
                            open_objects(y, &format!("{at}/{k}/{i}"), true, out);
                        }
                    }
                    _ => open_objects(x, &format!("{at}/{k}"), false, out),
                }
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                open_objects(x, &format!("{at}/{i}"), false, out);
            }
        }
        _ => {}
    }
}

#[test]
fn every_object_of_every_schema_is_closed() {
    for (file, schema) in schemas() {
        let mut open = Vec::new();
        open_objects(&schema, "#", false, &mut open);
        assert!(open.is_empty(), "{file}: open objects at {open:?}");
        assert_eq!(
            schema["$schema"], "https://json-schema.org/draft/2020-12/schema",
            "{file}"
        );
    }
}

#[test]
fn the_design_schema_names_exactly_the_keys_a_design_report_writes() {
    let all = schemas();
    let (_, schema) = all
        .iter()
        .find(|(f, _)| *f == "design.schema.json")
        .expect("design schema");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = fs::read_to_string(root.join("assets/loads/g1_m2_design.json")).expect("design");
    let report: ncgear::design::DesignReport = serde_json::from_str(&text).expect("a design");
    let written = serde_json::to_value(&report).expect("serialises");
    let keys: Vec<&String> = written.as_object().expect("an object").keys().collect();
    let props = schema["properties"].as_object().expect("properties");
    for k in &keys {
        assert!(
            props.contains_key(*k),
            "design.json key {k} is not in the schema"
        );
    }
    for r in schema["required"].as_array().expect("required") {
        let r = r.as_str().expect("a key");
        assert!(written.get(r).is_some(), "required key {r} not written");
    }
    // The teeth block is written (the file has teeth) and its schema is a reference into $defs.
    assert!(written.get("teeth").is_some());
    let teeth = &schema["$defs"]["TrainTeethReport"]["properties"];
    for k in written["teeth"].as_object().expect("teeth").keys() {
        assert!(teeth.get(k).is_some(), "teeth key {k} is not in the schema");
    }
}
