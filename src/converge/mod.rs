//! Convergence measurement: error of renders against a reference as the sample count grows.
//!
//! - [`metrics`]: RMSE and relative MSE of an image against a reference.
//! - [`fit_log_slope`]: the least-squares slope of log error against log spp (−0.5 for plain
//!   Monte Carlo; steeper for a good low-discrepancy sequence on a smooth integrand).
//! - [`write_csv`], [`write_plot`]: `converge.csv` and the log-log error-versus-time plot
//!   (plotters), both written atomically.
//! - [`read_exr`]: a reference image from an OpenEXR file (its R, G, B channels).

use crate::output::{OutputError, write_atomically};
use crate::render::Image;
use glam::Vec3;
use std::io::Write;
use std::path::{Path, PathBuf};

/// `ε` of the relative MSE `(x − r)² / (r² + ε)`: keeps black reference pixels from
/// dominating (the value used by Rousselle et al. 2011 and most denoising papers since).
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// Why a convergence run failed.
#[derive(Debug, thiserror::Error)]
pub enum ConvergeError {
    /// The reference could not be read.
    #[error(
        "cannot read the reference {path}: {message}; give an OpenEXR file with R, G, B channels (e.g. from glint render -o ref.exr)"
    )]
    Reference {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The reference does not match the render.
    #[error(
        "the reference {path} is {found_w}×{found_h} but the renders are {width}×{height}; pass --width {found_w} --height {found_h} or render a matching reference"
    )]
    Size {
        /// The file.
        path: PathBuf,
        /// Reference size.
        found_w: u32,
        /// Reference size.
        found_h: u32,
        /// Render size.
        width: u32,
        /// Render size.
        height: u32,
    },
    /// An output could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Error of an image against a reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Root mean squared error over all pixels and channels, W/(m²·sr).
    pub rmse: f64,
    /// Mean of `(x − r)² / (r² + ε)` over pixels and channels (dimensionless).
    pub rel_mse: f64,
}

/// Error of `image` against `reference` (same size; extra pixels of either are ignored).
pub fn metrics(image: &Image<Vec3>, reference: &Image<Vec3>) -> Metrics {
    let (mut se, mut rel, mut n) = (0.0f64, 0.0f64, 0usize);
    for (x, r) in image.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let (x, r) = (x[c] as f64, r[c] as f64);
            let d = x - r;
            se += d * d;
            rel += d * d / (r * r + REL_MSE_EPSILON);
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    Metrics {
        rmse: (se / n).sqrt(),
        rel_mse: rel / n,
    }
}

/// Least-squares slope of `ln y` against `ln x` over the points with both positive and
/// finite; `None` with fewer than two distinct x.
pub fn fit_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    if logs.len() < 2 {
        return None;
    }
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// One measured render of a convergence run.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The setting's label (e.g. `embree sobol box:0.5`).
    pub setting: String,
    /// Samples per pixel.
    pub spp: u32,
    /// Render time in seconds (passes only).
    pub seconds: f64,
    /// Rays traced.
    pub rays: u64,
    /// Error against the reference.
    pub metrics: Metrics,
}

/// Writes the measurements as CSV (header `setting,spp,seconds,rays,rmse,rel_mse`).
pub fn write_csv(path: &Path, rows: &[Measurement]) -> Result<(), OutputError> {
    write_atomically(path, |w| {
        let io = |source| OutputError::Io {
            path: path.to_path_buf(),
            source,
        };
        writeln!(w, "setting,spp,seconds,rays,rmse,rel_mse").map_err(io)?;
        for m in rows {
            writeln!(
                w,
                "{},{},{:.6},{},{:.6e},{:.6e}",
                m.setting, m.spp, m.seconds, m.rays, m.metrics.rmse, m.metrics.rel_mse
            )
            .map_err(io)?;
        }
        Ok(())
    })
}

/// Plot size in pixels.
pub const PLOT_SIZE: (u32, u32) = (900, 600);

