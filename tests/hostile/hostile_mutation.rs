//! A seeded mutation loop over the shared sample scenes: a few thousand structure-aware
//! mutants (JSON value edits, byte flips, truncations, splices; see `mutate/mod.rs`), each
//! loaded and prepared on every backend. Asserts zero panics and only one-line errors naming
//! the file; an abort (Embree) or a hang would fail the test binary as a whole.

use crate::mutate;

use rand::{Rng, SeedableRng};
use std::path::Path;

/// Mutants per run: about 20 s on one loaded core in the dev profile.
const MUTANTS: usize = 2000;
/// Seeds above this size are left to the fuzz loop (texture decoding dominates them).
const MAX_SEED_BYTES: u64 = 64 * 1024;

#[test]
fn mutants_of_the_shared_assets_never_panic() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    let seeds = mutate::seeds(
        &[shared.join("scenes"), shared.join("khronos")],
        MAX_SEED_BYTES,
    );
    assert!(seeds.len() >= 5, "too few seeds under {}", shared.display());
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
    let mut crashes = Vec::new();
    for round in 0..MUTANTS {
        let seed = &seeds[rng.random_range(0..seeds.len())];
        let mutant = mutate::mutate(&seed.bytes, &mut rng);
        if let mutate::Outcome::Crash(why) = mutate::execute(&mutant, &seed.name, &seed.dir) {
            crashes.push(format!("round {round}, {}: {why}", seed.name));
        }
    }
    let _ = std::panic::take_hook();
    assert!(
        crashes.is_empty(),
        "{} crashes:\n{}",
        crashes.len(),
        crashes.join("\n")
    );
}
