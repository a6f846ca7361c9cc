//! The unit tests' random numbers: a xorshift64 generator with a fixed seed, so every run
//! draws the same scenes.

/// Uniform numbers in `[0, 1)` (24 bits) from a xorshift64 state seeded with `seed` (not 0).
pub(crate) fn uniform(mut state: u64) -> impl FnMut() -> f32 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}
