//! Denoising a finished render with Intel Open Image Denoise (OIDN 2), behind the cargo
//! feature `denoise` (`glint render --denoise`, the batch key `denoise`, `denoise=True` in
//! Python).
//!
//! OIDN's "RT" filter (its model for path-traced images) runs on the CPU device, with the
//! render's thread count, on:
//! - `color`: the HDR radiance as rendered (W/(m²·sr), `hdr = true`); NaN and negative values,
//!   which no correct render has, are passed as 0;
//! - `albedo`: glint's first-hit albedo AOV ([`crate::render::AovSelection::albedo`]), clamped
//!   to [0, 1] as OIDN requires;
//! - `normal`: glint's first-hit shading-normal AOV, in world space (OIDN accepts world or
//!   camera space, any length, components in [−1, 1]).
//!
//! The auxiliary images are averages over the same samples as the colour: free of
//! light-transport noise (first hit only), but with as few samples per pixel as the colour at
//! edges, in depth of field and under fine textures. They are therefore passed as they are with
//! `cleanAux = false`, OIDN's setting for auxiliary images that may carry noise; they are not
//! prefiltered (the oidn crate's filter always takes a colour input, so OIDN's own recipe for
//! prefiltering auxiliaries, a filter with the auxiliary as its only input, is not reachable
//! through its safe API).
//!
//! A denoiser is not an unbiased estimator: the denoised image is a biased, lower-variance
//! estimate of the render. glint keeps the noisy radiance beside it (the EXR's `noisy.R/G/B`
//! layer). Without the feature, [`denoise`] fails with [`DenoiseError::Unavailable`], whose
//! message says how to get the library.

use crate::render::Image;
use glam::Vec3;

/// Whether this build can denoise (the cargo feature `denoise`).
pub const AVAILABLE: bool = cfg!(feature = "denoise");

/// Why an image could not be denoised.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    /// This glint was built without the `denoise` feature.
    #[error(
        "--denoise: this glint was built without Open Image Denoise; run scripts/setup.sh \
         (it gets the library) and build with `--features denoise` (README, \"Denoising\")"
    )]
    Unavailable,
    /// An auxiliary image does not match the colour image.
    #[error("denoise: the {name} image is {got}×{got_h}, the colour image {width}×{height}")]
    Size {
        /// Which image.
        name: &'static str,
        /// Its width.
        got: u32,
        /// Its height.
        got_h: u32,
        /// The colour image's width.
        width: u32,
        /// The colour image's height.
        height: u32,
    },
    /// OIDN refused (device creation, filter setup or execution).
    #[error("denoise: Open Image Denoise failed: {0}")]
    Oidn(String),
}

/// The auxiliary images OIDN is given beside the colour.
#[derive(Clone, Copy, Debug)]
pub struct Auxiliary<'a> {
    /// Reflectance at the first hit (clamped to [0, 1] before use).
    pub albedo: &'a Image<Vec3>,
    /// World-space shading normal at the first hit (each component clamped to [−1, 1]).
    pub normal: &'a Image<Vec3>,
}

/// The colour as OIDN takes it: interleaved RGB, NaN and negative values as 0.
pub fn color_input(image: &Image<Vec3>) -> Vec<f32> {
    interleave(image, |v| v.max(0.0))
}

/// The albedo as OIDN takes it: interleaved RGB in [0, 1], NaN as 0.
pub fn albedo_input(image: &Image<Vec3>) -> Vec<f32> {
    interleave(image, |v| v.clamp(0.0, 1.0))
}

/// The normal as OIDN takes it: interleaved XYZ, each component in [−1, 1], NaN as 0.
pub fn normal_input(image: &Image<Vec3>) -> Vec<f32> {
    interleave(image, |v| v.clamp(-1.0, 1.0))
}

/// `f` applied to every channel of every pixel, NaN replaced by 0 first (`f32::max` and
/// `clamp` would keep it).
fn interleave(image: &Image<Vec3>, f: impl Fn(f32) -> f32) -> Vec<f32> {
    image
        .pixels
        .iter()
        .flat_map(|p| p.to_array())
        .map(|v| if v.is_nan() { 0.0 } else { f(v) })
        .collect()
}

/// Denoises `color` with OIDN's RT filter on the CPU with `threads` threads (0: as many as the
/// process may use),
/// with `aux` as auxiliary images when given (colour alone otherwise).
pub fn denoise(
    color: &Image<Vec3>,
    aux: Option<Auxiliary<'_>>,
    threads: usize,
) -> Result<Image<Vec3>, DenoiseError> {
    if let Some(aux) = aux {
        for (name, image) in [("albedo", aux.albedo), ("normal", aux.normal)] {
            if (image.width, image.height) != (color.width, color.height) {
                return Err(DenoiseError::Size {
                    name,
                    got: image.width,
                    got_h: image.height,
                    width: color.width,
                    height: color.height,
                });
            }
        }
    }
    let pixels = run_filter(color, aux, resolved_threads(threads))?;
    Ok(Image {
        width: color.width,
        height: color.height,
        pixels: pixels
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect(),
    })
}

