//! Transplanter tolerance analysis (companion spec C.6).
use ncgear::analysis::transplanter::*;
use ncgear::assembly::Assembly;
use ncgear::golden::g1_mechanism;

fn g1() -> Assembly {
    Assembly::from_mechanism(&g1_mechanism(), [0.0, 0.0], 1, 720).unwrap()
}

#[test]
fn zero_errors_reproduce_the_rebuilt_train() {
    let asm = g1();
    let m = ExactModel::new(&asm, 20f64.to_radians(), 1).unwrap();
    let rb = asm.rebuild();
    let mut worst: f64 = 0.0;
    for p in m.grid(360) {
        let s = m.state(p, &[0.0; N_COORDS]).unwrap();
        let q = rb.pose(p);
        worst = worst.max((s.tip_mm[0] - q.tip_mm[0]).hypot(s.tip_mm[1] - q.tip_mm[1]));
    }
    println!("worst {worst:e}");
    assert!(worst < 1e-6, "{worst}");
}
