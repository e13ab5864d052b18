//! STEP (ISO 10303-21, AP214 `AUTOMOTIVE_DESIGN`) solids of extruded gears, in mm, written by
//! ncgear itself: one part per file, or an assembly of placed parts (the train, a pair).
//!
//! # Why planar side faces
//! Each gear is its tooth outline (a closed polyline already within the export chord tolerance of
//! the generated tooth flank) extruded by the face width. The side faces are one plane per outline
//! segment: the solid is then *exactly* the polyline the DXF carries, its volume exactly the
//! polygon area × face width, and every CAD kernel reads planes without fitting or healing. A
//! B-spline fit would add its own fitting error on top of the chord tolerance, and the faceting
//! is finer than the tolerance the teeth were checked to (1e-3·m by default). The caps are exact
//! planes; the bore is an exact cylinder (two half faces, so every edge bounds exactly two faces).
//!
//! # Determinism
//! The header carries a fixed time stamp (`2000-01-01T00:00:00`) and reals are written in their
//! shortest round-trip form: the same model gives the same bytes.
use crate::math::Point;
mod brep;

use super::{ExportError, io_err};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// One extruded gear body: a tooth outline in its body frame (rotation centre at the origin),
/// extruded along +z from 0 to the face width, with an optional central bore.
#[derive(Debug, Clone, PartialEq)]
pub struct Prism {
    /// Part name (e.g. `sun`), also the solid's name.
    pub name: String,
    /// Closed outline, mm, body frame, no repeated end vertex (either orientation).
    pub outline_mm: Vec<Point>,
    /// Face width (extrusion length along +z), mm.
    pub face_width_mm: f64,
    /// Bore diameter about the origin, mm (0 = no bore).
    pub bore_mm: f64,
}

/// One placed occurrence of a part in an assembly: the body frame's origin at `center_mm` (world,
/// z = 0), turned by `angle_rad` about +z.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// Occurrence name (e.g. `arm2_planet`).
    pub name: String,
    /// Index into [`StepModel::parts`].
    pub part: usize,
    /// Rotation centre, world frame, mm.
    pub center_mm: Point,
    /// Orientation about +z, rad.
    pub angle_rad: f64,
}

/// What a STEP file holds: one part (no instances) or an assembly named `name` of placed parts.
#[derive(Debug, Clone, PartialEq)]
pub struct StepModel {
    /// Model (assembly) name.
    pub name: String,
    /// The distinct parts.
    pub parts: Vec<Prism>,
    /// Placed occurrences; empty: the file is the single part `parts[0]` in its body frame.
    pub instances: Vec<Instance>,
}

/// Counts of a written STEP file, for reports and tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepStats {
    /// Solids written (one per part).
    pub solids: usize,
    /// Faces over all solids.
    pub faces: usize,
    /// Data entities.
    pub entities: usize,
}

/// The entity list of the DATA section, numbered from 1 in write order.
pub(crate) struct Ents {
    /// The DATA section so far: one `#n=…;` line per entity.
    data: String,
    /// The last id given.
    count: usize,
    /// False for a counting pass (ids only, no text).
    write: bool,
}

impl Ents {
    /// An empty list whose next entity gets id `after + 1`.
    fn after(after: usize, write: bool) -> Self {
        Self {
            data: String::new(),
            count: after,
            write,
        }
    }

    /// Adds an entity (its text without `#n=` and `;`), returns its id. Written straight into
    /// the DATA text: no string per entity (a 24-tooth pair has ≈ 100 000 entities).
    pub(crate) fn add(&mut self, text: std::fmt::Arguments<'_>) -> usize {
        self.count += 1;
        if self.write {
            let _ = writeln!(self.data, "#{}={text};", self.count);
        }
        self.count
    }
}

/// A STEP real: shortest round-trip digits, always with a decimal point, `E` exponent, no `-0.`
/// (a value to format with `{}`; nothing is allocated).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Real(f64);

/// [`Real`] of `x`.
pub(crate) fn real(x: f64) -> Real {
    Real(x)
}

