//! Draco seeds (filled in with the Draco decoder's support).

/// No Draco seeds yet.
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    Vec::new()
}
