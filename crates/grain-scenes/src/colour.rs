//! Per-grain procedural attributes after Fig. 16: a hashed value `t ∈ [0, 1)` per grain,
//! mapped through a colour ramp, packed as RGBA8.

/// The stops of the sand ramp: `t` and an sRGB-encoded RGBA8 colour. Piecewise linear
/// between stops (in the 8-bit encoded values), from dark umber through ochre to pale
/// beige, with a few darker grains near `t = 0`, as in the ramp under Fig. 16's images.
pub const SAND_RAMP: [(f64, [u8; 4]); 4] =
    [(0.0, [74, 52, 36, 255]), (0.15, [140, 100, 62, 255]), (0.6, [201, 164, 112, 255]), (1.0, [238, 224, 192, 255])];

/// Packs RGBA8 into a `u32` with red in the low byte: the layout of WGSL's
/// `unpack4x8unorm` (component 0 in bits 0..8) and of `[u8; 4]` on little-endian GPUs.
pub const fn pack_rgba8(c: [u8; 4]) -> u32 {
    u32::from_le_bytes(c)
}

/// The inverse of [`pack_rgba8`].
pub const fn unpack_rgba8(c: u32) -> [u8; 4] {
    c.to_le_bytes()
}

/// [`SAND_RAMP`] at `t` (clamped to `[0, 1]`), rounded to the nearest 8-bit value, packed.
pub fn sand_ramp(t: f64) -> u32 {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let mut i = 0;
    while i + 2 < SAND_RAMP.len() && t > SAND_RAMP[i + 1].0 {
        i += 1;
    }
    let (t0, c0) = SAND_RAMP[i];
    let (t1, c1) = SAND_RAMP[i + 1];
    let w = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    let mut out = [0u8; 4];
    for k in 0..4 {
        let v = f64::from(c0[k]) + w * (f64::from(c1[k]) - f64::from(c0[k]));
        out[k] = v.round().clamp(0.0, 255.0) as u8;
    }
    pack_rgba8(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_hits_its_stops_and_is_monotone_in_luminance() {
        for (t, c) in SAND_RAMP {
            assert_eq!(unpack_rgba8(sand_ramp(t)), c, "t = {t}");
        }
        assert_eq!(sand_ramp(-1.0), sand_ramp(0.0));
        assert_eq!(sand_ramp(2.0), sand_ramp(1.0));
        assert_eq!(sand_ramp(f64::NAN), sand_ramp(0.0));
        let lum = |c: u32| {
            let [r, g, b, _] = unpack_rgba8(c);
            u32::from(r) + u32::from(g) + u32::from(b)
        };
        let mut last = 0;
        for i in 0..=1000 {
            let l = lum(sand_ramp(f64::from(i) / 1000.0));
            assert!(l >= last);
            last = l;
        }
        assert_eq!(pack_rgba8([1, 2, 3, 4]), 0x0403_0201);
    }
}
