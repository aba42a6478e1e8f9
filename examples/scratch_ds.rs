use nmm::verify::cases::{direct_shear_on, JointOnMesh};
fn main() {
    let h = direct_shear_on(4e6, 40.0, "return-mapping", JointOnMesh::Between.origin()).unwrap();
    for s in &h {
        println!("{} cuts {}", s.iterations, s.cuts);
    }
}