/// The thread count OIDN is given: `threads`, or for 0 the cores this process may use (what
/// the render's pool starts), rather than OIDN's own default (its task scheduler's view of the
/// machine, which may count cores the process cannot use).
fn resolved_threads(threads: usize) -> usize {
    if threads > 0 {
        return threads;
    }
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

#[cfg(not(feature = "denoise"))]
fn run_filter(
    _color: &Image<Vec3>,
    _aux: Option<Auxiliary<'_>>,
    _threads: usize,
) -> Result<Vec<f32>, DenoiseError> {
    Err(DenoiseError::Unavailable)
}

#[cfg(feature = "denoise")]
fn run_filter(
    color: &Image<Vec3>,
    aux: Option<Auxiliary<'_>>,
    threads: usize,
) -> Result<Vec<f32>, DenoiseError> {
    let device = oidn_cpu::device(threads)?;
    let oidn_error = |e: oidn::Error| DenoiseError::Oidn(e.to_string());
    let mut filter = oidn::RayTracing::try_new(&device).map_err(oidn_error)?;
    filter
        .hdr(true)
        .clean_aux(false)
        .image_dimensions(color.width as usize, color.height as usize);
    let (albedo, normal);
    if let Some(aux) = aux {
        albedo = albedo_input(aux.albedo);
        normal = normal_input(aux.normal);
        filter.albedo_normal(&albedo, &normal);
    }
    let input = color_input(color);
    let mut output = vec![0.0; input.len()];
    filter.filter(&input, &mut output).map_err(oidn_error)?;
    Ok(output)
}

/// OIDN's CPU device with a thread count, the one place glint calls OIDN's C API directly (the
/// oidn crate commits a device as it creates it, before a thread count could be set).
#[cfg(feature = "denoise")]
#[allow(unsafe_code)]
mod oidn_cpu {
    use super::DenoiseError;
    use oidn::sys;

    /// A committed CPU device running `threads` threads, without pinning them to cores (the
    /// render's pool shares the machine).
    pub fn device(threads: usize) -> Result<oidn::Device, DenoiseError> {
        let threads = i32::try_from(threads).unwrap_or(i32::MAX);
        // SAFETY: oidnNewDevice returns a new handle or null; a non-null handle is configured
        // and committed before `Device::from_raw` takes ownership of it (its Drop releases
        // it), as from_raw requires. The parameter names are NUL-terminated literals.
        let device = unsafe {
            let handle = sys::oidnNewDevice(sys::OIDNDeviceType_OIDN_DEVICE_TYPE_CPU);
            if handle.is_null() {
                return Err(DenoiseError::Oidn(
                    "no CPU device (is libOpenImageDenoise_device_cpu beside the library?)".into(),
                ));
            }
            sys::oidnSetDeviceInt(handle, c"numThreads".as_ptr(), threads);
            sys::oidnSetDeviceBool(handle, c"setAffinity".as_ptr(), false);
            sys::oidnCommitDevice(handle);
            oidn::Device::from_raw(handle)
        };
        device
            .get_error()
            .map_err(|e| DenoiseError::Oidn(e.to_string()))?;
        Ok(device)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_are_clamped_to_what_oidn_accepts() {
        let image = Image {
            width: 2,
            height: 1,
            pixels: vec![Vec3::new(-1.0, f32::NAN, 2.0), Vec3::new(0.5, 1.5, -0.5)],
        };
        assert_eq!(color_input(&image), [0.0, 0.0, 2.0, 0.5, 1.5, 0.0]);
        assert_eq!(albedo_input(&image), [0.0, 0.0, 1.0, 0.5, 1.0, 0.0]);
        assert_eq!(normal_input(&image), [-1.0, 0.0, 1.0, 0.5, 1.0, -0.5]);
    }

    #[test]
    fn mismatched_auxiliaries_are_refused() {
        let color = Image::filled(4, 3, Vec3::ONE);
        let small = Image::filled(3, 3, Vec3::ONE);
        let err = denoise(
            &color,
            Some(Auxiliary {
                albedo: &small,
                normal: &color,
            }),
            1,
        )
        .unwrap_err();
        assert!(err.to_string().contains("albedo image is 3×3"), "{err}");
    }
}
