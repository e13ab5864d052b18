//! Benchmark of `ncgear pair` on the ncgears oracle law `phi - 0.08*sin(2*phi)`, 24 teeth, m 1.5:
//! the design (law → pitch curves → rack-generated outlines, no verification), the design with
//! the default 90-step mesh verification, and the exports. Run: `cargo bench --bench pair`.
use ncgear::cad::dxf::{DxfVersion, write_dxf};
use ncgear::cad::svg::to_svg_string;
use ncgear::pair::{Expr, Law, PairOptions, design_pair};

fn main() {
    divan::main();
}

fn law() -> Law {
    Law::Motion(Expr::parse("phi - 0.08*sin(2*phi)").expect("valid law"))
}

#[divan::bench(sample_count = 10)]
fn design_no_verification() {
    let mut opts = PairOptions::new(Some(24), 1.5);
    opts.toothing.verify_steps = 0;
    divan::black_box(design_pair(&law(), &opts).expect("pair"));
}

#[divan::bench(sample_count = 3)]
fn design_with_90_step_verification() {
    let mut opts = PairOptions::new(Some(24), 1.5);
    opts.toothing.verify_steps = 90;
    divan::black_box(design_pair(&law(), &opts).expect("pair"));
}

#[divan::bench(sample_count = 10)]
fn exports_svg_dxf(bencher: divan::Bencher) {
    let mut opts = PairOptions::new(Some(24), 1.5);
    opts.toothing.verify_steps = 0;
    let d = design_pair(&law(), &opts).expect("pair");
    let sheet = d.assembly_sheet();
    let path = std::env::temp_dir().join("ncgear_bench_pair.dxf");
    bencher.bench(|| {
        divan::black_box(to_svg_string(&sheet, 3.0));
        write_dxf(&sheet, &path, DxfVersion::R2010, 1.5e-3).expect("dxf");
    });
}
