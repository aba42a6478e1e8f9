//! The committed contact states a checkpoint keeps (`contact/set/saved.rs`), on a real
//! contact set: a block resting on an incline after some steps. `tests/restart.rs` checks
//! the whole restart through the `nmm` binary (history byte for byte after SIGINT/SIGKILL);
//! here the contact states themselves are compared, in the library, exactly.

use nmm::contact::set::ContactSet;
use nmm::simulation::checkpoint::{Checkpoint, SavedOptions, SavedOutputs};
use nmm::simulation::Simulation;
use std::path::Path;

const STEPS: usize = 30;
const MORE: usize = 20;

fn model() -> nmm::model::Model {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/incline.toml"
    ))
    .unwrap()
    .replace("size = 0.0625", "size = 0.125");
    assert!(text.contains("size = 0.125"));
    nmm::model::parse_model(&text, Path::new(".")).unwrap()
}

fn run(sim: &mut Simulation, steps: usize) {
    for _ in 0..steps {
        sim.advance().unwrap();
    }
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn saved_contact_states_survive_a_round_trip_and_the_restored_run_continues_as_the_original() {
    let mut sim = Simulation::new(model()).unwrap();
    run(&mut sim, STEPS);
    let saved = sim.contacts.saved();
    // a state worth saving: every step committed, the slider's corners closed on the base
    assert_eq!(saved.commits, STEPS);
    assert!(saved.committed.len() >= 2, "{saved:?}");
    assert!(saved.seen.len() >= saved.committed.len());
    assert!(
        saved
            .committed
            .iter()
            .all(|c| c.1.law.name() == "return-mapping"
                && nmm::contact::ShearHistory::from_state(&c.1.state).tn < 0.0
                && c.1.branch != nmm::contact::law::Branch::Open),
        "{saved:?}"
    );
    assert!(saved.lasting.is_empty(), "no law here keeps open contacts");
    // sorted, so that the same state saves the same bytes
    assert!(saved.committed.windows(2).all(|w| w[0].0 < w[1].0));
    assert!(saved.seen.windows(2).all(|w| w[0] < w[1]));

    // restore into a fresh set: the same state, and saving it again gives it back
    let mut fresh = ContactSet::default();
    assert_ne!(fresh.saved(), saved);
    fresh.restore(&saved);
    assert_eq!(fresh.saved(), saved);

    // through the checkpoint bytes into a fresh simulation of the same model
    let bytes = sim.checkpoint_bytes(
        "incline.toml",
        &SavedOptions::default(),
        &SavedOutputs::default(),
    );
    let ckpt = Checkpoint::from_bytes(&bytes).unwrap();
    let mut restored = Simulation::new(model()).unwrap();
    restored.restore(&ckpt).unwrap();
    assert_eq!(restored.contacts.saved(), saved);
    assert_eq!(bits(&restored.u), bits(&sim.u));

    // both continue identically, step by step, contact states included
    for k in 0..MORE {
        let a = sim.advance().unwrap();
        let b = restored.advance().unwrap();
        assert_eq!(a.iterations, b.iterations, "step {k} after the restore");
        assert_eq!(
            bits(&sim.u),
            bits(&restored.u),
            "u, step {k} after the restore"
        );
        assert_eq!(
            bits(&sim.v),
            bits(&restored.v),
            "v, step {k} after the restore"
        );
        assert_eq!(sim.contacts.saved(), restored.contacts.saved(), "step {k}");
    }
    assert_eq!(sim.contacts.saved().commits, STEPS + MORE);
}
