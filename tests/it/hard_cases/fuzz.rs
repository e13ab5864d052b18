//! Parser fuzz: every parser of the tool — trajectory CSV/JSON, design JSON,
//! dynamics scene TOML/JSON, tolerance error files TOML/JSON, orbit sensor CSV and model
//! TOML/JSON, pair law CSV and pair expressions — fed random bytes and mutated copies of the
//! bundled assets (tokens replaced by NaN/inf/huge/empty values, truncation, duplicated,
//! deleted and swapped lines, stray bytes). Each must return a typed error or a value; any value
//! must be finite, and the next stage run on it must again give a finite result or a typed error.
//! Fixed proptest seeds keep CI deterministic.
use ncgear::analysis::dynamics::scene::Scene;
use ncgear::analysis::dynamics::{Method, RunOptions, simulate};
use ncgear::analysis::orbit::measure::{ExtractOptions, Extractor, Record};
use ncgear::analysis::orbit::model::ModelParams;
use ncgear::analysis::peak::PeakOptions;
use ncgear::analysis::tolerance::{Analysis, ErrorFile};
use ncgear::config::Format;
use ncgear::design::trajectory::{DrawingOptions, DrawingUnits, Trajectory};
use ncgear::pair::{Expr, Law, Motion};
use ncgear::progress::Progress;
use ncgear::simulate::DesignFile;
use proptest::prelude::*;
use proptest::test_runner::{RngSeed, TestCaseError};
use std::sync::OnceLock;

const G1_CSV: &str = include_str!("../../../assets/trajectories/g1_ellipse.csv");
const KIDNEY_CSV: &str = include_str!("../../../assets/trajectories/designer_kidney.csv");
const ASYM_JSON: &str = include_str!("../../../assets/trajectories/asymmetric_cw.json");
const BULGE_DXF: &str = include_str!("../../../assets/drawings/g1_bulge.dxf");
const BEZIER_SVG: &str = include_str!("../../../assets/drawings/g1_bezier.svg");
/// A path that crosses itself, and the two ambiguous drawings of it (a junction, a spike).
const LOOPED_DXF: &str = include_str!("../../../assets/drawings/g1_looped_bulge.dxf");
const LOOPED_SVG: &str = include_str!("../../../assets/drawings/g1_looped_px.svg");
const JUNCTION_DXF: &str = include_str!("../../../assets/drawings/g1_looped_junction.dxf");
const SPIKE_DXF: &str = include_str!("../../../assets/drawings/g1_looped_spike.dxf");
const SCENES: [&str; 5] = [
    include_str!("../../../assets/dynamics/backlash_oscillator.toml"),
    include_str!("../../../assets/dynamics/full16.toml"),
    include_str!("../../../assets/dynamics/full16_hertz.toml"),
    include_str!("../../../assets/dynamics/sdof_6000.toml"),
    include_str!("../../../assets/dynamics/torsional4.toml"),
];
const ERRORS_TOML: &str = include_str!("../../../assets/tolerance/paper_3k.toml");
const SIGNALS_CSV: &str = include_str!("../../../assets/orbit/signals.csv");
const MODEL_TOML: &str = include_str!("../../../assets/orbit/model.toml");
const MODEL_JSON: &str = include_str!("../../../assets/orbit/model.json");
const LAW_CSV: &str = include_str!("../../../assets/pair/law.csv");

/// Replacement tokens: non-finite, huge, tiny, empty, wrong types, separators.
const BAD_TOKENS: [&str; 24] = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-320",
    "0",
    "-0",
    "-1",
    "99999999999999999999",
    "4294967296",
    "12345",
    "",
    "\"x\"",
    "[]",
    "{}",
    "true",
    "null",
    ",",
    "=",
    "#",
    "\"",
    "[[",
];

/// Fixed-seed config. For a deeper local run, `NCGEAR_FUZZ_SCALE=20` multiplies the case count
/// and `NCGEAR_FUZZ_SEED=n` changes the (still fixed) seed; CI uses neither.
fn cfg(cases: u32, seed: u64) -> ProptestConfig {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let scale = env("NCGEAR_FUZZ_SCALE").unwrap_or(1).max(1);
    ProptestConfig {
        cases: cases.saturating_mul(u32::try_from(scale).unwrap_or(u32::MAX)),
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed ^ env("NCGEAR_FUZZ_SEED").unwrap_or(0)),
        ..ProptestConfig::default()
    }
}

