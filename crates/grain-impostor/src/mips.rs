//! Premultiplied-alpha mip chains with dilation (§4.2, last paragraph: "special care must
//! be taken to account for alpha premultiplication when computing the mipmaps").
//!
//! Each level `k + 1` texel covers a `2 × 2` block of level `k`:
//!
//! - `α' = mean α` of the block, so coverage is conserved;
//! - every attribute `a' = Σ αᵢ aᵢ / Σ αᵢ`, i.e. the premultiplied values are averaged
//!   (`a'α' = mean aᵢαᵢ`): background texels (α = 0) contribute nothing, so no background
//!   colour bleeds into a silhouette. Normals are averaged without renormalisation (the
//!   shortening records the normals' spread; samplers renormalise).
//!
//! **Dilation.** Before each reduction, background texels get attributes from covered
//! neighbours ([`dilate`]), so that un-premultiplied values are meaningful everywhere:
//! blocks with no coverage at all reduce to the mean of their dilated attributes, and
//! layouts that store colour separately from α (the packed layout of [`crate::packed`],
//! or bilinear filtering of un-premultiplied values) never see a background colour near a
//! silhouette. In the premultiplied [`crate::scene::ATLAS_LAYERS`] the stored value of an
//! α = 0 texel is 0 whatever its attributes.

use crate::atlas_image::{AtlasImage, AtlasTexel};

/// How many rings of neighbour averaging [`dilate`] runs before filling the rest of a
/// view with the mean of its covered texels.
pub const DILATION_RINGS: u32 = 2;

/// Fills the attributes of background texels (α = 0): [`DILATION_RINGS`] passes give each
/// background texel next to a covered or already filled one the mean attributes of those
/// 8-neighbours; the remaining background texels of a view get the α-weighted mean of the
/// view's covered texels (or stay zero in an empty view). α is unchanged.
pub fn dilate(image: &mut AtlasImage) {
    let side = image.side as usize;
    let per_view = side * side;
    for view in image.texels.chunks_exact_mut(per_view) {
        let mut filled: Vec<bool> = view.iter().map(|t| t.alpha > 0.0).collect();
        let mut sum = [0.0f32; 9];
        let mut weight = 0.0;
        for texel in view.iter().filter(|t| t.alpha > 0.0) {
            for (s, a) in sum.iter_mut().zip(texel.attributes()) {
                *s += texel.alpha * a;
            }
            weight += texel.alpha;
        }
        if weight == 0.0 {
            continue;
        }
        for _ in 0..DILATION_RINGS {
            let mut updates = Vec::new();
            for y in 0..side {
                for x in 0..side {
                    if filled[y * side + x] {
                        continue;
                    }
                    let mut acc = [0.0f32; 9];
                    let mut count = 0.0;
                    for ny in y.saturating_sub(1)..(y + 2).min(side) {
                        for nx in x.saturating_sub(1)..(x + 2).min(side) {
                            if filled[ny * side + nx] {
                                for (s, a) in acc.iter_mut().zip(view[ny * side + nx].attributes()) {
                                    *s += a;
                                }
                                count += 1.0;
                            }
                        }
                    }
                    if count > 0.0 {
                        updates.push((y * side + x, acc.map(|s| s / count)));
                    }
                }
            }
            for (index, attributes) in updates {
                view[index] = AtlasTexel::from_attributes(attributes, 0.0);
                filled[index] = true;
            }
        }
        let mean = sum.map(|s| s / weight);
        for (texel, done) in view.iter_mut().zip(&filled) {
            if !done {
                *texel = AtlasTexel::from_attributes(mean, 0.0);
            }
        }
    }
}

/// The next mip level of a dilated level of even side (or side 1, returned unchanged):
/// premultiplied averages of `2 × 2` blocks (see the module documentation).
pub fn reduce(image: &AtlasImage) -> AtlasImage {
    if image.side <= 1 {
        return image.clone();
    }
    let side = image.side as usize;
    let half = side / 2;
    let mut texels = Vec::with_capacity(image.views as usize * half * half);
    for view in image.texels.chunks_exact(side * side) {
        for y in 0..half {
            for x in 0..half {
                let block = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| view[(2 * y + dy) * side + 2 * x + dx]);
                let alpha_sum: f32 = block.iter().map(|t| t.alpha).sum();
                let mut acc = [0.0f32; 9];
                for texel in &block {
                    let weight = if alpha_sum > 0.0 { texel.alpha / alpha_sum } else { 0.25 };
                    for (s, a) in acc.iter_mut().zip(texel.attributes()) {
                        *s += weight * a;
                    }
                }
                texels.push(AtlasTexel::from_attributes(acc, 0.25 * alpha_sum));
            }
        }
    }
    AtlasImage { side: half as u32, views: image.views, texels }
}

