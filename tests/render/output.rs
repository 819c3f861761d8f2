//! Output files: the sRGB encoding of known values, exposure, 16-bit PNG, an EXR round trip
//! with AOV channels, and atomic writes that leave nothing behind when they fail.

use glam::Vec3;
use glint::output::png::{SRGB_LINEAR_THRESHOLD, srgb_encode, srgb8, srgb16};
use glint::output::{
    OutputError, OutputFormat, PngDepth, PngOptions, write_atomically, write_exr, write_png,
};
use glint::render::{Aovs, Image};
use std::path::Path;

/// The sRGB curve in f64, from IEC 61966-2-1.
fn srgb_f64(v: f64) -> f64 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[test]
fn srgb_encoding_of_known_values() {
    assert_eq!(srgb8(0.0), 0);
    assert_eq!(srgb8(1.0), 255);
    assert_eq!(srgb8(0.5), 188);
    // At the threshold both segments agree (to the curve's published precision).
    let t = SRGB_LINEAR_THRESHOLD;
    assert!((srgb_encode(t) - (1.055 * t.powf(1.0 / 2.4) - 0.055)).abs() < 1e-6);
    assert_eq!(srgb8(t), (12.92f64 * 0.0031308 * 255.0).round() as u8);
    assert_eq!(srgb8(t), 10);
    // Clipping: above 1, below 0, and NaN.
    assert_eq!(srgb8(7.5), 255);
    assert_eq!(srgb8(-1.0), 0);
    assert_eq!(srgb8(f32::NAN), 0);
    for v in [1e-4f32, 0.001, 0.01, 0.18, 0.2, 0.73, 0.99] {
        let want = srgb_f64(v as f64);
        assert!((srgb_encode(v) as f64 - want).abs() < 1e-6, "{v}");
        assert!((srgb16(v) as f64 - want * 65535.0).abs() <= 0.51, "{v}");
    }
}

fn image_of(values: &[Vec3], width: u32) -> Image<Vec3> {
    Image {
        width,
        height: values.len() as u32 / width,
        pixels: values.to_vec(),
    }
}

#[test]
fn png_exposure_doubles_and_16_bit_keeps_precision() {
    let dir = tempfile::tempdir().unwrap();
    let base = image_of(&[Vec3::new(0.25, 0.1, 0.0), Vec3::new(0.5, 0.05, 1.0)], 2);
    let bright = Image {
        pixels: base.pixels.iter().map(|p| *p * 2.0).collect(),
        ..base.clone()
    };
    let (a, b) = (dir.path().join("ev1.png"), dir.path().join("ev0.png"));
    write_png(
        &a,
        &base,
        PngOptions {
            exposure_ev: 1.0,
            depth: PngDepth::Eight,
        },
    )
    .unwrap();
    write_png(&b, &bright, PngOptions::default()).unwrap();
    let (ra, rb) = (
        image::open(&a).unwrap().to_rgb8(),
        image::open(&b).unwrap().to_rgb8(),
    );
    assert_eq!(ra, rb);
    assert_eq!(ra.get_pixel(0, 0).0, [188, srgb8(0.2), 0]);
    assert_eq!(ra.get_pixel(1, 0).0, [255, srgb8(0.1), 255]);

    let c = dir.path().join("sixteen.png");
    write_png(
        &c,
        &base,
        PngOptions {
            exposure_ev: 0.0,
            depth: PngDepth::Sixteen,
        },
    )
    .unwrap();
    let decoded = image::open(&c).unwrap();
    assert_eq!(decoded.color(), image::ColorType::Rgb16);
    let rc = decoded.to_rgb16();
    let want = |v: f64| (srgb_f64(v) * 65535.0).round();
    for (got, v) in rc.get_pixel(0, 0).0.iter().zip([0.25, 0.1, 0.0]) {
        assert!((*got as f64 - want(v)).abs() <= 1.0, "{got} vs {}", want(v));
    }
    // Finer than 8 bits: a value between two 8-bit codes keeps its own 16-bit code.
    assert_ne!(rc.get_pixel(0, 0).0[0] % 257, 0);
}