/// First `n` lines of a text (keeps the big sensor record cheap to fuzz).
fn head(text: &str, n: usize) -> String {
    text.lines().take(n).collect::<Vec<_>>().join("\n") + "\n"
}

/// A TOML document re-encoded as JSON (the JSON flavour of a bundled TOML asset).
fn toml_to_json(text: &str) -> String {
    let v: toml::Value = toml::from_str(text).expect("bundled asset");
    serde_json::to_string_pretty(&v).expect("json")
}

/// A design.json written by the library from the G1 design (generated once, in a temp dir).
fn design_json() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let t = Trajectory::parse_csv(G1_CSV, "g1_ellipse.csv").expect("bundled");
        let d = ncgear::design::design(&t, &ncgear::design::DesignOptions::default()).expect("G1");
        let dir = std::env::temp_dir().join(format!("ncgear_fuzz_{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        ncgear::output::write_design(&d, &dir).expect("write");
        let text = std::fs::read_to_string(dir.join("design.json")).expect("design.json");
        let _ = std::fs::remove_dir_all(&dir);
        text
    })
}

/// One mutation of a text: `op` selects the kind, `a`, `b` pick positions.
#[derive(Debug, Clone)]
struct Mutation {
    op: u8,
    a: usize,
    b: usize,
    token: &'static str,
    bytes: Vec<u8>,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    (
        0u8..8,
        any::<usize>(),
        any::<usize>(),
        prop::sample::select(BAD_TOKENS.to_vec()),
        proptest::collection::vec(any::<u8>(), 0..8),
    )
        .prop_map(|(op, a, b, token, bytes)| Mutation {
            op,
            a,
            b,
            token,
            bytes,
        })
}

/// Byte ranges of the tokens (runs of alphanumerics and `._+-`) of `s`.
fn tokens(s: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in s.char_indices() {
        let inside = c.is_alphanumeric() || matches!(c, '.' | '_' | '+' | '-');
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s0)) => {
                out.push((s0, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s0) = start {
        out.push((s0, s.len()));
    }
    out
}

fn floor_boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut s = text.to_string();
    for m in muts {
        let lines: Vec<&str> = s.split('\n').collect();
        let nl = lines.len().max(1);
        s = match m.op {
            // Replace a token (numbers, keys, names) by a bad one.
            0..=2 => {
                let t = tokens(&s);
                if t.is_empty() {
                    s
                } else {
                    let (i0, i1) = t[m.a % t.len()];
                    format!("{}{}{}", &s[..i0], m.token, &s[i1..])
                }
            }
            // Truncate.
            3 => s[..floor_boundary(&s, m.a % (s.len() + 1))].to_string(),
            // Duplicate a line (duplicated keys, repeated rows).
            4 => {
                let k = m.a % nl;
                let mut v = lines.clone();
                v.insert(k, lines.get(k).copied().unwrap_or(""));
                v.join("\n")
            }
            // Delete a line.
            5 => {
                let mut v = lines.clone();
                if !v.is_empty() {
                    v.remove(m.a % nl);
                }
                v.join("\n")
            }
            // Swap two lines.
            6 => {
                let mut v = lines.clone();
                v.swap(m.a % nl, m.b % nl);
                v.join("\n")
            }
            // Insert stray bytes.
            _ => {
                let i = floor_boundary(&s, m.a % (s.len() + 1));
                format!(
                    "{}{}{}",
                    &s[..i],
                    String::from_utf8_lossy(&m.bytes),
                    &s[i..]
                )
            }
        };
    }
    s
}

fn finite(v: f64, what: &str) -> Result<(), TestCaseError> {
    prop_assert!(v.is_finite(), "{what} = {v} is not finite");
    Ok(())
}

// ---- per-parser checks: parse, and when it parses, run the next stage ----

fn check_trajectory(text: &str) -> Result<(), TestCaseError> {
    // Drawings read with their units given, so that a unitless text reaches the geometry.
    let mm = DrawingOptions::default().with_units(Some(DrawingUnits::Mm));
    for t in [
        Trajectory::parse_csv(text, "fuzz.csv"),
        Trajectory::parse_json(text, "fuzz.json"),
        Trajectory::from_dxf(text.as_bytes(), &mm, "fuzz.dxf"),
        Trajectory::from_svg(text, &mm, "fuzz.svg"),
    ]
    .into_iter()
    .flatten()
    {
        for p in t.points() {
            finite(p.x, "trajectory x")?;
            finite(p.y, "trajectory y")?;
        }
    }
    Ok(())
}