impl std::fmt::Display for Real {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0 == 0.0 {
            return f.write_str("0.");
        }
        // The shortest round-trip digits (Ryū, as serde_json prints reals): "1.0", "1e-7".
        let mut buf = ryu::Buffer::new();
        let s = buf.format_finite(self.0);
        let (mant, exp) = match s.split_once('e') {
            Some((m, e)) => (m, Some(e)),
            None => (s, None),
        };
        if mant.contains('.') {
            f.write_str(mant.trim_end_matches('0'))?;
        } else {
            f.write_str(mant)?;
            f.write_str(".")?;
        }
        match exp {
            Some(e) => write!(f, "E{e}"),
            None => Ok(()),
        }
    }
}

/// A STEP string literal (apostrophes doubled, non-ASCII replaced by `_`).
pub(crate) fn quote(s: &str) -> String {
    let clean: String = s
        .chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("'{}'", clean.replace('\'', "''"))
}

/// Twice the signed area of a closed polygon (positive when CCW), mm².
fn twice_area(p: &[Point]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - a.y * b.x
        })
        .sum()
}

/// Whether the origin lies inside a closed polygon (crossing number).
fn origin_inside(p: &[Point]) -> bool {
    let mut inside = false;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        if (a.y > 0.0) != (b.y > 0.0) && a.x - a.y * (b.x - a.x) / (b.y - a.y) > 0.0 {
            inside = !inside;
        }
    }
    inside
}

/// The part with a CCW outline, checked: ≥ 3 finite vertices, no zero-length segment, a positive
/// finite face width, a bore that fits inside the outline.
fn checked(p: &Prism) -> Result<Prism, ExportError> {
    let bad = |what| ExportError::BadContour {
        name: p.name.clone(),
        what,
    };
    if p.outline_mm.len() < 3 {
        return Err(bad("fewer than 3 vertices"));
    }
    if p.outline_mm
        .iter()
        .any(|q| !(q.x.is_finite() && q.y.is_finite()))
    {
        return Err(bad("non-finite coordinate"));
    }
    let n = p.outline_mm.len();
    if (0..n).any(|i| p.outline_mm[i] == p.outline_mm[(i + 1) % n]) {
        return Err(bad("repeated consecutive vertex"));
    }
    let a2 = twice_area(&p.outline_mm);
    if a2 == 0.0 {
        return Err(bad("zero area"));
    }
    check_solid_sizes(p.face_width_mm, p.bore_mm)?;
    if p.bore_mm > 0.0 {
        let inner = (0..n)
            .map(|i| {
                crate::math::polyline::seg_dist(
                    Point::ZERO,
                    p.outline_mm[i],
                    p.outline_mm[(i + 1) % n],
                )
            })
            .fold(f64::INFINITY, f64::min);
        if !(0.5 * p.bore_mm < inner) || !origin_inside(&p.outline_mm) {
            return Err(ExportError::InvalidOption {
                name: "bore",
                value: p.bore_mm,
                expected: "a bore diameter smaller than twice the gear's smallest radius to its outline",
            });
        }
    }
    let mut q = p.clone();
    if a2 < 0.0 {
        q.outline_mm.reverse();
    }
    Ok(q)
}

/// Checks the sizes of an extruded part that need no outline: a finite face width > 0 mm and a
/// finite bore diameter ≥ 0 mm (0 = none).
///
/// # Errors
/// [`ExportError::InvalidOption`] naming `face_width` or `bore`.
pub fn check_solid_sizes(face_width_mm: f64, bore_mm: f64) -> Result<(), ExportError> {
    if !(face_width_mm > 0.0 && face_width_mm.is_finite()) {
        return Err(ExportError::InvalidOption {
            name: "face_width",
            value: face_width_mm,
            expected: "a positive face width in mm",
        });
    }
    if !(bore_mm >= 0.0 && bore_mm.is_finite()) {
        return Err(ExportError::InvalidOption {
            name: "bore",
            value: bore_mm,
            expected: "a bore diameter ≥ 0 mm (0 = no bore)",
        });
    }
    Ok(())
}

