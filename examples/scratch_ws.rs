use nmm::simulation::Simulation;
fn main() {
    let text = std::fs::read_to_string("/work/scratch/ws10.toml").unwrap();
    let mut sim = Simulation::new(nmm::verify::cases::model(&text).unwrap()).unwrap();
    let last = sim.model.blocks.len() - 1;
    for _ in 0..3 {
        sim.advance().unwrap();
        let cs: Vec<_> = sim
            .contacts
            .contacts
            .iter()
            .filter(|c| c.key.0 == last || c.key.2 == last)
            .collect();
        for c in cs {
            println!(
                "  key {:?} pos {:?} n {:?} gn0 {:.3e} w {:.3} status {:?} tn {:.4e} ts {:.4e}",
                c.key,
                c.position,
                c.normal,
                c.gn0,
                c.weight,
                c.response.status,
                c.response.tn,
                c.response.ts
            );
        }
        println!("---");
    }
}
