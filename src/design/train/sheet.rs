//! The toothed train and its drawings: one gear in its body frame, or the whole train placed at
//! a carrier angle.
use super::TrainTeethReport;
use crate::cad::{Contour, Marker, Sheet};
use crate::design::Design;
use crate::geometry::assembly::Assembly;
use crate::geometry::pitch::PitchCurve;
use crate::math::Point;
use crate::math::periodic::uniform_angles;
use crate::teeth::Outline;

/// The toothed train.
#[derive(Debug, Clone)]
pub struct ToothedTrain {
    /// Report (`design.json` → `teeth`).
    pub report: TrainTeethReport,
    /// The scaled assembly (final gears), world frame.
    pub assembly: Assembly,
    /// Sun outline, body frame (about O), export chord tolerance.
    pub sun: Outline,
    /// Intermediate outline, body frame (about its centre).
    pub intermediate: Outline,
    /// Planet outline, body frame (about its centre).
    pub planet: Outline,
}

/// Places body-frame points at `centre` rotated by `angle` (rad).
fn place(points: &[Point], centre: Point, angle: f64) -> Vec<Point> {
    let (s, c) = angle.sin_cos();
    points
        .iter()
        .map(|p| Point::new(centre.x + c * p.x - s * p.y, centre.y + s * p.x + c * p.y))
        .collect()
}

fn pitch_polyline(curve: &PitchCurve) -> Vec<Point> {
    uniform_angles(1440)
        .iter()
        .map(|&t| curve.point_mm(t))
        .collect()
}

fn contour(name: &str, layer: &str, points_mm: Vec<Point>) -> Contour {
    Contour {
        name: name.into(),
        layer: layer.into(),
        points_mm,
        closed: true,
    }
}

/// Which gear of the train.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Gear {
    /// The fixed sun (centre O).
    Sun,
    /// The intermediate gear (centre D).
    Intermediate,
    /// The planet gear (centre A, carries the needle).
    Planet,
}

impl Gear {
    /// The three gears in train order.
    pub const ALL: [Gear; 3] = [Gear::Sun, Gear::Intermediate, Gear::Planet];

    /// Lower-case name (`sun`, `intermediate`, `planet`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Gear::Sun => "sun",
            Gear::Intermediate => "intermediate",
            Gear::Planet => "planet",
        }
    }
}

impl ToothedTrain {
    /// Records this train's report in `design.report.teeth` (the `teeth` block of
    /// `design.json`), replacing any earlier one.
    pub fn record(&self, design: &mut Design) {
        design.report.teeth = Some(self.report.clone());
        design.report.update_verdict();
    }

    fn parts(&self, gear: Gear) -> (&Outline, &PitchCurve) {
        match gear {
            Gear::Sun => (&self.sun, &self.assembly.sun),
            Gear::Intermediate => (&self.intermediate, &self.assembly.intermediate),
            Gear::Planet => (&self.planet, &self.assembly.planet),
        }
    }

    /// One gear in its body frame (rotation centre at the origin), for manufacturing: layers
    /// `<GEAR>_OUTLINE`, `<GEAR>_PITCH`, `CENTRES`.
    #[must_use]
    pub fn gear_sheet(&self, gear: Gear) -> Sheet {
        let (o, c) = self.parts(gear);
        let up = gear.name().to_uppercase();
        Sheet {
            contours: vec![
                contour(
                    &format!("{}_outline", gear.name()),
                    &format!("{up}_OUTLINE"),
                    o.points_mm.clone(),
                ),
                contour(
                    &format!("{}_pitch", gear.name()),
                    &format!("{up}_PITCH"),
                    pitch_polyline(c),
                ),
            ],
            markers: vec![Marker {
                name: format!("{}_center", gear.name()),
                layer: "CENTRES".into(),
                at_mm: Point::new(0.0, 0.0),
            }],
        }
    }

    /// The whole train at carrier angle `phi_h_rad`, world frame (mm): every gear's outline and
    /// pitch curve placed at its centre and orientation, the centres O, D, A and the needle tip.
    #[must_use]
    pub fn sheet(&self, phi_h_rad: f64) -> Sheet {
        let pose = self.assembly.rebuild().pose(phi_h_rad);
        let o = self.assembly.center_mm;
        let at = [
            (o, 0.0),
            (pose.intermediate_center_mm, pose.intermediate_angle_rad),
            (pose.planet_center_mm, pose.planet_angle_rad),
        ];
        let mut sheet = Sheet::default();
        for (gear, (centre, angle)) in Gear::ALL.into_iter().zip(at) {
            let body = self.gear_sheet(gear);
            for c in body.contours {
                sheet.contours.push(Contour {
                    points_mm: place(&c.points_mm, centre, angle),
                    ..c
                });
            }
            sheet.markers.push(Marker {
                name: format!("{}_center", gear.name()),
                layer: "CENTRES".into(),
                at_mm: centre,
            });
        }
        sheet.markers.push(Marker {
            name: "needle_tip".into(),
            layer: "CENTRES".into(),
            at_mm: pose.tip_mm,
        });
        sheet
    }
}