const CONTEXT: [&str; 9] = [
    "APPLICATION_CONTEXT('core data for automotive mechanical design processes')",
    "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#1)",
    "PRODUCT_CONTEXT('',#1,'mechanical')",
    "PRODUCT_DEFINITION_CONTEXT('part definition',#1,'design')",
    "(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))",
    "(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))",
    "(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())",
    "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#5,'distance_accuracy_value','confusion accuracy')",
    "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#8))\
     GLOBAL_UNIT_ASSIGNED_CONTEXT((#5,#6,#7))REPRESENTATION_CONTEXT('ncgear','3D, mm'))",
];
/// Entity id of the geometric representation context (units: mm, rad).
const CTX: usize = 9;

/// A product and its definition: returns `(product definition, product definition shape)`.
fn product(e: &mut Ents, name: &str) -> (usize, usize) {
    let q = quote(name);
    let p = e.add(format_args!("PRODUCT({q},{q},'',(#3))"));
    e.add(format_args!(
        "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{p}))"
    ));
    let f = e.add(format_args!("PRODUCT_DEFINITION_FORMATION('','',#{p})"));
    let d = e.add(format_args!("PRODUCT_DEFINITION('design','',#{f},#4)"));
    let s = e.add(format_args!("PRODUCT_DEFINITION_SHAPE('','',#{d})"));
    (d, s)
}