fn check_design_file(text: &str) -> Result<(), TestCaseError> {
    if let Ok((_, asm)) = DesignFile::parse(text, "fuzz.json") {
        let rb = asm.rebuild();
        finite(rb.ratio_means()[0], "sun ratio mean")?;
        finite(rb.ratio_means()[1], "intermediate ratio mean")?;
        for k in 0..12 {
            let p = rb.pose(std::f64::consts::TAU * k as f64 / 12.0);
            for v in [
                p.tip_mm.x,
                p.tip_mm.y,
                p.planet_center_mm.x,
                p.planet_center_mm.y,
                p.intermediate_center_mm.x,
                p.intermediate_center_mm.y,
                p.planet_angle_rad,
                p.intermediate_angle_rad,
                p.sun_mesh_error_mm,
                p.planet_mesh_error_mm,
            ] {
                finite(v, "pose")?;
            }
        }
    }
    Ok(())
}

fn check_scene(text: &str, json: bool) -> Result<(), TestCaseError> {
    if let Ok(s) = Scene::parse(text, "fuzz", if json { Format::Json } else { Format::Toml }) {
        let d = s
            .derived("fuzz")
            .map_err(|e| TestCaseError::fail(format!("parsed scene, then derived failed: {e}")))?;
        for (v, w) in [
            (d.m_e_kg, "m_e"),
            (d.k_mean_n_per_m, "k_mean"),
            (d.c_m_n_s_per_m, "c_m"),
            (d.omega_n_rad_s, "ωn"),
            (d.omega_e_rad_s, "ωe"),
            (d.t_mesh_s, "T_mesh"),
            (d.f0_n, "F0"),
        ] {
            finite(v, w)?;
        }
        // A short fixed window (RK4, one mesh period): finite samples or a typed error.
        let (model, _) = s
            .build("fuzz")
            .map_err(|e| TestCaseError::fail(format!("parsed scene, then build failed: {e}")))?;
        let _ = RunOptions::from_scene(&s, &model);
        let opts = RunOptions::window(
            Method::Rk4 {
                steps_per_mesh: 64,
                aligned: false,
            },
            1,
            8,
        );
        if let Ok(run) = simulate(&model, &vec![0.0; 2 * model.n()], &opts, &Progress::none()) {
            for v in run.dte_m.iter().chain(&run.mesh_force_n) {
                finite(*v, "simulated sample")?;
            }
        }
    }
    Ok(())
}

fn check_errors(text: &str, json: bool) -> Result<(), TestCaseError> {
    let format = if json {
        Format::Json
    } else {
        Format::detect(std::path::Path::new(""), text)
    };
    if let Ok(f) = ErrorFile::parse(text, "fuzz", format) {
        finite(f.base_radius(), "base radius")?;
        let a = Analysis::new(&f, PeakOptions::default());
        let betas = vec![0.3; a.free_count()];
        finite(a.peak(&betas, None).value, "peak")?;
        finite(a.amplitude_sum(), "amplitude sum")?;
    }
    Ok(())
}

fn model_format(toml: bool) -> Format {
    if toml { Format::Toml } else { Format::Json }
}

fn check_model(text: &str, toml: bool) -> Result<(), TestCaseError> {
    if let Ok(p) = ModelParams::parse(text, "fuzz", model_format(toml))
        && let Ok(set) = p.planet_set()
    {
        let s = set.solve();
        finite(s.orbit.z_plus_um.norm(), "Z+")?;
        finite(s.orbit.z_minus_um.norm(), "Z-")?;
        finite(s.common_mode_um.norm(), "common mode")?;
    }
    Ok(())
}

fn check_record(text: &str) -> Result<(), TestCaseError> {
    if let Ok(r) = Record::from_csv_reader(text.as_bytes(), "fuzz.csv") {
        for v in r.t_s().iter().chain(r.x_um()).chain(r.y_um()) {
            finite(*v, "record")?;
        }
        // ω_p of assets/orbit/model.toml (30 rpm planet speed).
        let ex = Extractor::new(std::f64::consts::PI, ExtractOptions::default()).expect("valid");
        if let Ok(m) = ex.extract(&r) {
            finite(m.orbit.z_plus_um.norm(), "extracted Z+")?;
            finite(m.orbit.z_minus_um.norm(), "extracted Z-")?;
        }
    }
    Ok(())
}

