//! Writes the JSON Schema of every report into a directory (`docs/schemas/` by
//! `scripts/write_schemas.sh`): `cargo run --release --example schemas -- DIR`.

use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "docs/schemas".into()),
    );
    std::fs::create_dir_all(&dir)?;
    for (file, schema) in ncgear::output::schemas::schemas() {
        let path = dir.join(file);
        std::fs::write(&path, ncgear::output::schemas::schema_text(&schema))?;
        println!("{}", path.display());
    }
    Ok(())
}
