//! Floating-point rounding constants for conservative error bounds.

/// Half the distance between 1 and the next larger `f32` (2⁻²⁴): the largest relative error of
/// one correctly rounded `f32` operation.
pub const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// γ(n) = nε / (1 − nε): a bound on the relative error accumulated by `n` successive rounded
/// operations (Higham's bound, as used by pbrt-v4).
#[inline]
pub fn gamma(n: i32) -> f32 {
    let n_eps = n as f32 * MACHINE_EPSILON;
    n_eps / (1.0 - n_eps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_matches_its_definition_in_f64() {
        for n in [1, 3, 7, 20] {
            let eps = 2f64.powi(-24);
            let expected = n as f64 * eps / (1.0 - n as f64 * eps);
            let got = gamma(n) as f64;
            assert!(
                (got - expected).abs() <= expected * 1e-6,
                "γ({n}) = {got}, want {expected}"
            );
        }
        assert!(gamma(7) > 7.0 * MACHINE_EPSILON);
    }
}
