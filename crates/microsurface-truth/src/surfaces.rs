//! The five generated surfaces of the Fig. 9 experiment and of the Smith-model selector:
//! three Gaussian spectra and two non-Gaussian textures, all at one RMS slope, with the
//! independent realizations a Gaussian surface's model is fitted on.

use crate::generate::{Spectrum, generate_cellular, generate_gaussian, generate_ridged};
use crate::heightfield::{HeightField, HeightFieldError};

/// RMS slope of every generated surface: Λ spans 0 … 20 over 0° … 89°.
pub const SLOPE_SIGMA: f64 = 0.5;

/// Seed offsets of the realizations a Gaussian surface's model is fitted on.
pub const FITTING_SEED_OFFSETS: [u64; 2] = [1000, 2000];

/// One surface of the experiments.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Its name (`gaussian_correlation`, `fbm_power_law`, `band_pass`, `cellular`,
    /// `ridged`, or a height map's file stem).
    pub name: String,
    /// Whether its heights are Gaussian (H3 holds).
    pub gaussian: bool,
    /// The surface measured.
    pub field: HeightField,
    /// Independent realizations of the same generator to fit the model on (empty: fit on
    /// `field` itself, as a renderer's pre-computation of a texture would).
    pub fitting_fields: Vec<HeightField>,
}

impl Surface {
    /// The fields its model is fitted on: the independent realizations, or the field
    /// itself for a texture.
    pub fn fitting(&self) -> &[HeightField] {
        if self.fitting_fields.is_empty() { std::slice::from_ref(&self.field) } else { &self.fitting_fields }
    }
}

/// The five generated surfaces at `size`² cells, with generator seeds shifted by
/// `seed_offset`, without fitting realizations.
pub fn realizations(size: usize, seed_offset: u64) -> Result<Vec<Surface>, HeightFieldError> {
    let surface = |name: &str, gaussian: bool, field: HeightField| Surface {
        name: name.to_owned(),
        gaussian,
        field,
        fitting_fields: Vec::new(),
    };
    Ok(vec![
        surface(
            "gaussian_correlation",
            true,
            generate_gaussian(size, Spectrum::Gaussian { wavelength: 16.0 }, SLOPE_SIGMA, 1 + seed_offset)?,
        ),
        surface(
            "fbm_power_law",
            true,
            generate_gaussian(
                size,
                Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: size as f64 / 4.0, exponent: 3.0 },
                SLOPE_SIGMA,
                2 + seed_offset,
            )?,
        ),
        surface(
            "band_pass",
            true,
            generate_gaussian(size, Spectrum::BandPass { wavelength: 24.0, width: 0.1 }, SLOPE_SIGMA, 3 + seed_offset)?,
        ),
        surface("cellular", false, generate_cellular(size, size / 8, SLOPE_SIGMA, 4 + seed_offset)?),
        surface("ridged", false, generate_ridged(size, 16.0, SLOPE_SIGMA, 5 + seed_offset)?),
    ])
}

/// [`realizations`] at `seed_offset`, each Gaussian surface with its fitting realizations
/// at [`FITTING_SEED_OFFSETS`] (the same for every `seed_offset`, so that every
/// realization of a material gets the same fitted model).
pub fn standard_surfaces(size: usize, seed_offset: u64) -> Result<Vec<Surface>, HeightFieldError> {
    let mut list = realizations(size, seed_offset)?;
    for offset in FITTING_SEED_OFFSETS {
        for (surface, fitting) in list.iter_mut().zip(realizations(size, offset)?) {
            if surface.gaussian {
                surface.fitting_fields.push(fitting.field);
            }
        }
    }
    Ok(list)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_surfaces_are_fitted_on_other_realizations_and_textures_on_themselves() {
        let list = standard_surfaces(32, 0).unwrap();
        let names: Vec<&str> = list.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["gaussian_correlation", "fbm_power_law", "band_pass", "cellular", "ridged"]);
        for s in &list {
            if s.gaussian {
                assert_eq!(s.fitting().len(), 2, "{}", s.name);
                assert!(s.fitting().iter().all(|f| f.heights() != s.field.heights()), "{}", s.name);
            } else {
                assert_eq!(s.fitting()[0].heights(), s.field.heights(), "{}", s.name);
            }
        }
        // Another realization: other heights, the same fitting fields.
        let other = standard_surfaces(32, 3000).unwrap();
        assert_ne!(other[0].field.heights(), list[0].field.heights());
        assert_eq!(other[0].fitting_fields[0].heights(), list[0].fitting_fields[0].heights());
    }
}