/// Every level from `level0` (side a power of two) down to `1 × 1`, each dilated.
pub fn build_mip_chain(mut level0: AtlasImage) -> Vec<AtlasImage> {
    dilate(&mut level0);
    let mut levels = vec![level0];
    while let Some(last) = levels.last().filter(|l| l.side > 1) {
        let mut next = reduce(last);
        dilate(&mut next);
        levels.push(next);
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A 2-view, 16 × 16 level: a disc of varying colour on a background whose attributes
    /// are a garish out-of-range marker (which must never reach a covered texel).
    fn disc_level() -> AtlasImage {
        let side = 16u32;
        let mut texels = Vec::new();
        for view in 0..2 {
            for y in 0..side {
                for x in 0..side {
                    let (u, v) = ((x as f32 + 0.5) / 8.0 - 1.0, (y as f32 + 0.5) / 8.0 - 1.0);
                    let r2 = u * u + v * v;
                    let alpha = ((0.8 - r2) * 4.0).clamp(0.0, 1.0);
                    texels.push(if alpha > 0.0 {
                        AtlasTexel {
                            normal: Vec3::new(u, v, (1.0 - r2).max(0.0).sqrt()).normalize(),
                            albedo: Vec3::new(0.2 + 0.5 * (u + 1.0) / 2.0, 0.3, 0.1 + 0.1 * view as f32),
                            roughness: 0.2 + 0.3 * (v + 1.0) / 2.0,
                            metallic: 0.1,
                            depth: (1.0 - r2).max(0.0).sqrt(),
                            alpha,
                        }
                    } else {
                        AtlasTexel::from_attributes([9.0; 9], 0.0)
                    });
                }
            }
        }
        AtlasImage { side, views: 2, texels }
    }

    #[test]
    fn alpha_of_each_level_is_the_mean_alpha_of_the_level_above() {
        let levels = build_mip_chain(disc_level());
        assert_eq!(levels.len(), 5);
        for pair in levels.windows(2) {
            let (fine, coarse) = (&pair[0], &pair[1]);
            for view in 0..2 {
                for y in 0..coarse.side {
                    for x in 0..coarse.side {
                        let mean: f32 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .iter()
                            .map(|(dx, dy)| fine.texels[fine.index(view, 2 * x + dx, 2 * y + dy).unwrap()].alpha)
                            .sum::<f32>()
                            / 4.0;
                        let alpha = coarse.texels[coarse.index(view, x, y).unwrap()].alpha;
                        assert!((alpha - mean).abs() < 1e-6, "view {view} ({x}, {y}): {alpha} vs {mean}");
                    }
                }
            }
        }
    }

    #[test]
    fn no_covered_mip_texel_leaves_the_range_of_the_covered_texels_it_came_from() {
        let level0 = disc_level();
        let levels = build_mip_chain(level0.clone());
        let covered0 = (0..2)
            .flat_map(|view| (0..level0.side * level0.side).map(move |i| (view, i % level0.side, i / level0.side)))
            .filter(|&(view, x, y)| level0.texels[level0.index(view, x, y).unwrap()].alpha > 0.0)
            .count();
        for (k, level) in levels.iter().enumerate() {
            let footprint = 1u32 << k;
            let mut compared = 0;
            for view in 0..2 {
                for y in 0..level.side {
                    for x in 0..level.side {
                        let texel = level.texels[level.index(view, x, y).unwrap()];
                        if texel.alpha <= 0.0 {
                            continue;
                        }
                        compared += 1;
                        let mut low = [f32::INFINITY; 9];
                        let mut high = [f32::NEG_INFINITY; 9];
                        for fy in y * footprint..(y + 1) * footprint {
                            for fx in x * footprint..(x + 1) * footprint {
                                let source = level0.texels[level0.index(view, fx, fy).unwrap()];
                                if source.alpha > 0.0 {
                                    for (i, a) in source.attributes().into_iter().enumerate() {
                                        low[i] = low[i].min(a);
                                        high[i] = high[i].max(a);
                                    }
                                }
                            }
                        }
                        // A weighted mean lies in the range of what it averages, up to the
                        // f32 rounding of the sums (values ≤ 1, ≤ 4 terms per level).
                        for (i, a) in texel.attributes().into_iter().enumerate() {
                            assert!(
                                a >= low[i] - 1e-5 && a <= high[i] + 1e-5,
                                "level {k} view {view} ({x}, {y}) attribute {i}: {a} outside [{}, {}]",
                                low[i],
                                high[i]
                            );
                        }
                    }
                }
            }
            // Every footprint holding a covered level-0 texel gives a covered texel here
            // (the premultiplied α of a mean of covered values is positive): at least one
            // per `footprint²` covered source texels.
            let footprint_area = (footprint * footprint) as usize;
            assert!(
                compared * footprint_area >= covered0,
                "level {k}: {compared} covered texels compared, from {covered0} covered at level 0"
            );
        }
    }

    #[test]
    fn dilation_replaces_every_background_attribute_and_keeps_alpha() {
        let mut level = disc_level();
        let before = level.clone();
        dilate(&mut level);
        for (after, before) in level.texels.iter().zip(&before.texels) {
            assert_eq!(after.alpha, before.alpha);
            if before.alpha > 0.0 {
                assert_eq!(after, before);
            } else {
                // The marker 9.0 is gone: attributes now lie in the covered range (albedo ≤ 0.8).
                assert!(after.albedo.max_element() <= 0.8, "{after:?}");
            }
        }
    }
}