#[test]
fn exr_round_trip_with_aovs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.exr");
    let values = [
        Vec3::new(0.1, 1e-30, 1e30),
        Vec3::new(0.0, 123.456, -0.5),
        Vec3::new(3.25, 0.2, 7e-8),
    ];
    let radiance = image_of(&values, 3);
    let aovs = Aovs {
        albedo: Some(image_of(&[Vec3::splat(0.5), Vec3::X, Vec3::ZERO], 3)),
        normal: Some(image_of(&[Vec3::Y, -Vec3::Z, Vec3::new(0.6, 0.8, 0.0)], 3)),
        depth: Some(Image {
            width: 3,
            height: 1,
            pixels: vec![1.5, 0.0, 1e6],
        }),
        alpha: Some(Image {
            width: 3,
            height: 1,
            pixels: vec![1.0, 0.25, 0.0],
        }),
        ..Aovs::default()
    };
    write_exr(&path, &radiance, &aovs).unwrap();

    use exr::prelude::traits::*;
    use exr::prelude::{FlatSamples, Vec2, read_first_flat_layer_from_file};
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(&path)
        .unwrap();
    assert_eq!(image.layer_data.len(), 1);
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, Vec2(3, 1));
    let channel = |name: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .unwrap_or_else(|| panic!("no channel {name}"));
        assert!(
            matches!(c.sample_data, FlatSamples::F32(_)),
            "{name} is not 32-bit float"
        );
        c.sample_data.values_as_f32().collect()
    };
    let mut names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z", "normal.X",
            "normal.Y", "normal.Z"
        ]
    );
    assert_eq!(channel("A"), vec![1.0, 0.25, 0.0]);
    for (axis, name) in ["R", "G", "B"].iter().enumerate() {
        let want: Vec<f32> = values.iter().map(|v| v[axis]).collect();
        assert_eq!(channel(name), want, "channel {name}");
    }
    assert_eq!(channel("normal.Z"), vec![0.0, -1.0, 0.0]);
    assert_eq!(channel("albedo.R"), vec![0.5, 1.0, 0.0]);
    assert_eq!(channel("depth.Z"), vec![1.5, 0.0, 1e6]);

    // Without AOVs: R, G, B only.
    let plain = dir.path().join("plain.exr");
    write_exr(&plain, &radiance, &Aovs::default()).unwrap();
    let image = read_first_flat_layer_from_file(&plain).unwrap();
    assert_eq!(image.layer_data.channel_data.list.len(), 3);
}

fn entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn failed_writes_leave_no_file_and_no_temp() {
    let dir = tempfile::tempdir().unwrap();
    let image = image_of(&[Vec3::ONE; 4], 2);

    // A folder that does not exist.
    let missing = dir.path().join("no/such/folder/out.png");
    let err = write_png(&missing, &image, PngOptions::default()).unwrap_err();
    assert!(matches!(err, OutputError::Io { .. }));
    assert!(err.to_string().contains("out.png"), "{err}");
    assert!(!missing.exists());
    let err = write_exr(&dir.path().join("nope/out.exr"), &image, &Aovs::default()).unwrap_err();
    assert!(matches!(err, OutputError::Io { .. }));

    // An encoder error (an image whose pixel count does not match its size), over an
    // existing file: the old file stays, nothing else appears.
    let path = dir.path().join("keep.png");
    std::fs::write(&path, b"old").unwrap();
    let broken = Image {
        width: 3,
        height: 3,
        pixels: vec![Vec3::ONE; 4],
    };
    assert!(write_png(&path, &broken, PngOptions::default()).is_err());
    assert!(
        write_exr(
            &dir.path().join("broken.exr"),
            &image,
            &Aovs {
                depth: Some(Image {
                    width: 1,
                    height: 1,
                    pixels: vec![0.0]
                }),
                ..Aovs::default()
            }
        )
        .is_err()
    );
    assert_eq!(std::fs::read(&path).unwrap(), b"old");

    // An error injected in the middle of writing.
    let injected = dir.path().join("injected.png");
    let result = write_atomically(&injected, |w| {
        use std::io::Write;
        w.write_all(&[0u8; 100_000]).unwrap();
        Err(OutputError::Encode {
            path: injected.clone(),
            format: "PNG",
            message: "injected".into(),
        })
    });
    assert!(result.is_err());
    assert_eq!(entries(dir.path()), vec!["keep.png".to_string()]);
}

#[test]
fn output_format_from_extension() {
    assert_eq!(
        OutputFormat::from_path(Path::new("a/b.PNG")).unwrap(),
        OutputFormat::Png
    );
    assert_eq!(
        OutputFormat::from_path(Path::new("x.exr")).unwrap(),
        OutputFormat::Exr
    );
    let err = OutputFormat::from_path(Path::new("x.jpg")).unwrap_err();
    assert!(err.to_string().contains(".png or .exr"), "{err}");
    assert!(OutputFormat::from_path(Path::new("noext")).is_err());
}
