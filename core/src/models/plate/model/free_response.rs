//! The exact free response of one damped linear mode, for the second starting value of
//! [`super::PlateModel::set_state`].

/// Exact free response at `t = -h` of `q̈ + c q̇ + ω² q = 0` with `q(0) = q0`, `q̇(0) = v0`:
/// `q(t) = e^{-σt} [q0 C(t) + (v0 + σ q0) S(t)]`, `σ = c/2`, with `C = cos(ω_d t)`,
/// `S = sin(ω_d t)/ω_d` (under-damped), `cosh`/`sinh` (over-damped) or `1`, `t` (critical).
pub(super) fn free_response_backward(omega: f64, c: f64, h: f64, q0: f64, v0: f64) -> f64 {
    let sigma = 0.5 * c;
    let disc = omega * omega - sigma * sigma;
    let (cc, ss) = if disc > 0.0 {
        let wd = disc.sqrt();
        ((wd * h).cos(), (wd * h).sin() / wd)
    } else if disc < 0.0 {
        let lam = (-disc).sqrt();
        ((lam * h).cosh(), (lam * h).sinh() / lam)
    } else {
        (1.0, h)
    };
    // C is even and S odd in t.
    (sigma * h).exp() * (q0 * cc - (v0 + sigma * q0) * ss)
}