fn check_motion(law: &Law) -> Result<(), TestCaseError> {
    if let Ok(m) = Motion::from_law(law, 64) {
        finite(m.unit_center_distance, "centre distance")?;
        for k in 0..16 {
            let f = std::f64::consts::TAU * k as f64 / 16.0;
            finite(m.psi(f), "ψ")?;
            let i = m.ratio(f);
            finite(i, "ratio")?;
            prop_assert!(i > 0.0, "ratio {i} ≤ 0 at φ = {f}");
        }
    }
    Ok(())
}

fn check_law_csv(text: &str) -> Result<(), TestCaseError> {
    if let Ok(law) = Law::parse_csv(text, "fuzz.csv") {
        check_motion(&law)?;
    }
    Ok(())
}

fn check_expr(text: &str) -> Result<(), TestCaseError> {
    if let Ok(e) = Expr::parse(text) {
        let _ = e.eval(0.7);
        let _ = e.derivative().eval(0.7);
        check_motion(&Law::Motion(e.clone()))?;
        check_motion(&Law::Centrode(e))?;
    }
    Ok(())
}

/// Every parser on one text.
fn check_all(text: &str) -> Result<(), TestCaseError> {
    check_trajectory(text)?;
    check_design_file(text)?;
    check_scene(text, false)?;
    check_scene(text, true)?;
    check_errors(text, false)?;
    check_errors(text, true)?;
    check_model(text, true)?;
    check_model(text, false)?;
    check_record(text)?;
    check_law_csv(text)?;
    check_expr(text)
}

#[test]
fn bundled_assets_parse() {
    // The mutation bases are valid inputs (so the fuzz explores near valid files).
    assert!(Trajectory::parse_csv(G1_CSV, "g").is_ok());
    assert!(Trajectory::parse_csv(KIDNEY_CSV, "k").is_ok());
    assert!(Trajectory::parse_json(ASYM_JSON, "a").is_ok());
    assert!(Trajectory::from_dxf(BULGE_DXF.as_bytes(), &DrawingOptions::default(), "b").is_ok());
    assert!(Trajectory::from_svg(BEZIER_SVG, &DrawingOptions::default(), "z").is_ok());
    let none = DrawingOptions::default();
    assert!(Trajectory::from_dxf(LOOPED_DXF.as_bytes(), &none, "l").is_ok());
    assert!(Trajectory::from_svg(LOOPED_SVG, &none, "l").is_ok());
    assert!(Trajectory::from_dxf(JUNCTION_DXF.as_bytes(), &none, "j").is_err());
    assert!(Trajectory::from_dxf(SPIKE_DXF.as_bytes(), &none, "s").is_err());
    assert!(DesignFile::parse(design_json(), "d").is_ok());
    for s in SCENES {
        assert!(Scene::parse(s, "s", Format::Toml).is_ok());
        assert!(Scene::parse(&toml_to_json(s), "s", Format::Json).is_ok());
    }
    assert!(ErrorFile::parse(ERRORS_TOML, "e", Format::Toml).is_ok());
    assert!(ErrorFile::parse(&toml_to_json(ERRORS_TOML), "e", Format::Json).is_ok());
    assert!(Record::from_csv_reader(head(SIGNALS_CSV, 400).as_bytes(), "r").is_ok());
    assert!(
        ModelParams::parse(MODEL_TOML, "m", Format::Toml).is_ok_and(|p| p.planet_set().is_ok())
    );
    assert!(
        ModelParams::parse(MODEL_JSON, "m", Format::Json).is_ok_and(|p| p.planet_set().is_ok())
    );
    assert!(Law::parse_csv(LAW_CSV, "l").is_ok());
    assert!(Expr::parse("phi - 0.08*sin(2*phi)").is_ok());
}