const ORIGIN: ([f64; 3], [f64; 3], [f64; 3]) = ([0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);

/// A part's product definition, shape representation and origin placement (entity ids).
type PartIds = (usize, usize, usize);

/// The STEP text of `model` and its counts. Every part is validated first.
pub fn step_text(model: &StepModel) -> Result<(String, StepStats), ExportError> {
    let parts = checked_parts(model)?;
    let mut e = Ents::after(0, true);
    for c in CONTEXT {
        e.add(format_args!("{c}"));
    }
    let (defs, faces) = write_parts(&mut e, &parts);
    if !model.instances.is_empty() {
        write_assembly(&mut e, model, &defs);
    }
    let stats = StepStats {
        solids: parts.len(),
        faces,
        entities: e.count,
    };
    let mut out = String::with_capacity(e.data.len() + 512);
    out.push_str("ISO-10303-21;\nHEADER;\n");
    let _ = writeln!(
        out,
        "FILE_DESCRIPTION(('ncgear extruded gear solids','lengths in mm, angles in rad'),'2;1');"
    );
    let _ = writeln!(
        out,
        "FILE_NAME({},'2000-01-01T00:00:00',('ncgear'),('ncgear'),'ncgear {}','ncgear','');",
        quote(&model.name),
        env!("CARGO_PKG_VERSION")
    );
    out.push_str("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n");
    out.push_str(&e.data);
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok((out, stats))
}

/// The model's parts, each checked ([`checked`]), with its instances: one part, or instances
/// of existing parts at finite positions.
fn checked_parts(model: &StepModel) -> Result<Vec<Prism>, ExportError> {
    let parts = model
        .parts
        .iter()
        .map(checked)
        .collect::<Result<Vec<_>, _>>()?;
    if parts.is_empty() || (model.instances.is_empty() && parts.len() != 1) {
        return Err(ExportError::BadContour {
            name: model.name.clone(),
            what: "a STEP model needs one part, or instances placing its parts",
        });
    }
    if let Some(i) = model
        .instances
        .iter()
        .find(|i| i.part >= parts.len() || !(i.center_mm.is_finite() && i.angle_rad.is_finite()))
    {
        return Err(ExportError::BadContour {
            name: i.name.clone(),
            what: "instance of a missing part or at a non-finite position",
        });
    }
    Ok(parts)
}

/// One part's entities: its product, its solid, its origin placement and its representation;
/// returns (product definition, representation, origin placement) and its face count.
fn part_entities(e: &mut Ents, p: &Prism) -> (PartIds, usize) {
    let (pd, pds) = product(e, &p.name);
    let (brep, nf) = brep::solid(e, p);
    let origin = brep::placement(e, ORIGIN.0, ORIGIN.1, ORIGIN.2);
    let rep = e.add(format_args!(
        "ADVANCED_BREP_SHAPE_REPRESENTATION({},(#{brep},#{origin}),#{CTX})",
        quote(&p.name)
    ));
    e.add(format_args!(
        "SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})"
    ));
    ((pd, rep, origin), nf)
}

/// Writes every part's entities after `e`'s, numbered in part order: a counting pass (ids only)
/// gives each part its first id, then the parts' texts are written side by side and joined in
/// order — the same text as one pass. Returns the parts' ids and the total face count.
fn write_parts(e: &mut Ents, parts: &[Prism]) -> (Vec<PartIds>, usize) {
    let mut starts = Vec::with_capacity(parts.len());
    let mut next = e.count;
    for p in parts {
        starts.push(next);
        let mut c = Ents::after(next, false);
        part_entities(&mut c, p);
        next = c.count;
    }
    let texts: Vec<(String, (PartIds, usize))> = parts
        .par_iter()
        .zip(&starts)
        .map(|(p, &start)| {
            let mut pe = Ents::after(start, true);
            let r = part_entities(&mut pe, p);
            (pe.data, r)
        })
        .collect();
    let mut faces = 0;
    let mut defs = Vec::with_capacity(parts.len());
    for (text, (def, nf)) in texts {
        e.data.push_str(&text);
        faces += nf;
        defs.push(def);
    }
    e.count = next;
    (defs, faces)
}

/// The assembly of `model`'s instances: its product, each instance's placement, and the
/// relationships placing the parts `defs` (ids of [`write_parts`]) in it.
fn write_assembly(e: &mut Ents, model: &StepModel, defs: &[PartIds]) {
    let (apd, apds) = product(e, &model.name);
    let aorigin = brep::placement(e, ORIGIN.0, ORIGIN.1, ORIGIN.2);
    let mut items = vec![format!("#{aorigin}")];
    let mut links = Vec::new();
    for inst in &model.instances {
        let (s, c) = inst.angle_rad.sin_cos();
        let at = [inst.center_mm.x, inst.center_mm.y, 0.0];
        let pl = brep::placement(e, at, [0.0, 0.0, 1.0], [c, s, 0.0]);
        items.push(format!("#{pl}"));
        links.push((inst, pl));
    }
    let arep = e.add(format_args!(
        "SHAPE_REPRESENTATION({},({}),#{CTX})",
        quote(&model.name),
        items.join(",")
    ));
    e.add(format_args!(
        "SHAPE_DEFINITION_REPRESENTATION(#{apds},#{arep})"
    ));
    for (k, (inst, pl)) in links.into_iter().enumerate() {
        let (pd, rep, origin) = defs[inst.part];
        let idt = e.add(format_args!(
            "ITEM_DEFINED_TRANSFORMATION('','',#{origin},#{pl})"
        ));
        let rr = e.add(format_args!(
            "(REPRESENTATION_RELATIONSHIP('','',#{rep},#{arep})\
             REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{idt})\
             SHAPE_REPRESENTATION_RELATIONSHIP())"
        ));
        let q = quote(&inst.name);
        let nauo = e.add(format_args!(
            "NEXT_ASSEMBLY_USAGE_OCCURRENCE('{}',{q},'',#{apd},#{pd},$)",
            k + 1
        ));
        let pds = e.add(format_args!("PRODUCT_DEFINITION_SHAPE({q},'',#{nauo})"));
        e.add(format_args!(
            "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{rr},#{pds})"
        ));
    }
}

/// Writes `model` to `path` (see [`step_text`]).
pub fn write_step(model: &StepModel, path: &Path) -> Result<StepStats, ExportError> {
    let (text, stats) = step_text(model)?;
    crate::files::write_whole(path, text).map_err(|e| io_err(path, e))?;
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::{quote, real};

    #[test]
    fn reals_have_a_point_and_an_upper_case_exponent_and_strings_are_escaped() {
        let got: Vec<String> = [0.0, -0.0, 1.0, 10.0, -2.5, 0.1, 1e-7, -1.25e21, 123456.0]
            .map(|x| real(x).to_string())
            .to_vec();
        let want = [
            "0.", "0.", "1.", "10.", "-2.5", "0.1", "1.E-7", "-1.25E21", "123456.",
        ];
        assert_eq!(got, want);
        assert_eq!(quote("arm's gear µ"), "'arm''s gear _'");
    }
}