/// Draws RMSE against render time on log-log axes, one curve per setting (in the order they
/// first appear), and writes it as PNG.
pub fn write_plot(path: &Path, title: &str, rows: &[Measurement]) -> Result<(), OutputError> {
    use plotters::prelude::*;
    let encode = |message: String| OutputError::Encode {
        path: path.to_path_buf(),
        format: "PNG",
        message,
    };
    let mut settings: Vec<&str> = Vec::new();
    for m in rows {
        if !settings.contains(&m.setting.as_str()) {
            settings.push(&m.setting);
        }
    }
    let positive = |v: f64| v > 0.0 && v.is_finite();
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter(|m| positive(m.seconds) && positive(m.metrics.rmse))
        .map(|m| (m.seconds, m.metrics.rmse))
        .collect();
    let range = |f: fn(&(f64, f64)) -> f64| {
        let lo = points.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = points.iter().map(f).fold(0.0, f64::max);
        if lo.is_finite() && hi > 0.0 {
            (lo / 1.5)..(hi * 1.5)
        } else {
            1e-3..1.0
        }
    };
    let (w, h) = PLOT_SIZE;
    let mut buffer = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| encode(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(range(|p| p.0).log_scale(), range(|p| p.1).log_scale())
            .map_err(|e| encode(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("render time (s)")
            // Log axes put labels at awkward values (0.0100000000000001): three significant
            // digits are enough to read a plot.
            .x_label_formatter(&|v| format!("{v:.3}"))
            .y_label_formatter(&|v| format!("{v:.1e}"))
            .y_desc("RMSE (W/(m²·sr))")
            .draw()
            .map_err(|e| encode(e.to_string()))?;
        for (i, setting) in settings.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let curve: Vec<(f64, f64)> = rows
                .iter()
                .filter(|m| m.setting == *setting)
                .filter(|m| positive(m.seconds) && positive(m.metrics.rmse))
                .map(|m| (m.seconds, m.metrics.rmse))
                .collect();
            chart
                .draw_series(LineSeries::new(curve.clone(), color.stroke_width(2)))
                .map_err(|e| encode(e.to_string()))?
                .label(*setting)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
            chart
                .draw_series(curve.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                .map_err(|e| encode(e.to_string()))?;
        }
        chart
            .configure_series_labels()
            // Upper right: the curves fall toward the lower right, away from the legend.
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| encode(e.to_string()))?;
        root.present().map_err(|e| encode(e.to_string()))?;
    }
    let rgb = image::RgbImage::from_raw(w, h, buffer)
        .ok_or_else(|| encode("plot buffer has the wrong size".into()))?;
    write_atomically(path, |writer| {
        rgb.write_to(writer, image::ImageFormat::Png)
            .map_err(|e| encode(e.to_string()))
    })
}

/// Reads the R, G, B channels of the first layer of an OpenEXR file.
pub fn read_exr(path: &Path) -> Result<Image<Vec3>, ConvergeError> {
    use exr::prelude::*;
    let fail = |message: String| ConvergeError::Reference {
        path: path.to_path_buf(),
        message,
    };
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![Vec3::ZERO; resolution.width() * resolution.height()],
            )
        },
        |(width, pixels): &mut (usize, Vec<Vec3>),
         position,
         (r, g, b, _a): (f32, f32, f32, f32)| {
            if let Some(p) = pixels.get_mut(position.y() * *width + position.x()) {
                *p = Vec3::new(r, g, b);
            }
        },
    )
    .map_err(|e| fail(e.to_string()))?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    let (width, height) = (
        u32::try_from(size.width()).map_err(|e| fail(e.to_string()))?,
        u32::try_from(size.height()).map_err(|e| fail(e.to_string()))?,
    );
    Ok(crate::render::Image {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law() {
        let points: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0, 16.0]
            .iter()
            .map(|&n: &f64| (n, 3.0 * n.powf(-0.75)))
            .collect();
        let slope = fit_log_slope(&points).unwrap();
        assert!((slope + 0.75).abs() < 1e-12, "{slope}");
        assert_eq!(fit_log_slope(&points[..1]), None);
        assert_eq!(fit_log_slope(&[(1.0, 1.0), (1.0, 2.0)]), None);
    }

    #[test]
    fn metrics_of_a_known_difference() {
        let reference = Image::filled(2, 1, Vec3::ONE);
        let mut image = reference.clone();
        image.pixels[0] = Vec3::new(1.0, 1.0, 4.0);
        let m = metrics(&image, &reference);
        // One channel of six off by 3: MSE 9/6.
        assert!((m.rmse - (9.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((m.rel_mse - 9.0 / 1.01 / 6.0).abs() < 1e-12);
        assert_eq!(metrics(&reference, &reference).rmse, 0.0);
    }
}