#[test]
fn hand_made_parser_edge_cases_are_typed_errors() {
    // Pair expressions: deep nesting, overlong input, empty input.
    let deep = "(".repeat(100_000) + "phi";
    assert!(Expr::parse(&deep).is_err());
    assert!(Expr::parse(&"-".repeat(100_000)).is_err());
    assert!(Expr::parse(&"sin(".repeat(40_000)).is_err());
    assert!(Expr::parse("").is_err());
    // A centrode whose scale overflows (r ≈ 1e308): typed error or finite motion.
    check_motion(&Law::Centrode(Expr::parse("1e308*(1.5+cos(phi))").unwrap())).unwrap();
    check_motion(&Law::Centrode(
        Expr::parse("1e-320*(1.5+cos(phi))").unwrap(),
    ))
    .unwrap();
    check_motion(&Law::Motion(Expr::parse("phi + 1e308*sin(phi)").unwrap())).unwrap();
    // Law CSV: NaN, duplicated rows, header only.
    assert!(Law::parse_csv("phi_deg,psi_deg\n0,nan\n", "l").is_err());
    assert!(Law::parse_csv("phi_deg,psi_deg\n", "l").is_err());
    let dup = LAW_CSV.replacen("5.000000,", "0.000000,", 1);
    assert!(Law::parse_csv(&dup, "l").is_err());
    // Deeply nested JSON / TOML documents: a typed error, not a stack overflow.
    let nested = "[".repeat(100_000);
    check_all(&nested).unwrap();
    let nested_toml = "a = ".to_string() + &"[".repeat(100_000);
    check_all(&nested_toml).unwrap();
    let inline = "a = ".to_string() + &"{b = ".repeat(20_000);
    check_all(&inline).unwrap();
}

proptest! {
    #![proptest_config(cfg(512, 0x8_0001))]

    /// Arbitrary bytes into every parser.
    #[test]
    fn every_parser_survives_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..1500)) {
        check_all(&String::from_utf8_lossy(&bytes))?;
    }

    /// Random text over the alphabet of the formats (digits, separators, keys, brackets).
    #[test]
    fn every_parser_survives_format_like_text(
        parts in proptest::collection::vec(prop::sample::select(vec![
            "0", "1", "2.5", "-3", "1e3", "nan", "inf", ",", "\n", " ", "=", "[", "]", "{", "}",
            "\"", ":", "#", "phi", "sin(", ")", "*", "^", "t_s", "x_um", "y_um", "points",
            "[gears]", "z1", "terms", "planet", "phi_deg,psi_deg\n", "t_s,x_um,y_um\n",
        ]), 0..200),
    ) {
        check_all(&parts.concat())?;
    }
}

proptest! {
    #![proptest_config(cfg(512, 0x8_0002))]

    #[test]
    fn mutated_trajectory_files(muts in proptest::collection::vec(mutation(), 1..4), which in 0usize..9) {
        let base = [
            G1_CSV, KIDNEY_CSV, ASYM_JSON, BULGE_DXF, BEZIER_SVG, LOOPED_DXF, LOOPED_SVG,
            JUNCTION_DXF, SPIKE_DXF,
        ][which];
        check_trajectory(&apply(base, &muts))?;
    }

    #[test]
    fn mutated_design_files(muts in proptest::collection::vec(mutation(), 1..4)) {
        check_design_file(&apply(design_json(), &muts))?;
    }

    #[test]
    fn mutated_scenes(muts in proptest::collection::vec(mutation(), 1..4), which in 0usize..5, json: bool) {
        let base = if json { toml_to_json(SCENES[which]) } else { SCENES[which].to_string() };
        check_scene(&apply(&base, &muts), json)?;
    }

    #[test]
    fn mutated_error_files(muts in proptest::collection::vec(mutation(), 1..4), json: bool) {
        let base = if json { toml_to_json(ERRORS_TOML) } else { ERRORS_TOML.to_string() };
        check_errors(&apply(&base, &muts), json)?;
    }

    #[test]
    fn mutated_orbit_files(muts in proptest::collection::vec(mutation(), 1..4), which in 0usize..3) {
        match which {
            0 => check_record(&apply(&head(SIGNALS_CSV, 300), &muts))?,
            1 => check_model(&apply(MODEL_TOML, &muts), true)?,
            _ => check_model(&apply(MODEL_JSON, &muts), false)?,
        }
    }

    #[test]
    fn mutated_pair_laws(muts in proptest::collection::vec(mutation(), 1..4), which in 0usize..4) {
        match which {
            0 | 1 => check_law_csv(&apply(LAW_CSV, &muts))?,
            2 => check_expr(&apply("phi - 0.08*sin(2*phi)", &muts))?,
            _ => check_expr(&apply("1 + 0.08*cos(2*phi) + 0.01*sqrt(abs(sin(phi)))^3", &muts))?,
        }
    }
}
