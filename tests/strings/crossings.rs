//! The pitch of one string of an instrument on a moving bridge (the tanpura, the sitar), read
//! from its sound as the tests play it: written here, apart from the tuner's own measurement
//! (`noether::models::tanpura::tune::first_partial_hz`), which steps a bare network.

use noether::models::network::BridgeInstrument;

/// The frequency (Hz) of string `string`'s first modal coordinate over steps `[from, to)` of
/// `inst` at `fs` Hz (steps it there; `steps` reads its step count): upward zero crossings,
/// linearly interpolated between steps. Panics with fewer than two crossings.
pub fn first_partial<T: BridgeInstrument>(
    inst: &mut T,
    steps: impl Fn(&T) -> u64,
    string: usize,
    fs: f64,
    from: u64,
    to: u64,
) -> f64 {
    let q_of = |inst: &T| inst.network().strings()[string].modal_displacement()[0];
    let mut prev = q_of(inst);
    let (mut first, mut last, mut count) = (None, 0.0, 0u64);
    while steps(inst) < to {
        inst.advance();
        let q = q_of(inst);
        let n = steps(inst);
        if n > from && prev < 0.0 && q >= 0.0 {
            let at = n as f64 - 1.0 + prev / (prev - q);
            first.get_or_insert(at);
            last = at;
            count += 1;
        }
        prev = q;
    }
    (count - 1) as f64 * fs / (last - first.expect("crossings"))
}
